/* test_console.c: every menu driven through key sequences on the running application; stored values and screen text checked. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <stdio.h>
#include <string.h>
#include <stdlib.h>
#include <math.h>
#include <cmocka.h>
#include "hal_host.h"
#include "st7920_emu.h"
#include "params.h"
#include "app.h"
#include "ctl.h"
#include "store.h"
#include "totals.h"
#include "diag.h"
#include "screen.h"
#include "keypad.h"
#include "console.h"
#include "console_int.h"
#include "target.h"
#include "ops.h"
#include "sim.h"

static uint64_t now_ns;
static uint32_t wheel_every_ms, flow_every_ms; /* pulse generators, 0 = off */
static uint32_t wheel_sent, flow_sent;
static sim_t *sim_active;           /* when set, the plant model runs the time (sim_step) */

/* Run the main loop for ms of simulated time, one app_poll() every 1 ms. */
static void run_ms(uint32_t ms)
{
    for (uint32_t i = 0; i < ms && sim_active; i++)
        sim_step(sim_active);
    for (uint32_t i = 0; i < ms && !sim_active; i++) {
        now_ns += 1000000u;
        hal_host_set_time_ns(now_ns);
        uint32_t t = (uint32_t)(now_ns / 1000000u);
        if (wheel_every_ms && t % wheel_every_ms == 0) {
            hal_host_wheel_edge(now_ns);
            wheel_sent++;
        }
        if (flow_every_ms && t % flow_every_ms == 0) {
            hal_host_flow_edge(now_ns);
            flow_sent++;
        }
        app_poll();
    }
}

static void press(char k)
{
    static const char map[] = "123A456B789C*0#D";
    const char *p = strchr(map, k);
    assert_non_null(p);
    hal_host_io.keys = (uint16_t)(1u << (p - map));
    run_ms(60);
    hal_host_io.keys = 0;
    run_ms(60);
}

static void keys(const char *s)
{
    while (*s)
        press(*s++);
}

/* A screen line as the LCD shows it (the emulator), checked against the screen model. */
static const char *lcd(uint8_t row)
{
    static char out[4][17];
    char model[17];
    run_ms(CONSOLE_REDRAW_MS + 50);
    st7920_emu_line(row, out[row]);
    for (int c = 0; c < 16; c++)
        model[c] = screen_char(row, (uint8_t)c);
    model[16] = 0;
    assert_string_equal(out[row], model);
    return out[row];
}

static void boot(void)
{
    wheel_every_ms = flow_every_ms = 0;
    hal_host_set_time_ns(0);
    st7920_emu_reset();
    hal_host_lcd_sink(st7920_emu_write);
    hal_init();
    app_init();
    run_ms(200);
}

static int setup(void **state)
{
    (void)state;
    hal_host_reset();
    now_ns = 0;
    sim_active = NULL;
    boot();
    return 0;
}

/* Independent formatting of a value for typing: "392.7" */
static void typed(char *out, uint32_t v, uint8_t dec)
{
    if (!dec) {
        sprintf(out, "%u", (unsigned)v);
        return;
    }
    uint32_t p = dec == 1 ? 10 : 100;
    sprintf(out, "%u#%0*u", (unsigned)(v / p), dec, (unsigned)(v % p));
}

static void trimmed(char *out, uint32_t v, uint8_t dec)
{
    char s[16];
    sprintf(s, "%.*f", dec, dec == 2 ? v / 100.0 : dec == 1 ? v / 10.0 : (double)v);
    if (strchr(s, '.')) {
        size_t n = strlen(s);
        while (s[n - 1] == '0')
            s[--n] = 0;
        if (s[n - 1] == '.')
            s[--n] = 0;
    }
    strcpy(out, s);
}

/* The cross-check's verdict on the settings with parameter id at v (they stay as they were). */
static uint8_t cross_with(uint8_t id, uint16_t v)
{
    uint16_t old = param_v[id];
    param_v[id] = v;
    uint8_t why = params_cross();
    param_v[id] = old;
    return why;
}

/* From the run screen to menu entry i. */
static void to_item(uint8_t i)
{
    press('C');
    press('C');
    press('C');
    press('A');
    for (uint8_t k = 0; k < i; k++)
        press('B');
    char title[17];
    snprintf(title, sizeof title, "Menu %2u/%u", i + 1u, (unsigned)MENU_COUNT);
    char want[48];
    snprintf(want, sizeof want, "%16s", title + 5);
    memcpy(want, "Menu ", 5);
    assert_string_equal(lcd(0), want);
}

static void eeprom_snapshot(uint8_t *buf)
{
    memcpy(buf, hal_host_eeprom(), HAL_EEPROM_SIZE);
}

/* The values in the EEPROM, as a reboot would load them. */
static uint16_t stored(uint8_t id)
{
    uint16_t live[P_COUNT], v;
    memcpy(live, param_v, sizeof live);
    store_load();
    v = param_v[id];
    memcpy(param_v, live, sizeof live);
    return v;
}

/* The run screen's figures against the inputs, worked by hand: a wheel pulse (0.3927 m) every
 * 200 ms is 7.07 km/h; with the 18 m boom at 150 L/ha the target is 150 x 18 x 7.07 / 600 =
 * 31.8 L/min; a meter pulse every 5 ms at 380 p/L is 31.6 L/min, so 149 L/ha applied; ADC 305
 * is 5.96 mA, 196 kPa of the 16 bar sensor (what 31.6 L/min needs on the told nozzles: no
 * alarm); ADC 614 is 12.0 mA, 500 L of the 1000 L tank. */
static void test_console_run_screen_shows_speed_flow_dose_pressure_tank_mode_controller(void **state)
{
    (void)state;
    store_status_clear();
    hal_host_io.adc[HAL_ADC_PRESSURE] = 205;    /* 4.0 mA: the line at rest reads 0 */
    hal_host_io.adc[HAL_ADC_LEVEL] = 614;
    run_ms(3000);
    /* standing: no area covered, no rate */
    assert_string_equal(lcd(2), "Now  --L/ha AUTO");
    hal_host_io.adc[HAL_ADC_PRESSURE] = 305;
    hal_host_io.sections = 0x3F;
    wheel_every_ms = 200;
    flow_every_ms = 5;
    run_ms(10000);
    double v, qt, qm, bar;
    int tank, dose;
    char mode[8], ctl[8];
    printf("# [%s] [%s] [%s] [%s]\n", lcd(0), lcd(1), lcd(2), lcd(3));
    assert_int_equal(sscanf(lcd(0), "%lfkm/h %lfbar", &v, &bar), 2);
    assert_true(fabs(v - 7.1) < 0.01);
    assert_true(fabs(bar - 1.96) < 0.005);
    assert_int_equal(sscanf(lcd(1), "Q %lf> %lfL/mn", &qt, &qm), 2);
    assert_true(fabs(qt - 31.8) < 0.01);
    assert_true(fabs(qm - 31.6) < 0.01);
    assert_int_equal(sscanf(lcd(2), "Now %dL/ha %7s", &dose, mode), 2);
    assert_true(abs(dose - 149) <= 1);
    assert_string_equal(mode, "AUTO");
    assert_int_equal(app_status.alarms, 0);
    assert_int_equal(sscanf(lcd(3), "T %dL %7s", &tank, ctl), 2);
    assert_int_equal(tank, 500);
    assert_string_equal(ctl, ctl_name(ctl_selected()));
    assert_string_equal(ctl, "ffmap");
    /* manual: the mode's word follows */
    press('#');
    assert_non_null(strstr(lcd(2), "MAN"));
    assert_int_equal(st7920_emu_stats()->unsupported, 0);
}

/* Sensors that read a live 4-20 mA loop: no sensor alarm. */
static void sensors_good(void)
{
    hal_host_io.adc[HAL_ADC_PRESSURE] = 300;    /* 5.87 mA: 187 kPa, below P max */
    hal_host_io.adc[HAL_ADC_LEVEL] = 700;       /* 13.7 mA: above Tank min */
}

static void test_console_first_boot_shows_the_eeprom_notice_until_acknowledged(void **state)
{
    (void)state;
    sensors_good();
    run_ms(1500);
    assert_int_equal(app_status.alarms, 0);
    assert_int_equal(store_status(), STORE_DEFAULTS);
    /* first the reset cause, for a message's time, then the EEPROM's state */
    assert_string_equal(lcd(3), "Reset: power-on ");
    run_ms(CONSOLE_MSG_MS);
    assert_string_equal(lcd(3), "!EE: defaults   ");
    press('*');
    assert_int_equal(store_status(), STORE_OK);
    assert_string_equal(lcd(3), "EE: seen        ");
}

/* An alarm takes the line from the notice; `*` acknowledges the alarm shown, says which, and
 * leaves the notice for a press of its own, after it has been shown. */
static void test_console_an_alarm_wins_the_line_over_the_notice(void **state)
{
    char want[17];
    (void)state;
    sensors_good();
    run_ms(CONSOLE_MSG_MS + 1500);
    assert_string_equal(lcd(3), "!EE: defaults   ");
    hal_host_io.adc[HAL_ADC_PRESSURE] = 0;      /* the pressure loop opens */
    run_ms(1500);
    assert_int_equal(app_status.alarms, 1u << AL_PSENS);
    snprintf(want, sizeof want, "!%-15s", "P sensor fault");
    assert_string_equal(lcd(3), want);
    press('*');
    assert_int_equal(app_status.alarms_unacked, 0);
    assert_int_equal(store_status(), STORE_DEFAULTS);       /* not seen yet: kept */
    assert_string_equal(lcd(2), "Acknowledged:   ");
    snprintf(want, sizeof want, " %-15s", "P sensor fault");
    assert_string_equal(lcd(3), want);
    run_ms(CONSOLE_MSG_MS);
    assert_non_null(strstr(lcd(2), "L/ha"));
    assert_string_equal(lcd(3), want);      /* active, acknowledged: still over the notice */
    press('*');                             /* the notice is shown first ... */
    assert_int_equal(store_status(), STORE_DEFAULTS);
    assert_string_equal(lcd(3), "!EE: defaults   ");
    press('*');                             /* ... then acknowledged */
    assert_int_equal(store_status(), STORE_OK);
    assert_string_equal(lcd(3), "EE: seen        ");
}

/* Two alarms not yet acknowledged: one `*` acknowledges the one shown, not the other. */
static void test_console_one_star_acknowledges_only_the_alarm_shown(void **state)
{
    (void)state;
    store_status_clear();
    run_ms(1500);                           /* both 4-20 mA loops read open */
    assert_int_equal(app_status.alarms_unacked, (1u << AL_PSENS) | (1u << AL_LSENS));
    const char *l3 = lcd(3);
    uint16_t shown = strstr(l3, diag_text(AL_PSENS)) ? 1u << AL_PSENS : 1u << AL_LSENS;
    assert_int_equal(l3[0], '!');
    assert_non_null(strstr(l3, diag_text(shown == (1u << AL_PSENS) ? AL_PSENS : AL_LSENS)));
    press('*');
    assert_int_equal(app_status.alarms_unacked, ((1u << AL_PSENS) | (1u << AL_LSENS)) & ~shown);
    run_ms(CONSOLE_MSG_MS);
    l3 = lcd(3);
    assert_int_equal(l3[0], '!');           /* the other one, not yet acknowledged */
    press('*');
    assert_int_equal(app_status.alarms_unacked, 0);
    press('*');
    assert_string_equal(lcd(3), "No new alarms   ");
}

/* Off the run screen `*` first shows the alarm waiting, then acknowledges it. */
static void test_console_star_off_the_run_screen_shows_before_it_acknowledges(void **state)
{
    char want[17];
    (void)state;
    store_status_clear();
    sensors_good();
    run_ms(1500);
    assert_int_equal(app_status.alarms_unacked, 0);
    press('A');                             /* the menu */
    hal_host_io.adc[HAL_ADC_LEVEL] = 0;     /* the level loop opens */
    run_ms(1500);
    assert_int_equal(app_status.alarms_unacked, 1u << AL_LSENS);
    assert_string_equal(lcd(3), "A^ Bv D:ok C:run");
    press('*');
    assert_int_equal(app_status.alarms_unacked, 1u << AL_LSENS);   /* not seen: kept */
    snprintf(want, sizeof want, "!%-15s", diag_text(AL_LSENS));
    assert_string_equal(lcd(3), want);
    press('*');
    assert_int_equal(app_status.alarms_unacked, 0);
    assert_string_equal(lcd(2), "Acknowledged:   ");
    assert_memory_equal(lcd(0), "Menu ", 5);                     /* still in the menu */
}

/* The rate now is the window's volume over its area: totals moved by hand, figures by hand. */
static void test_console_rate_now_is_the_window_volume_over_its_area(void **state)
{
    (void)state;
    store_status_clear();
    sensors_good();
    run_ms(4000);                           /* standing: nothing moves */
    assert_string_equal(lcd(2), "Now  --L/ha AUTO");
    /* 600 ml and 40 m^2 a second: 600 ml / 40 m^2 = 150 L/ha */
    for (int i = 0; i < 5; i++) {
        totals.job_ml += 600;
        totals.job_dm2 += 4000;
        run_ms(1000);
    }
    assert_string_equal(lcd(2), "Now 150L/ha AUTO");
    /* then 400 ml a second on the same area: 100 L/ha once the window holds only those */
    for (int i = 0; i < 4; i++) {
        totals.job_ml += 400;
        totals.job_dm2 += 4000;
        run_ms(1000);
    }
    assert_string_equal(lcd(2), "Now 100L/ha AUTO");
    /* volume with no area (spraying standing): over any figure */
    for (int i = 0; i < 4; i++) {
        totals.job_ml += 400;
        run_ms(1000);
    }
    assert_string_equal(lcd(2), "Now####L/ha AUTO");
    /* the job reset: the window starts there, no leftover of the job before */
    ops_totals_reset();
    totals.job_ml += 250;
    totals.job_dm2 += 10000;
    run_ms(1100);
    assert_string_equal(lcd(2), "Now  25L/ha AUTO");       /* 250 ml / 100 m^2 */
}

/* Every alarm's text fits the line after its mark, whole (a new row is checked too). */
static void test_console_every_alarm_text_fits_the_line(void **state)
{
    (void)state;
    for (uint8_t b = 0; b < AL_COUNT; b++) {
        size_t n = strlen(diag_text(b));
        assert_true(n >= 5 && n <= DIAG_TEXT_MAX);
        assert_true(1 + DIAG_TEXT_MAX <= SCREEN_COLS);
        for (uint8_t c = 0; c < b; c++)
            assert_string_not_equal(diag_text(b), diag_text(c));
    }
}

static void test_console_every_parameter_menu_stores_in_range_and_refuses_out_of_range(void **state)
{
    static uint8_t before[HAL_EEPROM_SIZE], after[HAL_EEPROM_SIZE];
    char s[24], want[48], lo[12], hi[12];
    (void)state;
    for (uint8_t id = 0; id < P_COUNT; id++) {
        if (id == P_CONTROLLER || id == P_MODE || id == P_REMOTE || id == P_LOG_UNIT || id == P_PRESET
            || id == P_UNITS || id == P_SPEED_SRC || id == P_AOG_SECT)
            continue;               /* the choices: named, tested below */
        const param_info_t *pi = param_info(id);
        to_item(id);
        assert_string_equal(lcd(1), (snprintf(want, sizeof want, "%-16s", pi->name), want));
        /* a new value in range (and within the cross-checks, tested below): stored and shown */
        uint16_t v = param_v[id] != pi->max ? pi->max : pi->min;
        if (cross_with(id, v) != PARAM_OK)
            v = param_v[id] != pi->min ? pi->min : pi->max;
        if (cross_with(id, v) != PARAM_OK)
            v = (uint16_t)(param_v[id] + 1);
        press('D');
        typed(s, v, pi->decimals);
        keys(s);
        press('D');
        assert_int_equal(param_v[id], v);
        for (uint32_t t = 0; t <= STORE_ERASE_MS && store_busy(); t += 10)
            run_ms(10);             /* a save that needs an erase waits for the budget (store.h) */
        assert_string_equal(lcd(3), "Saved           ");
        assert_int_equal(stored(id), v);
        /* out of range above, below, and a number too long for any parameter */
        trimmed(lo, pi->min, pi->decimals);
        trimmed(hi, pi->max, pi->decimals);
        snprintf(want, sizeof want, "Range %s..%s", lo, hi);
        assert_true(strlen(want) <= 16);
        uint32_t bad[3] = {(uint32_t)pi->max + 1, pi->min ? pi->min - 1u : 0xFFFFFFFFu, 9999999};
        press('D');
        for (int b = 0; b < 3; b++) {
            if (bad[b] == 0xFFFFFFFFu)
                continue;
            eeprom_snapshot(before);
            if (b == 2)
                strcpy(s, "9999999");
            else
                typed(s, bad[b], pi->decimals);
            keys(s);
            press('D');
            const char *l3 = lcd(3);
            char w16[64];
            snprintf(w16, sizeof w16, "%-16s", want);
            assert_string_equal(l3, w16);
            assert_int_equal(param_v[id], v);       /* the old value stays */
            eeprom_snapshot(after);
            assert_memory_equal(before, after, HAL_EEPROM_SIZE);  /* nothing written */
            assert_non_null(strstr(lcd(0), pi->name)); /* still editing */
        }
        press('C');
        assert_int_equal(param_v[id], v);
    }
}

static void test_console_entry_takes_the_parameter_decimals_only(void **state)
{
    (void)state;
    to_item(P_WHEEL);
    press('D');
    keys("392#75");                 /* one decimal only: the 5 is refused */
    assert_string_equal(lcd(3), "1 decimal only  ");
    assert_string_equal(lcd(2), "new 392.7_ mm/p ");
    press('D');
    assert_int_equal(param_v[P_WHEEL], 3927);
    to_item(P_NOZZLES);
    press('D');
    keys("2#");
    assert_string_equal(lcd(3), "Whole numbers   ");
    keys("4");
    press('C');                     /* clears the entry */
    assert_string_equal(lcd(2), "new _           ");
    keys("48");
    press('D');
    assert_int_equal(param_v[P_NOZZLES], 48);
    assert_int_equal(stored(P_NOZZLES), 48);
    /* a point typed into a whole number spoils the entry: 12#5 is refused, not 125 */
    static uint8_t before[HAL_EEPROM_SIZE];
    eeprom_snapshot(before);
    press('D');
    keys("12#5");
    assert_string_equal(lcd(2), "new 12.5_       ");
    press('D');
    assert_string_equal(lcd(3), "Whole numbers   ");
    assert_int_equal(param_v[P_NOZZLES], 48);
    assert_memory_equal(before, hal_host_eeprom(), HAL_EEPROM_SIZE);
    press('C');
    to_item(P_NOZZLE_Q3);
    press('D');
    keys("1#2");                    /* 1.2 L/min = 120 in hundredths */
    press('D');
    assert_int_equal(param_v[P_NOZZLE_Q3], 120);
    /* an empty entry leaves the value as it was */
    press('D');
    press('D');
    assert_int_equal(param_v[P_NOZZLE_Q3], 120);
}

/* A value in range that does not go with the other settings is refused with the reason,
 * nothing stored: a tank minimum at or above the tank, P start at or above P max, a meter K
 * whose pulses at the largest flow would exceed the interrupt budget. */
static void test_console_cross_checks_refuse_with_the_reason(void **state)
{
    static const struct { uint8_t id; const char *typed, *why; } cases[] = {
        {P_TANK_MIN, "1000", "Tank min>=size  "},
        {P_TANK_L, "30", "Tank min>=size  "},
        {P_P_MIN, "480", "P start>=P max  "},
        {P_P_MAX, "100", "P start>=P max  "},
        {P_METER_K, "6000", "Meter K:too fast"},
        {P_NOZZLE_Q3, "20", "Meter K:too fast"},
    };
    static uint8_t before[HAL_EEPROM_SIZE];
    (void)state;
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        uint16_t was = param_v[cases[i].id];
        to_item(cases[i].id);
        press('D');
        eeprom_snapshot(before);
        keys(cases[i].typed);
        press('D');
        assert_string_equal(lcd(3), cases[i].why);
        assert_int_equal(param_v[cases[i].id], was);
        assert_memory_equal(before, hal_host_eeprom(), HAL_EEPROM_SIZE);
        press('C');
    }
    /* just inside: accepted */
    to_item(P_TANK_MIN);
    press('D');
    keys("999");
    press('D');
    assert_int_equal(param_v[P_TANK_MIN], 999);
}

/* The I/O test screen: raw inputs and pulse rates shown, the relay, buzzer and valve each
 * switched by a key; reached and left from the menu without a parameter or the EEPROM
 * changing, the outputs back with the application afterwards. */
static void test_console_io_test_screen_checks_every_wire_and_changes_nothing(void **state)
{
    static uint8_t ee_before[HAL_EEPROM_SIZE];
    uint16_t p_before[P_COUNT];
    (void)state;
    store_status_clear();
    hal_host_io.adc[HAL_ADC_PRESSURE] = 300;    /* 5.87 mA: 187 kPa, below P max */
    hal_host_io.adc[HAL_ADC_LEVEL] = 205;
    wheel_every_ms = 100;                       /* 10 Hz */
    flow_every_ms = 4;                          /* 250 Hz */
    run_ms(1000);
    memcpy(p_before, param_v, sizeof p_before);
    eeprom_snapshot(ee_before);
    to_item(MENU_IOTEST);
    assert_string_equal(lcd(1), "I/O test        ");
    press('D');
    assert_true(ops_io & OPS_IO_ON);
    assert_false(hal_host_io.spray_on);
    run_ms(2500);
    assert_string_equal(lcd(0), "P 300  5.87mA R0");
    assert_string_equal(lcd(1), "L 205  4.01mA B0");
    const char *l2 = lcd(2);
    assert_true(strstr(l2, "  10Hz V0") != NULL);
    const char *l3 = lcd(3);
    assert_true(strstr(l3, "  250Hz") != NULL || strstr(l3, "  249Hz") != NULL || strstr(l3, "  251Hz") != NULL);
    /* the relay, the buzzer, the valve */
    press('1');
    assert_true(hal_host_io.spray_on);
    assert_string_equal(lcd(0), "P 300  5.87mA R1");
    press('3');
    assert_true(hal_host_io.buzzer);
    assert_string_equal(lcd(1), "L 205  4.01mA B1");
    press('1');
    press('3');
    assert_false(hal_host_io.spray_on);
    assert_false(hal_host_io.buzzer);
    hal_host_io.keys = 1u << 1;                 /* 2 held: the valve closes (more flow) */
    int closed = 0, opened = 0;
    for (int i = 0; i < 400; i++) {
        run_ms(1);
        closed |= hal_host_io.valve_dir == HAL_VALVE_CLOSE;
    }
    hal_host_io.keys = 0;
    run_ms(600);
    hal_host_io.keys = 1u << 9;                 /* 8 held: it opens */
    for (int i = 0; i < 400; i++) {
        run_ms(1);
        opened |= hal_host_io.valve_dir == HAL_VALVE_OPEN;
    }
    hal_host_io.keys = 0;
    run_ms(600);
    assert_true(closed && opened);
    /* the relay left on is switched off when the screen is left */
    press('1');
    assert_true(hal_host_io.spray_on);
    press('C');
    assert_false(ops_io);
    assert_false(hal_host_io.spray_on);
    assert_string_equal(lcd(1), "I/O test        ");
    press('C');
    run_ms(2000);
    assert_memory_equal(p_before, param_v, sizeof p_before);
    assert_memory_equal(ee_before, hal_host_eeprom(), HAL_EEPROM_SIZE);
    assert_false(app_status.manual);
}

static void test_console_controller_and_mode_are_chosen_by_name(void **state)
{
    char want[48];
    (void)state;
    uint16_t c0 = param_v[P_CONTROLLER];
    to_item(P_CONTROLLER);
    snprintf(want, sizeof want, "%16s", ctl_name((uint8_t)c0));
    assert_string_equal(lcd(2), want);
    press('D');
    press('A');
    uint8_t next = (uint8_t)((c0 + 1) % CTL_COUNT);
    snprintf(want, sizeof want, "new %12s", ctl_name(next));
    assert_string_equal(lcd(2), want);
    press('D');
    assert_int_equal(param_v[P_CONTROLLER], next);
    assert_int_equal(stored(P_CONTROLLER), next);
    /* every controller can be reached, B goes back */
    press('D');
    for (int i = 0; i < CTL_COUNT; i++)
        press('B');
    press('D');
    assert_int_equal(param_v[P_CONTROLLER], next);
    /* manual / auto from the menu */
    to_item(P_MODE);
    press('D');
    press('A');
    assert_string_equal(lcd(2), "new       Manual");
    press('D');
    assert_int_equal(param_v[P_MODE], 1);
    assert_int_equal(stored(P_MODE), 1);
    /* and # on the run screen */
    press('C');
    press('#');
    assert_int_equal(param_v[P_MODE], 0);
    assert_int_equal(stored(P_MODE), 0);
    run_ms(300);
    assert_non_null(strstr(lcd(2), " AUTO"));
    press('#');
    run_ms(300);
    assert_int_equal(param_v[P_MODE], 1);
    assert_non_null(strstr(lcd(2), "  MAN"));
    /* Remote: off / Raven at 9600 / Raven at 1200 baud / AgOpenGPS (this build has the
     * frames), round again to off */
    to_item(P_REMOTE);
    assert_string_equal(lcd(2), "             off");
    press('D');
    press('A');
    assert_string_equal(lcd(2), "new   Raven 9600");
    press('A');
    assert_string_equal(lcd(2), "new   Raven 1200");
    press('A');
    assert_string_equal(lcd(2), "new    AgOpenGPS");
    press('A');
    assert_string_equal(lcd(2), "new          off");
    press('B');
    assert_string_equal(lcd(2), "new    AgOpenGPS");
    press('B');
    press('D');
    assert_int_equal(param_v[P_REMOTE], 2);
    assert_int_equal(stored(P_REMOTE), 2);
    /* Log unit: metres / seconds */
    to_item(P_LOG_UNIT);
    assert_string_equal(lcd(2), "               s");
    press('D');
    press('A');
    assert_string_equal(lcd(2), "new            m");
    press('D');
    assert_int_equal(param_v[P_LOG_UNIT], 0);
    assert_int_equal(stored(P_LOG_UNIT), 0);
}

static void test_console_speed_calibration_over_100_m(void **state)
{
    (void)state;
    to_item(MENU_CAL_SPEED);
    assert_string_equal(lcd(1), "Speed cal 100 m ");
    press('D');
    assert_string_equal(lcd(2), "D: start count  ");
    press('D');
    wheel_every_ms = 20;            /* 250 pulses over the 100 m */
    uint32_t w0 = wheel_sent;
    run_ms(5000);
    wheel_every_ms = 0;
    run_ms(300);
    uint32_t n = wheel_sent - w0;
    press('D');
    char want[48];
    snprintf(want, sizeof want, "Pulses%10u", (unsigned)n);
    assert_string_equal(lcd(1), want);
    uint16_t k = (uint16_t)(1000000u / n);
    snprintf(want, sizeof want, "New %u.%u mm/p", k / 10, k % 10);
    char w16[64];
    snprintf(w16, sizeof w16, "New %12s", want + 4);
    assert_string_equal(lcd(2), w16);
    press('D');
    assert_int_equal(param_v[P_WHEEL], k);
    assert_int_equal(stored(P_WHEEL), k);
    /* too few pulses for the range (over 3000 mm a pulse): refused, old value kept */
    to_item(MENU_CAL_SPEED);
    press('D');
    press('D');
    wheel_every_ms = 200;
    run_ms(4000);                   /* about 20 pulses */
    wheel_every_ms = 0;
    run_ms(300);
    press('D');
    assert_string_equal(lcd(3), "Range 10..3000  ");
    assert_int_equal(param_v[P_WHEEL], k);
    /* cancelled half way: nothing changes */
    press('D');
    press('C');
    assert_int_equal(param_v[P_WHEEL], k);
}

static void test_console_meter_calibration_by_the_tank_method(void **state)
{
    char want[48];
    (void)state;
    to_item(MENU_CAL_TANK);
    press('D');
    press('D');
    flow_every_ms = 2;              /* 500 pulses a second */
    uint32_t f0 = flow_sent;
    run_ms(8000);
    flow_every_ms = 0;
    run_ms(300);
    uint32_t n = flow_sent - f0;
    press('D');
    assert_string_equal(lcd(2), "Sprayed _L      ");
    keys("0");
    press('D');
    assert_string_equal(lcd(3), "Volume? >0      ");
    keys("999");                    /* K would be about 4 p/L: refused */
    press('D');
    assert_string_equal(lcd(3), "Range 10..6000  ");
    assert_int_equal(param_v[P_METER_K], 3800);
    keys("10#5");
    press('D');
    uint16_t k = (uint16_t)((uint64_t)n * 100u / 105u);
    snprintf(want, sizeof want, "%u.%u p/L", k / 10, k % 10);
    char w16[64];
    snprintf(w16, sizeof w16, "New %12s", want);
    assert_string_equal(lcd(2), w16);
    press('D');
    assert_int_equal(param_v[P_METER_K], k);
    assert_int_equal(stored(P_METER_K), k);
}

/* The number in a screen line after a label, as the operator reads it. */
static double number_after(const char *line, const char *label)
{
    const char *p = strstr(line, label);
    assert_non_null(p);
    return atof(p + strlen(label));
}

/* The last menu entry learns the nozzle model again (after new nozzles): D starts it. */
static void test_console_nozzles_relearn_from_the_menu(void **state)
{
    char err[256];
    (void)state;
    /* a model learnt first: clean spraying at 6 then 9 km/h */
    scenario_t *s = malloc(sizeof *s);
    sim_t *sim = malloc(sizeof *sim);
    assert_non_null(s);
    assert_non_null(sim);
    assert_int_equal(scenario_parse(s, "[run]\nduration_s = 600\n[drive]\n0 6\n40 6\n45 9\n600 9\n", "relearn",
                                    err, sizeof err), 0);
    sim_init(sim, s);
    st7920_emu_reset();
    hal_host_lcd_sink(st7920_emu_write);
    sim_active = sim;
    for (int i = 0; i < 120 && diag_nozzle_learnt() == 0; i++)
        run_ms(1000);
    printf("# nozzle model learnt (%u) after %.0f s\n", diag_nozzle_learnt(), sim_time_s(sim));
    assert_true(diag_nozzle_learnt() != 0);
    press('*');
    to_item(MENU_NOZZLES);
    assert_string_equal(lcd(1), "Nozzles relearn ");
    press('D');
    assert_true(strstr(lcd(3), "Learning nozzles") != NULL);
    assert_int_equal(diag_nozzle_learnt(), 0);
    sim_active = NULL;
    sim_free(sim);
    free(sim);
    free(s);
}

/* The run screen's "Now" rate: the plant's true applied rate over the last seconds (boom flow
 * over true speed times the open width), within 3 %; "--" while the boom covers no area. */
static void test_console_run_screen_rate_is_the_applied_rate_now(void **state)
{
    char err[256];
    (void)state;
    scenario_t *s = malloc(sizeof *s);
    sim_t *sim = malloc(sizeof *sim);
    assert_non_null(s);
    assert_non_null(sim);
    assert_int_equal(scenario_parse(s, "[run]\nduration_s = 600\n[drive]\n0 8\n60 8\n64 11\n600 11\n"
                                       "[events]\n100 sections_open 0\n", "rate", err, sizeof err), 0);
    sim_init(sim, s);
    st7920_emu_reset();
    hal_host_lcd_sink(st7920_emu_write);
    sim_active = sim;
    const double at[2] = {50.0, 90.0};      /* 8 km/h, then 11 km/h */
    for (int k = 0; k < 2; k++) {
        while (sim_time_s(sim) < at[k] - 3.0)
            run_ms(100);
        double vol = 0, area = 0;
        sim_row_t r;
        for (int i = 0; i < 30; i++) {      /* the truth over the 3 s before the reading */
            run_ms(100);
            sim_row(sim, &r);
            vol += r.boom_lpm / 60.0 * 0.1;                 /* L */
            area += r.v_true_kmh / 3.6 * 0.1 * r.width_m;   /* m^2 */
        }
        double truth = vol / area * 10000.0;
        st7920_emu_line(2, err);            /* the line drawn last, without running on */
        assert_memory_equal(err, "Now", 3);
        double now = atof(err + 3);
        assert_true(fabs(now / truth - 1.0) < 0.03);
        assert_true(fabs(truth / 150.0 - 1.0) < 0.05);   /* (on target: not a start's figure) */
    }
    while (sim_time_s(sim) < 106.0)          /* the boom shut: no area */
        run_ms(100);
    assert_string_equal(lcd(2), "Now  --L/ha AUTO");
    sim_active = NULL;
    sim_free(sim);
    free(sim);
    free(s);
}

static void test_console_totals_show_and_reset_the_job(void **state)
{
    char err[256];
    (void)state;
    /* the real sprayer: 8 km/h with the 18 m boom for a minute */
    scenario_t *s = malloc(sizeof *s);
    sim_t *sim = malloc(sizeof *sim);
    assert_non_null(s);
    assert_non_null(sim);
    assert_int_equal(scenario_parse(s, "[run]\nduration_s = 600\n[drive]\n0 8\n600 8\n", "totals", err, sizeof err), 0);
    sim_init(sim, s);
    st7920_emu_reset();
    hal_host_lcd_sink(st7920_emu_write);
    sim_active = sim;
    run_ms(60000);
    press('*');
    uint32_t area = app_status.job_area_m2, vol = totals_get()->job_ml;
    assert_true(area > 1000 && vol > 10000);   /* about 0.2 ha, 30 L */
    press('B');
    const char *l0 = lcd(0);
    assert_true(fabs(number_after(l0, "Job") - app_status.job_area_m2 / 10000.0) < 0.011);
    assert_non_null(strstr(l0, " ha"));
    assert_true(fabs(number_after(lcd(1), "Job") - totals_get()->job_ml / 1000.0) < 2.0);
    /* the job's average, labelled: about the set rate after a minute at 8 km/h */
    double avg = number_after(lcd(2), "Job avg");
    assert_true(fabs(avg - app_status.applied_l_ha_x10 / 10.0) <= 0.6);
    assert_true(avg > 150 * 0.9 && avg < 150 * 1.1);
    assert_non_null(strstr(lcd(2), "L/ha"));
    /* the lifetime's area and volume, the work rate and the area left take turns on the last
     * line: 8 km/h x 18 m = 14.4 ha/h; the tank above Tank min (30 L) at 150 L/ha */
    int seen_ha = 0, seen_l = 0, seen_work = 0, seen_left = 0;
    for (int i = 0; i < 32; i++) {
        const char *l3 = lcd(3);
        if (strstr(l3, "Work")) {
            seen_work = 1;
            assert_non_null(strstr(l3, " ha/h"));
            assert_true(fabs(number_after(l3, "Work") - 14.4) < 14.4 * 0.03);  /* the wheel's speed */
        } else if (strstr(l3, "Left")) {
            seen_left = 1;
            double left = (app_status.tank_l - 30.0) / 150.0;
            assert_true(fabs(number_after(l3, "Left") - left) < 0.011);
        } else if (strstr(l3, " ha")) {
            seen_ha = 1;
            assert_true(fabs(number_after(l3, "Life") - totals_get()->life_m2 / 10000.0) < 0.011);
        } else if (strstr(l3, " L")) {
            seen_l = 1;
            assert_true(fabs(number_after(l3, "Life") - totals_get()->life_ml / 1000.0) < 1.0);
        }
    }
    assert_true(seen_ha && seen_l && seen_work && seen_left);
    uint32_t life_ml = totals_get()->life_ml;
    press('D');
    assert_string_equal(lcd(3), "Reset job? D=yes");
    press('D');
    assert_string_equal(lcd(3), "Job reset       ");
    /* the job starts again from nothing (a second of spraying at most); the life totals go on */
    assert_true(totals_get()->job_ml < vol / 20);
    assert_true(app_status.job_area_m2 < area / 20);
    assert_true(totals_get()->life_ml >= life_ml);
    assert_true(number_after(lcd(0), "Job") < 0.01);
    /* from the menu too; C instead of the second D keeps the totals */
    run_ms(5000);
    vol = totals_get()->job_ml;
    assert_true(vol > 1000);
    to_item(MENU_TOTALS);
    press('D');
    press('D');
    press('C');
    assert_true(totals_get()->job_ml >= vol);
    sim_active = NULL;
    sim_free(sim);
    free(sim);
    free(s);
}

static void test_console_jog_only_in_manual_mode(void **state)
{
    (void)state;
    store_status_clear();
    sensors_good();
    run_ms(1500);
    press('2');                     /* in auto: the rate nudged, the valve left to the loop */
    assert_int_equal(target_nudge_pct(), 5);
    assert_int_equal(ops_jog_take(), 0);
    press('5');
    assert_int_equal(target_nudge_pct(), 0);
    press('#');
    run_ms(300);
    assert_true(app_status.manual);
    int moved = 0;
    hal_host_io.keys = 1u << 1;     /* hold 2: repeats */
    for (int i = 0; i < 800; i++) {
        run_ms(1);
        moved |= hal_host_io.valve_dir != HAL_VALVE_OFF;
    }
    hal_host_io.keys = 0;
    run_ms(100);
    assert_true(moved);
}

static void test_console_a_reboot_keeps_every_setting(void **state)
{
    (void)state;
    to_item(P_RATE);
    press('D');
    keys("220");
    press('D');
    assert_int_equal(param_v[P_RATE], 2200);
    boot();                         /* power off and on: the EEPROM stays */
    assert_int_equal(param_v[P_RATE], 2200);
    assert_int_equal(store_status(), STORE_OK);
    to_item(P_RATE);
    assert_string_equal(lcd(2), "      220.0 L/ha");
}

/* The conversions from their definitions, not from the firmware's table. */
#define GAL_L 3.785411784
#define ACRE_M2 4046.8564224
#define MILE_M 1609.344
#define PSI_KPA 6.89475729
#define KFT2_M2 92.90304                    /* 1000 ft^2: 1000 x 0.3048^2 */

/* US units: the run screen in mph, PSI, gpm, gal/acre and gal against the inputs of the metric
 * run screen test (7.07 km/h, 196 kPa, 31.8 > 31.6 L/min, 149 L/ha, 500 L), converted here. */
static void test_console_us_units_on_the_run_screen(void **state)
{
    (void)state;
    store_status_clear();
    assert_true(param_set(P_UNITS, 1));
    hal_host_io.adc[HAL_ADC_PRESSURE] = 305;
    hal_host_io.adc[HAL_ADC_LEVEL] = 614;
    hal_host_io.sections = 0x3F;
    wheel_every_ms = 200;
    flow_every_ms = 5;
    run_ms(13000);
    double v, psi, qt, qm, rate;
    int tank;
    char unit[8];
    printf("# [%s] [%s] [%s] [%s]\n", lcd(0), lcd(1), lcd(2), lcd(3));
    assert_int_equal(sscanf(lcd(0), "%lfmph %lfPSI", &v, &psi), 2);
    assert_true(fabs(v - 0.3927 / 0.2 * 3.6 / (MILE_M / 1000.0)) < 0.051);
    assert_true(fabs(psi - app_status.in.pressure_kpa / PSI_KPA) < 0.051);
    assert_int_equal(sscanf(lcd(1), "Q%lf>%lfgpm", &qt, &qm), 2);
    assert_true(fabs(qt - app_status.in.target_lpm_x100 / 100.0 / GAL_L) < 0.0051);
    assert_true(fabs(qm - app_status.in.flow_lpm_x100 / 100.0 / GAL_L) < 0.0051);
    assert_int_equal(sscanf(lcd(2), "%lf%7s", &rate, unit), 2);
    assert_string_equal(unit, "gal/ac");
    assert_true(fabs(rate - 149.0 * GAL_L / (10000.0 / ACRE_M2) / GAL_L / GAL_L) < 0.2);
    assert_int_equal(sscanf(lcd(3), "T %dgal", &tank), 1);
    assert_int_equal(tank, (int)floor(500 / GAL_L + 0.5));
    assert_true(param_set(P_UNITS, 0));
}

/* A rate typed in gal/acre reads back unchanged and is the metric value to its last digit
 * (15.0 gal/acre = 140.3 L/ha); every rate of the range, typed, reads back as typed; the range
 * message in gal/acre; turf in gal/1000 ft^2. */
static void test_console_a_rate_typed_in_gal_per_acre_reads_back_unchanged(void **state)
{
    (void)state;
    store_status_clear();
    assert_true(param_set(P_UNITS, 1));
    to_item(P_RATE);
    assert_string_equal(lcd(2), "     16.0 gal/ac");    /* 150 L/ha: 16.04 gal/acre */
    press('D');
    keys("15#0");
    press('D');
    assert_int_equal(param_v[P_RATE], (int)floor(15.0 * GAL_L / ACRE_M2 * 10000.0 * 10.0 + 0.5));
    assert_int_equal(param_v[P_RATE], 1403);
    assert_string_equal(lcd(2), "     15.0 gal/ac");
    /* out of range: the limits in gal/acre, 10..1000 L/ha (1.1..106.9) */
    press('D');
    keys("2000");
    press('D');
    char want[32];
    snprintf(want, sizeof want, "Range %.1f..%.1f", 10.0 / GAL_L * ACRE_M2 / 10000.0, 1000.0 / GAL_L * ACRE_M2 / 10000.0);
    snprintf(want + strlen(want), sizeof want - strlen(want), "%*s", (int)(16 - strlen(want)), "");
    assert_string_equal(lcd(3), want);
    press('C');
    press('C');
    assert_true(param_set(P_UNITS, 0));
    to_item(P_RATE);
    assert_string_equal(lcd(2), "      140.3 L/ha");
    /* every rate in gal/acre x10 of the range: typed, stored, shown as typed */
    assert_true(param_set(P_UNITS, 1));
    int lo = (int)ceil(100 / GAL_L * ACRE_M2 / 10000.0), hi = (int)floor(10000 / GAL_L * ACRE_M2 / 10000.0);
    for (int g = lo; g <= hi; g++) {
        uint32_t in = unit_in(P_RATE, (uint32_t)g);
        assert_true(fabs(in - g * GAL_L / ACRE_M2 * 10000.0) <= 0.5);   /* the nearest 0.1 L/ha */
        assert_int_equal(unit_q(in, CU_RATE), g);
    }
    /* turf: gal / 1000 ft^2 with two decimals; 140.3 L/ha = 0.34 */
    assert_true(param_set(P_UNITS, 2));
    to_item(P_RATE);
    snprintf(want, sizeof want, "%.2f gal/M", 140.3 / GAL_L * KFT2_M2 / 10000.0);
    char w16[32];
    snprintf(w16, sizeof w16, "%16s", want);
    assert_string_equal(lcd(2), w16);
    assert_true(param_set(P_UNITS, 0));
}

/* A speed typed in mph: 10.0 mph is 16.09 km/h, kept as 16.1 (Given spd in 0.1 km/h), and
 * reads back as 10.0 mph; the range message in mph (0..30.0 km/h: 0..18.6). */
static void test_console_a_speed_typed_in_mph(void **state)
{
    (void)state;
    store_status_clear();
    assert_true(param_set(P_UNITS, 1));
    to_item(P_GIVEN_SPEED);
    press('D');
    keys("10#0");
    press('D');
    assert_int_equal(param_v[P_GIVEN_SPEED], (int)floor(10.0 * MILE_M / 1000.0 * 10 + 0.5));
    assert_int_equal(param_v[P_GIVEN_SPEED], 161);
    assert_string_equal(lcd(2), "        10.0 mph");
    press('D');
    keys("20");
    press('D');
    char want[32];
    snprintf(want, sizeof want, "Range 0..%.1f", 30.0 / (MILE_M / 1000.0));
    snprintf(want + strlen(want), sizeof want - strlen(want), "%*s", (int)(16 - strlen(want)), "");
    assert_string_equal(lcd(3), want);
    press('C');
    press('C');
    assert_true(param_set(P_UNITS, 0));
    to_item(P_GIVEN_SPEED);
    assert_string_equal(lcd(2), "       16.1 km/h");
}

/* The tank method in US units: the volume sprayed is typed in gallons (2.8 gal = 10.6 L, to
 * the 0.1 L the entry keeps), Meter K stays pulses a litre. */
static void test_console_meter_calibration_in_gallons(void **state)
{
    (void)state;
    store_status_clear();
    assert_true(param_set(P_UNITS, 1));
    to_item(MENU_CAL_TANK);
    press('D');
    press('D');
    flow_every_ms = 2;              /* 500 pulses a second */
    uint32_t f0 = flow_sent;
    run_ms(8000);
    flow_every_ms = 0;
    run_ms(300);
    uint32_t n = flow_sent - f0;
    press('D');
    assert_string_equal(lcd(2), "Sprayed _gal    ");
    keys("2#8");
    press('D');
    double litres = 2.8 * GAL_L;    /* 10.599 L */
    uint16_t k = (uint16_t)((uint64_t)n * 100u / (uint32_t)floor(litres * 10 + 0.5));
    printf("# %u pulses in %.3f L: %u (%.1f p/L by hand)\n", (unsigned)n, litres, k, n / litres);
    assert_true(fabs(k / 10.0 - n / litres) <= n / litres * 0.001);    /* the 0.1 L and the 0.1 p/L kept */
    press('D');
    assert_int_equal(param_v[P_METER_K], k);
    assert_true(param_set(P_UNITS, 0));
}

/* In auto 2 / 8 nudge the rate in use by Rate step (the target follows within the control
 * period), the run screen's bottom line shows it and its offset, 5 goes back to the preset; 0
 * switches Rate 1 <-> Rate 2, which the bottom line shows. */
static void test_console_nudge_and_preset_keys(void **state)
{
    (void)state;
    store_status_clear();
    assert_true(param_set(P_RATE_STEP, 10));
    hal_host_io.adc[HAL_ADC_PRESSURE] = 305;    /* as on the run screen above: no alarm */
    hal_host_io.adc[HAL_ADC_LEVEL] = 614;
    hal_host_io.sections = 0x3F;
    wheel_every_ms = 200;
    flow_every_ms = 5;
    run_ms(10000);
    assert_int_equal(app_status.alarms, 0);
    double t0 = app_status.in.target_lpm_x100;
    press('2');
    press('2');
    run_ms(100);
    assert_int_equal(target_rate_x10(), 1800);
    assert_true(fabs(app_status.in.target_lpm_x100 / t0 - 1.2) < 0.01);
    assert_string_equal(lcd(3), "180.0L/ha   +20%");
    press('8');
    assert_string_equal(lcd(3), "165.0L/ha   +10%");
    press('5');
    assert_int_equal(target_rate_x10(), 1500);
    assert_string_equal(lcd(3), "T  500L    ffmap");
    press('0');
    assert_int_equal(param_v[P_PRESET], 1);
    run_ms(3000);                   /* "Saved", then the line as it is */
    assert_string_equal(lcd(3), "T  500L   Rate 2");
    assert_int_equal(target_rate_x10(), 2000);
    press('0');
    assert_int_equal(target_rate_x10(), 1500);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_console_run_screen_shows_speed_flow_dose_pressure_tank_mode_controller, setup),
        cmocka_unit_test_setup(test_console_us_units_on_the_run_screen, setup),
        cmocka_unit_test_setup(test_console_a_rate_typed_in_gal_per_acre_reads_back_unchanged, setup),
        cmocka_unit_test_setup(test_console_nudge_and_preset_keys, setup),
        cmocka_unit_test_setup(test_console_first_boot_shows_the_eeprom_notice_until_acknowledged, setup),
        cmocka_unit_test_setup(test_console_an_alarm_wins_the_line_over_the_notice, setup),
        cmocka_unit_test_setup(test_console_one_star_acknowledges_only_the_alarm_shown, setup),
        cmocka_unit_test_setup(test_console_every_alarm_text_fits_the_line, setup),
        cmocka_unit_test_setup(test_console_star_off_the_run_screen_shows_before_it_acknowledges, setup),
        cmocka_unit_test_setup(test_console_rate_now_is_the_window_volume_over_its_area, setup),
        cmocka_unit_test_setup(test_console_every_parameter_menu_stores_in_range_and_refuses_out_of_range, setup),
        cmocka_unit_test_setup(test_console_entry_takes_the_parameter_decimals_only, setup),
        cmocka_unit_test_setup(test_console_cross_checks_refuse_with_the_reason, setup),
        cmocka_unit_test_setup(test_console_io_test_screen_checks_every_wire_and_changes_nothing, setup),
        cmocka_unit_test_setup(test_console_controller_and_mode_are_chosen_by_name, setup),
        cmocka_unit_test_setup(test_console_speed_calibration_over_100_m, setup),
        cmocka_unit_test_setup(test_console_meter_calibration_by_the_tank_method, setup),
        cmocka_unit_test_setup(test_console_meter_calibration_in_gallons, setup),
        cmocka_unit_test_setup(test_console_a_speed_typed_in_mph, setup),
        cmocka_unit_test_setup(test_console_totals_show_and_reset_the_job, setup),
        cmocka_unit_test_setup(test_console_run_screen_rate_is_the_applied_rate_now, setup),
        cmocka_unit_test_setup(test_console_nozzles_relearn_from_the_menu, setup),
        cmocka_unit_test_setup(test_console_jog_only_in_manual_mode, setup),
        cmocka_unit_test_setup(test_console_a_reboot_keeps_every_setting, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

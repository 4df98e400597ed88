/* console_view.c: the console's screens: run, totals, menus, entry, choices, calibrations, messages. */
#if defined(__SDCC)
#pragma stackauto           /* locals on the stack, not each its own XRAM (docs/MEMORY.md) */
#endif
#include "hal.h"
#include "params.h"
#include "ops.h"
#include "diag.h"
#include "ctl.h"
#include "target.h"
#include "store.h"
#include "screen.h"
#include "fmt.h"
#include "lcd.h"
#include "keypad.h"
#include "console.h"
#include "console_int.h"
#include "umath.h"

con_io_t con_io;

/* ---- small text helpers ---------------------------------------------------------------- */
void con_say(const char *s)
{
    con.msg = s;
    con.msg_range = NO_RANGE;
    con.msg_until_ms = (uint16_t)hal_ms() + CONSOLE_MSG_MS;
}

void con_say_none(void)
{
    con.msg = 0;
    con.msg_range = NO_RANGE;
}

uint8_t con_msg_on(void)
{
    return con.msg || con.msg_range != NO_RANGE;
}

/* The bottom-line screens put a whole line together in `line`, then screen_line() it: each
 * column is written once, so only real changes reach the LCD. */
uint8_t con_cat(uint8_t at, const char *s)
{
    while (*s && at < SCREEN_COLS)
        con.line[at++] = *s++;
    con.line[at] = 0;
    return at;
}

/* a number, right-aligned in width columns ('#'s when it does not fit); width 0: as long as it
 * is; fmt: CON_TRIM or CON_DROP(k) (console_int.h) */
uint8_t con_cat_num(uint8_t at, uint8_t width, uint32_t v, uint8_t decimals, uint8_t fmt)
{
    static const __code uint16_t half[4] = {0, 5, 50, 500};
    char num[FMT_MAX];
    uint8_t n, drop = (uint8_t)(fmt >> 1);
    n = fmt_u32(num, v + half[drop], (uint8_t)(decimals + drop), (uint8_t)(fmt & CON_TRIM));
    if (drop) {
        n -= drop;
        if (!decimals)
            n--;                    /* and the point */
        num[n] = 0;
    }
    if (width && n > width) {
        while (width--)
            at = con_cat(at, "#");
        return at;
    }
    while (width-- > n)
        at = con_cat(at, " ");
    return con_cat(at, num);
}

/* move line[from..] to the right end of the row, spaces in between */
void con_right_align(uint8_t from)
{
    uint8_t n = 0, shift;
    while (con.line[n])
        n++;
    shift = (uint8_t)(SCREEN_COLS - n);
    if (!shift || from > n)
        return;
    con.line[SCREEN_COLS] = 0;
    while (n > from) {
        n--;
        con.line[n + shift] = con.line[n];
    }
    while (shift--)
        con.line[from + shift] = ' ';
}

uint8_t con_is_choice(uint8_t id)
{
    return id == P_CONTROLLER || id == P_MODE || id == P_REMOTE;
}

const char *con_choice_name(uint8_t id, uint16_t v)
{
    if (id == P_MODE)
        return v ? "Manual" : "Auto";
    if (id == P_REMOTE)
        return v ? "Raven" : "off";
    return ctl_name((uint8_t)v);
}

/* append a parameter's value and unit, "150 L/ha" */
uint8_t con_cat_value(uint8_t at, uint8_t id, uint16_t v)
{
    const param_info_t *pi = param_info(id);
    if (con_is_choice(id))
        return con_cat(at, con_choice_name(id, v));
    at = con_cat_num(at, 0, v, pi->decimals, 0);
    if (pi->unit[0]) {
        at = con_cat(at, " ");
        at = con_cat(at, pi->unit);
    }
    return at;
}

/* "Range 10..1000", the limits with their decimals, trailing zeros dropped */
void con_say_range(uint8_t id)
{
    con_say(0);
    con.msg_range = id;
}

/* The message on the bottom line. */
void con_draw_msg(void)
{
    const param_info_t *pi;
    uint8_t at;
    if (con.msg_range == NO_RANGE) {
        screen_line(3, con.msg);
        return;
    }
    pi = param_info(con.msg_range);
    at = con_cat(0, "Range ");
    at = con_cat_num(at, 0, pi->min, pi->decimals, 1);
    at = con_cat(at, "..");
    con_cat_num(at, 0, pi->max, pi->decimals, 1);
    screen_line(3, con.line);
}

/* Set and store a value; the message says what happened. 0 when refused. */
uint8_t con_apply(uint8_t id, uint16_t v)
{
    uint8_t why = param_try(id, v);
    if (why == PARAM_E_RANGE) {
        con_say_range(id);
        return 0;
    }
    if (why != PARAM_OK) {
        con_say(param_why_text(why));   /* in range, but not with the other settings */
        return 0;
    }
    store_save_start(STORE_BY_CONSOLE);
    con_say(0);                     /* console_poll says how it ended, a few passes later */
    return 1;
}

/* ---- screens ------------------------------------------------------------------------------- */
static void draw_bottom(const char *otherwise)
{
    if (con_msg_on())
        con_draw_msg();
    else
        screen_line(3, otherwise);
}

/* The alarm to show: unacknowledged ones first, several take turns every 2 s; -1 for none. */
static int8_t alarm_shown(void)
{
    uint16_t set = app_status.alarms_unacked ? app_status.alarms_unacked : app_status.alarms;
    uint8_t n = 0, b, turn;
    for (b = 0; b < OPS_ALARM_BITS; b++)
        if (set & (1u << b))
            n++;
    if (!n)
        return -1;
    turn = (uint8_t)((hal_ms() / 2000u) % n);
    for (b = 0; b < OPS_ALARM_BITS; b++)
        if (set & (1u << b)) {
            if (!turn)
                return (int8_t)b;
            turn--;
        }
    return -1;
}

static void draw_run(void)
{
    const app_status_t *st = &app_status;
    uint8_t at;
    int8_t a;
    int16_t q;
    /* " 7.2km/h    AUTO": ground speed, mode (HIL: the inputs come from the PC's plant) */
    at = con_cat_num(0, 4, st->speed_kmh_x100, 1, CON_DROP(1));
    at = con_cat(at, "km/h ");
    con_cat(at, hal_hil_active() ? (st->manual ? "HIL MAN" : "HIL") : st->manual ? "MANUAL" : "AUTO");
    con_right_align(at);
    screen_line(0, con.line);
    /* "Q 49.5> 49.3L/mn": target flow > measured flow */
    at = con_cat(0, "Q");
    q = st->target_lpm_x100;
    at = con_cat_num(at, 5, q > 0 ? (uint16_t)q : 0, 1, CON_DROP(1));
    at = con_cat(at, ">");
    q = st->flow_lpm_x100;
    at = con_cat_num(at, 5, q > 0 ? (uint16_t)q : 0, 1, CON_DROP(1));
    con_cat(at, "L/mn");
    screen_line(1, con.line);
    /* " 150L/ha 4.40bar": dose applied so far, boom pressure */
    at = con_cat_num(0, 4, st->applied_l_ha_x10, 0, CON_DROP(1));
    at = con_cat(at, "L/ha");
    at = con_cat_num(at, 5, st->pressure_kpa, 2, 0);
    con_cat(at, "bar");
    screen_line(2, con.line);
    /* bottom: a message, EEPROM trouble, an alarm ("!" not yet acknowledged), or tank and controller */
    a = alarm_shown();
    if (con_msg_on()) {
        con_draw_msg();
    } else if (store_status() != STORE_OK) {
        at = con_cat(0, "!");
        con_cat(at, store_status_text(store_status()));
        screen_line(3, con.line);
    } else if (a >= 0) {
        at = con_cat(0, (st->alarms_unacked & (1u << a)) ? "!" : " ");
        con_cat(at, diag_text((uint8_t)a));
        screen_line(3, con.line);
    } else {
        at = con_cat(0, "T");
        at = con_cat_num(at, 5, st->tank_l, 0, 0);
        at = con_cat(at, "L ");
        if (target_rate_remote())           /* the rate comes from the field computer */
            con_cat_num(con_cat(at, "RC"), 0, target_rate_x10(), 1, 0);
        else
            con_cat(at, ctl_name(ctl_selected()));
        con_right_align(at);
        screen_line(3, con.line);
    }
}

static void draw_totals(void)
{
    const app_status_t *st = &app_status;
    uint8_t at;
    at = con_cat(0, "Job ");
    at = con_cat_num(at, 9, st->job_area_m2, 2, CON_DROP(2));
    con_cat(at, " ha");
    screen_line(0, con.line);
    at = con_cat(0, "Job ");
    at = con_cat_num(at, 10, st->job_volume_ml, 1, CON_DROP(2));
    con_cat(at, " L");
    screen_line(1, con.line);
    at = con_cat(0, "Life");
    at = con_cat_num(at, 9, st->life_area_m2, 2, CON_DROP(2));
    con_cat(at, " ha");
    screen_line(2, con.line);
    if (con.step) {
        draw_bottom("Reset job? D=yes");
    } else if (con_msg_on()) {
        con_draw_msg();
    } else {
        at = con_cat(0, "Life");
        at = con_cat_num(at, 10, st->life_volume_ml, 0, CON_DROP(3));
        con_cat(at, " L");
        screen_line(3, con.line);
    }
}

static const char *menu_name(uint8_t i)
{
    if (i == MENU_CAL_SPEED)
        return "Speed cal 100 m";
    if (i == MENU_CAL_TANK)
        return "Meter cal tank";
    if (i == MENU_IOTEST)
        return "I/O test";
    if (i == MENU_TOTALS)
        return "Totals";
    if (i == MENU_NOZZLES)
        return "Nozzles relearn";
    return param_info(i)->name;
}

static void draw_menu(void)
{
    uint8_t at = con_cat(0, "Menu ");
    at = con_cat_num(at, 2, con.item + 1u, 0, 0);
    at = con_cat(at, "/");
    con_cat_num(at, 0, MENU_COUNT, 0, 0);
    con_right_align(5);
    screen_line(0, con.line);
    screen_line(1, menu_name(con.item));
    if (con.item < P_COUNT) {
        con_cat_value(0, con.item, param_v[con.item]);
        con_right_align(0);
        screen_line(2, con.line);
    } else {
        screen_line(2, con.item == MENU_TOTALS ? "D: show, reset" : "D: start");
    }
    draw_bottom("A^ Bv D:ok C:run");
}

static void draw_edit(void)
{
    const param_info_t *pi = param_info(con.item);
    uint8_t at;
    screen_line(0, pi->name);
    at = con_cat(0, "now ");
    con_cat_value(at, con.item, param_v[con.item]);
    con_right_align(at);
    screen_line(1, con.line);
    at = con_cat(0, "new ");
    at = con_cat(at, con.entry);
    at = con_cat(at, "_");
    if (pi->unit[0]) {
        at = con_cat(at, " ");
        con_cat(at, pi->unit);
    }
    screen_line(2, con.line);
    draw_bottom("D:ok C:clear");
}

static void draw_choice(void)
{
    uint8_t at;
    screen_line(0, param_info(con.item)->name);
    at = con_cat(0, "now ");
    con_cat(at, con_choice_name(con.item, param_v[con.item]));
    con_right_align(at);
    screen_line(1, con.line);
    at = con_cat(0, "new ");
    con_cat(at, con_choice_name(con.item, con.step));
    con_right_align(at);
    screen_line(2, con.line);
    draw_bottom("A/B:choose D:ok");
}

static void draw_cal(void)
{
    uint8_t tank = con.state == S_CAL_TANK;
    uint32_t now = con_cal_now();
    uint8_t at;
    screen_line(0, tank ? "Meter cal tank" : "Speed cal 100 m");
    if (con.step == 0) {
        screen_line(1, tank ? "Tank at a mark" : "At the start");
        screen_line(2, "D: start count");
        draw_bottom("C:back");
        return;
    }
    at = con_cat(0, "Pulses");
    con_cat_num(at, 10, con.step == 1 ? now - con.cal_pulses : con.cal_pulses, 0, 0);
    screen_line(1, con.line);
    if (con.step == 1) {
        screen_line(2, tank ? "Spray; D: stop" : "At 100 m: D");
        draw_bottom("C:cancel");
    } else if (con.step == 2) {             /* tank: litres sprayed */
        at = con_cat(0, "Litres ");
        at = con_cat(at, con.entry);
        con_cat(at, "_");
        screen_line(2, con.line);
        draw_bottom("D:ok C:clear");
    } else {                            /* the new value, to save */
        at = con_cat(0, "New ");
        con_cat_value(at, tank ? P_METER_K : P_WHEEL, con.cal_value);
        con_right_align(at);
        screen_line(2, con.line);
        draw_bottom("D:save C:cancel");
    }
}

/*
 * The I/O test, for checking every wire from the keypad (docs/bringup.md):
 *   "P 512 10.01mA R0"   pressure input: raw ADC counts, loop current; spray relay (key 1)
 *   "L 205  4.01mA B0"   level input; buzzer (key 3)
 *   "W 1234   12Hz V0"   wheel pulses since start and their rate; valve drive (2 / 8 jog it)
 *   "M45678  340Hz"      meter pulses and rate
 * The rates are counted over windows of a second or more. C leaves (outputs back to the
 * application); no parameter is touched.
 */
static uint8_t cat_ma(uint8_t at, uint8_t ch)
{
    uint16_t counts = hal_adc_read(ch);
    at = con_cat_num(at, 4, counts, 0, 0);
    /* I = counts * 5 V / 1023 / 250 ohm, in hundredths of a mA: counts * 2000 / 1023 */
    at = con_cat_num(at, 6, ((uint32_t)counts * 32032u + 8192u) >> 14, 2, 0);
    return con_cat(at, "mA ");
}

/* "W 1234   12Hz ": a pulse input's count (5 digits) and rate */
static uint8_t cat_pulses(char name, uint32_t pulses, uint16_t hz)
{
    uint8_t at;
    con.line[0] = name;
    at = con_cat_num(1, 5, pulses % 100000u, 0, 0);
    at = con_cat_num(at, 5, hz, 0, 0);
    return con_cat(at, "Hz ");
}

void con_iotest_start(void)
{
    ops_io_test(OPS_IO_ON);
    con.cal_pulses = ops_wheel_pulses();
    con_io.meter0 = (uint16_t)ops_flow_pulses();
    con.cal_value = (uint16_t)hal_ms();
    con_io.wheel_hz = con_io.meter_hz = 0;
    con_say("1R 3B 2/8V C:end");
}

static void draw_iotest(void)
{
    uint16_t now = (uint16_t)hal_ms(), dt = (uint16_t)(now - con.cal_value);
    uint8_t at;
    if (dt >= 1000u) {
        con_io.wheel_hz = (uint16_t)um_muldiv(ops_wheel_pulses() - con.cal_pulses, 1000u, dt);
        con_io.meter_hz = (uint16_t)um_muldiv((uint16_t)((uint16_t)ops_flow_pulses() - con_io.meter0), 1000u, dt);
        con.cal_pulses = ops_wheel_pulses();
        con_io.meter0 = (uint16_t)ops_flow_pulses();
        con.cal_value = now;
    }
    at = cat_ma(con_cat(0, "P"), HAL_ADC_PRESSURE);
    con_cat(at, (ops_io & OPS_IO_RELAY) ? "R1" : "R0");
    screen_line(0, con.line);
    at = cat_ma(con_cat(0, "L"), HAL_ADC_LEVEL);
    con_cat(at, (ops_io & OPS_IO_BUZZER) ? "B1" : "B0");
    screen_line(1, con.line);
    at = cat_pulses('W', ops_wheel_pulses(), con_io.wheel_hz);
    con_cat(at, app_status.drive > 0 ? "V+" : app_status.drive < 0 ? "V-" : "V0");
    screen_line(2, con.line);
    if (con_msg_on()) {
        con_draw_msg();
        return;
    }
    cat_pulses('M', ops_flow_pulses(), con_io.meter_hz);
    screen_line(3, con.line);
}

void con_draw(void)
{
    if (con_msg_on() && (int16_t)((uint16_t)hal_ms() - con.msg_until_ms) >= 0)
        con_say_none();
    switch (con.state) {
    case S_RUN: draw_run(); break;
    case S_TOTALS: draw_totals(); break;
    case S_MENU: draw_menu(); break;
    case S_EDIT: draw_edit(); break;
    case S_CHOICE: draw_choice(); break;
    case S_IOTEST: draw_iotest(); break;
    default: draw_cal(); break;
    }
}


/* console.c: the operator console: run screen, menus for every parameter, calibrations, totals, alarms (keys in console.h). */
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
#include "totals.h"

console_t con;
__data uint8_t con_state, con_item, con_step, con_at;
__idata char *__data con_line;

/* ---- number entry -------------------------------------------------------------------------- */
void con_entry_clear(void)
{
    con.entry_n = 0;
    con.u.entry[0] = 0;
}

/* where the decimal point is in the entry, 0xFF for none */
static uint8_t entry_point(void)
{
    uint8_t i;
    for (i = 0; i < con.entry_n; i++)
        if (con.u.entry[i] == '.')
            return i;
    return 0xFF;
}

void con_entry_key(uint8_t decimals)
{
    uint8_t point = entry_point();
    if (con.k == '#') {
        if (!decimals)
            con_say("Whole numbers");   /* the point is kept: D refuses the entry, not 12#5 = 125 */
        if (point != 0xFF)
            return;
    } else if (point != 0xFF && decimals && con.entry_n - point > decimals) {
        con_say(decimals == 1 ? "1 decimal only" : "2 decimals only");
        return;
    }
    if (con.entry_n >= ENTRY_MAX)
        return;
    con.u.entry[con.entry_n++] = con.k == '#' ? '.' : con.k;
    con.u.entry[con.entry_n] = 0;
}

/* The typed number in units of 10^-decimals; ENTRY_TOO_BIG when it is larger than 65534. */
uint16_t con_entry_value(uint8_t decimals)
{
    uint16_t v = 0;
    uint8_t i, d, frac = 0, point = 0;
    for (i = 0; i < con.entry_n; i++) {
        d = (uint8_t)(con.u.entry[i] - '0');        /* (the character read once) */
        if (d == (uint8_t)('.' - '0')) {
            point = 1;
            continue;
        }
        if (point)
            frac++;
        if (v > 6553u || (v == 6553u && d > 4))
            return ENTRY_TOO_BIG;
        v = (uint16_t)(v * 10u + d);
    }
    while (frac++ < decimals) {
        if (v > 6553u)
            return ENTRY_TOO_BIG;
        v *= 10u;
    }
    return v;
}

/* The running pulse total the calibration in progress counts. */
uint32_t con_cal_now(void)
{
    if (con_state == S_CAL_TANK)
        return ops_flow_pulses();
    return ops_wheel_pulses();
}

/* ---- keys ---------------------------------------------------------------------------------- */
static void go(uint8_t s)
{
    con_state = s;
    con_step = 0;
    con_entry_clear();
    con_say_none();
}

static void key_run(void)
{
    if (con.k == 'A') {
        go(S_MENU);
        con_item = 0;
    } else if (con.k == 'B') {
        go(S_TOTALS);
    } else if (con.k == '#') {
        if (con_apply(P_MODE, param_v[P_MODE] ? 0 : 1))
            con_say(param_v[P_MODE] ? "Mode: MANUAL" : "Mode: AUTO");
    } else if (con.k == '2' || con.k == '8') {
        if (app_status.manual) {
            ops_jog(con.k == '2' ? 1 : -1);
        } else {                    /* auto: the rate in use a Rate step up or down */
            target_nudge(con.k == '2' ? 1 : -1);
        }
    } else if (con.k == '5') {
        target_nudge(0);            /* back to the preset */
    } else if (con.k == '0') {
        con_apply(P_PRESET, param_v[P_PRESET] ? 0 : 1);    /* the bottom line shows Rate 2 */
    }
}

static void key_totals(void)
{
    if (con.k == 'D') {
        if (con_step) {
            ops_totals_reset();
            con_step = 0;
            con_say("Job reset");
        } else {
            con_step = 1;
        }
    } else if (con.k == 'C' || con.k == 'B') {
        if (con_step)
            con_step = 0;
        else
            go(S_RUN);
    }
}

static void key_menu(void)
{
    if (con.k == 'A') {
        con_item = con_item ? con_item - 1 : MENU_COUNT - 1;
    } else if (con.k == 'B') {
        con_item = con_item + 1 < MENU_COUNT ? con_item + 1 : 0;
    } else if (con.k == 'C') {
        go(S_RUN);
    } else if (con.k == 'D') {
        if (con_item == MENU_CAL_SPEED)
            go(S_CAL_SPEED);
        else if (con_item == MENU_CAL_TANK)
            go(S_CAL_TANK);
        else if (con_item == MENU_TOTALS)
            go(S_TOTALS);
#if FW_IOTEST
        else if (con_item == MENU_IOTEST) {
            go(S_IOTEST);
            con_iotest_start();
        }
#endif
        else if (con_item == MENU_NOZZLES) {
            diag_nozzle_relearn();
            con_say("Learning nozzles");
        }
        else if (con_is_choice(con_item)) {
            go(S_CHOICE);
            con_step = (uint8_t)param_v[con_item];
        } else
            go(S_EDIT);
    }
}

/* Typing keys shared by the number entries; 1 when k was one of them. */
static uint8_t typing(uint8_t decimals)
{
    if ((con.k >= '0' && con.k <= '9') || con.k == '#') {
        con_entry_key(decimals);
        return 1;
    }
    return 0;
}

/* A number typed in the units chosen (console_units.c), back in the parameter's. */
static void key_edit(void)
{
    const __code unit_t *u = unit_of(unit_class(con_item));
    uint8_t dec = u ? u->dec : param_info(con_item)->decimals;
    uint32_t v;
    if (typing(dec))
        return;
    if (con.k == 'C') {
        if (con.entry_n)
            con_entry_clear();
        else
            go(S_MENU);
    } else if (con.k == 'D') {
        if (!con.entry_n) {
            go(S_MENU);
            return;
        }
        v = con_entry_value(dec);
        if (v != ENTRY_TOO_BIG)
            v = unit_in(con_item, v);
        if (!dec && entry_point() != 0xFF) {
            con_say("Whole numbers");
        } else if (v >= ENTRY_TOO_BIG) {
            con_say_range(con_item);
        } else if (con_apply(con_item, (uint16_t)v)) {
            con_state = S_MENU;
        }
        con_entry_clear();
    }
}

/* A and B step through the setting's range, wrapping: only the values this image takes (the
 * field image's Control: the controllers it carries, params.h P_CTL_MIN / MAX) */
static void key_choice(void)
{
    const __code param_info_t *pi = param_info(con_item);
    uint8_t lo = (uint8_t)pi->min, hi = (uint8_t)pi->max;
    if (con.k == 'A')
        con_step = con_step < hi ? con_step + 1 : lo;
    else if (con.k == 'B')
        con_step = con_step > lo ? con_step - 1 : hi;
    else if (con.k == 'C')
        go(S_MENU);
    else if (con.k == 'D') {
        if (con_apply(con_item, con_step))
            con_state = S_MENU;
    }
}

static void key_cal(void)
{
    uint8_t tank = con_state == S_CAL_TANK;
    uint8_t id = tank ? P_METER_K : P_WHEEL;
    uint32_t v;
    if (con_step == 2 && typing(1))
        return;
    if (con.k == 'C') {
        if (con_step == 2 && con.entry_n)
            con_entry_clear();
        else {
            go(S_MENU);
            con_say("Cancelled");
        }
        return;
    }
    if (con.k != 'D')
        return;
    if (con_step == 0) {
        con.cal_pulses = con_cal_now();
        con_step = 1;
    } else if (con_step == 1) {
        con.cal_pulses = con_cal_now() - con.cal_pulses;
        if (con.cal_pulses < 10u) {
            con_say("Too few pulses");
            con_step = 0;
        } else if (tank) {
            con_entry_clear();
            con_step = 2;
        } else {
            /* P_WHEEL in 0.1 mm a pulse: 100 m = 1 000 000 tenths of a millimetre */
            v = 1000000uL / con.cal_pulses;
            if (v > 0xFFFFu || !param_in_range(id, (uint16_t)v)) {
                con_say_range(id);
                con_step = 0;
            } else {
                con.cal_value = (uint16_t)v;
                con_step = 3;
            }
        }
    } else if (con_step == 2) {
        v = unit_in(P_TANK_L, con_entry_value(1));  /* litres x10 (typed in gallons in US units) */
        con_entry_clear();
        if (!v || v == ENTRY_TOO_BIG) {
            con_say("Volume? >0");
            return;
        }
        /* P_METER_K in 0.1 pulse a litre: pulses * 10 / litres = pulses * 100 / litres_x10 */
        if (con.cal_pulses > 0xFFFFFFFFu / 100u) {
            con_say_range(id);
            return;
        }
        v = con.cal_pulses * 100u / v;
        if (v > 0xFFFFu || !param_in_range(id, (uint16_t)v)) {
            con_say_range(id);
            return;
        }
        con.cal_value = (uint16_t)v;
        con_step = 3;
    } else {
        if (tank)
            diag_nozzle_relearn();          /* the meter reads anew: the nozzles are learnt anew */
        if (con_apply(id, con.cal_value))
            con_state = S_MENU;
    }
}

#if FW_IOTEST
/* The I/O test: 1 the relay, 3 the buzzer, 2 / 8 jog the valve, C back (outputs returned). */
static void key_iotest(void)
{
    if (con.k == '1')
        ops_io_test(ops_io ^ OPS_IO_RELAY);
    else if (con.k == '3')
        ops_io_test(ops_io ^ OPS_IO_BUZZER);
    else if (con.k == '2' || con.k == '8')
        ops_jog(con.k == '2' ? 1 : -1);
    else if (con.k == 'C') {
        ops_io_test(0);
        go(S_MENU);
    }
}
#endif

/* `*` acknowledges what the bottom line shows, and only that: an alarm not yet acknowledged,
 * or the EEPROM's notice. Something to acknowledge that is not shown is shown first. */
static void key_ack(void)
{
    uint8_t s = con.shown, b;
    uint16_t m;
    if (s < OPS_ALARM_BITS && (app_status.alarms_unacked & (1u << s))) {
        ops_alarm_ack_bits(1u << s);
        con_say(0);
        con.msg_range = CON_MSG_ACKED | s;
    } else if (s == CON_SHOWN_EE) {
        store_status_clear();
        con_say("EE: seen");
    } else if (app_status.alarms_unacked) {
        for (b = 0, m = app_status.alarms_unacked; !(m & 1u); b++)
            m >>= 1;                /* the first not yet acknowledged */
        con_say(0);
        con.msg_range = CON_MSG_PEEK | b;
    } else if (store_status() != STORE_OK) {
        con_say(0);
        con.msg_range = CON_MSG_PEEK | CON_SHOWN_EE;
    } else {
        con_say("No new alarms");
    }
}

static void key(void)
{
    if (con.k == '*') {
        key_ack();
        return;
    }
    switch (con_state) {
    case S_RUN: key_run(); break;
    case S_TOTALS: key_totals(); break;
    case S_MENU: key_menu(); break;
    case S_EDIT: key_edit(); break;
    case S_CHOICE: key_choice(); break;
#if FW_IOTEST
    case S_IOTEST: key_iotest(); break;
#endif
    default: key_cal(); break;
    }
}

/* Once a second: the applied rate over the last CON_RATE_N seconds, from the job totals the
 * control step adds (measured flow; measured speed times the open width), then the oldest
 * snapshot replaced by now's. Over a job reset the window starts at the reset. */
static void rate_second(void)
{
    __xdata uint32_t *snap = &con.rate_snap[con.rate_at].ml;
    uint32_t ml = totals.job_ml, dm2 = totals.job_dm2;
    uint16_t r = CON_RATE_NONE;
    if (snap[0] <= ml && snap[1] <= dm2) {
        ml -= snap[0];
        dm2 -= snap[1];
    }
    if (dm2 >= CON_RATE_MIN_DM2) {
        /* L/ha = ml / 1000 / (dm^2 / 1e6) = ml * 1000 / dm^2 (ml under 2^22 in 3 s) */
        ml = (ml * 1000u + dm2 / 2u) / dm2;
        r = ml < CON_RATE_OVER ? (uint16_t)ml : CON_RATE_OVER;
    } else if (ml) {
        r = CON_RATE_OVER;
    }
    con.rate_l_ha = r;
    snap[0] = totals.job_ml;
    snap[1] = totals.job_dm2;
    con.rate_at = (uint8_t)(con.rate_at + 1u < CON_RATE_N ? con.rate_at + 1u : 0);
}

void console_init(void)
{
    keypad_init();
    lcd_init();
    screen_clear();
    con_state = S_RUN;
    con_item = 0;
    con_step = 0;
    con_entry_clear();
    con_say(diag_reset_text());     /* why the controller (re)started */
    con.rc_seen = target_remote_refusals();
    con.next_draw_ms = (uint16_t)hal_ms();
    con.rate_ms = con.next_draw_ms;
    con.rate_l_ha = CON_RATE_NONE;
    con.rate_at = 0;
    con.top_drawn = 0;
}

void console_poll(void)
{
    uint16_t now = (uint16_t)hal_ms();
    con.k = keypad_poll();
    if ((uint16_t)(now - con.rate_ms) >= 1000u) {
        con.rate_ms += 1000u;
        rate_second();
        /* off the preset: a reminder in one second of every CONSOLE_REMIND_MS (the seconds'
         * grid meets each such span's first second once) */
        if (target_nudge_pct() && ((uint16_t)hal_ms() & (CONSOLE_REMIND_MS - 1u)) < 1000u)
            con_say("Nudged: 5=preset");
    }
    if (store_done(STORE_BY_CONSOLE)) {     /* the save of a value set here has ended */
        con_say(store_result() == STORE_OK ? "Saved" : store_status_text(store_result()));
        con.next_draw_ms = now;
    }
    if (con.rc_seen != target_remote_refusals()) {  /* a field computer's rate refused */
        con.rc_seen = target_remote_refusals();
        con_say("RC rate refused");
        con.next_draw_ms = now;
    }
    if (con.k != KEY_NONE) {
        key();
        con.next_draw_ms = now + 1u;    /* the new screen in the next pass: a key's work (a save,
                                           perhaps) and a redraw are a pass each */
    } else if ((int16_t)(now - con.next_draw_ms) >= 0) {
        if (con_draw())
            con.next_draw_ms = now + CONSOLE_REDRAW_MS;
        return;                     /* its LCD bytes in the next pass: a pass each */
    }
    lcd_poll();
}


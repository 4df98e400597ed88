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
#include "totals.h"
#include "mul.h"
#include "umath.h"

/* ---- small text helpers ---------------------------------------------------------------- */
void con_say(const __code char *s)
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

/* The bottom-line screens put a whole line together in `line` (con_at: where the next text
 * goes), then screen_line() it: each column is written once, so only real changes reach the LCD. */
void con_cat_ram(const char *s)
{
    uint8_t at = con_at;
    while (*s && at < SCREEN_COLS)
        con_line[at++] = *s++;
    con_line[at] = 0;
    con_at = at;
}

/* the same for a text in the code memory, as nearly all are: its callers pass two bytes, not a
 * generic pointer's three */
void con_cat(const __code char *s)
{
    con_cat_ram(s);
}

/* a new line, starting with s */
void con_start(const __code char *s)
{
    con_at = 0;
    con_cat(s);
}

/* the line put together, on the screen's row */
void con_show(uint8_t row)
{
    screen_line((char *)con_line, row);
}

/* a number, right-aligned in width columns ('#'s when it does not fit); width 0: as long as it
 * is; form: the decimals, | CON_TRIM or CON_DROP(k), | CON_Q(cls) (console_int.h) */
void con_cat_num(uint32_t v, uint8_t width, uint8_t form)
{
    static const __code uint16_t half[4] = {0, 5, 50, 500};
    char num[FMT_MAX];
    uint8_t n, drop = (uint8_t)((form >> 3) & 3u), decimals = (uint8_t)(form & CON_DEC_MASK);
    n = fmt_u32((__idata char *)num, v + half[drop], (uint8_t)(decimals + drop), (uint8_t)((form & CON_TRIM) != 0));
    if (drop) {
        n -= drop;
        if (!decimals)
            n--;                    /* and the point */
        num[n] = 0;
    }
    if (width && n > width) {
        while (width--)
            con_cat("#");
        return;
    }
    while (width-- > n)
        con_cat(" ");
    con_cat_ram(num);
}

/* con_cat_num of a quantity of class CON_Q(cls) in the units chosen; the conversion is done
 * before con_cat_num runs, not inside it (the console's deepest stack path goes through it) */
void con_cat_q(uint32_t v, uint8_t width, uint8_t form)
{
    con_cat_num(unit_q(v, (uint8_t)(form >> 5)), width, con_q_form(form));
}

/* move line[from..] to the right end of the row, spaces in between */
void con_right_align(uint8_t from)
{
    uint8_t n = 0, shift;
    while (con_line[n])
        n++;
    shift = (uint8_t)(SCREEN_COLS - n);
    if (!shift || from > n)
        return;
    con_line[SCREEN_COLS] = 0;
    while (n > from) {
        n--;
        con_line[n + shift] = con_line[n];
    }
    while (shift--)
        con_line[from + shift] = ' ';
}

/* The form of parameter id's values, CON_Q of its class; a speed setting (km/h x10) goes to
 * unit_q as the class's km/h x100 (pvalue) in US or turf units. */
static uint8_t pform(uint8_t id, uint8_t cls) __reentrant
{
    return (uint8_t)(param_info(id)->decimals | CON_Q(cls));
}

static uint32_t pvalue(uint8_t cls, uint16_t v) __reentrant
{
    return cls == CU_SPEED && param_v[P_UNITS] ? v * 10uL : v;
}

/* append parameter id's unit in the units chosen after a space, none when it has none */
static void cat_param_unit(uint8_t id) __reentrant
{
    const __code char *unit = con_unit_text(unit_class(id), param_info(id)->unit);
    if (unit[0]) {
        con_cat(" ");
        con_cat(unit);
    }
}

/* append a value v of parameter id in the units chosen, its decimals | trim (0 or CON_TRIM) */
static void cat_pvalue(uint8_t id, uint16_t v, uint8_t trim) __reentrant
{
    uint8_t cls = unit_class(id);
    con_cat_num(unit_q(pvalue(cls, v), cls), 0, con_q_form((uint8_t)(pform(id, cls) | trim)));
}

/* append a parameter's value and unit in the units chosen, "150.0 L/ha" */
void con_cat_value(uint8_t id, uint16_t v)
{
    if (con_is_choice(id)) {
        con_cat(con_choice_name(id, v));
        return;
    }
    cat_pvalue(id, v, 0);
    cat_param_unit(id);
}

/* "Range 10..1000", the limits with their decimals in the units chosen, trailing zeros dropped */
void con_say_range(uint8_t id)
{
    con_say(0);
    con.msg_range = id;
}

/* The message on the bottom line (an acknowledgement: on the two bottom lines). */
void con_draw_msg(void)
{
    uint8_t m = con.msg_range, b = (uint8_t)(m & CON_MSG_BIT);
    if (m == NO_RANGE) {
        screen_line(con.msg, 3);
        return;
    }
    if (m & CON_MSG_ACKED) {
        screen_line("Acknowledged:", 2);
        con_start(" ");
        con_cat(diag_text(b));
    } else if (m & CON_MSG_PEEK) {
        con.shown = b;
        con_start("!");
        con_cat(b == CON_SHOWN_EE ? store_status_text(store_status()) : diag_text(b));
    } else {
        for (b = 0; b < 2; b++) {   /* the word when the limits leave room for it */
            con_start(b ? "Range " : "");
            cat_pvalue(m, param_info(m)->min, CON_TRIM);
            con_cat("..");
            cat_pvalue(m, param_info(m)->max, CON_TRIM);
            if (con_at > SCREEN_COLS - 6u)
                break;
        }
    }
    con_show(3);
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

static void draw_bottom(const __code char *otherwise)
{
    if (con_msg_on())
        con_draw_msg();
    else
        screen_line(otherwise, 3);
}

/* The alarm to show: the first not yet acknowledged, held until `*` (the line never turns
 * under the key); with all acknowledged, the active ones take turns every 2 s; -1 for none. */
static int8_t alarm_shown(void)
{
    uint16_t set = app_status.alarms, m;
    uint8_t n = 0, b, turn = 0;
    uint32_t t;
    if (app_status.alarms_unacked)
        set = app_status.alarms_unacked;
    else {
        for (m = set; m; m >>= 1)   /* the bits set (OPS_ALARM_BITS: all 16) */
            n += (uint8_t)(m & 1u);
        if (!n)
            return -1;
        t = hal_ms() / 2000u;
        turn = (uint8_t)(t - t / n * n);    /* t % n (no remainder routine in the image) */
    }
    for (b = 0, m = set; b < OPS_ALARM_BITS; b++, m >>= 1)
        if (m & 1u) {
            if (!turn)
                return (int8_t)b;
            turn--;
        }
    return -1;
}

/* The run screen's bottom line: an alarm's message (its acknowledgement, or one shown by `*`),
 * else an alarm not yet acknowledged, a message, an acknowledged alarm, the EEPROM's notice,
 * and with none of them the tank and the controller (or the field computer's rate). */
static void draw_run_bottom(void)
{
    const __xdata app_status_t *st = &app_status;
    int8_t a = alarm_shown(), n;
    uint8_t at, alarm_msg = con.msg_range != NO_RANGE && con.msg_range >= CON_MSG_PEEK;
    if (!alarm_msg && a >= 0 && ((st->alarms_unacked & (1u << a)) || !con_msg_on())) {
        if (st->alarms_unacked & (1u << a)) {
            con.shown = (uint8_t)a;
            con_start("!");
        } else
            con_start(" ");
        con_cat(diag_text((uint8_t)a));
        con_show(3);
    } else if (con_msg_on()) {
        con_draw_msg();
    } else if (store_status() != STORE_OK) {
        con.shown = CON_SHOWN_EE;
        con_start("!");
        con_cat(store_status_text(store_status()));
        con_show(3);
    } else if (target_nudge_pct()) {        /* the rate in use and the operator's offset */
        con_at = 0;
        con_cat_q(target_rate_x10(), 0, 1 | CON_Q(CU_RATE));
        con_cat_unit(CU_RATE);
        con_cat(" ");
        at = con_at;
        con_cat(target_nudge_pct() > 0 ? "+" : "-");
        n = target_nudge_pct();
        con_cat_num((uint8_t)(n > 0 ? n : -n), 0, 0);
        con_cat("%");
        con_right_align(at);
        con_show(3);
    } else {
        con_start("T");
        con_cat_q(st->tank_l, 5, CON_Q(CU_VOL));
        con_cat_unit(CU_VOL);
        con_cat(" ");
        at = con_at;
        if (target_rate_remote()) {         /* the rate comes from the field computer */
            con_cat("RC");
            con_cat_q(target_rate_x10(), 0, 1 | CON_Q(CU_RATE));
        } else
            con_cat(param_v[P_PRESET] ? con_choice_name(P_PRESET, 1) : ctl_name(ctl_selected()));
        con_right_align(at);
        con_show(3);
    }
}

/* The run screen's top two lines (con_draw: the rest in the next pass) */
static void draw_run_top(void)
{
    const __xdata app_status_t *st = &app_status;
    int16_t q;
    /* " 7.2km/h 4.40bar": ground speed, boom pressure (US: " 4.5mph  63.8PSI") */
    con_at = 0;
    con_cat_q(st->in.speed_kmh_x100, 4, 1 | CON_DROP(1) | CON_Q(CU_SPEED));
    con_cat_unit(CU_SPEED);
    con_cat_q(st->in.pressure_kpa, 5, 2 | CON_Q(CU_PRESS));
    con_cat_unit(CU_PRESS);
    con_show(0);
    /* "Q 49.5> 49.3L/mn": target flow > measured flow (US: "Q13.08>13.02gpm") */
    con_start("Q");
    q = st->in.target_lpm_x100;
    con_cat_q(q > 0 ? (uint16_t)q : 0, 5, 1 | CON_DROP(1) | CON_Q(CU_FLOW));
    con_cat(">");
    q = st->in.flow_lpm_x100;
    con_cat_q(q > 0 ? (uint16_t)q : 0, 5, 1 | CON_DROP(1) | CON_Q(CU_FLOW));
    con_cat_unit(CU_FLOW);
    con_show(1);
}

static void draw_run(void)
{
    const __xdata app_status_t *st = &app_status;
    uint8_t at;
    /* "Now 150L/ha AUTO": the rate applied over the last seconds, the mode (HIL: the inputs
     * come from the PC's plant); US: "15.0gal/ac  AUTO" */
    con_start(param_v[P_UNITS] ? "" : "Now");
    if (con.rate_l_ha == CON_RATE_NONE)
        con_cat("  --");
    else
        con_cat_q(con.rate_l_ha * 10uL, 4, CON_DROP(1) | CON_Q(CU_RATE));
    con_cat_unit(CU_RATE);
    con_cat(" ");
    at = con_at;
    con_cat(hal_hil_active() ? (st->manual ? "HILM" : "HIL") : st->manual ? "MAN"
            : st->boom_wait ? "WAIT" : "AUTO");
    con_right_align(at);
    con_show(2);
    draw_run_bottom();
}

static const char *menu_name(uint8_t i)
{
    if (i == MENU_CAL_SPEED)
        return "Speed cal 100 m";
    if (i == MENU_CAL_TANK)
        return "Meter cal tank";
#if FW_IOTEST
    if (i == MENU_IOTEST)
        return "I/O test";
#endif
    if (i == MENU_TOTALS)
        return "Totals";
    if (i == MENU_NOZZLES)
        return "Nozzles relearn";
    return param_info(i)->name;
}

static void draw_menu(void)
{
    con_start("Menu ");
    con_cat_num(con_item + 1u, 2, 0);
    con_cat("/");
    con_cat_num(MENU_COUNT, 0, 0);
    con_right_align(5);
    con_show(0);
    screen_line(menu_name(con_item), 1);
    if (con_item < P_COUNT) {
        con_at = 0;
        con_cat_value(con_item, param_v[con_item]);
        con_right_align(0);
        con_show(2);
    } else {
        screen_line(con_item == MENU_TOTALS ? "D: show, reset" : "D: start", 2);
    }
    draw_bottom("A^ Bv D:ok C:run");
}

static void draw_edit(void)
{
    const __code param_info_t *pi = param_info(con_item);
    screen_line(pi->name, 0);
    con_start("now ");
    con_cat_value(con_item, param_v[con_item]);
    con_right_align(4);             /* the value after "now " */
    con_show(1);
    con_start("new ");
    con_cat_ram(con.u.entry);
    con_cat("_");
    cat_param_unit(con_item);
    con_show(2);
    draw_bottom("D:ok C:clear");
}

static void draw_choice(void)
{
    screen_line(param_info(con_item)->name, 0);
    con_start("now ");
    con_cat(con_choice_name(con_item, param_v[con_item]));
    con_right_align(4);
    con_show(1);
    con_start("new ");
    con_cat(con_choice_name(con_item, con_step));
    con_right_align(4);
    con_show(2);
    draw_bottom("A/B:choose D:ok");
}

static void draw_cal(void)
{
    uint8_t tank = con_state == S_CAL_TANK;
    uint32_t now = con_cal_now();
    screen_line(tank ? "Meter cal tank" : "Speed cal 100 m", 0);
    if (con_step == 0) {
        screen_line(tank ? "Tank at a mark" : "At the start", 1);
        screen_line("D: start count", 2);
        draw_bottom("C:back");
        return;
    }
    con_start("Pulses");
    con_cat_num(con_step == 1 ? now - con.cal_pulses : con.cal_pulses, 10, 0);
    con_show(1);
    if (con_step == 1) {
        screen_line(tank ? "Spray; D: stop" : "At 100 m: D", 2);
        draw_bottom("C:cancel");
    } else if (con_step == 2) {             /* tank: the volume sprayed, in the units chosen */
        con_start("Sprayed ");
        con_cat_ram(con.u.entry);
        con_cat("_");
        con_cat_unit(CU_VOL);
        con_show(2);
        draw_bottom("D:ok C:clear");
    } else {                            /* the new value, to save */
        con_start("New ");
        con_cat_value(tank ? P_METER_K : P_WHEEL, con.cal_value);
        con_right_align(4);         /* the value after "New " */
        con_show(2);
        draw_bottom("D:save C:cancel");
    }
}

uint8_t con_draw(void)
{
    char line[SCREEN_COLS + 1];
    con_line = (__idata char *)line;
    if (!con.top_drawn && (con_state == S_RUN || con_state == S_TOTALS)) {
        /* these screens' numbers take over a pass's time: the top rows in this pass, the
         * rest in the next */
        if (con_state == S_RUN)
            draw_run_top();
        else
            con_draw_totals_top();
        con.top_drawn = 1;
        return 0;
    }
    con.top_drawn = 0;
    if (con_msg_on() && (int16_t)((uint16_t)hal_ms() - con.msg_until_ms) >= 0)
        con_say_none();
    con.shown = CON_SHOWN_NONE;     /* the screen drawn says what it shows */
    switch (con_state) {
    case S_RUN: draw_run(); break;
    case S_TOTALS: con_draw_totals(); break;
    case S_MENU: draw_menu(); break;
    case S_EDIT: draw_edit(); break;
    case S_CHOICE: draw_choice(); break;
#if FW_IOTEST
    case S_IOTEST:                  /* its message drawn here, not under its frame (the stack) */
        con_draw_iotest();
        if (con_msg_on())
            con_draw_msg();
        break;
#endif
    default: draw_cal(); break;
    }
    return 1;
}


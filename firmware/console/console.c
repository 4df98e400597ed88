/* console.c: the operator console: run screen, menus for every parameter, calibrations, totals, alarms (keys in console.h). */
#if defined(__SDCC)
#pragma stackauto           /* locals on the stack, not each its own XRAM (docs/MEMORY.md) */
#endif
#include "hal.h"
#include "params.h"
#include "app.h"
#include "ctl.h"
#include "store.h"
#include "screen.h"
#include "fmt.h"
#include "lcd.h"
#include "keypad.h"
#include "console.h"

enum { S_RUN, S_TOTALS, S_MENU, S_EDIT, S_CHOICE, S_CAL_SPEED, S_CAL_TANK };

#define ENTRY_MAX 7                 /* characters of a number being typed */

static uint8_t state;               /* S_* */
static uint8_t item;                /* menu entry: a parameter id or MENU_* */
static uint8_t step;                /* step of a procedure; choice shown; totals: reset asked */
static uint8_t entry_n;
static char k;                      /* the key being handled */
static char entry[ENTRY_MAX + 1];   /* the number being typed */
static char line[SCREEN_COLS + 1];  /* one line being put together */
static const char *msg;             /* the message on the bottom line, 0 for none ... */
static uint8_t msg_range;           /* ... or the parameter whose range it shows, NO_RANGE */
#define NO_RANGE 0xFF
static uint16_t msg_until_ms;      /* hal_ms() low 16 bits: messages and redraws are short */
static uint16_t next_draw_ms;
static uint32_t cal_pulses;         /* pulse total at the start, then the pulses counted */
static uint16_t cal_value;          /* the new calibration value, in the parameter's units */

/* ---- small text helpers ---------------------------------------------------------------- */
static void say(const char *s)
{
    msg = s;
    msg_range = NO_RANGE;
    msg_until_ms = (uint16_t)hal_ms() + CONSOLE_MSG_MS;
}

static void say_none(void)
{
    msg = 0;
    msg_range = NO_RANGE;
}

static uint8_t msg_on(void)
{
    return msg || msg_range != NO_RANGE;
}

/* The bottom-line screens put a whole line together in `line`, then screen_line() it: each
 * column is written once, so only real changes reach the LCD. */
static uint8_t cat(uint8_t at, const char *s)
{
    while (*s && at < SCREEN_COLS)
        line[at++] = *s++;
    line[at] = 0;
    return at;
}

/* a number, right-aligned in width columns ('#'s when it does not fit); width 0: as long as it is */
static uint8_t cat_num(uint8_t at, uint8_t width, uint32_t v, uint8_t decimals, uint8_t trim)
{
    char num[FMT_MAX];
    uint8_t n = fmt_u32(num, v, decimals, trim);
    if (width && n > width) {
        while (width--)
            at = cat(at, "#");
        return at;
    }
    while (width-- > n)
        at = cat(at, " ");
    return cat(at, num);
}

/* move line[from..] to the right end of the row, spaces in between */
static void right_align(uint8_t from)
{
    uint8_t n = 0, shift;
    while (line[n])
        n++;
    shift = (uint8_t)(SCREEN_COLS - n);
    if (!shift || from > n)
        return;
    line[SCREEN_COLS] = 0;
    while (n > from) {
        n--;
        line[n + shift] = line[n];
    }
    while (shift--)
        line[from + shift] = ' ';
}

static uint8_t is_choice(uint8_t id)
{
    return id == P_CONTROLLER || id == P_MODE;
}

static const char *choice_name(uint8_t id, uint16_t v)
{
    if (id == P_MODE)
        return v ? "Manual" : "Auto";
    return ctl_name((uint8_t)v);
}

/* append a parameter's value and unit, "150 L/ha" */
static uint8_t cat_value(uint8_t at, uint8_t id, uint16_t v)
{
    const param_info_t *pi = param_info(id);
    if (is_choice(id))
        return cat(at, choice_name(id, v));
    at = cat_num(at, 0, v, pi->decimals, 0);
    if (pi->unit[0]) {
        at = cat(at, " ");
        at = cat(at, pi->unit);
    }
    return at;
}

/* "Range 10..1000", the limits with their decimals, trailing zeros dropped */
static void say_range(uint8_t id)
{
    say(0);
    msg_range = id;
}

/* The message on the bottom line. */
static void draw_msg(void)
{
    const param_info_t *pi;
    uint8_t at;
    if (msg_range == NO_RANGE) {
        screen_line(3, msg);
        return;
    }
    pi = param_info(msg_range);
    at = cat(0, "Range ");
    at = cat_num(at, 0, pi->min, pi->decimals, 1);
    at = cat(at, "..");
    cat_num(at, 0, pi->max, pi->decimals, 1);
    screen_line(3, line);
}

/* Set and store a value; the message says what happened. 0 when refused. */
static uint8_t apply(uint8_t id, uint16_t v)
{
    if (!param_set(id, v)) {
        say_range(id);
        return 0;
    }
    say(store_save() ? "Saved" : store_status_text(STORE_WRITE_ERR));
    return 1;
}

/* ---- number entry -------------------------------------------------------------------------- */
static void entry_clear(void)
{
    entry_n = 0;
    entry[0] = 0;
}

static void entry_key(uint8_t decimals)
{
    uint8_t i, point = 0xFF;
    for (i = 0; i < entry_n; i++)
        if (entry[i] == '.')
            point = i;
    if (k == '#') {
        if (!decimals) {
            say("Whole numbers");
            return;
        }
        if (point != 0xFF)
            return;
    } else if (point != 0xFF && entry_n - point > decimals) {
        say(decimals == 1 ? "1 decimal only" : "2 decimals only");
        return;
    }
    if (entry_n >= ENTRY_MAX)
        return;
    entry[entry_n++] = k == '#' ? '.' : k;
    entry[entry_n] = 0;
}

#define ENTRY_TOO_BIG 0xFFFFu         /* above every parameter's maximum (60000 at most) */
/* The typed number in units of 10^-decimals; ENTRY_TOO_BIG when it is larger than 65534. */
static uint16_t entry_value(uint8_t decimals)
{
    uint16_t v = 0;
    uint8_t i, d, frac = 0, point = 0;
    for (i = 0; i < entry_n; i++) {
        if (entry[i] == '.') {
            point = 1;
            continue;
        }
        if (point)
            frac++;
        d = (uint8_t)(entry[i] - '0');
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
static uint32_t cal_now(void)
{
    if (state == S_CAL_TANK)
        return app_flow_pulses();
    return app_wheel_pulses();
}

/* ---- screens ------------------------------------------------------------------------------- */
static void draw_bottom(const char *otherwise)
{
    if (msg_on())
        draw_msg();
    else
        screen_line(3, otherwise);
}

/* The alarm to show: unacknowledged ones first, several take turns every 2 s; -1 for none. */
static int8_t alarm_shown(void)
{
    uint16_t set = app_status.alarms_unacked ? app_status.alarms_unacked : app_status.alarms;
    uint8_t n = 0, b, turn;
    for (b = 0; b < APP_ALARM_BITS; b++)
        if (set & (1u << b))
            n++;
    if (!n)
        return -1;
    turn = (uint8_t)((hal_ms() / 2000u) % n);
    for (b = 0; b < APP_ALARM_BITS; b++)
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
    /* " 7.2km/h    AUTO": ground speed, mode */
    at = cat_num(0, 4, (st->speed_kmh_x100 + 5u) / 10u, 1, 0);
    at = cat(at, "km/h ");
    cat(at, st->manual ? "MANUAL" : "AUTO");
    right_align(at);
    screen_line(0, line);
    /* "Q 49.5> 49.3L/mn": target flow > measured flow */
    at = cat(0, "Q");
    q = st->target_lpm_x100;
    at = cat_num(at, 5, q > 0 ? ((uint16_t)q + 5u) / 10u : 0, 1, 0);
    at = cat(at, ">");
    q = st->flow_lpm_x100;
    at = cat_num(at, 5, q > 0 ? ((uint16_t)q + 5u) / 10u : 0, 1, 0);
    cat(at, "L/mn");
    screen_line(1, line);
    /* " 150L/ha 4.40bar": dose applied so far, boom pressure */
    at = cat_num(0, 4, (st->applied_l_ha_x10 + 5u) / 10u, 0, 0);
    at = cat(at, "L/ha");
    at = cat_num(at, 5, st->pressure_kpa, 2, 0);
    cat(at, "bar");
    screen_line(2, line);
    /* bottom: a message, EEPROM trouble, an alarm ("!" not yet acknowledged), or tank and controller */
    a = alarm_shown();
    if (msg_on()) {
        draw_msg();
    } else if (store_status() != STORE_OK) {
        at = cat(0, "!");
        cat(at, store_status_text(store_status()));
        screen_line(3, line);
    } else if (a >= 0) {
        at = cat(0, (st->alarms_unacked & (1u << a)) ? "!" : " ");
        cat(at, app_alarm_text((uint8_t)a));
        screen_line(3, line);
    } else {
        at = cat(0, "T");
        at = cat_num(at, 5, st->tank_l, 0, 0);
        at = cat(at, "L ");
        cat(at, ctl_name(ctl_selected()));
        right_align(at);
        screen_line(3, line);
    }
}

static void draw_totals(void)
{
    const app_status_t *st = &app_status;
    uint8_t at;
    at = cat(0, "Job ");
    at = cat_num(at, 9, (st->job_area_m2 + 50u) / 100u, 2, 0);
    cat(at, " ha");
    screen_line(0, line);
    at = cat(0, "Job ");
    at = cat_num(at, 10, (st->job_volume_ml + 50u) / 100u, 1, 0);
    cat(at, " L");
    screen_line(1, line);
    at = cat(0, "Life");
    at = cat_num(at, 9, (st->life_area_m2 + 50u) / 100u, 2, 0);
    cat(at, " ha");
    screen_line(2, line);
    if (step) {
        draw_bottom("Reset job? D=yes");
    } else if (msg_on()) {
        draw_msg();
    } else {
        at = cat(0, "Life");
        at = cat_num(at, 10, (st->life_volume_ml + 500u) / 1000u, 0, 0);
        cat(at, " L");
        screen_line(3, line);
    }
}

static const char *menu_name(uint8_t i)
{
    if (i == MENU_CAL_SPEED)
        return "Speed cal 100 m";
    if (i == MENU_CAL_TANK)
        return "Meter cal tank";
    if (i == MENU_TOTALS)
        return "Totals";
    return param_info(i)->name;
}

static void draw_menu(void)
{
    uint8_t at = cat(0, "Menu ");
    at = cat_num(at, 2, item + 1u, 0, 0);
    at = cat(at, "/");
    cat_num(at, 0, MENU_COUNT, 0, 0);
    right_align(5);
    screen_line(0, line);
    screen_line(1, menu_name(item));
    if (item < P_COUNT) {
        cat_value(0, item, param_v[item]);
        right_align(0);
        screen_line(2, line);
    } else {
        screen_line(2, item == MENU_TOTALS ? "D: show, reset" : "D: start");
    }
    draw_bottom("A^ Bv D:ok C:run");
}

static void draw_edit(void)
{
    const param_info_t *pi = param_info(item);
    uint8_t at;
    screen_line(0, pi->name);
    at = cat(0, "now ");
    cat_value(at, item, param_v[item]);
    right_align(at);
    screen_line(1, line);
    at = cat(0, "new ");
    at = cat(at, entry);
    at = cat(at, "_");
    if (pi->unit[0]) {
        at = cat(at, " ");
        cat(at, pi->unit);
    }
    screen_line(2, line);
    draw_bottom("D:ok C:clear");
}

static void draw_choice(void)
{
    uint8_t at;
    screen_line(0, param_info(item)->name);
    at = cat(0, "now ");
    cat(at, choice_name(item, param_v[item]));
    right_align(at);
    screen_line(1, line);
    at = cat(0, "new ");
    cat(at, choice_name(item, step));
    right_align(at);
    screen_line(2, line);
    draw_bottom("A/B:choose D:ok");
}

static void draw_cal(void)
{
    uint8_t tank = state == S_CAL_TANK;
    uint32_t now = cal_now();
    uint8_t at;
    screen_line(0, tank ? "Meter cal tank" : "Speed cal 100 m");
    if (step == 0) {
        screen_line(1, tank ? "Tank at a mark" : "At the start");
        screen_line(2, "D: start count");
        draw_bottom("C:back");
        return;
    }
    at = cat(0, "Pulses");
    cat_num(at, 10, step == 1 ? now - cal_pulses : cal_pulses, 0, 0);
    screen_line(1, line);
    if (step == 1) {
        screen_line(2, tank ? "Spray; D: stop" : "At 100 m: D");
        draw_bottom("C:cancel");
    } else if (step == 2) {             /* tank: litres sprayed */
        at = cat(0, "Litres ");
        at = cat(at, entry);
        cat(at, "_");
        screen_line(2, line);
        draw_bottom("D:ok C:clear");
    } else {                            /* the new value, to save */
        at = cat(0, "New ");
        cat_value(at, tank ? P_METER_K : P_WHEEL, cal_value);
        right_align(at);
        screen_line(2, line);
        draw_bottom("D:save C:cancel");
    }
}

static void draw(void)
{
    if (msg_on() && (int16_t)((uint16_t)hal_ms() - msg_until_ms) >= 0)
        say_none();
    switch (state) {
    case S_RUN: draw_run(); break;
    case S_TOTALS: draw_totals(); break;
    case S_MENU: draw_menu(); break;
    case S_EDIT: draw_edit(); break;
    case S_CHOICE: draw_choice(); break;
    default: draw_cal(); break;
    }
}

/* ---- keys ---------------------------------------------------------------------------------- */
static void go(uint8_t s)
{
    state = s;
    step = 0;
    entry_clear();
    say_none();
}

static void key_run(void)
{
    if (k == 'A') {
        go(S_MENU);
        item = 0;
    } else if (k == 'B') {
        go(S_TOTALS);
    } else if (k == '#') {
        if (apply(P_MODE, param_v[P_MODE] ? 0 : 1))
            say(param_v[P_MODE] ? "Mode: MANUAL" : "Mode: AUTO");
    } else if (k == '2' || k == '8') {
        if (app_status.manual)
            app_jog(k == '2' ? 1 : -1);
        else
            say("Jog: manual only");
    }
}

static void key_totals(void)
{
    if (k == 'D') {
        if (step) {
            app_totals_reset();
            step = 0;
            say("Job reset");
        } else {
            step = 1;
        }
    } else if (k == 'C' || k == 'B') {
        if (step)
            step = 0;
        else
            go(S_RUN);
    }
}

static void key_menu(void)
{
    if (k == 'A') {
        item = item ? item - 1 : MENU_COUNT - 1;
    } else if (k == 'B') {
        item = item + 1 < MENU_COUNT ? item + 1 : 0;
    } else if (k == 'C') {
        go(S_RUN);
    } else if (k == 'D') {
        if (item == MENU_CAL_SPEED)
            go(S_CAL_SPEED);
        else if (item == MENU_CAL_TANK)
            go(S_CAL_TANK);
        else if (item == MENU_TOTALS)
            go(S_TOTALS);
        else if (is_choice(item)) {
            go(S_CHOICE);
            step = (uint8_t)param_v[item];
        } else
            go(S_EDIT);
    }
}

/* Typing keys shared by the number entries; 1 when k was one of them. */
static uint8_t typing(uint8_t decimals)
{
    if ((k >= '0' && k <= '9') || k == '#') {
        entry_key(decimals);
        return 1;
    }
    return 0;
}

static void key_edit(void)
{
    const param_info_t *pi = param_info(item);
    uint16_t v;
    if (typing(pi->decimals))
        return;
    if (k == 'C') {
        if (entry_n)
            entry_clear();
        else
            go(S_MENU);
    } else if (k == 'D') {
        if (!entry_n) {
            go(S_MENU);
            return;
        }
        v = entry_value(pi->decimals);
        if (v == ENTRY_TOO_BIG) {
            say_range(item);
        } else if (apply(item, v)) {
            state = S_MENU;
            entry_clear();
            return;
        }
        entry_clear();
    }
}

static void key_choice(void)
{
    uint8_t n = item == P_MODE ? 2 : CTL_COUNT;
    if (k == 'A')
        step = step + 1 < n ? step + 1 : 0;
    else if (k == 'B')
        step = step ? step - 1 : n - 1;
    else if (k == 'C')
        go(S_MENU);
    else if (k == 'D') {
        if (apply(item, step))
            state = S_MENU;
    }
}

static void key_cal(void)
{
    uint8_t tank = state == S_CAL_TANK;
    uint8_t id = tank ? P_METER_K : P_WHEEL;
    uint32_t v;
    if (step == 2 && typing(1))
        return;
    if (k == 'C') {
        if (step == 2 && entry_n)
            entry_clear();
        else {
            go(S_MENU);
            say("Cancelled");
        }
        return;
    }
    if (k != 'D')
        return;
    if (step == 0) {
        cal_pulses = cal_now();
        step = 1;
    } else if (step == 1) {
        cal_pulses = cal_now() - cal_pulses;
        if (cal_pulses < 10u) {
            say("Too few pulses");
            step = 0;
        } else if (tank) {
            entry_clear();
            step = 2;
        } else {
            /* P_WHEEL in 0.1 mm a pulse: 100 m = 1 000 000 tenths of a millimetre */
            v = 1000000uL / cal_pulses;
            if (v > 0xFFFFu || !param_in_range(id, (uint16_t)v)) {
                say_range(id);
                step = 0;
            } else {
                cal_value = (uint16_t)v;
                step = 3;
            }
        }
    } else if (step == 2) {
        v = entry_value(1);             /* litres x10 */
        entry_clear();
        if (!v || v == ENTRY_TOO_BIG) {
            say("Litres? >0");
            return;
        }
        /* P_METER_K in 0.1 pulse a litre: pulses * 10 / litres = pulses * 100 / litres_x10 */
        if (cal_pulses > 0xFFFFFFFFu / 100u) {
            say_range(id);
            return;
        }
        v = cal_pulses * 100u / v;
        if (v > 0xFFFFu || !param_in_range(id, (uint16_t)v)) {
            say_range(id);
            return;
        }
        cal_value = (uint16_t)v;
        step = 3;
    } else {
        if (apply(id, cal_value))
            state = S_MENU;
    }
}

static void key(void)
{
    if (k == '*') {
        if (store_status() != STORE_OK) {
            store_status_clear();
            say("EE: seen");
        } else {
            say(app_status.alarms_unacked ? "Alarms acked" : "No new alarms");
        }
        app_alarm_ack();
        return;
    }
    switch (state) {
    case S_RUN: key_run(); break;
    case S_TOTALS: key_totals(); break;
    case S_MENU: key_menu(); break;
    case S_EDIT: key_edit(); break;
    case S_CHOICE: key_choice(); break;
    default: key_cal(); break;
    }
}

void console_init(void)
{
    keypad_init();
    lcd_init();
    screen_clear();
    state = S_RUN;
    item = 0;
    step = 0;
    entry_clear();
    say_none();
    next_draw_ms = (uint16_t)hal_ms();
}

void console_poll(void)
{
    uint16_t now = (uint16_t)hal_ms();
    k = keypad_poll();
    if (k != KEY_NONE) {
        key();
        draw();
        next_draw_ms = now + CONSOLE_REDRAW_MS;
    } else if ((int16_t)(now - next_draw_ms) >= 0) {
        draw();
        next_draw_ms = now + CONSOLE_REDRAW_MS;
    }
    lcd_poll();
}

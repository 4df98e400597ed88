/* console_int.h: the console's shared state and helpers, for console.c (keys) and console_view.c (screens). */
#ifndef CONSOLE_INT_H
#define CONSOLE_INT_H

#include "compiler.h"
#include "screen.h"
#include "units.h"

enum { S_RUN, S_TOTALS, S_MENU, S_EDIT, S_CHOICE, S_CAL_SPEED, S_CAL_TANK, S_IOTEST };

#define ENTRY_MAX 7                 /* characters of a number being typed */
#define ENTRY_TOO_BIG 0xFFFFu       /* above every parameter's maximum (60000 at most) */
#define NO_RANGE 0xFF
/* con.msg_range beyond the parameters: an alarm's message, the alarm bit in the low bits */
#define CON_MSG_PEEK 0x40           /* "!" and the alarm's text (or the EEPROM's, CON_SHOWN_EE) */
#define CON_MSG_ACKED 0x80          /* "Acknowledged:" over the alarm's text */
#define CON_MSG_BIT 0x3F
/* con.shown: what the bottom line showed at the last redraw, for `*` */
#define CON_SHOWN_EE 0x3F           /* the EEPROM's notice */
#define CON_SHOWN_NONE 0xFF         /* neither an unacknowledged alarm nor the notice */
/* The run screen's applied rate: the job's volume over its area, the last CON_RATE_N seconds */
#define CON_RATE_N 3
#define CON_RATE_MIN_DM2 100u       /* under 1 m^2 in the window: no rate */
#define CON_RATE_NONE 0xFFFFu       /* no area covered ("--") */
#define CON_RATE_OVER 0xFFFEu       /* volume with no area: over any figure the line holds */

/* the console's most used bytes, in the direct RAM */
extern __data uint8_t con_state;    /* S_* */
extern __data uint8_t con_item;     /* menu entry: a parameter id or MENU_* */
extern __data uint8_t con_step;     /* step of a procedure; choice shown; totals: reset asked */
extern __data uint8_t con_at;       /* where con_line's next text goes */
/* One line being put together while con_draw runs: on its stack (not a byte of XRAM between
 * the redraws), SCREEN_COLS + 1 characters. */
extern __idata char *__data con_line;

/* The I/O test's rate window (console_view.c). */
typedef struct {
    uint16_t meter0;                /* meter pulses at the window's start (low 16 bits) */
    uint16_t wheel_hz, meter_hz;    /* the last window's rates */
} con_io_t;

typedef struct {
    uint8_t entry_n;
    char k;                         /* the key being handled */
    union {                         /* one screen's or the other's: */
        char entry[ENTRY_MAX + 1];  /* the number being typed (edit, tank calibration) */
        con_io_t io;                /* the I/O test's window (go() clears the entry first) */
    } u;
    const __code char *msg;         /* the message on the bottom line, 0 for none ... */
    uint8_t msg_range;              /* ... or the parameter whose range it shows, NO_RANGE */
    uint16_t msg_until_ms;          /* hal_ms() low 16 bits: messages and redraws are short */
    uint16_t next_draw_ms;
    uint32_t cal_pulses;            /* pulse total at the start, then the pulses counted;
                                     * I/O test: the wheel's at the rate window's start */
    uint16_t cal_value;             /* the new calibration value, in the parameter's units;
                                     * I/O test: hal_ms() low 16 bits at the window's start */
    uint8_t rc_seen;                /* target_remote_refusals() last shown */
    uint8_t shown;                  /* CON_SHOWN_* or the unacknowledged alarm bit shown */
    uint8_t rate_at;                /* the oldest of the job totals' snapshots */
    uint16_t rate_ms;               /* hal_ms() low 16 bits of the newest snapshot */
    uint16_t rate_l_ha;             /* applied rate over the snapshots' window, CON_RATE_* */
    uint8_t top_drawn;              /* 1: a two-pass screen's top rows are drawn, the rest is due */
    struct {
        uint32_t ml, dm2;           /* the job's volume and area, a second apart */
    } rate_snap[CON_RATE_N];
} console_t;
extern console_t con;

/* text helpers and number entry (console_view.c, console.c); all __reentrant: both files keep
 * their locals on the stack */
void con_say(const __code char *s) __reentrant;
void con_say_none(void) __reentrant;
uint8_t con_msg_on(void) __reentrant;
void con_cat_ram(const char *s) __reentrant;
void con_cat(const __code char *s) __reentrant;
void con_start(const __code char *s) __reentrant;
void con_show(uint8_t row) __reentrant;     /* the line put together, on the screen's row */
/* form: the decimals shown (0..3), or'ed with CON_TRIM (no trailing zeros after the point) or
 * CON_DROP(k): v / 10^k rounded, without a divide (v + 10^k / 2 formatted with k more decimals,
 * those digits cut off again). One byte, not three: a push less at each of the many calls. */
#define CON_DEC_MASK 3u
#define CON_TRIM 4u
#define CON_DROP(k) ((k) << 3)
/* CON_Q(cls): v is a quantity of class cls (CU_*, in the firmware's scale) shown in the units
 * chosen (con_cat_q): in US or turf units converted, in the unit's decimals (the drop is
 * metric's only) */
#define CON_Q(cls) ((uint8_t)((cls) << 5))
void con_cat_num(uint32_t v, uint8_t width, uint8_t form) __reentrant;
void con_cat_q(uint32_t v, uint8_t width, uint8_t form) __reentrant;
void con_right_align(uint8_t from) __reentrant;
uint8_t con_is_choice(uint8_t id) __reentrant;
const __code char *con_choice_name(uint8_t id, uint16_t v) __reentrant;
void con_cat_value(uint8_t id, uint16_t v) __reentrant;
void con_say_range(uint8_t id) __reentrant;
void con_draw_msg(void) __reentrant;
uint8_t con_apply(uint8_t id, uint16_t v) __reentrant;
void con_entry_clear(void) __reentrant;
void con_entry_key(uint8_t decimals) __reentrant;
uint16_t con_entry_value(uint8_t decimals) __reentrant;
uint32_t con_cal_now(void) __reentrant;
uint8_t con_draw(void) __reentrant;   /* 1: the screen is drawn whole (run, totals: in two calls) */
/* units (console_units.c; the classes and their ratios: units.h) */
const __code char *con_unit_text(uint8_t cls, const __code char *metric) __reentrant;
void con_cat_unit(uint8_t cls) __reentrant;
uint8_t con_q_form(uint8_t form) __reentrant;
void con_iotest_start(void) __reentrant;
void con_draw_iotest(void) __reentrant;     /* console_io.c */
void con_draw_totals_top(void) __reentrant; /* console_totals.c: rows 0-1 */
void con_draw_totals(void) __reentrant;     /* ... rows 2-3 */

#endif

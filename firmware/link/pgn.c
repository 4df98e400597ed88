/* pgn.c: AgOpenGPS and RateControl PGN frames on the serial link: parsed, checked, applied, answered (pgn.h). */
#include "hal.h"
#include "params.h"
#include "ops.h"
#include "target.h"
#include "totals.h"
#include "umath.h"
#include "mul.h"
#include "diag_wheel.h"
#include "pgn.h"

#if FW_PGN

__xdata pgn_rx_t pgn_rx;

static __xdata struct {
    uint8_t f[PGN_BUF];             /* the frame coming in (its first PGN_BUF bytes) */
    uint8_t n;                      /* its bytes so far (0: none) */
    uint8_t total;                  /* its length once known (0: not yet) */
    uint8_t sum;                    /* the sum of its bytes so far */
    uint8_t due;                    /* replies due: Q_* */
    uint8_t off;                    /* "both": periods apart less periods together */
    uint8_t off_flag;               /* the speeds apart (WHEEL_NOISE) */
    uint8_t age_speed;              /* periods since the last 254 (saturates) */
    uint8_t age_sect;               /* ... since the last 239, 229 or 32501 */
    uint8_t age_rc;                 /* ... since the last 32500 of this module */
    uint16_t rc_rate_x10;           /* the rate last handed to the target (L/ha x10) */
    __xdata uint8_t *out;           /* where pgn_next's reply takes its next byte */
} pg;

#define Q_237 1u
#define Q_32400 2u
#define Q_32401 4u
#define RC_COMM_PERIODS 40u         /* 32400's status bit 0: the app heard within 4 s */

void pgn_init(void)
{
    uint8_t i;
    for (i = 0; i < sizeof pg; i++)     /* all as at power-up: no frame, nothing due, the ages 0
                                         * (Frames lost counts from power-up) */
        ((__xdata uint8_t *)&pg)[i] = 0;
    pg.age_rc = 255;
    pgn_rx.sections = 0xFF;
    pgn_rx.rc_cmd = 0x50;           /* MasterOn, AutoOn until a 32500 says otherwise */
    pgn_rx.taken = pgn_rx.bad = 0;
}

static uint16_t le16(uint8_t i) __reentrant
{
    return pg.f[i] | (uint16_t)pg.f[i + 1] << 8;
}

static uint32_t le24(uint8_t i) __reentrant
{
    return le16(i) | (uint32_t)pg.f[i + 2] << 16;
}

/* 32500's target flow as a rate over the open width at the speed used, to the target (its
 * window decides); a change under 1/128 is not handed on (the speed's noise) */
static void rc_rate(void) __reentrant
{
    uint32_t d = UMUL(app_status.in.speed_kmh_x100, target_width_cm());
    uint16_t r, last = pg.rc_rate_x10;
    if (!pgn_rx.rc_upm_x1000 || !(pgn_rx.rc_cmd & 0x40u) || app_status.in.speed_kmh_x100 < 100u || !d)
        return;
    r = (uint16_t)um_muldiv(pgn_rx.rc_upm_x1000, 60000u, d);    /* L/min x1000 -> L/ha x10 */
    if (((uint32_t)(r > last ? r - last : last - r) << 7) > last || !last) {
        pg.rc_rate_x10 = r;
        target_remote_rate(r);
    }
}

/* A whole frame with a good check: take what it carries. */
static void take(void) __reentrant
{
    uint8_t k = pg.f[3], m = (uint8_t)param_v[P_RC_ID];
    pgn_rx.taken++;
    if (pg.f[0] == 0x80) {          /* AgOpenGPS: f[3] the pgn */
        if (k == 254) {
            pgn_rx.gps_kmh_x10 = le16(5);
            pg.age_speed = 0;
        } else {
            pgn_rx.sections = pg.f[k == 239 ? 11 : 5];
            pg.age_sect = 0;
            if (k == 239 && param_v[P_AOG_REPLY])
                pg.due |= Q_237;
        }
        return;
    }
    k = pg.f[2];                    /* RateControl: module (<<4 | sensor) */
    if ((pg.f[0] == 0xF5 ? k : k >> 4) != m || (pg.f[0] != 0xF5 && (k & 15u))) {
        pgn_rx.taken--;             /* another module's */
        return;
    }
    if (pg.f[0] == 0xF4) {
        pgn_rx.rc_upm_x1000 = le24(3);
        pgn_rx.rc_cmd = pg.f[9];
        pg.age_rc = 0;
        pg.due |= Q_32400 | Q_32401;
        rc_rate();
    } else if (pg.f[0] == 0xF5) {
        pgn_rx.sections = pg.f[3];
        pg.age_sect = 0;
    }                               /* 32502: checked and counted; its valve settings have no
                                     * counterpart here (docs/PGN.md) */
}

uint8_t pgn_busy(void)
{
    return pg.n != 0;
}

void pgn_drop(void)
{
    if (pg.n) {
        pg.n = 0;
        pgn_rx.bad++;
    }
}

uint8_t pgn_byte(uint8_t b) __reentrant
{
    uint8_t n = pg.n, k, none = PGN_NO;
    if (n == 1 && b != (pg.f[0] == 0x80 ? 0x81 : 0x7E)) {
        pgn_drop();                 /* no second sync byte: the first was noise, b perhaps a start */
        n = 0;
        none = PGN_NOISE;
    }
    if (!n) {
        if (param_v[P_REMOTE] != REMOTE_PGN || !(b == 0x80 || (b >= 0xF4 && b <= 0xF6)))
            return none;
        pg.total = b == 0x80 ? 0 : b == 0xF4 ? 14 : b == 0xF5 ? 11 : 24;
        pg.sum = 0;
    }
    if (n < PGN_BUF)
        pg.f[n] = b;
    pg.n = ++n;
    if (n == 5 && !pg.total) {      /* AgOpenGPS: its pgn and length known */
        k = pg.f[3];
        pg.total = (uint8_t)(b + 6u);   /* (a length over 249 would not fit the count) */
        if ((k == 254 || k == 239) ? b != 8 : k == 229 ? b != 10 : b > 249)
            goto bad;
    }
    if (n != pg.total) {
        pg.sum += b;
        return PGN_IN;
    }
    /* the check: AgOpenGPS's leaves out 80 81 (their sum's low byte is 1) */
    if ((uint8_t)(pg.sum - (pg.f[0] == 0x80 ? 1u : 0u)) != b)
        goto bad;
    pg.n = 0;
    k = pg.f[3];
    if (pg.f[0] != 0x80 || k == 254 || k == 239 || k == 229)
        take();
    return PGN_END;
bad:
    pgn_drop();
    return PGN_END;
}

static uint8_t stale(uint8_t age) __reentrant
{
    return age > param_v[P_FRAMES_LOST];    /* (Frames lost in 0.1 s: periods) */
}

uint8_t pgn_lost(void) __reentrant
{
    if (param_v[P_REMOTE] != REMOTE_PGN)
        return 0;
    return (param_v[P_SPEED_SRC] != SPEED_SRC_WHEEL && stale(pg.age_speed))
           || (param_v[P_AOG_SECT] && stale(pg.age_sect));
}

uint8_t pgn_frames(void) __reentrant
{
    uint8_t f = pgn_lost() | (pg.off_flag << 1);
    if (param_v[P_REMOTE] == REMOTE_PGN && param_v[P_SPEED_SRC] != SPEED_SRC_WHEEL)
        f |= DIAG_FRAMES_GPS;
    return f;
}

uint16_t pgn_speed(uint16_t wheel_x100) __reentrant
{
    uint16_t gps = pgn_rx.gps_kmh_x10 * 10u, d;
    uint8_t src = (uint8_t)param_v[P_SPEED_SRC];
    if (pg.age_speed < 255u)
        pg.age_speed++;
    if (pg.age_sect < 255u)
        pg.age_sect++;
    if (pg.age_rc < 255u)
        pg.age_rc++;
    if (param_v[P_REMOTE] != REMOTE_PGN)
        src = SPEED_SRC_WHEEL;
    if (src != SPEED_SRC_BOTH)
        pg.off = pg.off_flag = 0;   /* judged with "both" only: a flag left from it goes */
    if (src == SPEED_SRC_WHEEL)
        return wheel_x100;
    if (stale(pg.age_speed))
        return src == SPEED_SRC_GPS ? 0 : wheel_x100;     /* both: the wheel, SPEED_LOST tells */
    if (src == SPEED_SRC_BOTH && gps >= PGN_CHECK_X100) {
        /* the wheel off the GPS by more than Speed diff % of it: counted up, together down */
        d = wheel_x100 > gps ? wheel_x100 - gps : gps - wheel_x100;
        if (UMUL(d, 100u) > UMUL(param_v[P_SPEED_DIFF], gps)) {
            if (pg.off < PGN_OFF_PERIODS)
                pg.off++;
            if (pg.off >= PGN_OFF_PERIODS)
                pg.off_flag = 1;
        } else if (pg.off && --pg.off == 0) {
            pg.off_flag = 0;
        }
    }
    return gps;
}

uint8_t pgn_sections(uint8_t switches) __reentrant
{
    if (param_v[P_REMOTE] != REMOTE_PGN || !param_v[P_AOG_SECT])
        return switches;
    if (stale(pg.age_sect) || !(pgn_rx.rc_cmd & 0x10u))
        return 0;                   /* frames stopped, or RateControl's master off */
    return switches & pgn_rx.sections;
}

/* The reply's next n bytes: v little-endian, at pg.out (then past them). */
static void put_le(uint32_t v, uint8_t n) __reentrant
{
    __xdata uint8_t *p = pg.out;
    while (n--) {
        *p++ = (uint8_t)v;
        v >>= 8;
    }
    pg.out = p;
}

uint8_t pgn_next(__xdata uint8_t *buf) __reentrant
{
    uint8_t i, n = 14, s = 0, from = 0;
    int16_t q = app_status.in.flow_lpm_x100;
    if (!pg.due)
        return 0;
    for (i = 0; i < PGN_OUT_MAX; i++)
        buf[i] = 0;
    pg.out = buf;
    if (pg.due & Q_237) {           /* a machine module's answer: the sections spraying */
        pg.due &= (uint8_t)~Q_237;
        put_le(0xED7F8180UL, 4);    /* 80 81 7F 237, then the length 8 */
        put_le(8u | (uint16_t)(app_status.spraying ? pgn_sections(hal_sections()) : 0) << 8, 2);
        from = 2;
        n = 13;
    } else if (pg.due & Q_32400) {  /* the rate applied and the meter */
        int16_t pwm;
        pg.due &= (uint8_t)~Q_32400;
        if (q < 0)
            q = 0;
        put_le(0x7E90UL | (uint32_t)(uint8_t)(param_v[P_RC_ID] << 4) << 16, 3);
        put_le(UMUL(q, 10u), 3);
        put_le(totals.job_ml / 100u, 3);
        pwm = app_status.drive >> 7;                        /* the module's PWM: -255..255 */
        put_le((uint16_t)(pwm < -255 ? -255 : pwm), 2);
        put_le(pg.age_rc < RC_COMM_PERIODS, 1);
        put_le(UMUL(q, param_v[P_METER_K]) / 6000u, 2);     /* meter pulses a second x10 */
    } else {                        /* module info: pressure, the boom spraying */
        pg.due = 0;
        put_le(0x7E91UL | (uint32_t)(uint8_t)param_v[P_RC_ID] << 16, 3);
        put_le(app_status.in.pressure_kpa, 2);
        buf[13] = app_status.spraying;
    }
    for (i = from; i < n; i++)
        s += buf[i];
    buf[n] = s;
    return (uint8_t)(n + 1u);
}
#endif

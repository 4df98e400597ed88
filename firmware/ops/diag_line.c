/* diag_line.c: the rules judged on the line and the tank: pump dry from the pressure and flow, the pressure sensor's zero at rest, the tank balance against the meter. */
#include "hal.h"
#include "params.h"
#include "umath.h"
#include "analog.h"
#include "flow.h"
#include "target.h"
#include "valve.h"
#include "ctl.h"
#include "mul.h"
#include "diag_line.h"

static struct {
    /* pump dry judged on the line (diag_dry_line) */
    uint8_t dry_cnt;                            /* periods the line said dry */
    uint8_t dry_line;                           /* 1: it did for DIAG_DRY_PERIODS (held: diag_dry_line) */
    uint16_t dry_l;                             /* the level then */
    /* the pressure sensor's zero (diag_zero) */
    uint16_t p_spray;                           /* kPa the boom sprays at, at working speed, filtered (0: none) */
    uint16_t z_lo, z_hi;                        /* the readings' range over the rest window */
    uint8_t z_n;                                /* periods of that window */
    uint8_t zero_off;                           /* 1: read over DIAG_ZERO_KPA at rest (until it reads 0 at rest) */
    /* the tank balance (diag_balance): the sums of the closed stretches, the open one */
    uint16_t bal_v10;                           /* metered volume, 0.1 L */
    uint16_t bal_dl;                            /* the level's fall, L */
    uint16_t bal_sv10;                          /* the open stretch's metered volume, 0.1 L */
    uint16_t bal_acc;                           /* ... its remainder, in L/min x100 periods (6000 a 0.1 L) */
    uint16_t bal_s0, bal_smin;                  /* ... the level at its start, its lowest */
    uint8_t bal_n;                              /* ... its periods (0: none open), at most 255 */
    uint16_t bal_l1;                            /* the level a period ago */
    uint8_t bal_wait;                           /* periods before a stretch may open (after a step) */
    uint16_t bal_k, bal_t;                      /* Meter K and Tank size the sums were made under */
} dl;

const __xdata app_status_t *__data diag_in;
__bit diag_settled, diag_working, diag_psens, diag_lsens, diag_metering;

void diag_period(const __xdata app_status_t *in, uint8_t settled) __reentrant
{
    diag_in = in;
    diag_settled = settled;
    diag_working = target_working_speed(in->in.speed_kmh_x100);
    diag_psens = analog_pressure_ok();
    diag_lsens = analog_level_ok();
    diag_metering = flow_quiet_periods() == 0;
}

void diag_line_init(void)
{
    dl.dry_cnt = dl.dry_line = 0;
    dl.p_spray = 0;
    dl.z_n = dl.zero_off = 0;
    dl.bal_t = 0;                   /* (the balance starts anew at its first call) */
}

/* Pump dry from the line, whatever the level says (a level sensor reading high): spraying at
 * working speed, the pressure under P start (the check valves shut) and under a quarter of the
 * target metered, for DIAG_DRY_PERIODS. Held until the pump pushes liquid again (P start or
 * more with the boom shut), the level rises by Tank size / 64 (a refill), or the operator
 * switches the sections off (to open them again after refilling): the boom is shut meanwhile,
 * so nothing else can tell. */
uint8_t diag_dry_line(void) __reentrant
{
    uint16_t p = diag_in->in.pressure_kpa, pmin = param_v[P_P_MIN];
    int16_t meter = flow_lpm_x100();
    if (diag_settled && diag_psens && p < pmin && diag_working
        && UMUL(meter > 0 ? meter : 0, 4u) < (uint16_t)diag_in->in.target_lpm_x100) {
        if (++dl.dry_cnt >= DIAG_DRY_PERIODS && !dl.dry_line) {
            dl.dry_line = 1;
            dl.dry_l = diag_in->tank_l;
        }
    } else
        dl.dry_cnt = 0;
    if (dl.dry_line && (!diag_in->open_nozzles || (!diag_in->spraying && diag_psens && p >= pmin)
                        || (diag_lsens && diag_in->tank_l > dl.dry_l + (param_v[P_TANK_L] >> 6))))
        dl.dry_line = 0;
    return dl.dry_line;
}

/* The pressure sensor's zero: with the boom shut at a standstill in auto, the bypass open by
 * DIAG_ZERO_OPEN_Q15 or more as far as valve.c knows (a closed one traps the line's pressure
 * when the pump stops; before a stop was found valve.c does not know where it is) and
 * the reading steady (within DIAG_ZERO_STEADY_KPA for DIAG_ZERO_PERIODS) under half the
 * pressure the boom sprays at, the pump pushes nothing (one that runs against the bypass, held
 * at the spraying pressure or opened further, keeps the line near that pressure or above): the
 * line is at rest, and a reading over DIAG_ZERO_KPA is a sensor off its zero, until it reads 0
 * at rest again. */
uint8_t diag_zero(void) __reentrant
{
    uint16_t p = diag_in->in.pressure_kpa;
    if (diag_in->manual || !diag_psens)
        dl.p_spray = 0;             /* the valve moved by hand: no spraying pressure to go by */
    else if (diag_settled && diag_working)
        dl.p_spray = dl.p_spray ? dl.p_spray + ((int16_t)(p - dl.p_spray + 32) >> 6) : p;  /* over 6.4 s: not a slow-down's */
    uint16_t pos = valve_position();
    if (diag_in->spraying || diag_in->in.speed_kmh_x100 || !dl.p_spray
        || !((valve_limit() & CTL_AT_OPEN) || (pos != VALVE_POS_UNKNOWN && pos >= DIAG_ZERO_OPEN_Q15))) {
        dl.z_n = 0;
        return dl.zero_off;
    }
    if (!dl.z_n || p < dl.z_lo)
        dl.z_lo = p;
    if (!dl.z_n || p > dl.z_hi)
        dl.z_hi = p;
    dl.z_n++;
    if ((uint16_t)(dl.z_hi - dl.z_lo) > DIAG_ZERO_STEADY_KPA || (uint16_t)(dl.z_hi << 1) >= dl.p_spray) {
        dl.z_n = 0;                 /* not at rest: the window starts again */
        return dl.zero_off;
    }
    if (dl.z_n >= DIAG_ZERO_PERIODS) {
        dl.zero_off = dl.z_hi > DIAG_ZERO_KPA;
        dl.z_n = 0;
    }
    return dl.zero_off;
}

/* The tank balance: the metered volume against the level's fall over the stretches of at least
 * DIAG_BAL_STRETCH periods in which the boom sprays with the meter in its full range
 * (DIAG_BAL_MIN_X100); shorter ones are dropped (a stretch's two ends carry the level's
 * rounding, and a flow about the range's edge makes many short ones). The level's resolution:
 * its 4-20 mA span is 819 counts of the 10-bit ADC, Tank size / 819 a count; m = Tank size /
 * 256 + 1 L (three counts and a litre) is what a fall's two ends may be off by. A meter off the
 * fall by more than DIAG_BAL_PCT % of it and m is METER_CAL, judged once the level fell by 8 m
 * (a stretch is summed every 32 m, the sums halved beyond 64 m: the balance follows the last
 * quarter of a tank). A level that
 * moves by m in a period or rises by m in a stretch (a refill, the sensor's step: no boom
 * drains 4 L of a 1000 L tank in 0.1 s, nor does a spraying tank fill) starts it anew
 * DIAG_BAL_WAIT later, when analog.c's filter has followed the step; a
 * new Meter K or Tank size at once (DIAG_BAL_ANEW: the alarm is cleared). Nothing is summed
 * while the level reads within m of Tank size: a tank over the sensor's span (or a Tank size
 * told too small) pins it at the top, where no fall shows. */
uint8_t diag_balance(void) __reentrant
{
    uint16_t l = diag_in->tank_l, m = (param_v[P_TANK_L] >> 8) + 1u, v, f;
    int16_t q = flow_lpm_x100();
    uint32_t a;
    uint8_t r = DIAG_BAL_NONE, run;
    if (dl.bal_k != param_v[P_METER_K] || dl.bal_t != param_v[P_TANK_L]) {
        r = DIAG_BAL_ANEW;
        dl.bal_k = param_v[P_METER_K];
        dl.bal_t = param_v[P_TANK_L];
        dl.bal_wait = 0;
        dl.bal_l1 = l;
        dl.bal_n = 0;
        dl.bal_v10 = dl.bal_dl = 0;
    }
    if (l > dl.bal_l1 + m || l + m < dl.bal_l1 || (dl.bal_n && l > dl.bal_smin + m)) {
        dl.bal_wait = DIAG_BAL_WAIT;
        dl.bal_n = 0;
        dl.bal_v10 = dl.bal_dl = 0;
    }
    dl.bal_l1 = l;
    if (dl.bal_wait)
        dl.bal_wait--;              /* the level's filter settles after a step */
    run = !dl.bal_wait && diag_settled && diag_lsens && q >= DIAG_BAL_MIN_X100 && diag_metering
          && l + m < dl.bal_t;      /* (at the span's top the level cannot show a fall) */
    f = dl.bal_n >= DIAG_BAL_STRETCH && dl.bal_s0 > l ? dl.bal_s0 - l : 0;   /* the stretch's fall */
    if ((!run || f >= (m << 5)) && dl.bal_n) {     /* closed, or long: into the sums, and anew */
        if (dl.bal_n >= DIAG_BAL_STRETCH) {
            dl.bal_dl += f;         /* a stretch long enough: into the sums */
            dl.bal_v10 += dl.bal_sv10;
            if (dl.bal_dl >= (m << 6)) {
                dl.bal_dl >>= 1;
                dl.bal_v10 >>= 1;
            }
        }
        dl.bal_n = f = 0;
    }
    if (run) {
        if (!dl.bal_n) {
            dl.bal_s0 = dl.bal_smin = l;    /* a stretch opens at the level now */
            dl.bal_sv10 = dl.bal_acc = 0;
        }
        if (l < dl.bal_smin)
            dl.bal_smin = l;
        if (dl.bal_n < 255u)
            dl.bal_n++;
        dl.bal_acc += (uint16_t)q;
        while (dl.bal_acc >= 6000u) {
            dl.bal_acc -= 6000u;
            dl.bal_sv10++;
        }
    }
    v = dl.bal_v10 + (f ? dl.bal_sv10 : 0);
    f += dl.bal_dl;
    if (f < (m << 3))
        return r;
    a = UMUL(f, 10u);
    a = v > a ? v - a : a - v;
    return UMUL(a, 10u) > UMUL(f, DIAG_BAL_PCT) + UMUL(m, 100u) ? DIAG_BAL_OFF : DIAG_BAL_ON;  /* (a < 2^16) */
}

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
    /* the tank balance (diag_balance) */
    uint16_t bal_v10;                           /* metered volume, 0.1 L */
    uint16_t bal_acc;                           /* ... its remainder, in L/min x100 periods (6000 a 0.1 L) */
    uint16_t bal_dl;                            /* the level's fall, L */
    uint16_t bal_l0;                            /* the lowest level of the open stretch */
    uint8_t bal_on;                             /* a stretch is open */
    uint16_t bal_k, bal_t;                      /* Meter K and Tank size the sums were made under */
} dl;

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
uint8_t diag_dry_line(const __xdata app_status_t *in, uint8_t settled) __reentrant
{
    uint16_t p = in->pressure_kpa, pmin = param_v[P_P_MIN];
    int16_t meter = flow_lpm_x100();
    uint8_t psens = analog_pressure_ok();
    if (settled && psens && p < pmin && target_working_speed(in->speed_kmh_x100)
        && UMUL(meter > 0 ? meter : 0, 4u) < (uint16_t)in->target_lpm_x100) {
        if (++dl.dry_cnt >= DIAG_DRY_PERIODS && !dl.dry_line) {
            dl.dry_line = 1;
            dl.dry_l = in->tank_l;
        }
    } else
        dl.dry_cnt = 0;
    if (dl.dry_line && (!in->open_nozzles || (!in->spraying && psens && p >= pmin)
                        || (analog_level_ok() && in->tank_l > dl.dry_l + (param_v[P_TANK_L] >> 6))))
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
uint8_t diag_zero(const __xdata app_status_t *in, uint8_t settled) __reentrant
{
    uint16_t p = in->pressure_kpa;
    if (in->manual || !analog_pressure_ok())
        dl.p_spray = 0;             /* the valve moved by hand: no spraying pressure to go by */
    else if (settled && target_working_speed(in->speed_kmh_x100))
        dl.p_spray = dl.p_spray ? dl.p_spray + ((int16_t)(p - dl.p_spray + 32) >> 6) : p;  /* over 6.4 s: not a slow-down's */
    uint16_t pos = valve_position();
    if (in->spraying || in->speed_kmh_x100 || !dl.p_spray
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

/* The tank balance: the metered volume against the level's fall over the periods the boom
 * sprays with the meter in its full range (DIAG_BAL_MIN_X100). The level's resolution: its
 * 4-20 mA span is 819 counts of the 10-bit ADC, Tank size / 819 a count; m = Tank size / 256
 * + 1 L (three counts and a litre) is what the level's two ends may be off by. A meter off the
 * fall by more than DIAG_BAL_PCT % of it and m is METER_CAL, judged once the level fell by 8 m
 * (the sums halved beyond 64 m: the balance follows the last quarter of a tank). A level that
 * rises by m, or falls by m in a period (a refill, the sensor's step: no boom drains that fast
 * by a tank whose m is 4 L a 1000), starts it anew; a new Meter K or Tank size too
 * (DIAG_BAL_ANEW: the alarm is cleared). */
uint8_t diag_balance(const __xdata app_status_t *in, uint8_t settled) __reentrant
{
    uint16_t l = in->tank_l, m = (param_v[P_TANK_L] >> 8) + 1u;
    int16_t q = flow_lpm_x100();
    uint32_t a, b;
    uint8_t r = DIAG_BAL_NONE;
    if (dl.bal_k != param_v[P_METER_K] || dl.bal_t != param_v[P_TANK_L]
        || (dl.bal_on && (l > dl.bal_l0 + m || l + m < dl.bal_l0))) {
        if (dl.bal_k != param_v[P_METER_K] || dl.bal_t != param_v[P_TANK_L])
            r = DIAG_BAL_ANEW;
        dl.bal_k = param_v[P_METER_K];
        dl.bal_t = param_v[P_TANK_L];
        dl.bal_v10 = dl.bal_acc = dl.bal_dl = 0;
        dl.bal_on = 0;
    }
    if (!(settled && analog_level_ok() && q >= DIAG_BAL_MIN_X100 && flow_quiet_periods() == 0))
        dl.bal_on = 0;
    else if (!dl.bal_on) {
        dl.bal_on = 1;              /* a stretch opens at the level now */
        dl.bal_l0 = l;
    } else {
        if (l < dl.bal_l0) {
            dl.bal_dl += dl.bal_l0 - l;
            dl.bal_l0 = l;
        }
        dl.bal_acc += (uint16_t)q;
        while (dl.bal_acc >= 6000u) {
            dl.bal_acc -= 6000u;
            dl.bal_v10++;
        }
        if (dl.bal_dl >= (m << 6)) {
            dl.bal_dl >>= 1;
            dl.bal_v10 >>= 1;
        }
    }
    if (dl.bal_dl < (m << 3))
        return r;
    a = UMUL(dl.bal_dl, 10u);
    a = dl.bal_v10 > a ? dl.bal_v10 - a : a - dl.bal_v10;
    b = UMUL(dl.bal_dl, DIAG_BAL_PCT) + UMUL(m, 100u);
    return UMUL(a, 10u) > b ? DIAG_BAL_OFF : DIAG_BAL_ON;  /* (a < 2^16: the sums are halved first) */
}


/* diag.c: the alarm rules (tank, pump, leak, clog, meter, speed, sensors, pressure, off-rate, valve) and their texts. */
#include "hal.h"
#include "params.h"
#include "umath.h"
#include "analog.h"
#include "flow.h"
#include "speed.h"
#include "target.h"
#include "valve.h"
#include "diag.h"
#include "diag_line.h"
#include "mul.h"
#include "store.h"
#include "ctl.h"
#include "diag_wheel.h"

static struct {
    uint32_t knoz;                  /* Q16: L/min x100 per 256 sqrt(kPa): n Q3 / sqrt(300) / 256 */
    uint32_t nq;                    /* n * Q3 (L/min x100 at 3 bar) */
    uint16_t offrate_cnt;
    uint16_t meter_glitches, wheel_glitches;    /* counts seen last period */
    uint16_t wheel_pulses;                      /* low bits of speed_pulses() last period */
    uint16_t alarms;
    uint8_t cnt[AL_COUNT];
    uint8_t meter_noise, wheel_noise;
    uint8_t meter_suspect;                      /* this period: the meter under a quarter of the nozzle model */
    uint8_t nozzles;
    uint8_t gen;
    /* the nozzle model learnt from the sprayer: P = pc + kp (q / n Q3)^2 (diag_learn) */
    uint16_t sx, sy;                            /* sums of x = (q / n Q3)^2 (Q8, < 512), y = P (kPa, < 512) */
    uint32_t sxx, sxy;                          /* ... of x^2 and x y */
    uint8_t ln;                                 /* samples summed */
    uint8_t learnt;                             /* 0 no model, 1 near xm only, 2 the whole range */
    uint8_t band;                               /* the fine band, % of the pressure (x_of) */
    uint16_t xm;                                /* Q8: the mean x of a model learnt near one flow */
    uint8_t ldiv;                               /* clean periods since the last sample */
    uint16_t pc_kpa, kp_kpa;                    /* the model: check valves, kPa at the rated flow */
    int16_t t1;                                 /* the target a period ago (diag_model) */
    uint8_t session;                            /* 1: a calibration is open: clean spraying teaches the model */
    uint16_t q3;                                /* P_NOZZLE_Q3 the model was learnt for */
} dg;

static __bit fitted;                /* a fit left the model's constant to diag_after_fit */
static __bit p_watch_now;           /* diag_step's p_watch, for diag_supply */

/* the nozzle model before one is learnt: the check valves DIAG_P_CHECK_KPA, 300 kPa (3 bar)
 * at the rated flow */
static void model_told(void)
{
    dg.pc_kpa = DIAG_P_CHECK_KPA;
    dg.kp_kpa = 300u;
}

void diag_init(void)
{
    uint8_t i;
    for (i = 0; i < AL_COUNT; i++)
        dg.cnt[i] = 0;
    dg.alarms = 0;
    dg.offrate_cnt = 0;
    dg.meter_noise = dg.wheel_noise = 0;
    dg.meter_suspect = 0;
    diag_wheel_init();
    dg.meter_glitches = flow_glitches();
    dg.wheel_glitches = speed_glitches();
    dg.wheel_pulses = (uint16_t)speed_pulses();
    dg.nozzles = 0;
    diag_line_init();
    diag_nozzle_relearn();
    /* the model held before: the EEPROM's record (CRC-checked, written by this firmware; the bytes
     * of diag_learnt_byte) or, without one (0xFF bytes, or out of what a fit gives), a calibration opens */
    dg.kp_kpa = store_learnt(STORE_LEARN_CTL + 2u) | (uint16_t)store_learnt(STORE_LEARN_CTL + 3u) << 8;
    dg.pc_kpa = store_learnt(STORE_LEARN_CTL);
    if (dg.kp_kpa >= 100u && dg.kp_kpa <= 1000u && dg.pc_kpa <= 150u) {   /* what learn_fit gives */
        i = store_learnt(STORE_LEARN_CTL + 1u);
        dg.xm = (uint16_t)i << 1;
        dg.learnt = i ? 1 : 2;
        dg.session = 0;
    } else
        model_told();
    dg.q3 = param_v[P_NOZZLE_Q3];
    dg.gen = (uint8_t)(param_generation - 1u);
    store_learnt_from(diag_learnt_byte);    /* a save writes what is learnt as this module says */
}

/* The held model's bytes: check valves (kPa, at most 150), then xm / 2 with its lowest bit set
 * for a model learnt near one flow (0 for one learnt over the range), then kp little endian;
 * 0xFF each without a model. */
uint8_t diag_learnt_byte(uint8_t i) __reentrant
{
    if (i < STORE_LEARN_CTL)
        return ctl_learnt_byte(i);
    if (!dg.learnt)
        return 0xFFu;
    i -= STORE_LEARN_CTL;
    if (i == 0)
        return (uint8_t)dg.pc_kpa;
    if (i == 1)
        return dg.learnt == 1 ? (uint8_t)((dg.xm >> 1) | 1u) : 0;
    return (uint8_t)(i == 2 ? dg.kp_kpa : dg.kp_kpa >> 8);
}

void diag_nozzle_relearn(void)
{
    dg.sx = dg.sy = dg.sxx = dg.sxy = 0;
    dg.ln = 0;
    dg.ldiv = 0;
    dg.learnt = 0;
    dg.xm = 0;
    dg.session = 1;
    model_told();
    dg.gen = (uint8_t)(param_generation - 1u);
    diag_set_nozzles(dg.nozzles);
}

#if FW_PROBES
uint8_t diag_nozzle_learnt(void)
{
    return dg.learnt;
}
#endif

/* x = (q / n Q3)^2, Q8; 0xFFFF beyond twice the rated pressure, and below the meter's range
 * (DIAG_METER_RANGE_X100: the turbine reads low there, docs/SCENARIOS.md: -3 % at 7.5 L/min,
 * -8 % at 5.5, -15 % at 3): nothing is learnt there, and the fine band on the pressure is
 * P_PDEV, not P_PDEV / 2 (six nozzles open at 5 L/min read 8 % low, 17 % of the pressure, and
 * raised a false CLOG; one of the six clogged is 70 % over) */
static uint16_t x_of(int16_t meter) __reentrant
{
    uint32_t r = um_muldiv((uint32_t)meter, 4096u, dg.nq);    /* Q12: q / (n Q3) */
    dg.band = (uint8_t)param_v[P_PDEV];
    if (meter < DIAG_METER_RANGE_X100)
        return 0xFFFFu;
    dg.band >>= 1;
    if (r > 5792u)
        return 0xFFFFu;
    return (uint16_t)(UMUL(r, r) >> 16);                       /* r <= 5792 */
}

/* The fit of the summed samples: a least-squares line when their flows spread enough (the whole
 * range: learnt 2; the squares' spread at least a quarter of their mean, since the meter's noise
 * flattens a line fitted over less, and the check valves it gives come out too high: flows
 * within a tenth of each other fitted them at 91 kPa for 61, and a false LEAK), else the rated curve scaled through their mean (check valves as the default),
 * trusted near that flow only (learnt 1: the sums are halved and learning goes on); clamped to
 * sane nozzles. A fit ends the calibration: the model is held from then on (a leak that grows or
 * nozzles that clog slowly never move it). */
static void learn_fit(void) __reentrant
{
    uint32_t n = (uint32_t)DIAG_LEARN_N * dg.sxx, a = UMUL(dg.sx, dg.sx);    /* sx, sy < 2^15 */
    uint32_t k = (uint32_t)DIAG_LEARN_N * dg.sxy, c = UMUL(dg.sx, dg.sy);
    /* (a: N^2 mean(x)^2, then N^2 var(x): the spread a quarter of the mean, and enough) */
    if (n > a + (a >> DIAG_LEARN_REL) && (a = n - a) >= DIAG_LEARN_SPREAD && k > c) {
        k = um_muldiv(k - c, 256u, a);                                  /* kPa at the rated flow */
        c = um_muldiv(dg.sx, (uint16_t)(k > 2000u ? 2000u : k), 256u);
        c = dg.sy > c ? (dg.sy - c) / DIAG_LEARN_N : 0;                 /* the check valves */
        if (k >= 100u && k <= 1000u && c <= 150u) {
            dg.kp_kpa = (uint16_t)k;
            dg.pc_kpa = (uint16_t)c;
            dg.learnt = 2;
            dg.session = 0;
            dg.ln = 0;
            return;
        }
    }
    c = (uint32_t)DIAG_P_CHECK_KPA * DIAG_LEARN_N;
    if (dg.sy > c && dg.sx > 0) {
        k = um_muldiv(dg.sy - c, 256u, dg.sx);
        if (k > 1000u)
            k = 1000u;
        dg.kp_kpa = (uint16_t)k < 100u ? 100u : (uint16_t)k;    /* (k <= 1000: 16 bits) */
        dg.pc_kpa = DIAG_P_CHECK_KPA;
        dg.xm = (uint16_t)(dg.sx / DIAG_LEARN_N);
        dg.learnt = 1;
        dg.session = 0;
        dg.ln = 0;
        return;
    }
    /* (no pressure above the check valves in the samples: the calibration goes on) */
    dg.sx >>= 1;
    dg.sy >>= 1;
    dg.sxx >>= 1;
    dg.sxy >>= 1;
    dg.ln = DIAG_LEARN_N / 2;
}

/* One clean period (steady flow on target, no flow alarm): every DIAG_LEARN_EVERY a sample;
 * 1 when DIAG_LEARN_N are summed (the caller fits them). */
static uint8_t learn(uint16_t r, uint16_t p) __reentrant
{
    if (!dg.session || ++dg.ldiv < DIAG_LEARN_EVERY)
        return 0;
    dg.ldiv = 0;
    if (r == 0xFFFFu)
        return 0;
    if (p > 511u)
        p = 511u;
    dg.sx += r;
    dg.sy += p;
    dg.sxx += UMUL(r, r);
    dg.sxy += UMUL(r, p);
    return ++dg.ln >= DIAG_LEARN_N;
}

void diag_set_nozzles(uint8_t open_nozzles) __reentrant
{
    if (open_nozzles == dg.nozzles && dg.gen == param_generation)
        return;
    dg.nozzles = open_nozzles;
    dg.gen = param_generation;
    dg.nq = UMUL(open_nozzles, param_v[P_NOZZLE_Q3]);
    /* q = n Q3 sqrt(dp / kp): knoz = 256 n Q3 / sqrt(kp), 65536 / (256 sqrt(kp)) from the root
     * of kp << 16 (a divide, only when the nozzles or the model change) */
    dg.knoz = um_muldiv(dg.nq, 65535u, um_sqrt32((uint32_t)dg.kp_kpa << 16));
}

int16_t diag_nozzle_flow_x100(uint16_t pressure_kpa, uint8_t open_nozzles) __reentrant
{
    uint32_t q;
    diag_set_nozzles(open_nozzles);
    if (pressure_kpa <= dg.pc_kpa)
        return 0;
    /* dp = P - P_check: sqrt(dp << 16) = 256 sqrt(dp) */
    q = um_mul32x16_shr16(dg.knoz, um_sqrt32((uint32_t)(uint16_t)(pressure_kpa - dg.pc_kpa) << 16));
    return q > 32767u ? 32767 : (int16_t)q;
}

uint16_t diag_nozzle_pressure_kpa(int16_t flow_x100, uint8_t open_nozzles) __reentrant
{
    uint32_t r, p;
    diag_set_nozzles(open_nozzles);
    if (dg.nq == 0 || flow_x100 <= 0)
        return flow_x100 > 0 ? 0xFFFFu : 0;
    r = um_muldiv((uint32_t)flow_x100, 4096u, dg.nq);      /* Q12: q / (n Q3) */
    if (r > 65535u)
        return 0xFFFFu;
    r = UMUL(r, r) >> 12;                                   /* Q12 (r <= 65535) */
    p = dg.pc_kpa + ((r * dg.kp_kpa + 2048u) >> 12);
    return p > 65535u ? 0xFFFFu : (uint16_t)p;
}

void diag_internal_fault(void)
{
    dg.alarms |= 1u << AL_INTERNAL;
}

/* the periods each timed rule's cause must last to raise its alarm (rule(): AL_OFFRATE's rule
 * only clears it, diag_offrate counts P_OFFRATE_S to raise it; AL_INTERNAL has no rule) */
static const __code uint8_t need_periods[AL_COUNT] = {
    DIAG_TANK_PERIODS, DIAG_TANK_PERIODS, DIAG_PDEV_PERIODS, DIAG_PDEV_PERIODS,
    DIAG_METER_PERIODS, 1, 1, 1, DIAG_OVERP_PERIODS, 1, 1, 1, 0,
    DIAG_BAL_PERIODS, 1, DIAG_MIN_FLOW_PERIODS
};

/* One timed rule: `set` for need_periods[bit] periods raises the alarm, `clr` for
 * DIAG_CLEAR_PERIODS clears it; neither (the rule cannot be judged now) holds the state. (The
 * periods from a table, not an argument: a push less at each of the thirteen calls.) */
static void rule(uint8_t bit, uint8_t set, uint8_t clr) __reentrant
{
    uint16_t m = 1u << bit;
    uint8_t active = (dg.alarms & m) != 0;
    __xdata uint8_t *cnt = &dg.cnt[bit];        /* (its address once) */
    if (!active ? set : clr) {
        if (*cnt < 255)
            (*cnt)++;
        if (*cnt >= (active ? DIAG_CLEAR_PERIODS : need_periods[bit])) {
            dg.alarms ^= m;
            *cnt = 0;
        }
    } else {
        *cnt = 0;
    }
}

/* Tank and pump, the sensors (debounced by analog.c; the pressure's zero by diag_zero),
 * over-pressure with 5 % hysteresis: while `p_watch` (spraying or the bypass parked open; at
 * power-up the pump may push against a bypass left closed until the parking opens it: the
 * relief valve's job, not a fault). */
static void diag_supply(void) __reentrant
{
    uint16_t tmin = param_v[P_TANK_MIN];
    uint16_t tank = diag_in->tank_l;
    uint16_t p = diag_in->in.pressure_kpa;
    uint8_t refill = diag_lsens && tank >= tmin + (param_v[P_TANK_L] >> 6) + 1u;
    uint32_t x = UMUL(tank, 100u);
    uint8_t dry = diag_lsens && x <= param_v[P_TANK_L];  /* (the 32-bit compare once) */
    rule(AL_TANK_LOW, diag_lsens && tank < tmin, refill);
    uint8_t line = diag_dry_line(), zero = diag_zero();
    rule(AL_PUMP_DRY, dry || line, !line && !dry && (refill || !diag_lsens));
    rule(AL_PSENS, !diag_psens || zero, diag_psens && !zero);
    rule(AL_LSENS, !diag_lsens, diag_lsens);
    x = UMUL(param_v[P_P_MAX], 19u);
    rule(AL_OVERPRESSURE, p_watch_now && diag_psens && p > param_v[P_P_MAX], !diag_psens || UMUL(p, 20u) < x);
}

/* The nozzle model against the meter. Flow meter lost: its pulses stopped while the model says
 * liquid flows, at working speed and at least P start (the pressure the operator says opens the
 * check valves: below it a silent meter may be a boom whose check valves shut, before the model
 * has learnt where they open; at a headland stop the meter falls silent below its range while
 * the line still holds the check valves' pressure); a live meter that reads low against
 * the pressure is a clog (or a wrong nozzle setting), never this. Leak and clog: the pressure
 * against what the model learnt from this sprayer needs for the metered flow, at working speed
 * (a headland's low pressures are where a model is least sure); clean spraying teaches it. */
static void diag_model(void) __reentrant
{
    uint16_t p = diag_in->in.pressure_kpa;
    int16_t meter = flow_lpm_x100();
    int16_t qp = diag_nozzle_flow_x100(p, dg.nozzles);
    int16_t target = diag_in->in.target_lpm_x100;
    uint8_t judge = diag_settled && diag_psens, g;
    uint16_t pexp, x, d;
    uint32_t a, lo, hi;
    dg.meter_suspect = judge && diag_working && qp >= DIAG_MODEL_MIN_X100 && p >= param_v[P_P_MIN]
                       && flow_quiet_periods() >= DIAG_METER_QUIET;
    rule(AL_METER_LOST, dg.meter_suspect, diag_metering && meter > 0);
    judge = judge && diag_working && !(dg.alarms & (1u << AL_METER_LOST)) && meter >= DIAG_MODEL_MIN_X100 && dg.nq;
    /* nor while the target moves by more than 1/2^DIAG_MOVE_SHIFT a period: the meter's rotor
     * lags the flow that the pressure follows at once, and through a slow-down the metered flow
     * reads high for the pressure (a false leak) */
    x = (uint16_t)(target >> DIAG_MOVE_SHIFT);
    if ((uint16_t)(target - dg.t1 + x) > (uint16_t)(x << 1))
        judge = 0;                  /* (abs(target - dg.t1) > x, one compare) */
    dg.t1 = target;
    pexp = diag_nozzle_pressure_kpa(meter, dg.nozzles);
    g = judge && diag_metering && !(dg.alarms & ((1u << AL_LEAK) | (1u << AL_CLOG)))
        && target > 0 && UMUL(meter > target ? meter - target : target - meter, 20u) <= (uint16_t)target;
    x = judge ? x_of(meter) : 0xFFFFu;
    if (g)
        learn(x, p);                /* (the fit is diag_step's: a shorter call chain) */
    judge = judge && pexp != 0xFFFFu;
    /* near the learnt model (learnt over the range, or near the flow it was learnt at: x within
     * 7/8 .. 8/7 of xm) the pressure above the check valves must be within P_PDEV / 2 (P_PDEV
     * below the meter's range, x_of); far above a model learnt at one flow nothing is judged; far
     * below it, below the meter's range on it (x_of's 0xFFFF), or not learnt yet, only a gross
     * deviation counts. (A model through one flow with the check valves' told 0.3 bar is wrong
     * by (pc - 0.3 bar)(1 - x / xm) elsewhere: with check valves at 1.0 bar, 0.18 bar at 3/4 of
     * xm, a false CLOG at 1 bar after a slow-down from 5.1 to 4.1 km/h.) Gross:
     * P_PDEV of it and DIAG_PDEV_FAR_KPA, more than a wrong check valve or a worn nozzle can
     * make. Either way a leak is a below lo, a clog a above hi. */
    g = dg.learnt == 2;
    if (dg.learnt == 1 && x != 0xFFFFu) {
        lo = UMUL(dg.xm, 7u);
        hi = UMUL(x, 7u);
        if (hi > UMUL(dg.xm, 8u))
            judge = 0;              /* a model learnt at one flow, carried far above it with the
                                     * check valves' told pressure, is wrong by more than a fault
                                     * (below it, by less than that pressure's error) */
        g = UMUL(x, 8u) >= lo;
    }
    if (g) {
        judge = judge && pexp >= dg.pc_kpa + DIAG_PDEV_MIN_KPA;
        a = UMUL(p > dg.pc_kpa ? p - dg.pc_kpa : 0, 100u);
        d = pexp - dg.pc_kpa;
        x = dg.band;                /* (P_PDEV <= 90) */
        lo = UMUL(d, 100u - x);
        hi = UMUL(d, 100u + x);
    } else {
        hi = (UMUL(pexp, param_v[P_PDEV]) + 50u) / 100u;
        if (hi < DIAG_PDEV_FAR_KPA)
            hi = DIAG_PDEV_FAR_KPA;
        a = p;
        lo = pexp > hi ? pexp - hi : 0;     /* p + dev < pexp */
        hi += pexp;                         /* p > pexp + dev */
    }
    g = a < lo;                     /* (each 32-bit compare once: set when it holds, else clear) */
    rule(AL_LEAK, judge && g, judge && !g);
    g = a > hi;
    rule(AL_CLOG, judge && g, judge && !g);
}

/* Off-rate: |q - q1| > P_OFFRATE % of q1 for P_OFFRATE_S with the boom settled, at working
 * speed (below it the minimum-flow rule sets the target, and a coupled pump slowing to a
 * headland stop cannot give it); in manual mode at any speed and after DIAG_MANUAL_PERIODS, a
 * warning there (app.c: the flow stays where the operator set it as the speed moves). The valve
 * at an end stop (a pump too small for the rate, a seized valve) is this
 * rule's too: the rate off target is what the operator must hear, whatever holds it there. */
static void diag_offrate(void) __reentrant
{
    int16_t target = diag_in->in.target_lpm_x100;
    int16_t qp = diag_in->in.flow_lpm_x100 - target;
    uint8_t off = diag_settled && target > 0 && (diag_in->manual || diag_working)
                  && UMUL(qp < 0 ? -qp : qp, 100u) > UMUL(param_v[P_OFFRATE], target);
    if (dg.alarms & (1u << AL_OFFRATE))
        rule(AL_OFFRATE, 0, !off);
    else if (!off)
        dg.offrate_cnt = 0;
    else if (++dg.offrate_cnt >= (diag_in->manual ? DIAG_MANUAL_PERIODS
                                  : (uint16_t)((uint8_t)param_v[P_OFFRATE_S] * (uint8_t)10u))) {  /* (<= 60 s: MUL AB) */
        dg.alarms |= 1u << AL_OFFRATE;
        dg.offrate_cnt = 0;
    }
}

/* Speed sensor lost: pulses stopped for 2 s after working speed (a tractor that slows down
 * keeps making pulses; one that stops dead from working speed inside one pulse distance is the
 * false alarm this rule accepts), or the pump says the wheels turn (diag_wheel.c). Minimum flow
 * (diag_wheel.c). */
static void diag_speed(void) __reentrant
{
    uint8_t g = target_speed_given(), pump = diag_pump();
    uint16_t x = speed_quiet_periods();
    uint8_t stopped = x >= DIAG_SPEED_PERIODS && target_working_speed(speed_at_last_pulse_x100());
    /* ... or the frames in use stopped (diag_wheel.h); the GPS's speed in use clears it unless
     * the wheel's verdict (stopped, or the pump's) holds */
    rule(AL_SPEED_LOST, DIAG_FRAMES(DIAG_FRAMES_LOST) || (!g && (pump || stopped)),
         !DIAG_FRAMES(DIAG_FRAMES_LOST) && (g || x < DIAG_SPEED_PERIODS / 2u
                                            || (DIAG_FRAMES(DIAG_FRAMES_GPS) && !pump && !stopped)));
    x = diag_in->in.speed_kmh_x100;
    g = diag_in->spraying && !diag_in->manual && x && UMUL(x, 11u) < UMUL(param_v[P_MINF_SPEED], 100u);
    rule(AL_MIN_FLOW, g, !g);
}

uint16_t diag_step(const __xdata app_status_t *in, uint8_t settled, uint8_t p_watch) __reentrant
{
    uint8_t g;
    uint16_t n, x;
    if (dg.q3 != param_v[P_NOZZLE_Q3]) {
        dg.q3 = param_v[P_NOZZLE_Q3];
        diag_nozzle_relearn();      /* other nozzles told: the model is learnt for them */
    }
    diag_period(in, settled);
    p_watch_now = p_watch;
    diag_supply();
    diag_model();
    g = diag_balance();
    if (g == DIAG_BAL_ANEW)
        dg.alarms &= ~(1u << AL_METER_CAL);
    rule(AL_METER_CAL, g == DIAG_BAL_OFF, g == DIAG_BAL_ON);
    /* the held model against the catalog (Q3 at 3 bar above the check valves, the square-root
     * law): nozzles that pass over 10 % more are worn, a notice; not while the tank balance
     * says the meter, by which the model was learnt, is off */
    g = dg.learnt && dg.kp_kpa < DIAG_WEAR_KP_KPA && !(dg.alarms & (1u << AL_METER_CAL));
    rule(AL_NOZZLE_WEAR, g, !g);
    if (dg.ln >= DIAG_LEARN_N) {    /* the samples are in: the nozzle model */
        learn_fit();
        dg.gen = (uint8_t)(param_generation - 1u);
        fitted = 1;                 /* its constant: diag_after_fit */
    }
    diag_speed();
    diag_offrate();
    /* pulse noise */
    x = flow_glitches();            /* (each count read once: the steps before set them) */
    g = x != dg.meter_glitches;
    dg.meter_glitches = x;
    /* the meter's: a leaky score of pulse glitches, +20 a glitch, -1 a period; above 60 the
     * alarm is raised, a period that began at 0 clears it (as before, when a function updated
     * the score inside rule()'s arguments: SDCC and gcc both read the clear's before the call) */
    n = dg.meter_noise == 0;
    if (g)
        dg.meter_noise = (uint8_t)(dg.meter_noise > 235 ? 255 : dg.meter_noise + 20);
    else if (dg.meter_noise)
        dg.meter_noise--;
    rule(AL_METER_NOISE, dg.meter_noise > 60, (uint8_t)n);
    /* the wheel's: +DIAG_WHEEL_GLITCH a rejected pulse, -1 a good one, so the score climbs only
     * while more than 1 pulse in DIAG_WHEEL_GLITCH + 1 is rejected (a bounce now and then is
     * rejected and forgotten) */
    n = speed_glitches();
    x = (uint16_t)(n - dg.wheel_glitches);
    dg.wheel_glitches = n;
    x = (x > 21u ? 255u : x * DIAG_WHEEL_GLITCH) + dg.wheel_noise;
    n = (uint16_t)((uint16_t)speed_pulses() - dg.wheel_pulses);
    dg.wheel_pulses += n;           /* (speed_pulses()'s low 16 bits) */
    x = x > n ? x - n : 0;
    dg.wheel_noise = (uint8_t)(x > 255u ? 255u : x);
    /* ... or a rise a tractor cannot make (speed.h SPEED_JUMP_PERIODS), held until a standstill;
     * or, Speed src both, the wheel off the GPS (diag_wheel.h) */
    rule(AL_WHEEL_NOISE, dg.wheel_noise > 60 || speed_jumped() || DIAG_FRAMES(DIAG_FRAMES_SPEED_OFF),
         dg.wheel_noise == 0 && !speed_jumped() && !DIAG_FRAMES(DIAG_FRAMES_SPEED_OFF));
    return dg.alarms;
}

/* The nozzle model's constant for the nozzles open after a fit: in a pass of its own (app.c),
 * else by the next diag_set_nozzles (the same value). Returns 1 when it derived it. */
uint8_t diag_after_fit(void)
{
    if (!fitted)
        return 0;
    fitted = 0;
    diag_set_nozzles(dg.nozzles);
    return 1;
}

uint16_t diag_alarms(void)
{
    return dg.alarms;
}

uint8_t diag_meter_suspect(void)
{
    return dg.meter_suspect;
}

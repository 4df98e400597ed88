/* plant.c: the sprayer model of docs/SCENARIOS.md: one implicit step of the line pressure a tick, sensors with exact edge times (the pulse trains in plant_pulses.c, the valve's motor in plant_valve.c). */
#include <math.h>
#include <string.h>
#include "plant.h"
#include "plant_int.h"

#define TWO_PI 6.283185307179586

void plant_params_default(plant_params_t *p)
{
    memset(p, 0, sizeof *p);
#define PLANT_KEY_DEF(key, def, lo, hi, isint) p->key = (def);
    PLANT_KEYS(PLANT_KEY_DEF)
#undef PLANT_KEY_DEF
    p->nozzles = 36;
    p->spacing_m = 0.5;
}

void plant_init(plant_t *pl, const plant_params_t *p, uint64_t seed)
{
    memset(pl, 0, sizeof *pl);
    pl->p = *p;
    /* q = K_n sqrt(P - P_check) with 1.18 L/min at 3 bar: K_n = 1.18 / sqrt(3) (check valve
     * cracking pressure is part of the 3 bar rating: TeeJet rates the tip, we add the check valve) */
    pl->kn = p->nozzle_lpm_at_3bar / sqrt(3.0) * (1.0 + p->nozzle_wear_pct / 100.0);
    pl->k_line = p->line_loss_bar_at_50lpm / 2500.0;
    pl->m_per_pulse = TWO_PI * p->wheel_radius_m / p->wheel_elements;
    pl->pto_rpm = p->pto_rpm;
    pl->theta = p->valve_start_pos;
    pl->motor = p->valve_start_pos;         /* the motor sits in the middle of the backlash gap */
    pl->cv = plant_cv(pl, pl->theta);
    pl->cv_theta = pl->theta;
    pl->open_nozzles = p->nozzles;
    pl->tank_v = p->tank_start_l;
    pl->bounce_pct = p->speed_bounce_pct;
    pl->wheel_mult = 1.0;
    pl->boom_m = -1;
    rng_seed(&pl->rng, seed);
    pl->pulse_phase = TWO_PI * rng_uniform(&pl->rng);
    pl->pulse_c = cos(pl->pulse_phase);
    pl->pulse_s = sin(pl->pulse_phase);
    pl->pulse_a = 0.0;                      /* no turn yet: cos 0, sin 0 */
    pl->pulse_ca = 1.0;
    pl->pulse_sa = 0.0;
    plant_teeth_init(&pl->meter_teeth, (int)p->meter_blades, p->meter_blade_jitter_pct, seed, 0x6d65746572ull,
               rng_uniform(&pl->rng));
    plant_teeth_init(&pl->wheel_teeth, (int)p->wheel_elements, p->wheel_spacing_jitter_pct, seed, 0x776865656cull,
               rng_uniform(&pl->rng));
}

/* exp(-dt / tau) and log(r) of the last arguments: the tick and the constants rarely change. */
double plant_decay_of(plant_decay_t *c, double dt, double tau)
{
    if (dt != c->dt || tau != c->tau) {
        c->dt = dt;
        c->tau = tau;
        c->k = exp(-dt / tau);
    }
    return c->k;
}

static double log_of(double r)
{
    static double last_r = 1.0, last_log = 0.0;
    if (r != last_r) {
        last_log = log(r);
        last_r = r;
    }
    return last_log;
}

/* Equal percentage with rangeability R, shifted so that Cv(0) = 0 and Cv(1) = valve_cv_open. */
double plant_cv(const plant_t *pl, double theta)
{
    double r = pl->p.valve_rangeability;
    if (theta <= 0.0)
        return 0.0;
    if (theta > 1.0)
        theta = 1.0;
    return pl->p.valve_cv_open * (exp((theta - 1.0) * log_of(r)) - 1.0 / r) / (1.0 - 1.0 / r);
}

/* Nozzles that pass liquid now: open sections less the clogged ones, none with the boom shut. */
static int flowing_nozzles(const plant_t *pl)
{
    int m = pl->open_nozzles - pl->clogged;
    return pl->spray_on && m > 0 ? m : 0;
}

/* Boom coefficient A with the line loss folded in: Q = m K sqrt(P - k Q^2 - Pc) solves to
 * Q = A sqrt(P - Pc), A = m K / sqrt(1 + (m K)^2 k). */
static double boom_coef(const plant_t *pl, int m)
{
    double a = m * pl->kn;
    return a / sqrt(1.0 + a * a * pl->k_line);
}

double plant_boom_flow(const plant_t *pl, double p_bar)
{
    double a = boom_coef(pl, pl->open_nozzles - pl->clogged > 0 ? pl->open_nozzles - pl->clogged : 0);
    return p_bar > pl->p.check_valve_bar ? a * sqrt(p_bar - pl->p.check_valve_bar) : 0.0;
}

/* The turbine's K curve: the nominal K in its range, falling off below it (docs/SCENARIOS.md):
 * -3 % at 7.5 L/min, -15 % at 3 L/min, -40 % at 1.5 L/min, nothing below 1.5; linear between
 * the points, the full K from 15 L/min up. */
double plant_meter_k(const plant_t *pl, double q)
{
    static const double qs[] = {1.5, 3.0, 7.5, 15.0};
    static const double fs[] = {0.60, 0.85, 0.97, 1.0};
    double f = 1.0;
    int i;
    if (q >= qs[3])
        return pl->p.meter_k_ppl;
    if (q < qs[0])
        return 0.0;
    for (i = 0; i < 3; i++)
        if (q < qs[i + 1]) {
            f = fs[i] + (fs[i + 1] - fs[i]) * (q - qs[i]) / (qs[i + 1] - qs[i]);
            break;
        }
    return pl->p.meter_k_ppl * f;
}

double plant_pump_flow(const plant_t *pl, double p_bar)
{
    double slip = 1.0 - pl->p.pump_slip_per_bar * p_bar;
    return pl->p.pump_lpm_at_540 * pl->pto_now_rpm / 540.0 * (slip > 0.0 ? slip : 0.0);
}

double plant_speed_kmh(const plant_t *pl)
{
    return pl->v_mps * 3.6;
}

/* One implicit Euler step of C dP/dt = Qin(P) - Qout(P) (flows in L/min, C in L/bar):
 * f(P) = G (P - P0) - Qp0 (1 - ks P)+ + kr (P - Ps)+ + Cb sqrt(P) + A sqrt(P - Pc)+ + kl sqrt(P)
 * is strictly increasing with f(0) <= 0, so it has one root in [0, P0 + Qp0/G]: safeguarded
 * Newton (bisection whenever a step leaves the bracket). */
typedef struct {
    double g, p0, qp0, ks, kr, ps, cb, a, pc, kl;
    double hi;                      /* the bracket's top, P0 + Qp0 / G */
    double guess;                   /* where Newton starts (inside the bracket or not) */
} line_eq_t;

/* Where f was last evaluated: p, f'(p), the square roots sqrt(p), sqrt(p - Pc) (0 where their
 * term is off) and their slopes 0.5 / root. */
typedef struct {
    double p, d, s, sc, hs, hc;
} line_pt_t;

static double line_f(const line_eq_t *e, double p, line_pt_t *at)
{
    double f = e->g * (p - e->p0), d = e->g;
    double slip = 1.0 - e->ks * p;
    at->p = p;
    at->s = at->sc = at->hs = at->hc = 0.0;
    if (slip > 0.0) {
        f -= e->qp0 * slip;
        d += e->qp0 * e->ks;
    }
    if (p > e->ps) {
        f += e->kr * (p - e->ps);
        d += e->kr;
    }
    /* a root's slope 0.5 / sqrt(x) as sqrt(x) * (0.5 / x): the division runs beside the root,
     * not after it */
    if (p > 0.0) {
        at->s = sqrt(p);
        at->hs = at->s * (0.5 / p);
        f += (e->cb + e->kl) * at->s;
        d += (e->cb + e->kl) * at->hs;
    }
    if (p > e->pc && e->a > 0.0) {
        at->sc = sqrt(p - e->pc);
        at->hc = at->sc * (0.5 / (p - e->pc));
        f += e->a * at->sc;
        d += e->a * at->hc;
    }
    at->d = d;
    return f;
}

/* The root; *at gets the point of the last evaluation (the next tick's first step starts from it). */
static double line_solve(const line_eq_t *e, line_pt_t *at)
{
    double lo = 0.0, hi = e->hi;
    double x = e->guess, f;
    int i;
    if (x < lo || x > hi)
        x = 0.5 * (lo + hi);
    for (i = 0; i < 60; i++) {
        double xn;
        f = line_f(e, x, at);
        if (f > 0.0)
            hi = x;
        else
            lo = x;
        xn = x - f / at->d;
        /* converged (tested before the bracket: xn may sit on lo): the compliance term makes
         * f' at least g = 60 C / dt, so f''/2f' is small and a step this short leaves xn far
         * closer to the root than the pressure's own 1e-9 bar */
        if (fabs(xn - x) < 1e-6)
            return xn < lo ? lo : xn > hi ? hi : xn;
        if (!(xn > lo && xn < hi))
            xn = 0.5 * (lo + hi);
        x = xn;
    }
    return x < 0.0 ? 0.0 : x;
}

/* counts rounded half up and clipped to 0..1023 (floor by truncation above 1) */
static uint16_t adc_round(double c)
{
    c += 0.5;
    return c < 1.0 ? 0 : c >= 1023.0 ? 1023 : (uint16_t)c;
}

static uint16_t adc_of_ma(plant_t *pl, double ma, double noise_lsb)
{
    double c = ma * PLANT_ADC_PER_MA;
    if (noise_lsb > 0.0)
        c += noise_lsb * rng_normal(&pl->rng);
    return adc_round(c);
}

/* The pulsation's phase as a unit vector turned by angle a each tick (a recurrence instead of a
 * sin a tick): cos a and sin a from their series (for a up to PLANT_SERIES_RAD: the terms left
 * out are below 1e-12), again only when a changes; the length is pulled back to 1 each turn so
 * that rounding cannot make it drift. Returns the pulsation the tick's pump flow takes: its value
 * at the tick's end, or over a longer turn (a fast mode's long tick) its mean over the tick. */
static double pulse_turn(plant_t *pl, double a)
{
    double c, s, k, ca = pl->pulse_ca, sa = pl->pulse_sa;
    if (a > PLANT_SERIES_RAD) {
        double c0 = pl->pulse_c, da = a - pl->pulse_a;
        if (da != 0.0) {
            if (fabs(da) < 1e-3) {
                /* a long turn that changed a little (the speed moved): turn cos a, sin a by the
                 * change, from its series (the terms left out are below 1e-13 of it) */
                double cd = 1.0 - 0.5 * da * da, sd = da * (1.0 - da * da * (1.0 / 6));
                ca = pl->pulse_ca * cd - pl->pulse_sa * sd;
                sa = pl->pulse_sa * cd + pl->pulse_ca * sd;
            } else {
                ca = cos(a);
                sa = sin(a);
            }
            pl->pulse_a = a;
            pl->pulse_ca = ca;
            pl->pulse_sa = sa;
        }
        c = c0 * ca - pl->pulse_s * sa;
        s = pl->pulse_s * ca + c0 * sa;
        k = 1.5 - 0.5 * (c * c + s * s);
        pl->pulse_c = c * k;
        pl->pulse_s = s * k;
        return (c0 - c) / a;        /* the mean of sin over the turn */
    }
    if (a != pl->pulse_a) {
        /* the coefficients 1/n! with their signs, grouped in powers of a^2 (Estrin) so that
         * the terms are formed side by side rather than one after the other */
        double a2 = a * a, a4 = a2 * a2;
        ca = (1.0 - 0.5 * a2) + a4 * ((1.0 / 24 - a2 * (1.0 / 720)) + a4 * (1.0 / 40320 - a2 * (1.0 / 3628800)));
        sa = a * ((1.0 - a2 * (1.0 / 6)) + a4 * ((1.0 / 120 - a2 * (1.0 / 5040)) +
             a4 * (1.0 / 362880 - a2 * (1.0 / 39916800))));
        pl->pulse_a = a;
        pl->pulse_ca = ca;
        pl->pulse_sa = sa;
    }
    c = pl->pulse_c * ca - pl->pulse_s * sa;
    s = pl->pulse_s * ca + pl->pulse_c * sa;
    k = 1.5 - 0.5 * (c * c + s * s);
    pl->pulse_c = c * k;
    pl->pulse_s = s * k;
    return s;                       /* the tick's pulsation (before the length's correction, which
                                       is for the turns to come) */
}

static void step_tractor(plant_t *pl, double dt, double inv_lag)
{
    const plant_params_t *p = &pl->p;
    double acc = (pl->v_cmd_kmh * (1.0 / 3.6) - pl->v_mps) * inv_lag;
    if (acc > p->tractor_accel_max)
        acc = p->tractor_accel_max;
    if (acc < -p->tractor_accel_max)
        acc = -p->tractor_accel_max;
    pl->v_mps += acc * dt;
    if (pl->v_mps < 0.0)
        pl->v_mps = 0.0;
    pl->dist_m += pl->v_mps * dt;
}

static void meter_step(plant_t *pl, double q_lpm, uint64_t t0, uint32_t dt_ns, double dt, double dt_min)
{
    double lag = pl->p.meter_lag_s;
    pl->q_rotor = lag > 0.0 ? pl->q_rotor + (q_lpm - pl->q_rotor) * (1.0 - plant_decay_of(&pl->rotor_decay, dt, lag)) : q_lpm;
    if (!pl->meter_fail) {
        double n = plant_meter_k(pl, pl->q_rotor) * pl->q_rotor * dt_min;
        if (n > 0.0)
            pl->flow_pulses += plant_train_advance(pl, &pl->meter_teeth, n, t0, dt_ns, pl->flow_edge, 0.0);
    }
}

static void wheel_step(plant_t *pl, double v_mps, uint64_t t0, uint32_t dt_ns, double pulses_per_mps)
{
    if (!pl->speed_fail && v_mps > 0.0) {
        double n = v_mps * pulses_per_mps * pl->wheel_mult;
        if (n > 0.0)
            pl->wheel_pulses += plant_train_advance(pl, &pl->wheel_teeth, n, t0, dt_ns, pl->wheel_edge, pl->bounce_pct);
    }
}

void plant_meter_step(plant_t *pl, double q_lpm, uint64_t t0, uint32_t dt_ns)
{
    double dt = dt_ns * 1e-9;
    meter_step(pl, q_lpm, t0, dt_ns, dt, dt / 60.0);
}

void plant_wheel_step(plant_t *pl, double v_mps, uint64_t t0, uint32_t dt_ns)
{
    wheel_step(pl, v_mps, t0, dt_ns, (1.0 + pl->p.wheel_slip_pct / 100.0) * (dt_ns * 1e-9) / pl->m_per_pulse);
}

/* The tick's constants, computed again when the tick or a parameter they come from changes. */
static const plant_tick_t *tick_of(plant_t *pl, uint32_t dt_ns)
{
    const plant_params_t *p = &pl->p;
    plant_tick_t *k = &pl->tick;
    if (dt_ns != k->dt_ns || p->wheel_slip_pct != k->slip_pct || p->v_rated_kmh != k->v_rated_kmh ||
        p->pump_lpm_at_540 != k->pump_lpm || p->line_compliance_l_per_bar != k->compliance ||
        p->tank_l != k->tank_l || p->tractor_lag_s != k->lag_s || pl->m_per_pulse != k->m_per_pulse) {
        double slip = 1.0 + p->wheel_slip_pct / 100.0;
        k->dt_ns = dt_ns;
        k->slip_pct = p->wheel_slip_pct;
        k->v_rated_kmh = p->v_rated_kmh;
        k->pump_lpm = p->pump_lpm_at_540;
        k->compliance = p->line_compliance_l_per_bar;
        k->tank_l = p->tank_l;
        k->lag_s = p->tractor_lag_s;
        k->m_per_pulse = pl->m_per_pulse;
        k->dt = dt_ns * 1e-9;
        k->g = p->line_compliance_l_per_bar * 60.0 / k->dt;
        k->inv_g = 1.0 / k->g;
        k->pto_per_mps = 3.6 * slip / p->v_rated_kmh;
        k->turn_per_rpm = TWO_PI * 3.0 / 60.0 * k->dt;
        k->pump_per_rpm = p->pump_lpm_at_540 / 540.0;
        k->dt_min = k->dt / 60.0;
        k->level_ma_per_l = 16.0 / p->tank_l;
        k->inv_lag = 1.0 / p->tractor_lag_s;
        k->wheel_per_mps = slip * k->dt / pl->m_per_pulse;
    }
    return k;
}

/* The flows at the line's new pressure. The square roots there: to first order from the last
 * evaluation when Newton's last step there was short against the pressure (the second-order
 * term is then below (dp/p)^2/8 of the root: rounding), else anew; they also start the next
 * tick's guess, with 1 / f'. */
static void line_flows(plant_t *pl, const line_eq_t *e, const line_pt_t *at)
{
    double P = pl->p_bar, dp = P - at->p, slip = 1.0 - e->ks * P, s, sc;
    s = at->s > 0.0 && fabs(dp) < 1e-7 * at->p ? at->s + dp * at->hs : sqrt(P);
    sc = P > e->pc ? (at->sc > 0.0 && fabs(dp) < 1e-7 * (at->p - e->pc) ? at->sc + dp * at->hc : sqrt(P - e->pc)) : 0.0;
    pl->root_p = P;
    pl->root_s = s;
    pl->root_sc = sc;
    pl->root_d = 1.0 / at->d;
    pl->q_pump = e->qp0 * (slip > 0.0 ? slip : 0.0);
    pl->q_relief = P > e->ps ? e->kr * (P - e->ps) : 0.0;
    pl->q_bypass = e->cb * s;
    pl->q_leak = e->kl * s;
    pl->q_boom = e->a * sc;
    pl->q_meter = pl->q_boom + pl->q_leak;
}

/* The 4-20 mA loops of the pressure and level sensors, into the 10-bit ADC. */
static void loops_step(plant_t *pl, const plant_tick_t *k)
{
    double ma, lv;
    pl->psens_offset_bar += pl->psens_drift_bar_per_min * k->dt_min;
    ma = 4.0 + 16.0 * (pl->p_bar + pl->psens_offset_bar) / PLANT_PSENS_BAR;
    ma = ma > PLANT_MA_MAX ? PLANT_MA_MAX : ma < PLANT_MA_MIN ? PLANT_MA_MIN : ma;
    if (pl->psens_open)
        ma = 0.0;
    pl->ma_pressure = ma;
    lv = 4.0 + (pl->tank_v + pl->level_offset_l) * k->level_ma_per_l;
    pl->ma_level = lv > PLANT_MA_MAX ? PLANT_MA_MAX : lv < PLANT_MA_MIN ? PLANT_MA_MIN : lv;
}

void plant_step(plant_t *pl, const plant_in_t *in, uint32_t dt_ns)
{
    const plant_params_t *p = &pl->p;
    const plant_tick_t *k = tick_of(pl, dt_ns);
    double dt = k->dt;
    uint64_t t0 = pl->t_ns;
    double drive = in->drive > 1.0 ? 1.0 : in->drive < -1.0 ? -1.0 : in->drive;
    line_eq_t e;
    line_pt_t at;
    double dry, puls;
    int m;

    pl->spray_on = in->spray_on ? 1 : 0;
    step_tractor(pl, dt, k->inv_lag);
    plant_valve_step(pl, drive, dt);
    if (pl->theta != pl->cv_theta) {
        pl->cv = plant_cv(pl, pl->theta);
        pl->cv_theta = pl->theta;
    }

    /* PTO: coupled (the engine turns the driven wheel, whose speed the sensor reads, and the PTO
     * through fixed gears: n follows the wheel's speed, slip included) or fixed */
    pl->pto_now_rpm = p->pto_coupled >= 0.5 ? pl->pto_rpm * (pl->v_mps * k->pto_per_mps) : pl->pto_rpm;
    /* 3 diaphragms: pulsation at 3 n / 60 Hz, after the air chamber */
    puls = 1.0 + p->pump_pulsation_pct * 0.01 * pulse_turn(pl, pl->pto_now_rpm * k->turn_per_rpm);
    dry = pl->tank_v / PLANT_DRY_L;
    dry = dry > 1.0 ? 1.0 : dry < 0.0 ? 0.0 : dry;

    m = flowing_nozzles(pl);
    e.g = k->g;
    e.p0 = pl->p_bar;
    e.qp0 = k->pump_per_rpm * pl->pto_now_rpm * puls * dry;
    e.hi = e.p0 + e.qp0 * k->inv_g + 1e-12;
    e.ks = p->pump_slip_per_bar;
    e.kr = p->relief_lpm_per_bar;
    e.ps = p->relief_bar;
    e.cb = pl->cv;
    if (m != pl->boom_m || pl->kn != pl->boom_kn || pl->k_line != pl->boom_kline) {
        pl->boom_m = m;                     /* the coefficient a sqrt: only when the boom changes */
        pl->boom_kn = pl->kn;
        pl->boom_kline = pl->k_line;
        pl->boom_a = m > 0 ? boom_coef(pl, m) : 0.0;
    }
    e.a = pl->boom_a;
    e.pc = p->check_valve_bar;
    e.kl = pl->spray_on ? pl->leak_lpm * (1.0 / sqrt(PLANT_LEAK_REF_BAR)) : 0.0;
    /* Newton's first guess: one step from the last tick's pressure with this tick's flows there
     * (from the square roots the last tick left, no new ones) along the last tick's slope;
     * without them the pressure's own trend. A guess only decides how soon Newton converges. */
    if (pl->root_d > 0.0 && pl->root_p == e.p0) {
        /* the flows out first (they are known early), the pump's last: it waits on the pulsation */
        double P = e.p0, slip = 1.0 - e.ks * P, f;
        f = (e.cb + e.kl) * pl->root_s + e.a * pl->root_sc;
        if (P > e.ps)
            f += e.kr * (P - e.ps);
        if (slip > 0.0)
            f -= e.qp0 * slip;
        e.guess = P - f * pl->root_d;
    } else
        e.guess = 2.0 * e.p0 - pl->p_last;
    pl->p_last = e.p0;
    pl->p_bar = line_solve(&e, &at);
    line_flows(pl, &e, &at);
    pl->tank_v -= pl->q_meter * k->dt_min;
    if (pl->tank_v < 0.0)
        pl->tank_v = 0.0;

    pl->t_ns = t0 + dt_ns;

    meter_step(pl, pl->q_meter, t0, dt_ns, dt, k->dt_min);
    wheel_step(pl, pl->v_mps, t0, dt_ns, k->wheel_per_mps);
    loops_step(pl, k);
}

uint16_t plant_adc_ideal(const plant_t *pl, int ch)
{
    return adc_round((ch == 0 ? pl->ma_pressure : pl->ma_level) * PLANT_ADC_PER_MA);
}

uint16_t plant_adc_sample(plant_t *pl, int ch)
{
    if (ch == 0)
        return pl->adc_pressure = adc_of_ma(pl, pl->ma_pressure, pl->p.pressure_noise_lsb);
    return pl->adc_level = adc_of_ma(pl, pl->ma_level, pl->p.level_noise_lsb);
}

double plant_bypass_needed(const plant_t *pl, double q_boom)
{
    const plant_params_t *p = &pl->p;
    double a = plant_boom_flow(pl, p->check_valve_bar + 1.0), P, q_byp, cv, x, r = p->valve_rangeability;
    if (a <= 0.0 || q_boom <= 0.0)
        return NAN;
    P = p->check_valve_bar + (q_boom / a) * (q_boom / a);
    q_byp = plant_pump_flow(pl, P) - q_boom - (P > p->relief_bar ? p->relief_lpm_per_bar * (P - p->relief_bar) : 0.0);
    if (q_byp <= 0.0)
        return 0.0;
    cv = q_byp / sqrt(P);
    if (cv >= p->valve_cv_open)
        return 1.0;
    x = cv / p->valve_cv_open * (1.0 - 1.0 / r) + 1.0 / r;
    return 1.0 + log(x) / log(r);
}

/* helper_ctl_twin.c: double-precision twins of the controllers, the references of tests/test_ctl.c. */
#include <math.h>
#include <string.h>
#include "ctl_twin.h"
#include "ctl_int.h"

double ctltw_pid_du_stroke(double e, double e1, double e2, double kp, double ki, double kd)
{
    return (kp * (e - e1) + ki * e + kd * (e - 2 * e1 + e2)) / CTL_FLOW_SCALE_LPM;
}

double ctltw_drive(double du_stroke, double travel_periods)
{
    return du_stroke * travel_periods;
}

static double ctltw_clamp(double x, double lo, double hi)
{
    return x < lo ? lo : x > hi ? hi : x;
}

/* bilinear blend of a rule table at level coordinates le, lc in [0, 6] */
static double ctltw_blend(int t, double le, double lc)
{
    int i = (int)floor(le), j = (int)floor(lc);
    double fe, fc;
    if (i > 5)
        i = 5;
    if (j > 5)
        j = 5;
    fe = le - i;
    fc = lc - j;
    return fz_tab[t][i][j] * (1 - fe) * (1 - fc) + fz_tab[t][i][j + 1] * (1 - fe) * fc
           + fz_tab[t][i + 1][j] * fe * (1 - fc) + fz_tab[t][i + 1][j + 1] * fe * fc;
}

void ctltw_fuzzy_gains(double e_lpm, double ec_lpm, double k[3])
{
    static const double k0[3] = {1.2, 0.2, 0.8}, q[3] = {0.2, 0.05, 0.2};
    double le = ctltw_clamp(e_lpm / (FZ_E_LEVEL / 100.0), -3, 3) + 3;
    double lc = ctltw_clamp(ec_lpm / (FZ_EC_LEVEL / 100.0), -3, 3) + 3;
    for (int t = 0; t < 3; t++) {
        k[t] = k0[t] + q[t] * ctltw_blend(t, le, lc);
        if (k[t] < 0)
            k[t] = 0;
    }
}

void ctltw_bp_forward(const double w[5][4], const double v[3][5], double target_lpm, double flow_lpm,
                      double o[5], double k[3])
{
    double e = ctltw_clamp(target_lpm - flow_lpm, -15, 15);
    double x[4] = {1.0, ctltw_clamp(target_lpm, 0, 160) / 50.0, ctltw_clamp(flow_lpm, 0, 160) / 50.0, e / 5.0};
    for (int i = 0; i < 5; i++) {
        double a = 0;
        for (int j = 0; j < 4; j++)
            a += w[i][j] * x[j];
        o[i] = tanh(a);
    }
    for (int l = 0; l < 3; l++) {
        double a = 0;
        for (int j = 0; j < 5; j++)
            a += v[l][j] * o[j];
        k[l] = (1 + tanh(a)) / 2;
    }
}

void ctltw_bp_learn(double w[5][4], double v[3][5], const double dw0[5][4], const double dv0[3][5],
                    const double x[4], const double o[5], const double k[3], double n, double n1, double n2,
                    double wmax)
{
    const double eta = 0.2, alpha = 0.05;
    double dn[3] = {n - n1, n, n - 2 * n1 + n2}, delta[3];
    for (int l = 0; l < 3; l++) {
        delta[l] = n * dn[l] * 2 * k[l] * (1 - k[l]);
        for (int i = 0; i < 5; i++)
            v[l][i] = ctltw_clamp(v[l][i] + eta * delta[l] * o[i] + alpha * dv0[l][i], -wmax, wmax);
    }
    for (int i = 0; i < 5; i++) {
        double sigma = 0;
        for (int l = 0; l < 3; l++)
            sigma += delta[l] * v[l][i];    /* the output weights just updated */
        double dh = (1 - o[i] * o[i]) * sigma;
        for (int j = 0; j < 4; j++)
            w[i][j] = ctltw_clamp(w[i][j] + eta * dh * x[j] + alpha * dw0[i][j], -wmax, wmax);
    }
}

/* ---- ffmap --------------------------------------------------------------------------------- */

void ctltw_ffmap_load(ctltw_ffmap_t *tw, const ffmap_state_t *fm, int first, q15_t carry)
{
    tw->e1 = fm->e1 / 100.0;
    tw->e2 = fm->e2 / 100.0;
    tw->err_filt = fm->err_filt / 100.0;
    tw->target_last = fm->target_last / 100.0;
    tw->moved = fm->moved;
    tw->ramp = fm->ramp / 100.0;
    tw->rev_min = fm->rev_min / 32768.0;
    tw->rest = fm->rest;
    tw->dir = fm->dir;
    tw->stall_n = fm->stall_n;
    tw->warm = fm->warm;
    tw->rev_age = fm->rev_age;
    tw->slow_n = fm->slow_n;
    tw->brk_age = fm->brk_age;
    tw->stall_flow = fm->stall_flow / 100.0;
    tw->err_peak = fm->err_peak / 100.0;
    tw->big = fm->big;
    tw->rlim = ffmap_rlim;
    tw->rl1 = ffmap_rl1;
    tw->up = ffmap_up;
    tw->brk_extra = fm->brk_extra / 32768.0;
    tw->gain = fm->gain / 256.0;
    tw->gain_start = fm->gain_start / 256.0;
    tw->carry = carry / 32768.0;
    tw->last = ctl_last / 32768.0;
    tw->lead = fm->lead;
    tw->cap = fm->cap;
    tw->cap_run = fm->cap_run;
    tw->flow_last = fm->flow_last / 100.0;
    tw->hold = fm->hold;
    tw->quiet = fm->quiet;
    tw->lone_n = fm->lone_n;
    tw->lone_flow = fm->lone_flow / 100.0;
    tw->first = first;
}

/* |x - t| within a few LSB of rounding: the firmware may decide the other way */
static int ctltw_near(double x, double t, double lsb)
{
    return fabs(x - t) <= lsb;
}

/* The loop gain at this pressure (ffmap_gain_at_p): cut by sqrt(FFMAP_P_REF / P) above FFMAP_P_REF,
 * with the firmware's integer roundings (the root's floor, the product's). */
static unsigned long ctltw_root_at_p(double p_kpa)
{
    unsigned long p = (unsigned long)p_kpa, x, f;
    if (p <= FFMAP_P_REF)
        return 256;
    x = ((unsigned long)FFMAP_P_REF << 16) / p;
    f = (unsigned long)sqrt((double)x);
    while (f * f > x)
        f--;
    while ((f + 1) * (f + 1) <= x)
        f++;
    return f;
}

/* ... the gain cut by that root f (256: not cut) and times the nozzles' factor q / 4 (the
 * product f q / 4 floored first, as ffmap_gain_at_p takes it) */
static double ctltw_gain_at_root(double g, unsigned long f, int q)
{
    return floor(g * 256 * floor(f * q / 4.0) / 256) / 256;
}

/* the duty cap up by an eighth (ffmap_cap_up) */
static int ctltw_cap_up(int cap)
{
    cap += cap / 8 + 1;
    return cap > 255 ? 255 : cap;
}

ctltw_ffmap_out_t ctltw_ffmap_step(ctltw_ffmap_t *m, const ctltw_ffmap_in_t *in)
{
    ctltw_ffmap_out_t o = {0, 0, 0};
    double q = in->target, e = ctltw_clamp(q - in->flow, -CTLTW_E_MAX, CTLTW_E_MAX);
    double dq, c, du, mv, d, k, db, run = CTLTW_RUN;
    int s, capc, hi_t;
    unsigned long root = ctltw_root_at_p(in->pressure);   /* ffmap_gain_at_p's, once a step */
    if (m->first) {
        m->e1 = m->e2 = m->err_filt = e;
        m->target_last = q;
        m->rest = 0;
        m->stall_n = 0;
        m->warm = 0;
        m->err_peak = 0;
        m->big = 0;
        /* (the firmware compares x100 L/min with half the target rounded down) */
        o.near |= ctltw_near(e, q / 2, 0.02);
        m->lead = e <= q - q / 4;
        m->cap_run = 0;
        m->gain_start = m->gain;
        m->hold = 0;
    }
    /* the nozzles open changed: FFMAP_P_WAIT periods in which the step sees no change of the error */
    if (in->noz_new && !m->first)
        m->hold = FFMAP_P_WAIT;
    if (m->hold) {
        m->hold--;
        m->e1 = m->e2 = e;
    }
    m->quiet = m->last != 0 ? 0 : m->quiet < 255 ? m->quiet + 1 : 255;
    /* deadband on the error filtered over 4 periods */
    dq = q - m->target_last;
    /* the filtered error in the firmware's own integer steps (x100 L/min, the rest integral's
     * input: at a long Valve time its rounding alone is worth more than the tolerance) */
    m->err_filt = (round(m->err_filt * 100) + floor((round(e * 100) - round(m->err_filt * 100) + 2) / 4)) / 100;
    c = fabs(m->err_filt);
    o.near |= ctltw_near(fabs(dq) * CTLTW_FFMAP_MOVE, q, 0.02 * CTLTW_FFMAP_MOVE);
    if (fabs(dq) * CTLTW_FFMAP_MOVE > q)
        m->moved = 1, m->up = dq > 0;
    /* past the target the way it last moved, the valve rests only nearer */
    db = (m->err_filt < 0) == (m->up != 0) ? CTLTW_FFMAP_DB_PAST : CTLTW_FFMAP_DB_IN;
    o.near |= ctltw_near(c, q / (m->rest ? CTLTW_FFMAP_DB_OUT : db), 0.03);
    if (fabs(dq) * CTLTW_FFMAP_MOVE > q || (m->rest && c > q / CTLTW_FFMAP_DB_OUT)) {
        if (m->rest && (m->carry > 0) != (e > 0))
            m->carry = 0;
        m->rest = 0;
    } else if (!m->rest && c <= q / db && q > 0) {
        m->rest = 1;
        m->carry = 0;
        m->stall_n = 0;
    }
    /* stall */
    if (m->stall_n >= 2 * FFMAP_STALL_N) {
        k = m->dir > 0 ? in->flow - m->stall_flow : m->stall_flow - in->flow;
        o.near |= ctltw_near(k, q / (1 << FFMAP_STALL_MOVE), 0.02);
        if (k <= q / (1 << FFMAP_STALL_MOVE) && (m->dir > 0 ? e > 0 : e < 0)) {
            /* a stall begun at a reversal: its slack not taken up, the reversal grows */
            if (m->rev_age < 2 * FFMAP_STALL_N && m->rev_min < FFMAP_REV_MIN / 32768.0)
                m->rev_min += floor(m->rev_min * 32768 / 8) / 32768;
            else if (m->brk_extra < 0)
                m->brk_extra = 0;       /* lone pulses took it under Min duty: back to it */
            else if (m->brk_extra <= (FFMAP_BRK_MAX - FFMAP_BRK_STEP) / 32768.0)
                m->brk_extra += FFMAP_BRK_STEP / 32768.0;
        }
        m->stall_n = 0;
    }
    /* a lone smallest pulse judged FFMAP_LONE_N periods on: a step of the flow its way beyond
     * target >> FFMAP_LONE_SH, after the start, the speed steady, takes the smallest pulse down by
     * FFMAP_BRK_DN, from Min duty or under it, to half Min duty */
    if (m->lone_n && !--m->lone_n) {
        k = m->dir * (in->flow - m->lone_flow);
        o.near |= ctltw_near(k, q / (1 << FFMAP_LONE_SH), 0.02);
        if (k > q / (1 << FFMAP_LONE_SH) && m->brk_extra <= 0 && m->warm >= FFMAP_WARM
            && fabs(m->ramp) <= FFMAP_FF_RAMP / 100.0
            && m->brk_extra - FFMAP_BRK_DN / 32768.0 >= -floor(lround(CTLTW_STICTION * 32768) / 2) / 32768)
            m->brk_extra -= FFMAP_BRK_DN / 32768.0;
    }
    if (m->brk_extra > 0 && ++m->brk_age >= (int)FFMAP_BRK_AGE) {
        m->brk_extra -= FFMAP_BRK_STEP / 32768.0;
        m->brk_age = 0;
    }
    if (fabs(e) > m->err_peak)
        m->err_peak = fabs(e);
    /* the law (the firmware's rest integral works on its own filtered error); no proportional
     * term in the first FFMAP_P_WAIT periods */
    if (m->rest)
        du = CTLTW_FFMAP_REST_KI * m->err_filt;
    else
        du = (m->warm < FFMAP_P_WAIT ? 0 : CTLTW_FFMAP_KP * (e - m->e1)) + CTLTW_FFMAP_KI * e
             + CTLTW_FFMAP_KD * (e - 2 * m->e1 + m->e2);
    /* after a start-up closing, while the valve runs fast: the integral on the flow FFMAP_LEAD
     * periods ahead when it comes toward the target */
    if (!m->rest && m->lead && m->warm < FFMAP_WARM && fabs(m->last) > FFMAP_LEAD_DRIVE / 32768.0) {
        double dy = (q - e) - (m->target_last - m->e1);
        if ((dy > 0) == (e > 0))
            du -= CTLTW_FFMAP_KI * FFMAP_LEAD * dy;
    }
    /* the firmware carries du to the drive in Q4 x100 L/min, 16 bits: +-32767 / 16 / 100 */
    du = ctltw_clamp(du, -32767 / 1600.0, 32767 / 1600.0);
    /* the gain's learning: a long run of error one way (four times as fast beyond target >>
     * FFMAP_BIG_SHIFT); in the start's first periods only back to where the start found it; not
     * against a stop or refusal the error pushes toward, nor at the top duty from FFMAP_G_INIT on */
    o.near |= ctltw_near(fabs(e), q / (1 << FFMAP_BIG_SHIFT), 0.02);
    if (m->warm < FFMAP_WARM)
        m->warm++;
    if (m->rest || (e > 0) != (m->e1 > 0) || (m->warm < FFMAP_WARM && (m->gain >= m->gain_start || m->cap != 255))
        || (in->limit & (e > 0 ? CTL_CLOSE_BLOCKED : CTL_AT_OPEN)))
        m->slow_n = 0;
    else if ((!m->cap_run || m->gain < FFMAP_G_INIT / 256.0)    /* (not at the top with the gain at its start or over) */
             && (m->slow_n += fabs(e) > q / (1 << FFMAP_BIG_SHIFT) ? 4 : 1) >= FFMAP_SLOW_N) {
        m->slow_n = 0;
        if (m->gain < FFMAP_G_MAX / 256.0)
            m->gain += (floor(m->gain * 256 / 16) + floor(m->gain * 256 / 32)) / 256;
        m->cap = ctltw_cap_up(m->cap);
    }
    if (m->rev_age < 255)
        m->rev_age++;
    /* the duty cap: the flow's change (x100 L/min, as the firmware has it) after FFMAP_CAP_N periods
     * at the cap one way */
    {
        long dq100 = lround(in->flow * 100) - lround(m->flow_last * 100), th = lround(q * 100) >> FFMAP_CAP_SH;
        capc = m->cap_run;
        m->cap_run = 0;
        m->flow_last = in->flow;
        if (capc >= FFMAP_CAP_N) {
            if (m->dir < 0)
                dq100 = -dq100;
            if (dq100 > th) {
                if (m->cap > FFMAP_CAP_MIN)
                    m->cap -= m->cap / 4;
            } else if (dq100 < th / 2) {
                m->cap = ctltw_cap_up(m->cap);
            }
            if (capc == 255)
                capc--;
        }
    }
    /* the output stage: the motion owed, limits, the running friction, the smallest pulse */
    /* the target's pressure P (target / flow)^2 over 400 kPa (ffmap_gain_at_p, in its integers:
     * target x100 FFMAP_P_T_F against flow x100 times the root), on a gain learnt under FFMAP_G_INIT */
    {
        double lhs = (double)lround(q * 100) * FFMAP_P_T_F, rhs = (double)lround(in->flow * 100) * root;
        hi_t = root < 256 && m->gain < FFMAP_G_INIT / 256.0 && lhs > rhs;
        o.near |= root < 256 && fabs(lhs - rhs) <= 2.0 * root;
    }
    mv = du / CTL_FLOW_SCALE_LPM * in->travel * ctltw_gain_at_root(m->gain, root, in->noz_q) + m->carry;
    mv = ctltw_clamp(mv, -32767.0 / 32768, 32767.0 / 32768);
    if ((mv > 0 && (in->limit & CTL_CLOSE_BLOCKED)) || (mv < 0 && (in->limit & CTL_AT_OPEN)))
        mv = 0;
    s = mv > 0 ? 1 : mv < 0 ? -1 : 0;
    if (s == 0) {
        m->carry = 0;
    } else if (s == m->dir && !m->moved && m->rev_age < FFMAP_ANSWER && m->gain < FFMAP_G_INIT / 2 / 256.0
               && m->brk_extra <= 0 && fabs(m->ramp) <= FFMAP_FF_RAMP / 100.0) {
        m->carry = 0;               /* a fast valve's reversal: nothing more that way until the flow answers */
    } else if (s != m->dir && m->dir != 0 && fabs(mv) < m->rev_min) {
        o.near |= ctltw_near(fabs(mv), m->rev_min, 0.002);
        m->carry = mv;              /* a reversal waits until it is worth more than the slack */
    } else {
        o.near |= ctltw_near(fabs(mv), m->rev_min, 0.002);
        /* (its integers: |m| - rmin < rmin >> 1) */
        int lim = floor(fabs(mv) * 32768) - m->rev_min * 32768 < floor(m->rev_min * 32768 / 2);
        o.near |= s != m->dir && m->dir != 0 && ctltw_near(fabs(mv), 1.5 * m->rev_min, 0.002);
        d = run + fabs(mv) * (1 - run);
        if (m->brk_extra < 0)   /* under Min duty: the running friction 10/16 of it down */
            d += (floor(m->brk_extra * 32768 / 2) + floor(m->brk_extra * 32768 / 8)) / 32768;
        k = CTLTW_STICTION + m->brk_extra;
        o.near |= ctltw_near(d, k, 0.002);
        if (d < k) {
            m->carry = mv;
        } else {
            m->carry = 0;
            /* the duty cap, never under the smallest pulse; within 1/256 of it is at it */
            double cap = ((k * 32768 >= (m->cap << 7) ? k * 32768 : ((m->cap << 7) | 0x7F))) / 32768;
            o.near |= ctltw_near(d, cap, 0.002) || ctltw_near(d, floor(cap * 256) / 256, 0.002)
                      || ctltw_near(k * 32768, m->cap << 7, 128);
            int top = capc >= FFMAP_TOP_N;     /* the half cycle ended at the top duty */
            if (s != m->dir)
                capc = 255;
            if (d >= floor(cap * 256) / 256) {
                if (d > cap)
                    d = cap;
                m->cap_run = (capc + 1) & 255;
            }
            if (s != m->dir && m->dir != 0) {
                int big = m->err_peak > q / (1 << FFMAP_BIG_SHIFT);
                o.near |= ctltw_near(d, 2 * k, 0.002);
                o.near |= ctltw_near(m->err_peak, q / (1 << FFMAP_BIG_SHIFT), 0.02);
                /* a half cycle's bound: longer on a valve whose stroke takes FFMAP_SLOW_T periods
                 * at the learnt gain, at a steady speed */
                int gap = fabs(m->ramp) <= FFMAP_FF_RAMP / 100.0 && in->travel * m->gain >= FFMAP_SLOW_T
                          ? FFMAP_OSC_GAP_SLOW : FFMAP_OSC_GAP;
                int smaller = 0;        /* smaller reversals (at a steady target) */
                int floor_big = 0;      /* ... or big swings with the gain at its floor */
                if (big && m->big && m->rev_age <= gap) {
                    /* after a reversal near the smallest, the gain is cut only down to half of
                     * where a new valve starts; below that the reversals are made smaller */
                    if (m->gain > (m->rlim ? FFMAP_G_INIT / 2 : FFMAP_G_MIN) / 256.0)
                        m->gain -= floor(m->gain * 256 / (m->warm < FFMAP_WARM && top ? 2 : 4)) / 256;
                    else
                        smaller = floor_big = m->rlim;
                } else if (m->rev_age <= gap && (m->warm >= FFMAP_WARM || root < FFMAP_P_HI_F || !m->moved)
                           && d > 2 * k && fabs(e) <= q) {
                    /* (cycles cut the gain in a start too over FFMAP_P_HI_F's pressure or at a
                     * steady target; smaller reversals are learnt only after it) */
                    if (m->gain > FFMAP_G_MIN / 256.0)
                        m->gain -= floor(m->gain * 256 / 8) / 256;
                    smaller = 1;
                } else if (m->rev_age <= gap && m->warm >= FFMAP_WARM && !m->moved && m->brk_extra > 0) {
                    m->brk_extra -= FFMAP_BRK_STEP / 32768.0;   /* cycles near the smallest pulse: it is too big */
                }
                if (smaller && (floor_big || (!m->moved && m->warm >= FFMAP_WARM))
                    && m->rev_min > FFMAP_REV_LOW / 32768.0)
                    m->rev_min -= floor(m->rev_min * 32768 / 8) / 32768;
                m->rlim = lim;
                m->big = big;
                m->err_peak = 0;
                m->rev_age = 0;
                m->moved = 0;
                m->slow_n = 0;
                m->rl1 = 0;
            } else if (m->rl1) {
                m->rlim = 0;            /* a second pulse after the reversal */
            } else {
                m->rl1 = 1;
            }
            o.near |= ctltw_near(d, 2 * k, 0.002) || ctltw_near(d, k * 9 / 8, 0.002);
            m->lone_n = 0;
            if (s == m->dir && d <= k * 9 / 8 && m->quiet >= FFMAP_LONE_N && !m->hold) {
                m->lone_n = FFMAP_LONE_N;
                m->lone_flow = in->flow;
            }
            if (d <= 2 * k && s == m->dir) {
                if (m->stall_n == 0)
                    m->stall_flow = in->flow;
                if (m->stall_n < 250)
                    m->stall_n += d <= k * 9 / 8 ? 2 : 1;
            } else {
                m->stall_n = 0;
            }
            m->dir = s;
            /* closing toward a target over 400 kPa: at most the smallest pulse + FFMAP_P_T_DUTY */
            if (s > 0 && hi_t) {
                o.near |= ctltw_near(d, k + FFMAP_P_T_DUTY / 32768.0, 0.002);
                if (d > k + FFMAP_P_T_DUTY / 32768.0)
                    d = k + FFMAP_P_T_DUTY / 32768.0;
            }
            o.drive = s * d;
        }
    }
    m->e2 = m->e1;
    m->e1 = e;
    m->target_last = q;
    m->first = 0;
    o.rest = m->rest;
    return o;
}

/* ---- the peers ---------------------------------------------------------------------------------- */
/* RateControl's valve PID as aog.c reads it: a 100 ms period of its 150 ms loop. */
double ctltw_ag_step(ctltw_ag_t *a, double t, double y)
{
    double e, f, auth, c, band = 0.015 * t;
    int near;
    if (t <= 0 || a->first) {
        a->integ = 0;
        a->ref = 0;
        a->pos = 1;
        a->first = 0;
    }
    if (t > a->ref)
        a->ref = t;
    e = t - y;
    if ((e > band && !a->pos) || (e < -band && a->pos)) {
        a->pos = !a->pos;
        a->integ = 0;
    }
    if (t <= 0 || fabs(e) <= band) {
        a->integ = 0;
        return 0;
    }
    e = ctltw_clamp(e, -t, t);
    f = e / a->ref;
    auth = a->max_pwm > a->min_pwm ? a->max_pwm - a->min_pwm : 0;
    near = fabs(f) <= a->brake;
    if (near)
        a->integ += ctltw_clamp(f * a->ki / 100.0 * auth * 2.0 / 3.0, -25.0 * 2.0 / 3.0, 25.0 * 2.0 / 3.0);
    if (a->ki == 0)
        a->integ = 0;
    a->integ = ctltw_clamp(a->integ, -auth, auth);
    c = f * a->kp / 100.0 * (near ? a->slow : 1.0) * auth + a->integ;
    if (fabs(c) < 0.1)
        return 0;
    return (c > 0 ? 1 : -1) * ctltw_clamp(fabs(c) + a->min_pwm, a->min_pwm, a->max_pwm > a->min_pwm ? a->max_pwm : a->min_pwm) / 255.0;
}

/* Raven's valve cal as read in raven.c. */
double ctltw_rv_step(ctltw_rv_t *r, double t, double y, int *reversed)
{
    int b = r->cal / 1000, s = r->cal / 100 % 10, p = r->cal / 10 % 10, d = r->cal % 10;
    double v = b == 0 ? (10 - s) / 10.0 : (s + 1) / 10.0;
    double brake = p ? p / 10.0 : 0.05;
    double e = ctltw_clamp(t - y, -CTLTW_E_MAX, CTLTW_E_MAX), m;
    int dir;
    *reversed = 0;
    if (v > 1)
        v = 1;
    if (t <= 0 || fabs(e) <= d / 100.0 * t)
        return 0;
    m = fabs(e) >= brake * t ? v : v * fabs(e) / (brake * t);
    dir = e > 0 ? 1 : -1;
    if (dir != r->dir) {
        if (r->dir)
            m += b * 0.1;
        *reversed = 1;
        r->dir = dir;
    }
    return dir * m;
}

/* helper_ctl_twin.c: double-precision twins of the controllers, the references of tests/test_ctl.c. */
#include <math.h>
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

void ctltw_bp_dv(const double k[3], const double o[5], double n, double n1, double n2, double dv[3][5])
{
    double dn[3] = {n - n1, n, n - 2 * n1 + n2};
    for (int l = 0; l < 3; l++) {
        double delta = n * dn[l] * 2 * k[l] * (1 - k[l]);
        for (int j = 0; j < 5; j++)
            dv[l][j] = 0.2 * delta * o[j];
    }
}

/* ---- ffmap --------------------------------------------------------------------------------- */
void ctltw_fm_load(ctltw_fm_t *tw, const fm_state_t *fm, int first)
{
    tw->seen = 0;
    for (int j = 0; j < FM_NODES; j++) {
        tw->node[j] = fm->node[j] / 32768.0;
        if (fm->seen[j >> 3] & (1u << (j & 7)))
            tw->seen |= 1ul << j;
    }
    tw->p_hat = fm->p_hat / 32768.0;
    tw->p_ref = fm->p_ref / 32768.0;
    tw->takeup = fm->takeup / 32768.0;
    tw->y1 = fm->y1 / 100.0;
    tw->t1 = fm->t1 / 100.0;
    tw->dir = fm->dir;
    tw->calm = fm->calm;
    tw->warm = fm->warm;
    tw->rest = fm->rest;
    tw->first = first;
}

/* Flows and speeds are decimals of 0.01 (the firmware's x100 integers): a tie between two of
 * them, or between one and a power-of-two fraction of another, must stay a tie after the twin's
 * divisions by 100, so a > b is asked with a tolerance far under the smallest real gap (0.01 /
 * 256 L/min). */
static int ctltw_gt(double a, double b)
{
    return a > b + 1e-9;
}

/* What the firmware's value minus the twin's can be, from the firmware's rounding: [lo, hi]. */
typedef struct {
    double lo, hi;
} ctltw_iv_t;

static ctltw_iv_t ctltw_iv(double lo, double hi)
{
    ctltw_iv_t v = {lo, hi};
    return v;
}

/* 1 when the twin's x and the firmware's (x plus an error within err) may lie on different
 * sides of (or on) a threshold: thr for the twin, thr_f as the firmware holds it */
static int ctltw_tips(double x, ctltw_iv_t err, double thr, double thr_f)
{
    double a = x - thr, lo = x + err.lo - thr_f, hi = x + err.hi - thr_f;
    return !(a > 0 && lo > 1e-12) && !(a < 0 && hi < -1e-12);
}

/* the same for |x| against thr (x inside or outside -thr .. thr) */
static int ctltw_tips_abs(double x, ctltw_iv_t err, double thr, double thr_f)
{
    return ctltw_tips(x, err, thr, thr_f) || ctltw_tips(x, err, -thr, -thr_f);
}

/* a node holds an int16: closures saturate at -1 and 1 */
static double ctltw_node_sat(double x)
{
    return ctltw_clamp(x, -1.0, 1.0);
}

/* the bin of target flow q (node i, fraction f from it to node i+1); a target exactly on a node
 * or half-way stays there (see ctltw_gt). 0 beyond the last node. */
static int ctltw_fm_bin(double q, int *i, double *f)
{
    double x = (q < 0 ? 0 : q) / CTLTW_FM_BIN;
    if (fabs(x - floor(x + 0.5)) < 1e-9)
        x = floor(x + 0.5);
    if (x >= FM_NODES - 1)
        return 0;
    *i = (int)x;
    *f = x - *i;
    if (fabs(*f - 0.5) < 1e-9)
        *f = 0.5;
    return 1;
}

/* map(q): closure for a target flow, linear between nodes, the last node beyond them */
static double ctltw_fm_map(const ctltw_fm_t *m, double q)
{
    int i;
    double f;
    if (!ctltw_fm_bin(q, &i, &f))
        return m->node[FM_NODES - 1];
    return m->node[i] + (m->node[i + 1] - m->node[i]) * f;
}

/* fm_known: the map around q rests on learned nodes (always, unless FM_SEEN_ONLY) */
static int ctltw_fm_known(const ctltw_fm_t *m, double q)
{
    int i;
    double f;
    if (!CTLTW_FM_SEEN_ONLY)
        return 1;
    if (q < 0 || !ctltw_fm_bin(q, &i, &f))
        return 0;
    return (m->seen >> i & 1u) && (m->seen >> (i + 1) & 1u);
}

/* fm_learn: pull the two nodes around q toward p_hat (weights by distance, rate FM_LR); the
 * very first point moves the whole default curve; a node's first visit moves the unlearned
 * nodes (but the two) with it. */
static void ctltw_fm_learn(ctltw_fm_t *m, double q, ctltw_fm_out_t *o)
{
    double f, err, d0, d1, shift;
    int i, near;
    if (q < 0 || !ctltw_fm_bin(q, &i, &f))
        return;
    near = f < 0.5 ? i : i + 1;
    err = m->p_hat - ctltw_fm_map(m, q);
    o->path |= CTLTW_P_LEARN;
    if (!m->seen) {
        for (int j = 0; j < FM_NODES; j++)
            m->node[j] = ctltw_node_sat(m->node[j] + err);
        m->seen |= 1ul << near;
        o->path |= CTLTW_P_ANCHOR;
        return;
    }
    d0 = err * (1 - f) * CTLTW_FM_LR;
    d1 = err * f * CTLTW_FM_LR;
    shift = near == i ? d0 : d1;
    m->node[i] = ctltw_node_sat(m->node[i] + d0);
    m->node[i + 1] = ctltw_node_sat(m->node[i + 1] + d1);
    if (!(m->seen >> near & 1u)) {
        for (int j = 0; j < FM_NODES; j++)
            if (!(m->seen >> j & 1u) && j != i && j != i + 1)
                m->node[j] = ctltw_node_sat(m->node[j] + shift);
        m->seen |= 1ul << near;
        o->path |= CTLTW_P_VISIT;
    }
}

/* fm_step's output stage on a drive: cut at full duty, the break-away rounding, the end stops'
 * cut. full, brk, half: full duty, the break-away duty and its half as the step holds them (the
 * firmware's, to see where its drive lands). Monotone in x. */
static double ctltw_fm_out(double x, int limit, double full, double brk, double half)
{
    x = ctltw_clamp(x, -full, full);
    if (x < brk && x > -brk)
        x = x >= half ? brk : x <= -half ? -brk : 0;
    if ((x > 0 && (limit & CTL_AT_CLOSED)) || (x < 0 && (limit & CTL_AT_OPEN)))
        x = 0;
    return x;
}

ctltw_fm_out_t ctltw_fm_step(ctltw_fm_t *m, const ctltw_fm_in_t *in)
{
    ctltw_fm_out_t o = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    const double lsb = 1 / 32768.0;
    double q = in->target, y = in->flow;
    double e = ctltw_clamp(q - y, -CTLTW_E_MAX, CTLTW_E_MAX), ae = fabs(e);
    double d, du, hi, lo, need, c, e_c = 0, pre, drive, mv, ph, b_du;
    ctltw_iv_t e_ff, e_ref0, e_d, e_ref, e_need, e_pre;
    int s, moving, calm_if;

    if (m->first) {
        m->y1 = y;
        m->t1 = q;
        m->p_ref = m->p_hat;
        m->calm = m->warm = m->rest = 0;
        m->first = 0;
    }
    /* end stops calibrate the estimate (the firmware's closed end is 32767, an LSB under 1) */
    if (in->limit & CTL_AT_CLOSED)
        m->p_hat = 1.0;
    else if (in->limit & CTL_AT_OPEN)
        m->p_hat = 0.0;
    ph = in->limit & CTL_AT_CLOSED ? -lsb : 0;
    e_ref0 = ctltw_iv(0, 0);        /* the state comes from the firmware's: p_ref is exact */
    if (in->limit)
        o.path |= CTLTW_P_ENDSTOP;

    /* feed-forward: how far the map says the valve must go for the target's change (the
     * firmware rounds two lookups to half an LSB each; none while the target holds) */
    d = ctltw_fm_known(m, q) && ctltw_fm_known(m, m->t1) ? ctltw_fm_map(m, q) - ctltw_fm_map(m, m->t1) : 0;
    e_ff = ctltw_gt(fabs(q - m->t1), 0) ? ctltw_iv(-lsb, lsb) : ctltw_iv(0, 0);

    /* deadband with hysteresis; a moving target (|dq| > q / 64) wakes the loop */
    moving = ctltw_gt(fabs(q - m->t1) * 64, q);
    if (moving) {
        m->rest = 0;
    } else if (m->rest) {
        if (ctltw_gt(ae, q / CTLTW_FM_DB_OUT))
            m->rest = 0;
    } else if (!ctltw_gt(ae, q / CTLTW_FM_DB_IN) && ctltw_gt(q, 0)) {
        m->rest = 1;
        if (CTLTW_FM_DB_STOP) {
            m->p_ref = m->p_hat;
            e_ref0 = ctltw_iv(ph, ph);
        }
    }

    /* the PI increment in stroke: P on the measurement, the integral held while the servo
     * still travels; inside the band the slow integral alone */
    if (m->rest) {
        du = CTLTW_FM_REST_KI * e;
        b_du = fabs(CTLTW_FM_REST_KI - Q12(CTLTW_FM_REST_KI) / 4096.0) * ae;
        o.path |= CTLTW_P_REST;
    } else {
        double g = d + m->p_ref - m->p_hat, dy = ctltw_clamp(m->y1 - y, -327.67, 327.67);
        du = CTLTW_FM_KP * dy;
        b_du = fabs(CTLTW_FM_KP - Q12(CTLTW_FM_KP) / 4096.0) * fabs(dy);
        if (ctltw_tips_abs(g, ctltw_iv(e_ff.lo - ph, e_ff.hi - ph), CTLTW_FM_IGATE, Q15(CTLTW_FM_IGATE) * lsb))
            o.border |= CTLTW_B_IGATE;
        if (fabs(g) < CTLTW_FM_IGATE) {
            du += CTLTW_FM_KI * e;
            b_du += fabs(CTLTW_FM_KI - Q12(CTLTW_FM_KI) / 4096.0) * ae;
            o.path |= CTLTW_P_INTEGRAL;
        } else {
            o.path |= CTLTW_P_HELD;
        }
    }
    /* the increment's rounding: the gains in Q12 (above, in L/min; nothing of it once both cut
     * the increment), du to Q4 (0.1 LSB) and the stroke to an LSB (0.5), 26844 / 2^17 for
     * 0.2048 (1.7e-5 of it) */
    du /= CTL_FLOW_SCALE_LPM;
    b_du /= CTL_FLOW_SCALE_LPM;
    if (fabs(du) > CTLTW_FM_DU_MAX) {
        if (fabs(du) - b_du > CTLTW_FM_DU_MAX)
            b_du = 0;
        du = ctltw_clamp(du, -CTLTW_FM_DU_MAX, CTLTW_FM_DU_MAX);
        o.path |= CTLTW_P_DUCUT;
    }
    b_du += 0.61 * lsb + 1.7e-5 * fabs(du);
    d += du + m->p_ref;
    e_d = ctltw_iv(e_ff.lo - b_du + e_ref0.lo, e_ff.hi + b_du + e_ref0.hi);

    /* p_ref within FM_LEAD of p_hat and within the stroke; the firmware's cuts (p_hat and the
     * top of the stroke as it holds them) applied to the ends of its possible d */
    hi = m->p_hat + CTLTW_FM_LEAD < 1 ? m->p_hat + CTLTW_FM_LEAD : 1;
    lo = m->p_hat - CTLTW_FM_LEAD > 0 ? m->p_hat - CTLTW_FM_LEAD : 0;
    if (d > hi || d < lo)
        o.path |= CTLTW_P_LEADCUT;
    m->p_ref = ctltw_clamp(d, lo, hi);
    {
        double hi_f = hi + (hi == 1 ? -lsb : ph), lo_f = lo + (lo > 0 ? ph : 0);
        e_ref = ctltw_iv(ctltw_clamp(d + e_d.lo, lo_f, hi_f) - m->p_ref,
                         ctltw_clamp(d + e_d.hi, lo_f, hi_f) - m->p_ref);
    }
    if (((in->limit & CTL_AT_CLOSED) && m->p_ref > m->p_hat) || ((in->limit & CTL_AT_OPEN) && m->p_ref < m->p_hat)) {
        m->p_ref = m->p_hat;        /* (not reached: p_ref is within the stroke and p_hat at its end) */
        e_ref = ctltw_iv(ph, ph);
    }
    o.ref_lo = e_ref.lo;
    o.ref_hi = e_ref.hi;

    /* the servo: the move still needed, plus the backlash to take up on a reversal */
    need = m->p_ref - m->p_hat;
    e_need = ctltw_iv(e_ref.lo - ph, e_ref.hi - ph);
    s = need > 0 ? 1 : need < 0 ? -1 : 0;
    if (s != 0 && s != m->dir && ctltw_tips_abs(need, e_need, CTLTW_FM_REV_MIN, Q15(CTLTW_FM_REV_MIN) * lsb))
        o.border |= CTLTW_B_REV;
    /* As ctl.c has it, a step without a direction (need 0, or a reversal too small) takes up
     * the backlash still pending with a positive drive whatever the last direction: after an
     * opening motion (dir -1) a need just under 0 drives -takeup, one of 0 +takeup. (Every
     * reversal's drive takes up the whole backlash unless it is cut at full duty with
     * T_travel over 50 periods, so takeup is 0 between steps at the default 40.) */
    if (m->dir < 0 && m->takeup > 0 && ctltw_tips(need, e_need, 0, 0))
        o.border |= CTLTW_B_REV;
    if (s != 0 && s != m->dir && fabs(need) < CTLTW_FM_REV_MIN) {
        s = 0;
        need = 0;
        e_need = ctltw_iv(0, 0);
        o.path |= CTLTW_P_HYST;
    }
    if (s != 0 && s != m->dir) {
        c = CTLTW_FM_BACKLASH;
        e_c = s * (Q15(CTLTW_FM_BACKLASH) * lsb - CTLTW_FM_BACKLASH);      /* the firmware's is 655/32768 */
        o.path |= CTLTW_P_REVERSAL;
    } else {
        c = m->takeup;
    }
    pre = (need + (s < 0 ? -c : c)) * in->travel;
    /* the firmware's product is exact: its error is need's and the backlash's, times T_travel */
    e_pre = ctltw_iv((e_need.lo + e_c) * in->travel, (e_need.hi + e_c) * in->travel);

    /* full duty at most; under the break-away duty a move of at least half of it is made at
     * it, a smaller none; nothing against an end stop */
    o.sat_edge = ctltw_tips_abs(pre, e_pre, 1, 1);
    o.sat = pre > 1 || pre < -1;
    drive = ctltw_fm_out(pre, 0, 1, CTLTW_STICTION, CTLTW_STICTION / 2);
    if (fabs(ctltw_clamp(pre, -1, 1)) < CTLTW_STICTION) {
        if (ctltw_tips_abs(ctltw_clamp(pre, -1, 1), e_pre, CTLTW_STICTION / 2, Q15(CTLTW_STICTION / 2) * lsb))
            o.border |= CTLTW_B_STICTION;
        if (pre != 0)
            o.path |= CTLTW_P_ROUNDED;
    }
    if ((drive > 0 && (in->limit & CTL_AT_CLOSED)) || (drive < 0 && (in->limit & CTL_AT_OPEN))) {
        drive = 0;
        o.sat = 1;
    }
    if (o.sat)
        o.path |= CTLTW_P_SAT;
    {
        double full = 1 - lsb, brk = Q15(CTLTW_STICTION) * lsb, half = Q15(CTLTW_STICTION / 2) * lsb;
        o.drive_lo = ctltw_fm_out(pre + e_pre.lo, in->limit, full, brk, half) - drive;
        o.drive_hi = ctltw_fm_out(pre + e_pre.hi, in->limit, full, brk, half) - drive;
    }

    /* account the motion: backlash first, then the valve */
    if (drive != 0) {
        s = drive > 0 ? 1 : -1;
        if (s != m->dir) {
            m->takeup = CTLTW_FM_BACKLASH;
            m->dir = s;
        }
        mv = fabs(drive) / in->travel;
        c = mv < m->takeup ? mv : m->takeup;
        m->takeup -= c;
        mv -= c;
        m->p_hat = ctltw_clamp(m->p_hat + s * mv, 0, 1);
    }
    if (m->takeup > 0)
        o.path |= CTLTW_P_TAKEUP;

    /* learning where the loop is calm: target steady, |e| <= q / 16, nothing cut, fast enough */
    calm_if = !moving && !ctltw_gt(ae * 16, q) && ctltw_gt(q, 0) && !in->limit
              && (!CTLTW_FM_MINF_GATE || !ctltw_gt(in->minf_speed, in->speed));
    if (calm_if && o.sat_edge)
        o.border |= CTLTW_B_SAT;    /* calm, and the learning, hang on the saturation flag */
    if (calm_if && !o.sat) {
        if (m->calm < 255)
            m->calm++;
    } else {
        m->calm = 0;
    }
    if (m->warm < FM_WARM)
        m->warm++;
    else if (CTLTW_FM_LEARN && m->calm >= CTLTW_FM_CALM)
        ctltw_fm_learn(m, q, &o);

    m->y1 = y;
    m->t1 = q;
    o.drive = drive;
    return o;
}

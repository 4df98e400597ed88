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
#define LSB (1 / 32768.0)

void ctltw_fm_load(ctltw_fm_t *tw, const fm_state_t *fm, int first, q15_t last)
{
    tw->seen = 0;
    for (int j = 0; j < FM_NODES; j++) {
        tw->node[j] = fm->node[j] / 32768.0;
        if (fm->seen[j >> 3] & (1u << (j & 7)))
            tw->seen |= 1ul << j;
    }
    tw->off = fm->off / 32768.0;
    tw->p_hat = fm->p_hat / 32768.0;
    tw->p_ref = fm->p_ref / 32768.0;
    tw->takeup = fm->takeup / 32768.0;
    tw->y1 = fm->y1 / 100.0;
    tw->t1 = fm->t1 / 100.0;
    tw->dir = fm->dir;
    tw->calm = fm->calm;
    tw->warm = fm->warm;
    tw->rest = fm->rest;
    tw->hold = fm->hold;
    tw->cal = fm->cal;
    tw->stopd = fm->stopd;
    tw->pend = fm->pend;
    tw->last = last / 32768.0;
    tw->first = first;
    tw->gain = fm->gain / 256.0;
    tw->stall_n = fm->stall_n;
    tw->stall_y = fm->stall_y / 100.0;
    tw->stall_v = fm->stall_v / 100.0;
    tw->stall_mv = fm->stall_mv / 32768.0;
    tw->brk = fm->brk / 32768.0;
    tw->brk_age = fm->brk_age;
    tw->rev = fm->rev;
    tw->hunt = fm->hunt;
    tw->tk_cut = fm->tk_cut / 32768.0;
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

/* x's sign against the firmware's (0 a sign of its own; both exactly 0 is no tip) */
static int ctltw_tips_sign(double x, ctltw_iv_t err)
{
    if (x == 0 && err.lo == 0 && err.hi == 0)
        return 0;
    return ctltw_tips(x, err, 0, 0);
}

/* int16 closures saturate at -1 and at the closed stop (CTLTW_FM_TOP) */
static double ctltw_sat(double x)
{
    return ctltw_clamp(x, -1.0, CTLTW_FM_TOP);
}

/* lo .. hi clear of both int16 ends */
static int ctltw_in16(double lo, double hi)
{
    return lo > -1.0 + 1e-12 && hi < CTLTW_FM_TOP - 1e-12;
}

/* The firmware's closures minus the twin's through a step (intervals), and whether off's holds. */
typedef struct {
    ctltw_iv_t ph, ref, rel, tk, off;   /* p_hat, p_ref, p_ref - p_hat, takeup, off */
    ctltw_iv_t smv;                 /* stall_mv */
    int off_ok;
} ctltw_fm_err_t;

static const ctltw_fm_err_t ctltw_fm_exact = {{0, 0}, {0, 0}, {0, 0}, {0, 0}, {0, 0}, {0, 0}, 1};

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

/* map(q) before its int16 cut: off plus the nodes interpolated (their difference an int16), the
 * last node beyond them. r: the firmware's minus the twin's, from the firmware's rounding of the
 * interpolation (half up to an LSB; none on a node). */
static double ctltw_fm_map_u(const ctltw_fm_t *m, double q, ctltw_iv_t *r)
{
    int i;
    double f;
    if (!ctltw_fm_bin(q, &i, &f)) {
        *r = ctltw_iv(0, 0);
        return m->off + m->node[FM_NODES - 1];
    }
    *r = f == 0 ? ctltw_iv(0, 0) : ctltw_iv(-0.5 * LSB, 0.5 * LSB);
    return m->off + m->node[i] + ctltw_sat(m->node[i + 1] - m->node[i]) * f;
}

/* fm_learned: both nodes around q were learned from the loop */
static int ctltw_fm_learned(const ctltw_fm_t *m, double q)
{
    int i;
    double f;
    if (q < 0 || !ctltw_fm_bin(q, &i, &f))
        return 0;
    return (m->seen >> i & 1u) && (m->seen >> (i + 1) & 1u);
}

/* the feed-forward map(q) - map(t1), and e_d, the firmware's minus it: the lookups' rounding
 * (off, the same in both, cancels unless a lookup may saturate) */
static double ctltw_fm_ff(const ctltw_fm_t *m, double q, const ctltw_fm_err_t *er, ctltw_iv_t *e_d)
{
    ctltw_iv_t r1, r2;
    double u1, u2, d, l1, h1, l2, h2;
    int i;
    double f;
    *e_d = ctltw_iv(0, 0);
    u1 = ctltw_fm_map_u(m, q, &r1);
    u2 = ctltw_fm_map_u(m, m->t1, &r2);
    d = ctltw_sat(u1) - ctltw_sat(u2);
    if (!ctltw_gt(fabs(q - m->t1), 0) || (!ctltw_fm_bin(q, &i, &f) && !ctltw_fm_bin(m->t1, &i, &f)))
        return d;                   /* the same lookup twice: exactly 0 */
    l1 = u1 + er->off.lo + r1.lo;
    h1 = u1 + er->off.hi + r1.hi;
    l2 = u2 + er->off.lo + r2.lo;
    h2 = u2 + er->off.hi + r2.hi;
    if (ctltw_in16(l1, h1) && ctltw_in16(l2, h2) && ctltw_in16(u1, u1) && ctltw_in16(u2, u2))
        *e_d = ctltw_iv(r1.lo - r2.hi, r1.hi - r2.lo);
    else
        *e_d = ctltw_iv(ctltw_sat(l1) - ctltw_sat(h2) - d, ctltw_sat(h1) - ctltw_sat(l2) - d);
    return d;
}

/* the feed-forward only the way the target went, and not while the flow is already past the
 * target that way (up/down: the target rose/fell; over/under: the flow is above/below the
 * target by more than the band). Monotone in d. */
static double ctltw_fm_gate(double d, int up, int down, int over, int under)
{
    if ((up && d < 0) || (down && d > 0) || (d > 0 && over) || (d < 0 && under))
        return 0;
    return d;
}

/* The inputs of the PI increment. */
typedef struct {
    int rest, integral;
    double e, dy, dq;               /* L/min: error, y1 - y, target's change */
    double e0;                      /* L/min: inside the band the integral ignores |e| <= e0 */
} ctltw_fm_pi_t;

/* The error the slow integral sees inside the band: |e| less e0, 0 within it (flows are x100
 * integers in the firmware: a tie is a tie, see ctltw_gt). */
static double ctltw_fm_rest_e(const ctltw_fm_pi_t *p)
{
    return ctltw_gt(p->e, p->e0) ? p->e - p->e0 : ctltw_gt(-p->e0, p->e) ? p->e + p->e0 : 0;
}

/* The PI increment, stroke, for the flow K the feed-forward covers: inside the band the slow
 * integral; outside it P on the measurement plus the part k of the target's change the
 * feed-forward does not cover (between 0 and dq), the integral when asked. bg (L/min) is added
 * before the cut at CTLTW_FM_DU_MAX (the Q12 gains' error, for the firmware's ends). k: that
 * part; raw: the increment before the cut, L/min. Decreasing in K. */
static double ctltw_fm_du(const ctltw_fm_pi_t *p, double K, double bg, double *kk, double *raw)
{
    double du, k = 0;
    if (p->rest) {
        du = CTLTW_FM_REST_KI * ctltw_fm_rest_e(p);
    } else {
        k = p->dq - K;
        k = ctltw_gt(0, p->dq) ? ctltw_clamp(k, p->dq, 0) : ctltw_clamp(k, 0, p->dq);
        du = CTLTW_FM_KP * ctltw_clamp(p->dy + k, -327.68, 327.67) + (p->integral ? CTLTW_FM_KI * p->e : 0);
    }
    du += bg;
    if (kk)
        *kk = k;
    if (raw)
        *raw = du;
    return ctltw_clamp(du / CTL_FLOW_SCALE_LPM, -CTLTW_FM_DU_MAX, CTLTW_FM_DU_MAX);
}

/* 1 / T_travel as the firmware holds it (ctl_inv_travel, Q15) */
static double ctltw_inv_travel_f(double travel)
{
    int t = (int)travel;
    if (t < 1)
        t = 40;
    return ((32768 + t / 2) / t) * LSB;
}

/* fm_account: the valve got drive dr (duty) for a period; below the break-away duty it does not
 * move; a change of direction takes up the backlash first. The errors: the firmware's move
 * rounded to an LSB with 1/T_travel in Q15, the backlash at 655/32768. */
static void ctltw_fm_calibrate(ctltw_fm_t *m, double at, ctltw_fm_err_t *er, ctltw_fm_out_t *o);
static void ctltw_fm_account(ctltw_fm_t *m, double dr, double travel, ctltw_fm_err_t *er, ctltw_fm_out_t *o)
{
    double mv, xs, tk, c, mr, lo, hi, tk_lo, tk_hi, mr_lo, mr_hi, ph0 = m->p_hat;
    ctltw_iv_t e_mv;
    int s;
    if (fabs(dr) < CTLTW_STICTION) {
        if (dr != 0)
            o->path |= CTLTW_P_STILL;
        return;
    }
    s = dr > 0 ? 1 : -1;
    if (s == m->stopd) {
        o->path |= CTLTW_P_INTOSTOP;    /* into the stop a report set: the valve cannot go further */
        return;
    }
    m->stopd = 0;
    o->path |= CTLTW_P_MOVED;
    if (s != m->dir) {
        m->takeup = CTLTW_FM_BACKLASH - m->tk_cut;
        double eb = Q15(CTLTW_FM_BACKLASH) * LSB - CTLTW_FM_BACKLASH;     /* the firmware's is 655/32768 */
        er->tk = ctltw_iv(eb, eb);
        m->dir = s;
    }
    mv = fabs(dr) / travel;
    xs = fabs(dr) * ctltw_inv_travel_f(travel);    /* the firmware's product, before its rounding */
    e_mv = ctltw_iv(xs - 0.5 * LSB - mv, xs + 0.5 * LSB - mv);
    tk = m->takeup;
    if (!(tk + er->tk.hi <= 1e-12) && !(tk + er->tk.lo > 1e-12))
        o->border |= CTLTW_B_STALL;     /* the firmware's take-up may be 0 or not */
    c = mv < tk ? mv : tk;
    m->takeup = tk - c;
    mr = mv - c;
    tk_lo = fmax(tk + er->tk.lo - (mv + e_mv.hi), 0);
    tk_hi = fmax(tk + er->tk.hi - (mv + e_mv.lo), 0);
    mr_lo = fmax(mv + e_mv.lo - (tk + er->tk.hi), 0);
    mr_hi = fmax(mv + e_mv.hi - (tk + er->tk.lo), 0);
    er->tk = ctltw_iv(tk_lo - m->takeup, tk_hi - m->takeup);
    m->p_hat = ctltw_sat(ph0 + s * mr);
    lo = s > 0 ? ctltw_sat(ph0 + er->ph.lo + mr_lo) : ctltw_sat(ph0 + er->ph.lo - mr_hi);
    hi = s > 0 ? ctltw_sat(ph0 + er->ph.hi + mr_hi) : ctltw_sat(ph0 + er->ph.hi - mr_lo);
    er->ph = ctltw_iv(lo - m->p_hat, hi - m->p_hat);
    er->rel = ctltw_iv(er->ref.lo - er->ph.hi, er->ref.hi - er->ph.lo);    /* p_ref stays */
    /* a small pulse (no take-up in it, at most 2 Min duty + brk): counted for the stall check */
    if (c == 0 && mr > 0 && fabs(dr) <= 2 * Q15(CTLTW_STICTION) * LSB + m->brk + 1e-12) {
        if (m->stall_n < 255)
            m->stall_n++;
        m->stall_mv = ctltw_sat(m->stall_mv + mr);
        er->smv = ctltw_iv(er->smv.lo + mr_lo - mr, er->smv.hi + mr_hi - mr);
    } else {
        m->stall_n = 0;
        m->stall_mv = 0;
        er->smv = ctltw_iv(0, 0);
    }
    /* past a stop nobody reported: the frame moves so the estimate is at the stop */
    if (m->p_hat > CTLTW_FM_CLOSED)
        ctltw_fm_calibrate(m, CTLTW_FM_CLOSED, er, o);
    else if (m->p_hat < CTLTW_FM_OPEN)
        ctltw_fm_calibrate(m, CTLTW_FM_OPEN, er, o);
}

/* fm_calibrate: at an end stop (at) the estimate jumps there, p_ref and the map's frame move
 * with it. */
static void ctltw_fm_calibrate(ctltw_fm_t *m, double at, ctltw_fm_err_t *er, ctltw_fm_out_t *o)
{
    double ph0 = m->p_hat, ref0 = m->p_ref, off0 = m->off, sh = ctltw_sat(at - ph0);
    double fl = at - (ph0 + er->ph.hi), fh = at - (ph0 + er->ph.lo);     /* the firmware's at - p_hat */
    double sh_lo = ctltw_sat(fl), sh_hi = ctltw_sat(fh);
    ctltw_iv_t ref = er->ref;
    if (sh != 0)
        o->path |= CTLTW_P_CALIB;
    m->p_hat = at;
    m->p_ref = ctltw_sat(ref0 + sh);
    m->off = ctltw_sat(off0 + sh);
    er->ph = ctltw_iv(0, 0);
    if (ctltw_in16(fl, fh) && ctltw_in16(at - ph0, at - ph0) && ctltw_in16(ref0 + ref.lo + sh_lo, ref0 + ref.hi + sh_hi)
        && ctltw_in16(ref0 + sh, ref0 + sh)) {
        /* nothing saturates: p_ref - p_hat is kept exactly */
        er->ref = ctltw_iv(er->ph.lo + er->rel.lo, er->ph.hi + er->rel.hi);
    } else {
        er->ref = ctltw_iv(ctltw_sat(ref0 + ref.lo + sh_lo) - m->p_ref, ctltw_sat(ref0 + ref.hi + sh_hi) - m->p_ref);
        er->rel = ctltw_iv(er->ref.lo - er->ph.hi, er->ref.hi - er->ph.lo);
    }
    er->off = ctltw_iv(ctltw_sat(off0 + er->off.lo + sh_lo) - m->off, ctltw_sat(off0 + er->off.hi + sh_hi) - m->off);
}

/* fm_learn: the very first point moves the frame (off: the whole default curve); later ones pull
 * the two nodes around q toward p_hat (weights by distance, rate FM_LR); the nearer node is
 * marked learned. */
static void ctltw_fm_learn(ctltw_fm_t *m, double q, ctltw_fm_err_t *er, ctltw_fm_out_t *o)
{
    double f, u, err, d0, d1, off0 = m->off;
    ctltw_iv_t r;
    int i, near;
    if (q < 0 || !ctltw_fm_bin(q, &i, &f))
        return;
    near = f < 0.5 ? i : i + 1;
    u = ctltw_fm_map_u(m, q, &r);
    err = ctltw_sat(m->p_hat - ctltw_sat(u));
    o->path |= CTLTW_P_LEARN;
    if (!m->seen) {
        m->off = ctltw_sat(off0 + err);
        o->path |= CTLTW_P_ANCHOR;
        /* the firmware's off + (p_hat - (off + nodes)): p_hat less the nodes' part as it rounds it */
        if (ctltw_in16(u - 4 * LSB, u + 4 * LSB) && ctltw_in16(m->p_hat - u - 4 * LSB, m->p_hat - u + 4 * LSB)
            && ctltw_in16(off0 + err - 4 * LSB, off0 + err + 4 * LSB))
            er->off = ctltw_iv(er->ph.lo - r.hi, er->ph.hi - r.lo);
        else
            er->off_ok = 0;
    } else {
        d0 = err * (1 - f) * CTLTW_FM_LR;
        d1 = err * f * CTLTW_FM_LR;
        m->node[i] = ctltw_sat(m->node[i] + d0);
        m->node[i + 1] = ctltw_sat(m->node[i + 1] + d1);
    }
    m->seen |= 1ul << near;
}

/* FM_TAB in double: table t at x (in nodes, 0 <= x < the last node), linear between the nodes */
static double ctltw_tab(const int16_t *t, double x)
{
    int i = (int)floor(x);
    return i == x ? t[i] : t[i] + (t[i + 1] - t[i]) * (x - i);
}

/* fm_gain's sum 1/Q_v + (1 - Pc/P)/Q_b in Q16 of 1/(L/min) (the firmware's s before its cut) at the
 * estimate ph (stroke), the pressure p (kPa) and the flow y (L/min), from the firmware's tables.
 * h 0: the tables interpolated exactly (the twin's); h -0.5 / +0.5: the least / most the
 * firmware's arithmetic makes of the same lookups (each rounded to an integer of its table,
 * +-0.5, each product's shift +-0.5; all of it non-negative, so the bounds are the products of
 * the bounds). tab: the lookups' rounding alone through the sum (Q16). */
static double ctltw_fm_gs_sum(double ph, double p, double y, double h, double *tab)
{
    double o = 32767 - ctltw_clamp(ph * 32768 - FM_AT_OPEN, 0, 32767);      /* opening, Q15 */
    double pk = ctltw_clamp(p, 64, 1599), yq = ctltw_clamp(floor(y * 100 + 0.5), 0, 8191);   /* x100 */
    double a = ctltw_tab(fm_inv_cv, o / 2048), b = ctltw_tab(fm_inv_sqp, pk / 64);
    double c = ctltw_tab(fm_pc_p, pk / 64), d = ctltw_tab(fm_inv_q, yq / 256);
    if (tab)
        *tab = (0.5 * (a + b) + 0.25) / 256 + (0.5 * (c + d) + 0.25) / 32768;
    return fmax(a + h, 0) * fmax(b + h, 0) / 256 + h + fmax(c + h, 0) * fmax(d + h, 0) / 32768 + h;
}

/* fm_gain: the gain schedule at this step's estimate (1 until an end stop has set the frame):
 * K times the sum, clamped. e: the firmware's (Q8 / 256) minus it, from p_hat's interval (the sum
 * grows with the closure: fm_inv_cv falls with the opening), the lookups' and shifts' rounding,
 * FM_GS_K in Q10, the result rounded and clamped to FM_GS_MIN .. FM_GS_MAX (all monotone). */
static double ctltw_fm_gain(const ctltw_fm_t *m, const ctltw_fm_in_t *in, const ctltw_fm_err_t *er,
                            ctltw_iv_t *e, double *tab, ctltw_fm_out_t *o)
{
    double s, g, lo, hi;
    *e = ctltw_iv(0, 0);
    *tab = 0;
    if (!m->cal)
        return 1;
    s = fmin(ctltw_fm_gs_sum(m->p_hat, in->pressure, in->target, 0, tab) / 65536, CTLTW_FM_GS_SCUT);
    g = ctltw_clamp(CTLTW_FM_GS_K * s, CTLTW_FM_GS_MIN, CTLTW_FM_GS_MAX);
    o->path |= g == CTLTW_FM_GS_MIN ? CTLTW_P_GAIN_MIN : g == CTLTW_FM_GS_MAX ? CTLTW_P_GAIN_MAX : CTLTW_P_GAIN;
    *tab *= FM_GS_K / 1024.0;
    lo = fmin(ctltw_fm_gs_sum(m->p_hat + er->ph.lo, in->pressure, in->target, -0.5, NULL), 8191);
    hi = fmin(ctltw_fm_gs_sum(m->p_hat + er->ph.hi, in->pressure, in->target, 0.5, NULL), 8191);
    lo = ctltw_clamp(lo * FM_GS_K / 1024 - 0.5, FM_GS_MIN, FM_GS_MAX);
    hi = ctltw_clamp(hi * FM_GS_K / 1024 + 0.5, FM_GS_MIN, FM_GS_MAX);
    *e = ctltw_iv(lo / 256 - g, hi / 256 - g);
    return g;
}

/* u (stroke) times a factor within fl .. fh (> 0): the least and the most it can be */
static double ctltw_mul_lo(double u, double fl, double fh)
{
    return u >= 0 ? u * fl : u * fh;
}

static double ctltw_mul_hi(double u, double fl, double fh)
{
    return u >= 0 ? u * fh : u * fl;
}

/* fm_step's output stage on a drive: cut at full duty, the break-away rounding, the end stops'
 * (and over-pressure's) cut. full, brk, half: full duty, the break-away duty and its half as the
 * step holds them (the firmware's, to see where its drive lands). Monotone in x. */
static double ctltw_fm_out(double x, int limit, double full, double brk, double half)
{
    x = ctltw_clamp(x, -full, full);
    if (x < brk && x > -brk)
        x = x >= half ? brk : x <= -half ? -brk : 0;
    if ((x > 0 && (limit & CTL_CLOSE_BLOCKED)) || (x < 0 && (limit & CTL_AT_OPEN)))
        x = 0;
    return x;
}

/* the servo's move: x (the new p_ref less p_hat before the cuts) within FM_LEAD, p_ref an int16
 * (p_hat at ph), held at p_hat against a stop or over-pressure. Monotone (in x up, in ph down). */
static double ctltw_fm_need(double x, double ph, int limit)
{
    x = ctltw_clamp(ctltw_clamp(x, -CTLTW_FM_LEAD, CTLTW_FM_LEAD), -1 - ph, CTLTW_FM_TOP - ph);
    if ((limit & CTL_CLOSE_BLOCKED) && x > 0)
        x = 0;
    if ((limit & CTL_AT_OPEN) && x < 0)
        x = 0;
    return x;
}

static void ctltw_fm_frame(const ctltw_fm_t *m, ctltw_fm_out_t *o, const ctltw_fm_err_t *er)
{
    if (m->p_hat < 0 || m->p_hat > 1 || m->p_ref < 0 || m->p_ref > 1)
        o->path |= CTLTW_P_FRAME;
    o->ref_lo = er->ref.lo;
    o->ref_hi = er->ref.hi;
    o->hat_lo = er->ph.lo;
    o->hat_hi = er->ph.hi;
    o->take_lo = er->tk.lo;
    o->take_hi = er->tk.hi;
    o->off_lo = er->off.lo;
    o->off_hi = er->off.hi;
    o->off_iv = er->off_ok;
}

ctltw_fm_out_t ctltw_fm_applied(ctltw_fm_t *m, double drive, int limit, double travel)
{
    ctltw_fm_out_t o;
    ctltw_fm_err_t er = ctltw_fm_exact;
    memset(&o, 0, sizeof o);
    m->pend = 0;
    if (limit & CTL_AT_CLOSED)
        ctltw_fm_calibrate(m, CTLTW_FM_CLOSED, &er, &o), m->cal = 1, m->stopd = 1;
    else if (limit & CTL_AT_OPEN)
        ctltw_fm_calibrate(m, CTLTW_FM_OPEN, &er, &o), m->cal = 1, m->stopd = -1;
    ctltw_fm_account(m, drive, travel, &er, &o);
    ctltw_fm_frame(m, &o, &er);
    o.drive = drive;
    return o;
}

ctltw_fm_out_t ctltw_fm_step(ctltw_fm_t *m, const ctltw_fm_in_t *in)
{
    ctltw_fm_out_t o;
    ctltw_fm_err_t er = ctltw_fm_exact;
    ctltw_fm_pi_t pi;
    const double lsb = LSB;
    double q = in->target, y = in->flow, T = in->travel;
    double e = ctltw_clamp(q - y, -CTLTW_E_MAX, CTLTW_E_MAX), ae = fabs(e);
    double d, g, dq, band, du, raw, k, bg = 0, r, rb, need, need0, c, pre, drive, rel, xr, xl, xh, gn, fl, fh, rev_min;
    ctltw_iv_t e_d, e_need, e_c, e_pre, e_gn;
    int s, moving, calm_if;
    memset(&o, 0, sizeof o);

    /* the drive sent last, if nobody said what the valve got */
    if (m->pend) {
        m->pend = 0;
        o.path |= CTLTW_P_PEND;
        ctltw_fm_account(m, m->last, T, &er, &o);
    }
    if (m->first) {
        m->y1 = y;
        m->t1 = q;
        m->p_ref = m->p_hat;
        er.ref = er.ph;
        er.rel = ctltw_iv(0, 0);
        m->calm = m->warm = m->rest = m->hold = 0;
        m->first = 0;
    }
    /* end stops calibrate the estimate; over-pressure (CTL_NO_CLOSE) is not a stop */
    if (in->limit & CTL_AT_CLOSED)
        ctltw_fm_calibrate(m, CTLTW_FM_CLOSED, &er, &o), m->cal = 1, m->stopd = 1;
    else if (in->limit & CTL_AT_OPEN)
        ctltw_fm_calibrate(m, CTLTW_FM_OPEN, &er, &o), m->cal = 1, m->stopd = -1;
    if (in->limit & (CTL_AT_CLOSED | CTL_AT_OPEN))
        o.path |= CTLTW_P_ENDSTOP;
    /* a stall: FM_STALL_N smallest pulses one way, flow within q / 256 of where they started,
     * speed within 1/64, and the error still asking for more that way: the pulses are taken back
     * from p_hat and p_ref, and the smallest pulse grows by FM_BRK_STEP up to FM_BRK_MAX */
    if (m->stall_n >= FM_STALL_N) {
        if (!ctltw_gt(fabs(y - m->stall_y), q / 256) && (m->dir > 0 ? ctltw_gt(e, 0) : ctltw_gt(0, e))
            && !ctltw_gt(fabs(in->speed - m->stall_v) * 64, in->speed)) {
            double c0 = m->dir > 0 ? m->stall_mv : -m->stall_mv;
            ctltw_iv_t ec = m->dir > 0 ? er.smv : ctltw_iv(-er.smv.hi, -er.smv.lo);
            m->p_hat = ctltw_sat(m->p_hat - c0);
            m->p_ref = ctltw_sat(m->p_ref - c0);
            er.ph = ctltw_iv(er.ph.lo - ec.hi, er.ph.hi - ec.lo);
            er.ref = ctltw_iv(er.ref.lo - ec.hi, er.ref.hi - ec.lo);
            if (m->brk < FM_BRK_MAX / 32768.0 - 1e-12)
                m->brk += FM_BRK_STEP / 32768.0;
            m->brk_age = 0;
            o.path |= CTLTW_P_STALL;
        }
        m->stall_n = 0;
        m->stall_mv = 0;
        er.smv = ctltw_iv(0, 0);
    }
    if ((m->brk > 1e-12 || m->tk_cut > 1e-12) && ++m->brk_age >= (int)FM_BRK_AGE) {
        if (m->brk > 1e-12)
            m->brk -= FM_BRK_STEP / 32768.0;    /* 10 min without a stall or hunt: a step back */
        if (m->tk_cut > 1e-12)
            m->tk_cut -= FM_TK_STEP / 32768.0;
        m->brk_age = 0;
    }
    /* the last reversal ages; too old, the run of close reversals is over */
    if (m->rev != 0) {
        m->rev += m->rev > 0 ? 1 : -1;
        int gap = FM_HUNT_GAP((int)T);
        if (m->rev > gap || m->rev < -gap)
            m->rev = m->hunt = 0;
    }

    /* feed-forward: how far the map says the valve must go for the target's change, only the
     * way the target went and not while the flow is past the target that way */
    d = ctltw_fm_ff(m, q, &er, &e_d);
    dq = q - m->t1;
    band = q / CTLTW_FM_DB_IN;
    {
        int up = ctltw_gt(dq, 0), down = ctltw_gt(0, dq), over = ctltw_gt(-e, band), under = ctltw_gt(e, band);
        g = ctltw_fm_gate(d, up, down, over, under);
        e_d = ctltw_iv(ctltw_fm_gate(d + e_d.lo, up, down, over, under) - g,
                       ctltw_fm_gate(d + e_d.hi, up, down, over, under) - g);
        if (g != d)
            o.path |= CTLTW_P_GATED;
        d = g;
    }
    /* 13/16 of it where the map around the target or the last one is not learned (the firmware
     * rounds the Q15 product: +-0.5 LSB more) */
    if (d != 0 && (!ctltw_fm_learned(m, q) || !ctltw_fm_learned(m, m->t1))) {
        double ds = ctltw_sat(d) * CTLTW_FM_FF_UNLEARNED;
        e_d = ctltw_iv((ctltw_sat(d + e_d.lo) - ctltw_sat(d)) * CTLTW_FM_FF_UNLEARNED - 0.5 * LSB,
                       (ctltw_sat(d + e_d.hi) - ctltw_sat(d)) * CTLTW_FM_FF_UNLEARNED + 0.5 * LSB);
        d = ds;
        o.path |= CTLTW_P_UNLEARNED;
    }
    /* a move over one period at full duty: the integral waits FM_HOLD periods */
    if (ctltw_tips_abs(d, e_d, 1 / T, ctltw_inv_travel_f(T)))
        o.border |= CTLTW_B_HOLD;
    if (fabs(d) > 1 / T) {
        m->hold = CTLTW_FM_HOLD;
        o.path |= CTLTW_P_HOLDSET;
    } else if (m->hold) {
        m->hold--;
    }

    /* deadband with hysteresis; a moving target (|dq| > q / 64) wakes the loop */
    moving = ctltw_gt(fabs(dq) * 64, q);
    if (moving) {
        m->rest = 0;
        m->stall_n = 0;             /* the flow follows the target: no stall to tell, nor a hunt */
        m->stall_mv = 0;
        er.smv = ctltw_iv(0, 0);
        m->hunt = 0;
    } else if (m->rest) {
        if (ctltw_gt(ae, q / CTLTW_FM_DB_OUT))
            m->rest = 0;
    } else if (!ctltw_gt(ae, band) && ctltw_gt(q, 0)) {
        m->rest = 1;
        m->p_ref = m->p_hat;        /* entering the band stops the servo where it is */
        er.ref = er.ph;
        er.rel = ctltw_iv(0, 0);
    }

    /* the PI increment in stroke: P on the measurement and on the part of the target's change
     * the feed-forward leaves, the integral while the servo is near its goal and no big
     * feed-forward move is under way; inside the band the slow integral alone */
    rel = m->p_ref - m->p_hat;
    pi.rest = m->rest;
    pi.e = e;
    pi.e0 = floor(round(q * 100) / CTLTW_FM_REST_E0) / 100;   /* the firmware's q >> FM_REST_E0 */
    pi.dy = m->y1 - y;
    pi.dq = dq;
    pi.integral = 0;
    if (m->rest) {
        o.path |= CTLTW_P_REST;
        if (ctltw_fm_rest_e(&pi) == 0)
            o.path |= CTLTW_P_RESTZERO;
    } else {
        ctltw_iv_t e_g = ctltw_iv(e_d.lo + er.rel.lo, e_d.hi + er.rel.hi);
        g = ctltw_sat(d + rel);
        if (!m->hold && ctltw_tips_abs(g, e_g, CTLTW_FM_IGATE, Q15(CTLTW_FM_IGATE) * lsb))
            o.border |= CTLTW_B_IGATE;
        pi.integral = fabs(g) < CTLTW_FM_IGATE && !m->hold;
        o.path |= pi.integral ? CTLTW_P_INTEGRAL : fabs(g) < CTLTW_FM_IGATE ? CTLTW_P_HOLDING : CTLTW_P_HELD;
    }
    du = ctltw_fm_du(&pi, ctltw_sat(d) * CTLTW_FM_COVER, 0, &k, &raw);
    if (!m->rest && fabs(k) > 1e-9 && fabs(k - dq) > 1e-9)
        o.path |= CTLTW_P_COVER;
    if (fabs(raw) / CTL_FLOW_SCALE_LPM > CTLTW_FM_DU_MAX)
        o.path |= CTLTW_P_DUCUT;
    /* the gain schedule scales the increment (the firmware's gain within gn + e_gn) */
    gn = ctltw_fm_gain(m, in, &er, &e_gn, &o.gain_tab, &o);
    m->gain = gn;
    o.gain = gn;
    o.gain_lo = e_gn.lo;
    o.gain_hi = e_gn.hi;
    o.du = du;
    /* The firmware's increment: its feed-forward (e_d) through the covered flow, rounded to an
     * x100 L/min (r; exact for a feed-forward exactly 0), the gains in Q12 (bg, L/min), du to Q4
     * (half of 1/16 x100 L/min: 0.1 LSB before the gain), times the gain's factor (fl .. fh: its
     * Q8 interval e_gn times 13422 / 256, rounded to an integer, over 13421.77 for 0.2048; exactly
     * 13422 before the frame is set) and the stroke rounded to an LSB (0.5; rb); none of it where
     * the firmware's increment is exactly 0. d + g du grows with d (P takes back 0.6 of a
     * feed-forward change, times at most 1.6: 0.96), so its ends are at d's, and for a given d it
     * is linear in g: the four corners are tried. */
    if (m->cal) {
        fl = (CTLTW_FM_DU_F * (gn + e_gn.lo) - 0.5) / CTLTW_FM_DU_F_EXACT;
        fh = (CTLTW_FM_DU_F * (gn + e_gn.hi) + 0.5) / CTLTW_FM_DU_F_EXACT;
    } else {
        fl = fh = CTLTW_FM_DU_F / CTLTW_FM_DU_F_EXACT;
    }
    r = d == 0 && e_d.lo == 0 && e_d.hi == 0 ? 0 : 0.005;
    if (m->rest) {
        bg = fabs(CTLTW_FM_REST_KI - Q12(CTLTW_FM_REST_KI) / 4096.0) * fabs(ctltw_fm_rest_e(&pi));
    } else {
        double kerr = CTLTW_FM_COVER * fmax(-e_d.lo, e_d.hi) + r;
        bg = fabs(CTLTW_FM_KP - Q12(CTLTW_FM_KP) / 4096.0) * fmin(fabs(pi.dy + k) + kerr, 327.68);
        if (pi.integral)
            bg += fabs(CTLTW_FM_KI - Q12(CTLTW_FM_KI) / 4096.0) * ae;
    }
    {
        double dd[2] = {d + e_d.lo, d + e_d.hi}, ul[2], uh[2], rw[4], q4;
        for (int j = 0; j < 2; j++) {
            ul[j] = ctltw_fm_du(&pi, ctltw_sat(dd[j]) * CTLTW_FM_COVER + r, -bg, NULL, &rw[2 * j]);
            uh[j] = ctltw_fm_du(&pi, ctltw_sat(dd[j]) * CTLTW_FM_COVER - r, bg, NULL, &rw[2 * j + 1]);
        }
        if (rw[0] == 0 && rw[1] == 0 && rw[2] == 0 && rw[3] == 0) {
            q4 = rb = 0;
        } else {
            q4 = 0.5 / 16 / 100 / CTL_FLOW_SCALE_LPM + 1e-12;   /* du_q4's rounding, stroke */
            rb = 0.5 * lsb + 1e-12;
        }
        for (int j = 0; j < 2; j++) {
            ul[j] -= q4;
            uh[j] += q4;
            if (ul[j] < -CTLTW_FM_DU_MAX)
                ul[j] = -32768.0 / 16 / 100 / CTL_FLOW_SCALE_LPM;  /* fx_sat16's low end is -32768 */
        }
        xl = fmin(dd[0] + ctltw_mul_lo(ul[0], fl, fh), dd[1] + ctltw_mul_lo(ul[1], fl, fh)) - rb + rel + er.rel.lo;
        xh = fmax(dd[0] + ctltw_mul_hi(uh[0], fl, fh), dd[1] + ctltw_mul_hi(uh[1], fl, fh)) + rb + rel + er.rel.hi;
    }
    xr = d + gn * du + rel;

    /* p_ref within FM_LEAD of p_hat, an int16, held at p_hat against a stop (or over-pressure) */
    if (xr > CTLTW_FM_LEAD || xr < -CTLTW_FM_LEAD)
        o.path |= CTLTW_P_LEADCUT;
    need0 = ctltw_fm_need(xr, m->p_hat, 0);
    need = ctltw_fm_need(xr, m->p_hat, in->limit);
    if (need != need0 && (in->limit & CTL_NO_CLOSE) && !(in->limit & CTL_AT_CLOSED))
        o.path |= CTLTW_P_NOCLOSE;
    e_need = ctltw_iv(ctltw_fm_need(xl, m->p_hat + er.ph.hi, in->limit) - need,
                      ctltw_fm_need(xh, m->p_hat + er.ph.lo, in->limit) - need);
    m->p_ref = m->p_hat + need;
    er.ref = ctltw_iv(er.ph.lo + e_need.lo, er.ph.hi + e_need.hi);

    /* the servo: the move still needed, plus the backlash to take up on a reversal (or still
     * pending); nothing to do, no take-up either */
    s = need > 0 ? 1 : need < 0 ? -1 : 0;
    rev_min = m->rest ? CTLTW_FM_REV_MIN_REST : CTLTW_FM_REV_MIN;
    if (s != 0 && s != m->dir && ctltw_tips_abs(need, e_need, rev_min, Q15(rev_min) * lsb))
        o.border |= CTLTW_B_REV;
    /* need against 0 where it decides whether the pending backlash is taken up */
    if (m->dir != 0 && m->takeup + er.tk.hi > 1e-12 && ctltw_tips_sign(need, e_need))
        o.border |= CTLTW_B_ZERO;
    if (s != 0 && s != m->dir && fabs(need) < rev_min) {
        s = 0;
        need = 0;
        e_need = ctltw_iv(0, 0);
        o.path |= CTLTW_P_HYST;
    }
    if (s != 0 && s != m->dir) {
        double eb = s * (Q15(CTLTW_FM_BACKLASH) * lsb - CTLTW_FM_BACKLASH);  /* the firmware's is 655/32768 */
        /* hunting: close reversals, each against the last one's error: the take-up shrinks */
        if (m->rev != 0 && (m->rev > 0 ? ctltw_gt(0, e) : ctltw_gt(e, 0)) && ++m->hunt >= FM_HUNT_N) {
            m->hunt = 0;
            if (m->tk_cut <= (Q15(CTLTW_FM_BACKLASH) - FM_TK_MIN - FM_TK_STEP) / 32768.0 + 1e-12)
                m->tk_cut += FM_TK_STEP / 32768.0;
            m->brk_age = 0;
            o.path |= CTLTW_P_HUNT;
        }
        m->rev = ctltw_gt(e, 0) ? 1 : ctltw_gt(0, e) ? -1 : 0;
        c = CTLTW_FM_BACKLASH - m->tk_cut;
        e_c = ctltw_iv(eb, eb);
        o.path |= CTLTW_P_REVERSAL;
    } else if (s == 0) {
        c = 0;
        e_c = ctltw_iv(0, 0);
    } else {
        c = m->takeup;
        e_c = s > 0 ? er.tk : ctltw_iv(-er.tk.hi, -er.tk.lo);
        if (c > 0)
            o.path |= CTLTW_P_TAKEUP;
    }
    pre = (need + (s < 0 ? -c : c)) * T;
    /* the firmware's product is exact: its error is need's and the backlash's, times T_travel */
    e_pre = ctltw_iv((e_need.lo + e_c.lo) * T, (e_need.hi + e_c.hi) * T);

    /* full duty at most; under the break-away duty a move of at least half of it is made at
     * it, a smaller none; nothing against an end stop, no closing under over-pressure */
    o.sat_edge = ctltw_tips_abs(pre, e_pre, 1, 1);
    o.sat = pre > 1 || pre < -1;
    drive = ctltw_fm_out(pre, 0, 1, CTLTW_STICTION + m->brk, CTLTW_STICTION / 2);
    if (fabs(ctltw_clamp(pre, -1, 1)) < CTLTW_STICTION + m->brk) {
        if (ctltw_tips_abs(ctltw_clamp(pre, -1, 1), e_pre, CTLTW_STICTION / 2, Q15(CTLTW_STICTION / 2) * lsb))
            o.border |= CTLTW_B_STICTION;
        if (pre != 0)
            o.path |= CTLTW_P_ROUNDED;
    }
    if ((drive > 0 && (in->limit & CTL_CLOSE_BLOCKED)) || (drive < 0 && (in->limit & CTL_AT_OPEN))) {
        if (drive > 0 && (in->limit & CTL_NO_CLOSE) && !(in->limit & CTL_AT_CLOSED))
            o.path |= CTLTW_P_NOCLOSE;
        drive = 0;
        o.sat = 1;
    }
    if (o.sat)
        o.path |= CTLTW_P_SAT;
    {
        double full = 1 - lsb, brk = Q15(CTLTW_STICTION) * lsb + m->brk, half = (Q15(CTLTW_STICTION) / 2) * lsb;
        o.drive_lo = ctltw_fm_out(pre + e_pre.lo, in->limit, full, brk, half) - drive;
        o.drive_hi = ctltw_fm_out(pre + e_pre.hi, in->limit, full, brk, half) - drive;
    }
    /* the drive is accounted when the valve has had it (ctltw_fm_applied, or the next step) */
    m->pend = 1;
    m->last = drive;

    /* learning where the loop is calm: target steady, |e| <= q / 16, nothing cut, no stop or
     * over-pressure, fast enough */
    calm_if = !moving && !ctltw_gt(ae * 16, q) && ctltw_gt(q, 0) && !in->limit
              && !ctltw_gt(in->minf_speed, in->speed);
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
    else if (m->calm >= CTLTW_FM_CALM)
        ctltw_fm_learn(m, q, &er, &o);

    m->y1 = y;
    m->t1 = q;
    if (m->stall_n == 0) {
        m->stall_y = y;             /* where a run of smallest pulses starts from */
        m->stall_v = in->speed;
    }
    o.drive = drive;
    ctltw_fm_frame(m, &o, &er);
    return o;
}

/* ---- the peers ---------------------------------------------------------------------------------- */
/* AgOpenGPS's loop as described (aog.c has the reading): two 50 ms loops a 100 ms period. */
double ctltw_ag_step(ctltw_ag_t *a, double t, double y)
{
    double e, o, sf, lim;
    int far;
    if (t < 0)
        t = 0;
    e = ctltw_clamp(t - y, -t, t);
    if (a->first) {
        a->y1 = y;
        a->first = 0;
    }
    if (fabs(e) <= 0.04 * t) {
        a->y1 = y;
        return 0;
    }
    far = fabs(e) > 0.2 * t;
    sf = far ? 1.0 : 0.75;
    a->integ = ctltw_clamp(a->integ + 2.0 * a->ki * e, -a->max_pwm, a->max_pwm);
    o = (e > 0 ? a->min_pwm : -a->min_pwm) + a->kp * sf * e + a->integ + a->kd / 2.0 * (a->y1 - y);
    a->y1 = y;
    lim = a->max_pwm * sf;
    if (o == 0)
        o = e > 0 ? 1e-9 : -1e-9;
    o = (o > 0 ? 1 : -1) * ctltw_clamp(fabs(o), a->min_pwm, lim > a->min_pwm ? lim : a->min_pwm);
    if (fabs(o) > lim)
        o = (o > 0 ? 1 : -1) * lim;
    return o / 255.0;
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

/* steps.c: the step figures of docs/SCENARIOS.md: holds of the reference target, each change scored against the firmware's target, start_s. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "metrics.h"

typedef struct {
    int a, b;                       /* covered samples [a, b] */
    double level;                   /* median of the reference over [a, b] */
} hold_t;

static double absd(double x)
{
    return x < 0 ? -x : x;
}

static double maxd(double a, double b)
{
    return a > b ? a : b;
}

static int cmp_double(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return a < b ? -1 : a > b;
}

/* Median of p[a..b], with scratch space for the sort. */
static double median(const double *p, int a, int b, double *scratch)
{
    int n = b - a + 1;
    memcpy(scratch, p + a, sizeof *scratch * (size_t)n);
    qsort(scratch, (size_t)n, sizeof *scratch, cmp_double);
    return n % 2 ? scratch[n / 2] : 0.5 * (scratch[n / 2 - 1] + scratch[n / 2]);
}

/* 1 when the window [k - W, k] of p stays within 1 % of p[k] (at least 0.01 L/min). */
static int steady(const double *p, int k, int W)
{
    double lo = p[k], hi = p[k];
    int j;
    for (j = k - W; j < k; j++) {
        lo = p[j] < lo ? p[j] : lo;
        hi = p[j] > hi ? p[j] : hi;
    }
    return hi - lo <= METRICS_STEADY_FRAC * maxd(absd(p[k]), 1.0);
}

/* The holds of the reference: runs of samples whose trailing 2 s window is steady (a run of
 * steady samples k0..b covers [k0 - W, b]); a hold whose level is within 5 % of the previous
 * one's continues it. Returns the number of holds written to h. */
static int find_holds(const double *R, int n, int W, hold_t *h, double *scratch)
{
    int k = W, nh = 0;
    while (k < n) {
        int a, b;
        double level;
        if (!steady(R, k, W)) {
            k++;
            continue;
        }
        a = k - W;
        b = k;
        while (b + 1 < n && steady(R, b + 1, W))
            b++;
        level = median(R, a, b, scratch);
        if (nh > 0 && absd(level - h[nh - 1].level) <= METRICS_MERGE_FRAC * maxd(absd(level), absd(h[nh - 1].level))) {
            h[nh - 1].b = b;
            h[nh - 1].level = median(R, h[nh - 1].a, b, scratch);
        } else {
            h[nh].a = a;
            h[nh].b = b;
            h[nh].level = level;
            nh++;
        }
        k = b + 1;
    }
    return nh;
}

/* Time (in samples, fractional) of the first crossing of `level` by y[] from k0 on, in the
 * direction sgn; -1 when it never gets there. */
static double crossing(const double *y, int k0, int k1, double level, double sgn)
{
    int k;
    for (k = k0; k <= k1; k++)
        if ((y[k] - level) * sgn >= 0) {
            if (k == 0 || y[k] == y[k - 1])
                return k;           /* else interpolated with the sample before (t_c - 1 too) */
            return (k - 1) + (level - y[k - 1]) / (y[k] - y[k - 1]);
        }
    return -1;
}

/* Settling: samples from k0 until abs(y - r) <= tol at every sample up to k1 (the entry
 * interpolated between the last sample outside and the next one); *settled 0 when the last
 * sample is outside (then k1 - k0). */
static double settle(const double *y, const double *r, int k0, int k1, double tol, int *settled)
{
    int k, last = -1;
    double e0, e1;
    for (k = k0; k <= k1; k++)
        if (absd(y[k] - r[k]) > tol)
            last = k;
    *settled = last < k1;
    if (last < 0)
        return 0.0;
    if (last == k1)
        return (double)(k1 - k0);
    e0 = absd(y[last] - r[last]);
    e1 = absd(y[last + 1] - r[last + 1]);
    return (last - k0) + (e0 - tol) / (e0 - e1);
}

static int all_set(const unsigned char *v, int a, int b)
{
    int k;
    for (k = a; k <= b; k++)
        if (!v[k])
            return 0;
    return 1;
}

/* One scored change from hold o to hold h. */
static metrics_step_t score_change(const metrics_series_t *s, const hold_t *o, const hold_t *h, int E)
{
    const double *r = s->target, *y = s->flow;
    double D = h->level - o->level, sgn = D > 0 ? 1.0 : -1.0, c10, c90, over = 0.0, sum = 0.0;
    int tc = o->b + 1, te = h->b - E, ta, k, nlast;
    metrics_step_t st;
    if (te < tc)
        te = tc;
    for (ta = tc; ta < te; ta++)
        if (absd(r[ta] - h->level) <= METRICS_ARRIVE_FRAC * absd(h->level))
            break;
    st.t_s = tc * s->dt_s;
    st.from_lpm = o->level;
    st.to_lpm = h->level;
    c10 = crossing(y, tc, te, o->level + 0.1 * D, sgn);
    c90 = c10 < 0 ? -1 : crossing(y, tc, te, o->level + 0.9 * D, sgn);
    st.rise_s = (c10 >= 0 && c90 >= 0) ? (c90 - c10) * s->dt_s : NAN;
    for (k = ta; k <= te; k++) {
        double e = sgn * (y[k] - r[k]);
        over = e > over ? e : over;
    }
    st.overshoot_pct = over / absd(D) * 100.0;
    st.settle_5pct_s = settle(y, r, tc, te, 0.05 * absd(h->level), &st.settled_5) * s->dt_s;
    st.settle_2pct_s = settle(y, r, tc, te, 0.02 * absd(h->level), &st.settled_2) * s->dt_s;
    nlast = (int)floor(0.2 * (te - ta + 1));
    if (nlast < 1)
        nlast = 1;
    for (k = te - nlast + 1; k <= te; k++)
        sum += y[k] - r[k];
    st.sse_pct = h->level != 0 ? sum / nlast / absd(h->level) * 100.0 : NAN;
    return st;
}

int metrics_find_steps(const metrics_series_t *s, metrics_step_t *out, int max)
{
    int W = (int)floor(METRICS_STEADY_S / s->dt_s + 0.5);
    int E = (int)floor(METRICS_END_S / s->dt_s + 0.5);
    int nh, i, count = 0;
    hold_t *h;
    double *scratch;

    if (s->n <= W || W < 1)
        return 0;
    h = malloc(sizeof *h * (size_t)(s->n / (W + 1) + 2));
    scratch = malloc(sizeof *scratch * (size_t)s->n);
    if (!h || !scratch) {
        fprintf(stderr, "metrics: out of memory\n");
        abort();
    }
    nh = find_holds(s->ref, s->n, W, h, scratch);
    for (i = 1; i < nh; i++) {
        const hold_t *o = &h[i - 1], *c = &h[i];
        if (!(o->level > 0))
            continue;
        if (absd(c->level - o->level) < METRICS_CHANGE_FRAC * maxd(absd(c->level), absd(o->level)))
            continue;
        if (!all_set(s->work, o->a, o->b) || !all_set(s->work, c->a, c->b))
            continue;
        if (count < max)
            out[count] = score_change(s, o, c, E);
        count++;
    }
    free(h);
    free(scratch);
    return count;
}

void metrics_start(const metrics_series_t *s, double *first, double *longest)
{
    int W = (int)floor(METRICS_START_HOLD_S / s->dt_s + 0.5);
    int k = 0, n_starts = 0, unsettled = 0;
    double worst = 0.0;
    *first = *longest = NAN;
    if (!s->spray)
        return;
    while (k < s->n) {
        int open, in = -1, done = 0;
        while (k < s->n && !(s->spray[k] && s->target[k] > 0))
            k++;
        if (k >= s->n)
            break;
        open = k;
        for (; k < s->n && s->spray[k]; k++) {
            int inside = absd(s->flow[k] - s->target[k]) <= METRICS_START_BAND * absd(s->target[k]) && s->target[k] > 0;
            if (!inside) {
                in = -1;
                continue;
            }
            if (in < 0)
                in = k;
            if (k - in >= W) {
                done = 1;
                break;
            }
        }
        if (done) {
            double t = (in - open) * s->dt_s;
            if (n_starts == 0)
                *first = t;
            worst = t > worst ? t : worst;
        } else if (n_starts == 0 || k < s->n) {
            unsettled = 1;      /* the boom shut (or the run ended on the first) before it settled */
        }
        n_starts++;
        while (k < s->n && s->spray[k])
            k++;            /* on to the boom's next opening */
    }
    if (n_starts > 0 && !unsettled)
        *longest = worst;
}


/* metrics.c: dose, zone uniformity and step response figures from the simulated truth. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "metrics.h"

static void *grow(void *p, int *cap, int need, size_t size)
{
    if (need <= *cap)
        return p;
    {
        int c = *cap ? *cap * 2 : 256;
        void *q;
        while (c < need)
            c *= 2;
        q = realloc(p, (size_t)c * size);
        if (!q) {
            fprintf(stderr, "metrics: out of memory\n");
            abort();
        }
        *cap = c;
        return q;
    }
}

void metrics_init(metrics_t *m, double sample_dt_s)
{
    memset(m, 0, sizeof *m);
    m->sample_dt_s = sample_dt_s;
}

void metrics_free(metrics_t *m)
{
    free(m->zones);
    free(m->ref);
    free(m->target);
    free(m->flow);
    free(m->work);
    free(m->spray);
    free(m->alarms);
    free(m->steps);
    memset(m, 0, sizeof *m);
}

static void zone_add(metrics_t *m, double frac, double vol, double expect, double dt)
{
    m->cur.vol_l += vol * frac;
    m->cur.expect_l += expect * frac;
    m->cur.time_s += dt * frac;
}

void metrics_add(metrics_t *m, double dt_s, double v_mps, double nozzle_lpm, double width_m,
                 double rate_l_ha, double p_bar, int spraying)
{
    double dist = v_mps * dt_s;
    double vol = nozzle_lpm * dt_s / 60.0;
    double area = dist * width_m;
    double expect = rate_l_ha * area / 10000.0;
    double done = 0.0;              /* fraction of this slice already put into zones */

    m->sim_s += dt_s;
    m->vol_l += vol;
    m->area_m2 += area;
    m->expect_l += expect;
    if (spraying) {
        if (!m->p_seen_any || p_bar < m->p_min_any)
            m->p_min_any = p_bar;
        if (!m->p_seen_any || p_bar > m->p_max_any)
            m->p_max_any = p_bar;
        m->p_seen_any = 1;
    }
    if (v_mps * 3.6 >= METRICS_MIN_KMH) {
        m->vol4_l += vol;
        m->area4_m2 += area;
        m->expect4_l += expect;
        if (spraying) {
            if (!m->p_seen || p_bar < m->p_min)
                m->p_min = p_bar;
            if (!m->p_seen || p_bar > m->p_max)
                m->p_max = p_bar;
            m->p_seen = 1;
        }
    }
    /* zones end exactly at every 5 m of travel: split the slice there */
    while (dist > 0.0 && m->zone_dist_m + dist * (1.0 - done) >= METRICS_ZONE_M) {
        double f = (METRICS_ZONE_M - m->zone_dist_m) / dist;
        zone_add(m, f, vol, expect, dt_s);
        done += f;
        m->zones = grow(m->zones, &m->cap_zones, m->n_zones + 1, sizeof *m->zones);
        m->zones[m->n_zones++] = m->cur;
        memset(&m->cur, 0, sizeof m->cur);
        m->zone_dist_m = 0.0;
    }
    zone_add(m, 1.0 - done, vol, expect, dt_s);
    m->zone_dist_m += dist * (1.0 - done);
}

void metrics_target(metrics_t *m, double dt_s, double v_mps, double meter_lpm, double target_lpm, int at_stop)
{
    if (v_mps * 3.6 < METRICS_MIN_KMH)
        return;
    m->target4_l += target_lpm * dt_s / 60.0;
    m->meter4_l += meter_lpm * dt_s / 60.0;
    if (at_stop) {
        m->stop_meter4_l += meter_lpm * dt_s / 60.0;
        m->stop_target4_l += target_lpm * dt_s / 60.0;
    }
}

void metrics_valve(metrics_t *m, double dt_s, double reversals, double travel_strokes, int spraying)
{
    if (spraying) {
        m->spray_s += dt_s;
        m->valve_reversals_spray += reversals - m->valve_rev_last;
    }
    m->valve_rev_last = reversals;
    m->valve_reversals = reversals;
    m->valve_travel = travel_strokes;
}

void metrics_sample(metrics_t *m, double ref_lpm, double target_lpm, double flow_lpm, double work_kmh,
                    int spraying)
{
    if (m->n_samples + 1 > m->cap_samples) {
        int cap = m->n_samples + 1 < 256 ? 256 : 2 * (m->n_samples + 1);
        m->ref = realloc(m->ref, sizeof *m->ref * (size_t)cap);
        m->target = realloc(m->target, sizeof *m->target * (size_t)cap);
        m->flow = realloc(m->flow, sizeof *m->flow * (size_t)cap);
        m->work = realloc(m->work, (size_t)cap);
        m->spray = realloc(m->spray, (size_t)cap);
        if (!m->ref || !m->target || !m->flow || !m->work || !m->spray) {
            fprintf(stderr, "metrics: out of memory\n");
            abort();
        }
        m->cap_samples = cap;
    }
    m->ref[m->n_samples] = ref_lpm;
    m->target[m->n_samples] = target_lpm;
    m->flow[m->n_samples] = flow_lpm;
    m->work[m->n_samples] = work_kmh >= METRICS_MIN_KMH;
    m->spray[m->n_samples] = spraying != 0;
    m->n_samples++;
}

void metrics_alarm(metrics_t *m, double t_s, const char *code)
{
    m->alarms = grow(m->alarms, &m->cap_alarms, m->n_alarms + 1, sizeof *m->alarms);
    m->alarms[m->n_alarms].t_s = t_s;
    snprintf(m->alarms[m->n_alarms].code, sizeof m->alarms[0].code, "%s", code);
    m->n_alarms++;
}

/* ---- steps ------------------------------------------------------------------------------------ */
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

static void step_means(const metrics_step_t *st, int n, metrics_result_t *r);

static void num(FILE *f, const char *key, double v, int comma)
{
    if (isfinite(v))
        fprintf(f, "\"%s\":%.6g%s", key, v, comma ? "," : "");
    else
        fprintf(f, "\"%s\":null%s", key, comma ? "," : "");
}

/* ---- the figures -------------------------------------------------------------------------------- */
void metrics_finish(metrics_t *m, metrics_result_t *r)
{
    int i, n4 = 0, nall = 0;
    double s4 = 0, ss4 = 0, sall = 0, ssall = 0;
    memset(r, 0, sizeof *r);
    r->volume_l = m->vol_l;
    r->area_ha = m->area_m2 / 10000.0;
    r->sim_s = m->sim_s;
    r->applied_l_ha = m->area_m2 > 0 ? m->vol_l / r->area_ha : NAN;
    r->dose_error_pct = m->expect4_l > 0 ? (m->vol4_l / m->expect4_l - 1.0) * 100.0 : NAN;
    r->dose_error_all_pct = m->expect_l > 0 ? (m->vol_l / m->expect_l - 1.0) * 100.0 : NAN;
    r->dose_target_pct = m->expect4_l > 0 ? (m->target4_l / m->expect4_l - 1.0) * 100.0 : NAN;
    r->dose_meter_pct = m->expect4_l > 0 ? (m->vol4_l - m->meter4_l) / m->expect4_l * 100.0 : NAN;
    r->dose_ctl_pct = m->expect4_l > 0 ? (m->meter4_l - m->target4_l) / m->expect4_l * 100.0 : NAN;
    r->dose_ctl_stop_pct = m->expect4_l > 0 ? (m->stop_meter4_l - m->stop_target4_l) / m->expect4_l * 100.0 : NAN;
    r->valve_reversals = m->valve_reversals;
    r->valve_reversals_per_min = m->spray_s > 0 ? m->valve_reversals_spray / (m->spray_s / 60.0) : NAN;
    r->valve_travel_strokes = m->valve_travel;
    r->pressure_min_bar = m->p_seen ? m->p_min : m->p_seen_any ? m->p_min_any : NAN;
    r->pressure_max_bar = m->p_seen ? m->p_max : m->p_seen_any ? m->p_max_any : NAN;

    /* zones: the ratio applied / expected, so a change of rate or width does not count as spread */
    r->zone_error_min_pct = r->zone_error_max_pct = NAN;
    r->zone_error_all_min_pct = r->zone_error_all_max_pct = NAN;
    for (i = 0; i < m->n_zones; i++) {
        const metrics_zone_t *z = &m->zones[i];
        double q, e;
        if (z->expect_l <= 0)
            continue;
        q = z->vol_l / z->expect_l;
        e = (q - 1.0) * 100.0;
        nall++;
        sall += q;
        ssall += q * q;
        if (nall == 1 || e < r->zone_error_all_min_pct)
            r->zone_error_all_min_pct = e;
        if (nall == 1 || e > r->zone_error_all_max_pct)
            r->zone_error_all_max_pct = e;
        if (METRICS_ZONE_M / z->time_s * 3.6 >= METRICS_MIN_KMH) {
            n4++;
            s4 += q;
            ss4 += q * q;
            if (n4 == 1 || e < r->zone_error_min_pct)
                r->zone_error_min_pct = e;
            if (n4 == 1 || e > r->zone_error_max_pct)
                r->zone_error_max_pct = e;
        }
    }
    r->zones_used = n4;
    r->zones_all = nall;
    /* coefficient of variation with the sample standard deviation (n - 1) */
#define CV(n, s, ss) ((n) > 1 && (s) > 0 ? sqrt(fmax(0.0, ((ss) - (s) * (s) / (n)) / ((n) - 1))) / ((s) / (n)) * 100.0 : NAN)
    r->cv_pct = CV(n4, s4, ss4);
    r->cv_all_pct = CV(nall, sall, ssall);
#undef CV

    free(m->steps);
    m->steps = NULL;
    {
        metrics_series_t ser;
        ser.ref = m->ref;
        ser.target = m->target;
        ser.flow = m->flow;
        ser.work = m->work;
        ser.spray = m->spray;
        ser.n = m->n_samples;
        ser.dt_s = m->sample_dt_s;
        r->n_steps = metrics_find_steps(&ser, NULL, 0);
        if (r->n_steps > 0) {
            m->steps = malloc(sizeof *m->steps * (size_t)r->n_steps);
            if (!m->steps) {
                fprintf(stderr, "metrics: out of memory\n");
                abort();
            }
            metrics_find_steps(&ser, m->steps, r->n_steps);
        }
        metrics_start(&ser, &r->start_s, &r->start_max_s);
    }
    r->steps = m->steps;
    step_means(m->steps, r->n_steps, r);
}

static void steps_array(FILE *f, const metrics_step_t *st, int n)
{
    int i;
    fputs("\"steps\":[", f);
    for (i = 0; i < n; i++) {
        const metrics_step_t *s = &st[i];
        fputc('{', f);
        num(f, "t_s", s->t_s, 1);
        num(f, "from_lpm", s->from_lpm, 1);
        num(f, "to_lpm", s->to_lpm, 1);
        num(f, "rise_s", s->rise_s, 1);
        num(f, "overshoot_pct", s->overshoot_pct, 1);
        num(f, "settle_5pct_s", s->settle_5pct_s, 1);
        num(f, "settle_2pct_s", s->settle_2pct_s, 1);
        fprintf(f, "\"settled_5pct\":%s,\"settled_2pct\":%s,", s->settled_5 ? "true" : "false",
                s->settled_2 ? "true" : "false");
        num(f, "sse_pct", s->sse_pct, 0);
        fprintf(f, "}%s", i + 1 < n ? "," : "");
    }
    fputs("],", f);
}

/* The means of a set of steps (NaN for none). */
static void step_means(const metrics_step_t *st, int n, metrics_result_t *r)
{
    int i;
    double so = 0, ss = 0, mo = 0, ms = 0;
    r->overshoot_mean_pct = r->overshoot_max_pct = r->settle_mean_s = r->settle_max_s = NAN;
    if (n <= 0)
        return;
    for (i = 0; i < n; i++) {
        so += st[i].overshoot_pct;
        ss += st[i].settle_5pct_s;
        mo = fmax(mo, st[i].overshoot_pct);
        ms = fmax(ms, st[i].settle_5pct_s);
    }
    r->overshoot_mean_pct = so / n;
    r->overshoot_max_pct = mo;
    r->settle_mean_s = ss / n;
    r->settle_max_s = ms;
}

void metrics_steps_json(FILE *f, const metrics_series_t *s)
{
    metrics_result_t r;
    metrics_step_t *st = NULL;
    int n = metrics_find_steps(s, NULL, 0);
    memset(&r, 0, sizeof r);
    if (n > 0) {
        st = malloc(sizeof *st * (size_t)n);
        if (!st) {
            fprintf(stderr, "metrics: out of memory\n");
            abort();
        }
        metrics_find_steps(s, st, n);
    }
    step_means(st, n, &r);
    metrics_start(s, &r.start_s, &r.start_max_s);
    fputc('{', f);
    steps_array(f, st, n);
    num(f, "overshoot_mean_pct", r.overshoot_mean_pct, 1);
    num(f, "overshoot_max_pct", r.overshoot_max_pct, 1);
    num(f, "settle_mean_s", r.settle_mean_s, 1);
    num(f, "settle_max_s", r.settle_max_s, 1);
    fprintf(f, "\"steps_scored\":%d,", n);
    num(f, "start_s", r.start_s, 1);
    num(f, "start_max_s", r.start_max_s, 1);
    fprintf(f, "\"samples\":%d}\n", s->n);
    free(st);
}

void metrics_samples_csv(FILE *f, const metrics_t *m)
{
    int k;
    fputs("t_s,ref_lpm,target_lpm,flow_lpm,work,spray\n", f);
    for (k = 0; k < m->n_samples; k++)
        fprintf(f, "%.1f,%.17g,%.17g,%.17g,%d,%d\n", k * m->sample_dt_s, m->ref[k], m->target[k], m->flow[k],
                m->work[k], m->spray[k]);
}

void metrics_json(FILE *f, const metrics_t *m, const metrics_result_t *r, const char *extra, double wall_s)
{
    int i;
    fputc('{', f);
    if (extra)
        fputs(extra, f);
    num(f, "applied_l_ha", r->applied_l_ha, 1);
    num(f, "dose_error_pct", r->dose_error_pct, 1);
    num(f, "dose_error_all_pct", r->dose_error_all_pct, 1);
    num(f, "dose_target_pct", r->dose_target_pct, 1);
    num(f, "dose_meter_pct", r->dose_meter_pct, 1);
    num(f, "dose_ctl_pct", r->dose_ctl_pct, 1);
    num(f, "dose_ctl_stop_pct", r->dose_ctl_stop_pct, 1);
    num(f, "valve_reversals", r->valve_reversals, 1);
    num(f, "valve_reversals_per_min", r->valve_reversals_per_min, 1);
    num(f, "valve_travel_strokes", r->valve_travel_strokes, 1);
    num(f, "cv_pct", r->cv_pct, 1);
    num(f, "cv_all_pct", r->cv_all_pct, 1);
    num(f, "zone_error_min_pct", r->zone_error_min_pct, 1);
    num(f, "zone_error_max_pct", r->zone_error_max_pct, 1);
    num(f, "zone_error_all_min_pct", r->zone_error_all_min_pct, 1);
    num(f, "zone_error_all_max_pct", r->zone_error_all_max_pct, 1);
    fprintf(f, "\"zones\":%d,\"zones_v4\":%d,", r->zones_all, r->zones_used);
    steps_array(f, r->steps, r->n_steps);
    num(f, "overshoot_mean_pct", r->overshoot_mean_pct, 1);
    num(f, "overshoot_max_pct", r->overshoot_max_pct, 1);
    num(f, "settle_mean_s", r->settle_mean_s, 1);
    num(f, "settle_max_s", r->settle_max_s, 1);
    fprintf(f, "\"steps_scored\":%d,", r->n_steps);
    num(f, "start_s", r->start_s, 1);
    num(f, "start_max_s", r->start_max_s, 1);
    num(f, "pressure_min_bar", r->pressure_min_bar, 1);
    num(f, "pressure_max_bar", r->pressure_max_bar, 1);
    num(f, "volume_l", r->volume_l, 1);
    num(f, "area_ha", r->area_ha, 1);
    fputs("\"alarms\":[", f);
    for (i = 0; i < m->n_alarms; i++)
        fprintf(f, "{\"t_s\":%.3f,\"code\":\"%s\"}%s", m->alarms[i].t_s, m->alarms[i].code,
                i + 1 < m->n_alarms ? "," : "");
    fputs("],", f);
    num(f, "sim_s", r->sim_s, 1);
    num(f, "wall_s", wall_s, 1);
    num(f, "speed_x_realtime", wall_s > 0 ? r->sim_s / wall_s : NAN, 0);
    fputs("}\n", f);
}

void metrics_zones_csv(FILE *f, const metrics_t *m)
{
    int i;
    fputs("zone,start_m,vol_l,expect_l,time_s,mean_kmh,error_pct\n", f);
    for (i = 0; i < m->n_zones; i++) {
        const metrics_zone_t *z = &m->zones[i];
        fprintf(f, "%d,%.0f,%.5f,%.5f,%.3f,%.3f,", i, i * METRICS_ZONE_M, z->vol_l, z->expect_l, z->time_s,
                z->time_s > 0 ? METRICS_ZONE_M / z->time_s * 3.6 : 0.0);
        if (z->expect_l > 0)
            fprintf(f, "%.3f\n", (z->vol_l / z->expect_l - 1.0) * 100.0);
        else
            fputs("\n", f);
    }
}

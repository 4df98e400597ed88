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
    free(m->target);
    free(m->flow);
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

void metrics_target(metrics_t *m, double dt_s, double v_mps, double nozzle_lpm, double target_lpm, int at_stop)
{
    if (v_mps * 3.6 < METRICS_MIN_KMH)
        return;
    m->target4_l += target_lpm * dt_s / 60.0;
    if (at_stop) {
        m->stop_vol4_l += nozzle_lpm * dt_s / 60.0;
        m->stop_target4_l += target_lpm * dt_s / 60.0;
    }
}

void metrics_valve(metrics_t *m, double drive, double theta)
{
    int s = drive > 0 ? 1 : drive < 0 ? -1 : 0;
    if (s != 0) {
        if (m->valve_dir != 0 && s != m->valve_dir)
            m->valve_reversals++;
        m->valve_dir = s;
    }
    if (m->valve_seen)
        m->valve_travel += theta > m->valve_theta ? theta - m->valve_theta : m->valve_theta - theta;
    m->valve_theta = theta;
    m->valve_seen = 1;
}

void metrics_sample(metrics_t *m, double target_lpm, double flow_lpm)
{
    if (m->n_samples + 1 > m->cap_samples) {
        int cap = m->cap_samples;   /* both arrays grow to the same capacity */
        m->target = grow(m->target, &cap, m->n_samples + 1, sizeof *m->target);
        m->flow = grow(m->flow, &m->cap_samples, m->n_samples + 1, sizeof *m->flow);
    }
    m->target[m->n_samples] = target_lpm;
    m->flow[m->n_samples] = flow_lpm;
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
    double first, last;             /* level at its start (mean of the first window) and at its end */
} plateau_t;

static double absd(double x)
{
    return x < 0 ? -x : x;
}

static double maxd(double a, double b)
{
    return a > b ? a : b;
}

/* Time (in samples, fractional) of the first upward crossing of `level` by p[] from k0 on;
 * -1 when it never gets there. */
static double crossing(const double *p, int k0, int k1, double level)
{
    int k;
    for (k = k0; k <= k1; k++)
        if (p[k] >= level) {
            if (k == k0 || p[k] == p[k - 1])
                return k;
            return (k - 1) + (level - p[k - 1]) / (p[k] - p[k - 1]);
        }
    return -1;
}

/* Settling: time from k0 until y stays within tol of `to` up to k1 (the crossing interpolated
 * between the last sample outside and the next one). */
static double settle(const double *y, int k0, int k1, double to, double tol, int *settled)
{
    int k, last = -1;
    double e0, e1;
    for (k = k0; k <= k1; k++)
        if (absd(y[k] - to) > tol)
            last = k;
    *settled = last < k1;
    if (last < 0)
        return 0.0;
    if (last == k1)
        return (double)(k1 - k0 + 1);
    e0 = absd(y[last] - to);
    e1 = absd(y[last + 1] - to);
    return (last - k0) + (e0 - tol) / (e0 - e1);
}

int metrics_find_steps(const double *T, const double *Y, int n, double dt, metrics_step_t *out, int max)
{
    int W = (int)floor(METRICS_STEADY_S / dt + 0.5);
    int k, np = 0, count = 0, i;
    plateau_t *pl;
    double *prog;

    if (n <= W || W < 1)
        return 0;
    pl = malloc(sizeof *pl * (size_t)(n / (W + 1) + 2));
    prog = malloc(sizeof *prog * (size_t)n);
    if (!pl || !prog) {
        free(pl);
        free(prog);
        return 0;
    }
    /* plateaus: runs of samples whose trailing 2 s window is within 1 % of the sample */
    k = W;
    while (k < n) {
        double lo = T[k], hi = T[k], thr;
        int j;
        for (j = k - W; j < k; j++) {
            lo = T[j] < lo ? T[j] : lo;
            hi = T[j] > hi ? T[j] : hi;
        }
        thr = METRICS_STEADY_FRAC * maxd(absd(T[k]), 1.0);
        if (hi - lo <= thr) {
            /* start of a run: it covers [k - W, ...]; extend while steady */
            int a = k - W, b = k, mm;
            double s = 0;
            for (j = a; j <= k; j++)
                s += T[j];
            while (b + 1 < n) {
                double l2 = T[b + 1], h2 = T[b + 1];
                for (j = b + 1 - W; j <= b; j++) {
                    l2 = T[j] < l2 ? T[j] : l2;
                    h2 = T[j] > h2 ? T[j] : h2;
                }
                if (h2 - l2 > METRICS_STEADY_FRAC * maxd(absd(T[b + 1]), 1.0))
                    break;
                b++;
            }
            mm = np;
            /* a plateau within 5 % of the previous one continues it (no change between them) */
            if (np > 0) {
                double from = pl[np - 1].last, to = s / (W + 1);
                if (absd(to - from) <= METRICS_CHANGE_FRAC * maxd(absd(from), absd(to))) {
                    pl[np - 1].b = b;
                    pl[np - 1].last = T[b];
                    k = b + 1;
                    continue;
                }
            }
            pl[mm].a = a;
            pl[mm].b = b;
            pl[mm].first = s / (W + 1);
            pl[mm].last = T[b];
            np++;
            k = b + 1;
        } else {
            k++;
        }
    }
    /* one change between each two plateaus */
    for (i = 1; i < np; i++) {
        metrics_step_t st;
        double from = pl[i - 1].last, to = pl[i].first, ch = to - from, sgn = ch > 0 ? 1.0 : -1.0;
        int k0 = pl[i].a, k1 = pl[i].b, kb = pl[i - 1].b, nlast;
        double c10, c90, over = 0.0, tol, s;
        for (k = kb; k <= k1; k++)
            prog[k] = (Y[k] - from) / ch;
        c10 = crossing(prog, kb, k1, 0.1);
        c90 = c10 < 0 ? -1 : crossing(prog, kb, k1, 0.9);
        st.t_s = k0 * dt;
        st.from_lpm = from;
        st.to_lpm = to;
        st.rise_s = (c10 >= 0 && c90 >= 0) ? (c90 - c10) * dt : NAN;
        for (k = k0; k <= k1; k++) {
            double o = (Y[k] - to) * sgn / absd(ch) * 100.0;
            over = o > over ? o : over;
        }
        st.overshoot_pct = over;
        tol = absd(to) > 0 ? absd(to) : absd(from);
        st.settle_5pct_s = settle(Y, k0, k1, to, 0.05 * tol, &st.settled_5) * dt;
        st.settle_2pct_s = settle(Y, k0, k1, to, 0.02 * tol, &st.settled_2) * dt;
        nlast = (int)floor(0.2 * (k1 - k0 + 1));
        if (nlast < 1)
            nlast = 1;
        s = 0;
        for (k = k1 - nlast + 1; k <= k1; k++)
            s += Y[k] - to;
        st.sse_pct = to != 0 ? s / nlast / absd(to) * 100.0 : NAN;
        if (count < max)
            out[count] = st;
        count++;
    }
    free(pl);
    free(prog);
    return count;
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
    r->dose_ctl_pct = m->expect4_l > 0 ? (m->vol4_l - m->target4_l) / m->expect4_l * 100.0 : NAN;
    r->dose_ctl_stop_pct = m->expect4_l > 0 ? (m->stop_vol4_l - m->stop_target4_l) / m->expect4_l * 100.0 : NAN;
    r->valve_reversals = m->valve_reversals;
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
    r->n_steps = metrics_find_steps(m->target, m->flow, m->n_samples, m->sample_dt_s, NULL, 0);
    if (r->n_steps > 0) {
        m->steps = malloc(sizeof *m->steps * (size_t)r->n_steps);
        if (!m->steps) {
            fprintf(stderr, "metrics: out of memory\n");
            abort();
        }
        metrics_find_steps(m->target, m->flow, m->n_samples, m->sample_dt_s, m->steps, r->n_steps);
    }
    r->steps = m->steps;
    r->overshoot_mean_pct = r->overshoot_max_pct = r->settle_mean_s = r->settle_max_s = NAN;
    if (r->n_steps > 0) {
        double so = 0, ss = 0, mo = 0, ms = 0;
        for (i = 0; i < r->n_steps; i++) {
            so += m->steps[i].overshoot_pct;
            ss += m->steps[i].settle_5pct_s;
            mo = fmax(mo, m->steps[i].overshoot_pct);
            ms = fmax(ms, m->steps[i].settle_5pct_s);
        }
        r->overshoot_mean_pct = so / r->n_steps;
        r->overshoot_max_pct = mo;
        r->settle_mean_s = ss / r->n_steps;
        r->settle_max_s = ms;
    }
}

static void num(FILE *f, const char *key, double v, int comma)
{
    if (isfinite(v))
        fprintf(f, "\"%s\":%.6g%s", key, v, comma ? "," : "");
    else
        fprintf(f, "\"%s\":null%s", key, comma ? "," : "");
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
    num(f, "dose_ctl_pct", r->dose_ctl_pct, 1);
    num(f, "dose_ctl_stop_pct", r->dose_ctl_stop_pct, 1);
    num(f, "valve_reversals", r->valve_reversals, 1);
    num(f, "valve_travel_strokes", r->valve_travel_strokes, 1);
    num(f, "cv_pct", r->cv_pct, 1);
    num(f, "cv_all_pct", r->cv_all_pct, 1);
    num(f, "zone_error_min_pct", r->zone_error_min_pct, 1);
    num(f, "zone_error_max_pct", r->zone_error_max_pct, 1);
    num(f, "zone_error_all_min_pct", r->zone_error_all_min_pct, 1);
    num(f, "zone_error_all_max_pct", r->zone_error_all_max_pct, 1);
    fprintf(f, "\"zones\":%d,\"zones_v4\":%d,", r->zones_all, r->zones_used);
    fputs("\"steps\":[", f);
    for (i = 0; i < r->n_steps; i++) {
        const metrics_step_t *s = &r->steps[i];
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
        fprintf(f, "}%s", i + 1 < r->n_steps ? "," : "");
    }
    fputs("],", f);
    num(f, "overshoot_mean_pct", r->overshoot_mean_pct, 1);
    num(f, "overshoot_max_pct", r->overshoot_max_pct, 1);
    num(f, "settle_mean_s", r->settle_mean_s, 1);
    num(f, "settle_max_s", r->settle_max_s, 1);
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

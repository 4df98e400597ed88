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
    double vol = nozzle_lpm * dt_s * (1.0 / 60);        /* reciprocals: no division a tick */
    double area = dist * width_m;
    double expect = rate_l_ha * area * (1.0 / 10000);
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
    if (!(dist > 0.0 && m->zone_dist_m + dist >= METRICS_ZONE_M)) {
        m->cur.vol_l += vol;        /* the whole slice in the zone (most ticks) */
        m->cur.expect_l += expect;
        m->cur.time_s += dt_s;
        m->zone_dist_m += dist;
        return;
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

void metrics_target(metrics_t *m, double dt_s, double v_mps, double meter_lpm, double target_lpm, int at)
{
    if (v_mps * 3.6 < METRICS_MIN_KMH)
        return;
    double dt_min = dt_s * (1.0 / 60);
    m->target4_l += target_lpm * dt_min;
    m->meter4_l += meter_lpm * dt_min;
    if (at & METRICS_AT_STOP) {
        m->stop_meter4_l += meter_lpm * dt_min;
        m->stop_target4_l += target_lpm * dt_min;
    }
    if (at & METRICS_AT_START) {
        m->start_meter4_l += meter_lpm * dt_min;
        m->start_target4_l += target_lpm * dt_min;
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

void metrics_alarm(metrics_t *m, double t_s, const char *code, const char *text)
{
    char *t;
    m->alarms = grow(m->alarms, &m->cap_alarms, m->n_alarms + 1, sizeof *m->alarms);
    m->alarms[m->n_alarms].t_s = t_s;
    snprintf(m->alarms[m->n_alarms].code, sizeof m->alarms[0].code, "%s", code);
    snprintf(m->alarms[m->n_alarms].text, sizeof m->alarms[0].text, "%s", text ? text : "");
    for (t = m->alarms[m->n_alarms].text; *t; t++)
        if (*t == '"' || *t == '\\' || (unsigned char)*t < 32)
            *t = '\'';                /* the JSON string stays plain */
    m->n_alarms++;
}

static void step_means(const metrics_step_t *st, int n, metrics_result_t *r);

int metrics_dose_wrong(const metrics_watch_t *w)
{
    if (!w->sections_on)
        return 0;
    if (!w->spraying)
        return w->v_kmh >= METRICS_SHUT_KMH;
    if (w->v_kmh < METRICS_STAND_KMH)
        return w->boom_lpm > 0.0;
    if (w->width_m <= 0.0 || w->rate_l_ha <= 0.0)
        return 1;
    /* L/ha = L/min / (km/h x m) x 600 */
    return fabs(w->boom_lpm * 600.0 / (w->v_kmh * w->width_m) / w->rate_l_ha - 1.0) > METRICS_WRONG_FRAC;
}

static void silent_end(metrics_t *m)
{
    if (m->silent_run_s >= METRICS_WRONG_MIN_S - 1e-9) {
        m->silent_total_s += m->silent_run_s;
        if (m->silent_run_s > m->silent_max_s)
            m->silent_max_s = m->silent_run_s;
    }
    m->silent_run_s = 0.0;
}

void metrics_watch(metrics_t *m, double dt_s, const metrics_watch_t *w)
{
    if (!w->told && metrics_dose_wrong(w))
        m->silent_run_s += dt_s;
    else
        silent_end(m);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

double metrics_ripple_p95(const metrics_series_t *s)
{
    int hold = (int)(METRICS_RIPPLE_HOLD_S / s->dt_s + 0.5), k, j, n = 0;
    double *e, p95;
    if (s->n <= hold)
        return NAN;
    e = malloc(sizeof *e * (size_t)s->n);
    if (!e) {
        fprintf(stderr, "metrics: out of memory\n");
        abort();
    }
    for (k = hold; k < s->n; k++) {
        double band = METRICS_RIPPLE_FRAC * s->ref[k];
        if (!(s->target[k] > 0.0) || !(s->ref[k] > 0.0))
            continue;
        for (j = k; j >= k - hold; j--)
            if (!s->work[j] || (s->spray && !s->spray[j]) || fabs(s->ref[j] - s->ref[k]) > band)
                break;
        if (j < k - hold)
            e[n++] = fabs(s->flow[k] / s->target[k] - 1.0);
    }
    if (n == 0) {
        free(e);
        return NAN;
    }
    qsort(e, (size_t)n, sizeof *e, cmp_double);
    p95 = e[(int)ceil(0.95 * n) - 1] * 100.0;
    free(e);
    return p95;
}

static void num(FILE *f, const char *key, double v, int comma)
{
    if (isfinite(v))
        fprintf(f, "\"%s\":%.6g%s", key, v, comma ? "," : "");
    else
        fprintf(f, "\"%s\":null%s", key, comma ? "," : "");
}

/* ---- the figures -------------------------------------------------------------------------------- */
/* The zones' figures: the ratio applied / expected, so a change of rate or width does not count
 * as spread; the zones driven at METRICS_MIN_KMH or faster, and all of them. */
static void zones_finish(const metrics_t *m, metrics_result_t *r)
{
    int i, n4 = 0, nall = 0;
    double s4 = 0, ss4 = 0, sall = 0, ssall = 0;
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
}

void metrics_finish(metrics_t *m, metrics_result_t *r)
{
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
    r->dose_ctl_start_pct = m->expect4_l > 0 ? (m->start_meter4_l - m->start_target4_l) / m->expect4_l * 100.0 : NAN;
    r->valve_reversals = m->valve_reversals;
    r->valve_reversals_per_min = m->spray_s > 0 ? m->valve_reversals_spray / (m->spray_s / 60.0) : NAN;
    r->valve_travel_strokes = m->valve_travel;
    r->pressure_min_bar = m->p_seen ? m->p_min : m->p_seen_any ? m->p_min_any : NAN;
    r->pressure_max_bar = m->p_seen ? m->p_max : m->p_seen_any ? m->p_max_any : NAN;

    zones_finish(m, r);

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
        r->ripple_p95_pct = metrics_ripple_p95(&ser);
    }
    silent_end(m);
    r->silent_wrong_s = m->silent_max_s;
    r->silent_wrong_total_s = m->silent_total_s;
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

void metrics_json(FILE *f, const metrics_t *m, const metrics_result_t *r, const char *extra, double wall_s,
                  double cpu_s)
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
    num(f, "dose_ctl_start_pct", r->dose_ctl_start_pct, 1);
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
    num(f, "silent_wrong_s", r->silent_wrong_s, 1);
    num(f, "silent_wrong_total_s", r->silent_wrong_total_s, 1);
    num(f, "ripple_p95_pct", r->ripple_p95_pct, 1);
    num(f, "pressure_min_bar", r->pressure_min_bar, 1);
    num(f, "pressure_max_bar", r->pressure_max_bar, 1);
    num(f, "volume_l", r->volume_l, 1);
    num(f, "area_ha", r->area_ha, 1);
    fputs("\"alarms\":[", f);
    for (i = 0; i < m->n_alarms; i++)
        fprintf(f, "{\"t_s\":%.3f,\"code\":\"%s\",\"text\":\"%s\"}%s", m->alarms[i].t_s, m->alarms[i].code,
                m->alarms[i].text, i + 1 < m->n_alarms ? "," : "");
    fputs("],", f);
    num(f, "sim_s", r->sim_s, 1);
    num(f, "wall_s", wall_s, 1);
    num(f, "cpu_s", cpu_s, 1);
    num(f, "speed_x_realtime", wall_s > 0 ? r->sim_s / wall_s : NAN, 0);
    fputs("}\n", f);
}

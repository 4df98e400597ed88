/* summary.c: a run's figures for a person to read (summary.h). */
#include <math.h>
#include "summary.h"
#include "ctl.h"
#include "params.h"

#define SUMMARY_RULE "--------------------------------------------------"

/* v with the given decimals, or "n/a" when undefined */
static const char *num(char *buf, size_t n, double v, int decimals)
{
    if (isnan(v) || isinf(v))
        snprintf(buf, n, "n/a");
    else
        snprintf(buf, n, "%.*f", decimals, v);
    return buf;
}

static void row(FILE *f, const char *label, double v)
{
    char b[32];
    fprintf(f, "%-40s %9s\n", label, num(b, sizeof b, v, 2));
}

/* 1 when an event of the scenario changes the set rate during the run */
static int rate_changes(const scenario_t *s)
{
    int i;
    for (i = 0; i < s->n_events; i++)
        if (s->events[i].kind == EV_RATE || s->events[i].kind == EV_PRESET || s->events[i].kind == EV_NUDGE)
            return 1;
    return 0;
}

void sim_summary(const sim_t *sim, const metrics_result_t *r, FILE *f)
{
    const scenario_t *s = sim->scn;
    const metrics_t *m = &sim->metrics;
    char label[64], a[32], b[32], c[32];
    int i;

    fprintf(f, "%s, controller %s, seed %llu\n", s->name, ctl_name((uint8_t)param_v[P_CONTROLLER]),
            (unsigned long long)s->seed);
    fprintf(f, "%-40s %9s\n%s\n", "figure", "this run", SUMMARY_RULE);
    row(f, "mean overshoot, %", r->overshoot_mean_pct);
    row(f, "mean settling time, s", r->settle_mean_s);
    snprintf(label, sizeof label, "applied dose, L/ha (set %g%s)", s->param[P_RATE] * 0.1,
             rate_changes(s) ? " at first" : "");
    row(f, label, r->applied_l_ha);
    row(f, "dose error, % (v >= 4 km/h)", r->dose_error_pct);
    row(f, "dose error, % (whole run)", r->dose_error_all_pct);
    row(f, "CV of 5 m zones, % (v >= 4 km/h)", r->cv_pct);
    row(f, "CV of 5 m zones, % (whole run)", r->cv_all_pct);
    row(f, "zone error min, %", r->zone_error_min_pct);
    row(f, "zone error max, %", r->zone_error_max_pct);
    fprintf(f, "%s\n", SUMMARY_RULE);
    fprintf(f, "changes of the target found: %d (max overshoot %s %%, max settling %s s)\n", r->n_steps,
            num(a, sizeof a, r->overshoot_max_pct, 2), num(b, sizeof b, r->settle_max_s, 2));
    fprintf(f, "start: %s s from the boom's first opening to the flow within 5 %% of the target\n",
            num(a, sizeof a, r->start_s, 2));
    fprintf(f, "valve: %s reversals a minute of spraying, %s strokes travelled\n",
            num(a, sizeof a, r->valve_reversals_per_min, 1), num(b, sizeof b, r->valve_travel_strokes, 2));
    fprintf(f, "pressure at v >= 4 km/h: %s .. %s bar; volume %s L over %s ha\n",
            num(a, sizeof a, r->pressure_min_bar, 2), num(b, sizeof b, r->pressure_max_bar, 2),
            num(c, sizeof c, r->volume_l, 2), num(label, sizeof label, r->area_ha, 2));
    fprintf(f, "alarms:");
    for (i = 0; i < m->n_alarms; i++)
        fprintf(f, "%s %s at %.1f s", i ? "," : "", m->alarms[i].code, m->alarms[i].t_s);
    fprintf(f, "%s\n", m->n_alarms ? "" : " none");
}

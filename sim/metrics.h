/* metrics.h: the control-quality figures of PLANT.md (dose, 5 m zones, steps of the target, pressure, alarms). */
#ifndef SIM_METRICS_H
#define SIM_METRICS_H

#include <stdio.h>

#define METRICS_ZONE_M 5.0          /* zone length along the travel */
#define METRICS_MIN_KMH 4.0         /* "v >= 4 km/h" parts of the run */
#define METRICS_STEADY_S 2.0        /* a plateau: target steady within 1 % for 2 s */
#define METRICS_STEADY_FRAC 0.01
#define METRICS_CHANGE_FRAC 0.05    /* a change: more than 5 % (of the larger of the two levels) */

/* One 5 m zone of true travel. */
typedef struct {
    double vol_l;                   /* what left the nozzles while the boom crossed it */
    double expect_l;                /* set rate x open boom width x 5 m */
    double time_s;                  /* time to travel it: mean speed = 5 m / time_s */
} metrics_zone_t;

/* One change of the target flow (PLANT.md "steps"). Times from the moment the target reached
 * its new plateau; NaN where a figure does not exist (never rose, target 0). */
typedef struct {
    double t_s;                     /* when the target reached the new plateau */
    double from_lpm, to_lpm;
    double rise_s;                  /* 10 % to 90 % of the change (searched from the end of the old plateau) */
    double overshoot_pct;           /* excursion beyond the new level, % of the change (>= 0) */
    double settle_5pct_s;           /* into and staying within +-5 % of the new level */
    double settle_2pct_s;           /* ... +-2 % */
    int settled_5, settled_2;       /* 0: still outside at the end of the plateau (time is a lower bound) */
    double sse_pct;                 /* mean error over the last 20 % of the plateau, % of the new level */
} metrics_step_t;

typedef struct {
    double t_s;
    char code[24];
} metrics_alarm_t;

typedef struct {
    /* totals (whole run) and the part with v >= 4 km/h */
    double vol_l, area_m2, expect_l;
    double vol4_l, area4_m2, expect4_l;
    /* the dose error's split (v >= 4 km/h): the target flow the controller was given, and the
     * nozzle and target volumes while the bypass valve sat at an end stop */
    double target4_l, stop_vol4_l, stop_target4_l;
    /* the valve's motor: direction changes (drives of the other sign than the last nonzero one)
     * and the stroke the valve travelled (metrics_valve) */
    int valve_dir, valve_reversals, valve_seen;
    double valve_theta, valve_travel;
    double p_min, p_max;            /* while spraying at v >= 4 km/h ... */
    int p_seen;
    double p_min_any, p_max_any;    /* ... or, for a run that never gets there, while spraying */
    int p_seen_any;
    double sim_s;
    /* zones: the one being crossed, and the finished ones */
    double zone_dist_m;
    metrics_zone_t cur;
    metrics_zone_t *zones;
    int n_zones, cap_zones;
    /* target and flow sampled every sample_dt_s, for the steps */
    double sample_dt_s;
    double *target, *flow;
    int n_samples, cap_samples;
    /* the steps found by metrics_finish */
    metrics_step_t *steps;
    /* alarms */
    metrics_alarm_t *alarms;
    int n_alarms, cap_alarms;
} metrics_t;

/* The figures, from metrics_finish. NaN where undefined (no area, no zone...). */
typedef struct {
    double applied_l_ha, dose_error_pct, dose_error_all_pct;
    /* dose_error_pct = dose_target_pct + dose_ctl_pct: the target's own error against the set
     * rate over the true area (speed measurement, the minimum-flow rule), and what the flow
     * delivered beyond the target; dose_ctl_stop_pct is the part of the latter while the valve
     * sat at an end stop (no controller can change it) */
    double dose_target_pct, dose_ctl_pct, dose_ctl_stop_pct;
    /* the valve's wear: motor reversals (each takes up the backlash) and strokes travelled */
    double valve_reversals, valve_travel_strokes;
    double cv_pct, cv_all_pct, zone_error_min_pct, zone_error_max_pct;
    double zone_error_all_min_pct, zone_error_all_max_pct;
    int zones_used, zones_all;      /* zones at v >= 4 km/h, all zones */
    metrics_step_t *steps;          /* owned by the metrics_t */
    int n_steps;
    double overshoot_mean_pct, overshoot_max_pct, settle_mean_s, settle_max_s;
    double pressure_min_bar, pressure_max_bar, volume_l, area_ha, sim_s;
} metrics_result_t;

void metrics_init(metrics_t *m, double sample_dt_s);
void metrics_free(metrics_t *m);
/* One slice of time: true ground speed, the flow leaving the nozzles, the open boom width, the
 * set rate, the boom pressure and whether the boom sprays. Zones are split exactly at 5 m. */
void metrics_add(metrics_t *m, double dt_s, double v_mps, double nozzle_lpm, double width_m,
                 double rate_l_ha, double p_bar, int spraying);
/* One sample (every sample_dt_s, the first at time 0) of the target and the actual flow. */
void metrics_sample(metrics_t *m, double target_lpm, double flow_lpm);
/* An alarm raised at t. */
void metrics_alarm(metrics_t *m, double t_s, const char *code);
/* Work out the figures (steps are kept in m until metrics_free). */
/* The same slice seen by the controller: the target flow it was given and whether the valve sat
 * at an end stop (for the dose error's split; call it beside metrics_add, same slice). */
void metrics_target(metrics_t *m, double dt_s, double v_mps, double nozzle_lpm, double target_lpm, int at_stop);
/* The valve motor's drive in this slice (signed duty, 0: off) and the valve's position after it. */
void metrics_valve(metrics_t *m, double drive, double theta);
void metrics_finish(metrics_t *m, metrics_result_t *r);
/* The step analysis alone, on any sampled series: returns the number of changes found (at most
 * max are written). */
int metrics_find_steps(const double *target, const double *flow, int n, double dt_s,
                       metrics_step_t *out, int max);
/* The finished zones as CSV: zone, start_m, vol_l, expect_l, time_s, mean_kmh, error_pct. */
void metrics_zones_csv(FILE *f, const metrics_t *m);
/* The result as one JSON object on one line (keys as in PLANT.md; NaN prints as null).
 * extra (may be NULL) is inserted verbatim after the opening brace, e.g. "\"scenario\":\"x\",". */
void metrics_json(FILE *f, const metrics_t *m, const metrics_result_t *r, const char *extra, double wall_s);

#endif

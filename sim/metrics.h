/* metrics.h: the control-quality figures of docs/SCENARIOS.md (dose, 5 m zones, steps of the target, pressure, alarms). */
#ifndef SIM_METRICS_H
#define SIM_METRICS_H

#include <stdio.h>

#define METRICS_ZONE_M 5.0          /* zone length along the travel */
#define METRICS_MIN_KMH 4.0         /* "v >= 4 km/h" parts of the run */
#define METRICS_STEADY_S 2.0        /* a hold: every trailing 2 s window of the reference within 1 % */
#define METRICS_STEADY_FRAC 0.01
#define METRICS_MERGE_FRAC 0.05     /* neighbouring holds within 5 % of each other are one hold */
#define METRICS_CHANGE_FRAC 0.10    /* a scored change: at least 10 % of the larger of the two levels */
#define METRICS_ARRIVE_FRAC 0.01    /* t_a: the firmware's target within 1 % of the new level */
#define METRICS_END_S 1.0           /* t_e: 1 s before the new hold ends */
#define METRICS_START_BAND 0.05     /* start_s: the flow within 5 % of the target ... */
#define METRICS_START_HOLD_S 2.0    /* ... for 2 s */
#define METRICS_WRONG_FRAC 0.10     /* silent_wrong: the true rate more than 10 % off the set rate ... */
#define METRICS_WRONG_MIN_S 5.0     /* ... untold for 5 s at least */
#define METRICS_STAND_KMH 0.5       /* below this the tractor stands: any liquid out is wrong */
#define METRICS_SHUT_KMH 2.0        /* the boom shut while the sections are on at this speed: wrong */
#define METRICS_RIPPLE_HOLD_S 8.0   /* ripple_p95: samples 8 s into a hold of the reference ... */
#define METRICS_RIPPLE_FRAC 0.01    /* ... every one of those 8 s within 1 % of the sample's */

/* What the operator gets at one instant, for silent_wrong (metrics_watch). */
typedef struct {
    double boom_lpm;                /* out of the nozzles (truth) */
    double v_kmh;                   /* true ground speed */
    double width_m;                 /* the width of the open nozzles that are not clogged */
    double rate_l_ha;               /* the rate the operator set */
    int spraying;                   /* the master boom valve open */
    int sections_on;                /* the operator has a section on */
    int told;                       /* an alarm, warning or notice is shown (or the screen is dark) */
} metrics_watch_t;

/* One 5 m zone of true travel. */
typedef struct {
    double vol_l;                   /* what left the nozzles while the boom crossed it */
    double expect_l;                /* set rate x open boom width x 5 m */
    double time_s;                  /* time to travel it: mean speed = 5 m / time_s */
} metrics_zone_t;

/* One scored change of the target flow (docs/SCENARIOS.md "steps"): between two holds of the
 * reference target, errors against the firmware's target at the same instant. Times from t_c,
 * the first sample after the old hold; NaN where a figure does not exist (never rose). */
typedef struct {
    double t_s;                     /* t_c */
    double from_lpm, to_lpm;        /* the holds' levels (medians of the reference) */
    double rise_s;                  /* the flow from 10 % to 90 % of the change, searched from t_c */
    double overshoot_pct;           /* max over [t_a, t_e] of sign(D) (y - r), % of abs(D) (>= 0) */
    double settle_5pct_s;           /* from t_c until abs(y - r) <= 5 % of the new level up to t_e */
    double settle_2pct_s;           /* ... 2 % */
    int settled_5, settled_2;       /* 0: outside the band at t_e (the time is t_e - t_c) */
    double sse_pct;                 /* mean (y - r) over the last 20 % of [t_a, t_e], % of the new level */
} metrics_step_t;

/* The series the step analysis reads, one entry a sample. */
typedef struct {
    const double *ref;              /* reference target: the firmware's settings at the true wheel speed */
    const double *target;           /* the firmware's target r */
    const double *flow;             /* the true flow y, mean over the sample */
    const unsigned char *work;      /* 1: working speed (measured or given) >= 4 km/h */
    const unsigned char *spray;     /* 1: the boom sprays (start_s); may be NULL */
    int n;
    double dt_s;
} metrics_series_t;

typedef struct {
    double t_s;
    char code[24];
    char text[24];                  /* what the LCD shows ("" when not known) */
} metrics_alarm_t;

typedef struct {
    /* totals (whole run) and the part with v >= 4 km/h */
    double vol_l, area_m2, expect_l;
    double vol4_l, area4_m2, expect4_l;
    /* the dose error's split (v >= 4 km/h): the target flow the controller was given, what a
     * meter true to its calibration would read, and the same while the valve sat at an end stop */
    double target4_l, meter4_l, stop_meter4_l, stop_target4_l, start_meter4_l, start_target4_l;
    /* the valve's wear (metrics_valve): the motor's reversals, those while spraying, the strokes
     * travelled and the time spraying */
    double valve_reversals, valve_reversals_spray, valve_travel, spray_s;
    double valve_rev_last;
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
    /* reference, target and flow sampled every sample_dt_s, for the steps */
    double sample_dt_s;
    double *ref, *target, *flow;
    unsigned char *work, *spray;
    int n_samples, cap_samples;
    /* the steps found by metrics_finish */
    metrics_step_t *steps;
    /* alarms */
    metrics_alarm_t *alarms;
    int n_alarms, cap_alarms;
    /* silent_wrong: the untold wrong stretch running now, the longest and the sum of those >= 5 s */
    double silent_run_s, silent_max_s, silent_total_s;
} metrics_t;

/* The figures, from metrics_finish. NaN where undefined (no area, no zone...). */
typedef struct {
    double applied_l_ha, dose_error_pct, dose_error_all_pct;
    /* dose_error_pct = dose_target_pct + dose_meter_pct + dose_ctl_pct: the target's own error
     * against the set rate over the true area (speed measurement, the minimum-flow rule); what
     * the meter misreports of the nozzles' flow (its K off the calibration, its fall-off below
     * range, a leak after it); and the loop's own share, what a meter true to its calibration
     * reads beyond the target. dose_ctl_stop_pct is the part of the last while the valve sat at
     * an end stop (no controller can change it); dose_ctl_start_pct its part in the start, from
     * power-up until 5 s after the boom first opened (the wait for the pressure, the start-up
     * closing, the first approach) */
    double dose_target_pct, dose_meter_pct, dose_ctl_pct, dose_ctl_stop_pct, dose_ctl_start_pct;
    /* the valve's wear: motor reversals (each takes up the backlash), per minute of spraying
     * (those while spraying), strokes travelled */
    double valve_reversals, valve_reversals_per_min, valve_travel_strokes;
    double cv_pct, cv_all_pct, zone_error_min_pct, zone_error_max_pct;
    double zone_error_all_min_pct, zone_error_all_max_pct;
    int zones_used, zones_all;      /* zones at v >= 4 km/h, all zones */
    metrics_step_t *steps;          /* owned by the metrics_t */
    int n_steps;
    double overshoot_mean_pct, overshoot_max_pct, settle_mean_s, settle_max_s;
    double start_s;                 /* first boom opening until the flow stayed within 5 % of the target for 2 s */
    double start_max_s;             /* the longest over every opening (NaN: never settled) */
    double pressure_min_bar, pressure_max_bar, volume_l, area_ha, sim_s;
    /* the longest stretch of 5 s or more in which the dose was wrong and the operator not told,
     * the sum of such stretches; the 95th percentile of abs(flow / target - 1) on holds, % */
    double silent_wrong_s, silent_wrong_total_s, ripple_p95_pct;
} metrics_result_t;

void metrics_init(metrics_t *m, double sample_dt_s);
void metrics_free(metrics_t *m);
/* One slice of time: true ground speed, the flow leaving the nozzles, the open boom width, the
 * set rate, the boom pressure and whether the boom sprays. Zones are split exactly at 5 m. */
void metrics_add(metrics_t *m, double dt_s, double v_mps, double nozzle_lpm, double width_m,
                 double rate_l_ha, double p_bar, int spraying);
/* One sample (every sample_dt_s, the first at time 0): the reference target, the firmware's
 * target, the true flow, the working speed the firmware uses (km/h) and whether it sprays. */
void metrics_sample(metrics_t *m, double ref_lpm, double target_lpm, double flow_lpm, double work_kmh,
                    int spraying);
/* An alarm raised at t: its code and its LCD text (NULL: not known). */
void metrics_alarm(metrics_t *m, double t_s, const char *code, const char *text);
/* Work out the figures (steps are kept in m until metrics_free). */
/* The same slice seen by the controller: the target flow it was given, what a meter true to
 * its calibration reads, whether the valve sat at an end stop or the run is in its start
 * (METRICS_AT_*: the dose error's split; call it beside metrics_add, same slice). */
#define METRICS_AT_STOP 1           /* at: the valve sat at an end stop */
#define METRICS_AT_START 2          /* at: the start (power-up until 5 s after the boom first opened) */
void metrics_target(metrics_t *m, double dt_s, double v_mps, double meter_lpm, double target_lpm, int at);
/* The valve's wear so far: the motor's reversals and the strokes travelled (running totals from
 * the plant), and whether this slice of dt_s sprays. */
void metrics_valve(metrics_t *m, double dt_s, double reversals, double travel_strokes, int spraying);
void metrics_finish(metrics_t *m, metrics_result_t *r);
/* 1 when what the operator gets is wrong: liquid out while the tractor stands; the true rate
 * (boom flow over true speed and the flowing width) more than 10 % off the set rate while the
 * boom is open with a section on; the boom shut while a section is on at 2 km/h or more. */
int metrics_dose_wrong(const metrics_watch_t *w);
/* One slice of dt_s (the simulator: every sample): a wrong stretch grows while the dose is wrong
 * and the operator is not told, and ends otherwise. */
void metrics_watch(metrics_t *m, double dt_s, const metrics_watch_t *w);
/* ripple_p95_pct of a series: over the samples that spray at working speed with the reference
 * within 1 % of theirs for the 8 s before, the 95th percentile (nearest rank) of
 * abs(flow / target - 1), in %; NaN when there is none. */
double metrics_ripple_p95(const metrics_series_t *s);
/* The step analysis alone, on any sampled series: returns the number of scored changes (at most
 * max are written). */
int metrics_find_steps(const metrics_series_t *s, metrics_step_t *out, int max);
/* start_s of the series: the first opening (first) and the longest (max); NaN where none. */
void metrics_start(const metrics_series_t *s, double *first, double *longest);
/* The step series as CSV: t_s, ref_lpm, target_lpm, flow_lpm, work, spray (one row a sample). */
void metrics_samples_csv(FILE *f, const metrics_t *m);
/* The step figures of a series alone (steps, their means, steps_scored, start_s) as one JSON
 * object on one line: what `score` prints for a series read back from CSV. */
void metrics_steps_json(FILE *f, const metrics_series_t *s);
/* The finished zones as CSV: zone, start_m, vol_l, expect_l, time_s, mean_kmh, error_pct. */
void metrics_zones_csv(FILE *f, const metrics_t *m);
/* One of those CSVs (write: metrics_samples_csv or metrics_zones_csv) into the file path; -1,
 * said on stderr after "prog: ", when it cannot be written. */
int metrics_write_csv(const char *prog, const char *path, void (*write)(FILE *, const metrics_t *),
                      const metrics_t *m);
/* The result as one JSON object on one line (keys as in docs/SCENARIOS.md; NaN prints as null).
 * extra (may be NULL) is inserted verbatim after the opening brace, e.g. "\"scenario\":\"x\",". */
void metrics_json(FILE *f, const metrics_t *m, const metrics_result_t *r, const char *extra, double wall_s,
                  double cpu_s);

#endif

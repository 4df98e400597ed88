/* score_main.c: the simulator's metrics (sim/metrics.c) of a recorded run: a CSV from the simulator, the monitor or the serial logger. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "args.h"
#include "metrics.h"
#include "scenario.h"
#include "params.h"
#include "app.h"
#include "target.h"

/*
 * Columns are found by name in the header; what a row does not carry is taken from the closest
 * stand-in, and the JSON's "score_source" says which was used:
 *   time          t_s (required)
 *   ground speed  v_true_kmh (simulator), else the firmware's speed_kmh / v_meas_kmh
 *   nozzle flow   boom_lpm (simulator), else the measured flow_lpm / flow_meas_lpm
 *   sample flow   flow_true_lpm (simulator: through the meter), else the measured flow
 *   target        target_lpm (required); reference ref_lpm, else the target
 *   work speed    v_meas_kmh, else speed_kmh
 *   pressure      p_bar, else pressure_kpa / 100, else pressure_mpa * 10
 *   spraying      spray_on, else target > 0
 *   width, rate   width_m, rate_l_ha; else the settings (--scenario, or --nozzles/--spacing-cm/--rate)
 *   alarms        alarms / alarms_hex (hex bits; a rising bit is an alarm at that row)
 * Row i stands for the slice (t[i-1], t[i]] (the first for one sample period before it); the
 * step series takes one sample a row, at the rows' median spacing.
 */

#define MAX_COLS 64

enum { C_T, C_VTRUE, C_SPEED, C_VMEAS, C_BOOM, C_FLOW, C_FLOWMEAS, C_FLOWTRUE, C_TARGET, C_REF, C_PBAR,
       C_PKPA, C_PMPA, C_SPRAY, C_WIDTH, C_RATE, C_ALARMS, C_ALARMSHEX, C_OPEN, C_N };
static const char *const col_names[C_N] = {
    "t_s", "v_true_kmh", "speed_kmh", "v_meas_kmh", "boom_lpm", "flow_lpm", "flow_meas_lpm", "flow_true_lpm",
    "target_lpm", "ref_lpm", "p_bar", "pressure_kpa", "pressure_mpa", "spray_on", "width_m", "rate_l_ha",
    "alarms", "alarms_hex", "open_nozzles"
};

typedef struct {
    double t, v[C_N];
    unsigned alarms;
} row_t;

static void usage(FILE *f)
{
    fputs("usage: score RUN.csv [--scenario FILE] [--rate L_HA] [--nozzles N] [--spacing-cm CM] [--name NAME]\n"
          "             [--zones OUT.csv]\n"
          "  the metrics of docs/SCENARIOS.md (sim/metrics.c, the simulator's own) of a recorded run, as one JSON line:\n"
          "  a simulator trace (sim --csv), a monitor or serial_log recording (tools/monitor.py, serial_log.py).\n"
          "  The settings (rate, nozzles, spacing) come from the scenario, the options, or the defaults.\n", f);
}

/* Split a CSV line in place (no quoting: the recorders write none); returns the field count. */
static int split(char *line, char **f, int max)
{
    int n = 0;
    char *p = line;
    line[strcspn(line, "\r\n")] = 0;
    while (n < max) {
        f[n++] = p;
        p = strchr(p, ',');
        if (!p)
            break;
        *p++ = 0;
    }
    return p ? -1 : n;
}

/* The ground speed of a row: the truth when the row has it, else the firmware's. */
static double speed_of(const row_t *rw, const int *col)
{
    return col[C_VTRUE] >= 0 ? rw->v[C_VTRUE] : col[C_SPEED] >= 0 ? rw->v[C_SPEED] : rw->v[C_VMEAS];
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The recording as read: its file, its columns found by name, its rows. */
typedef struct {
    const char *path;
    int col[C_N];                   /* the field of each column (-1: not recorded) */
    int n_fields, n_rows, cap;
    row_t *rows;
} run_t;

/* The settings: defaults, then the scenario's, then the options; the width set. 0, or the
 * exit status. */
static int settings(const char *scn_path, double rate, double nozzles, double spacing, scenario_t **s)
{
    char err[512];
    int i;
    params_defaults();
    if (scn_path) {
        *s = malloc(sizeof **s);
        if (!*s || scenario_load(*s, scn_path, err, sizeof err) < 0) {
            fprintf(stderr, "score: %s\n", *s ? err : "out of memory");
            return 1;
        }
        for (i = 0; i < P_COUNT; i++)
            param_set((uint8_t)i, (*s)->param[i]);
    }
    if (rate > 0 && !param_set(P_RATE, (uint16_t)floor(rate * 10 + 0.5)))
        return 2;
    if (nozzles > 0)
        param_v[P_NOZZLES] = (uint16_t)floor(nozzles + 0.5);
    if (spacing > 0)
        param_v[P_SPACING] = (uint16_t)floor(spacing + 0.5);
    return 0;
}

/* The header line: the columns by name; 0, or -1 (said on stderr). */
static int read_header(FILE *in, run_t *run)
{
    char line[4096], *f[MAX_COLS];
    int i, k;
    if (!fgets(line, sizeof line, in)) {
        fprintf(stderr, "score: %s: empty file (a CSV with a header line was expected)\n", run->path);
        return -1;
    }
    run->n_fields = split(line, f, MAX_COLS);
    if (run->n_fields < 0) {
        fprintf(stderr, "score: %s:1: more than %d columns\n", run->path, MAX_COLS);
        return -1;
    }
    for (i = 0; i < C_N; i++) {
        run->col[i] = -1;
        for (k = 0; k < run->n_fields; k++)
            if (!strcmp(f[k], col_names[i]))
                run->col[i] = k;
    }
    if (run->col[C_T] < 0 || run->col[C_TARGET] < 0) {
        fprintf(stderr, "score: %s:1: the header has no t_s or no target_lpm column (not a recorded run)\n", run->path);
        return -1;
    }
    if (run->col[C_VTRUE] < 0 && run->col[C_SPEED] < 0 && run->col[C_VMEAS] < 0) {
        fprintf(stderr, "score: %s:1: no speed column (v_true_kmh, speed_kmh or v_meas_kmh)\n", run->path);
        return -1;
    }
    if (run->col[C_BOOM] < 0 && run->col[C_FLOW] < 0 && run->col[C_FLOWMEAS] < 0) {
        fprintf(stderr, "score: %s:1: no flow column (boom_lpm, flow_lpm or flow_meas_lpm)\n", run->path);
        return -1;
    }
    return 0;
}

/* The recorded columns of a row's fields into rw; 0, or -1 (said on stderr). */
static int parse_row(const run_t *run, int line_no, char **f, row_t *rw)
{
    int i;
    memset(rw, 0, sizeof *rw);
    for (i = 0; i < C_N; i++) {
        char *end;
        const char *txt;
        if (run->col[i] < 0)
            continue;
        txt = f[run->col[i]];
        if (i == C_ALARMS || i == C_ALARMSHEX) {
            unsigned long a;
            errno = 0;
            a = strtoul(txt, &end, 16);
            if (!*txt || *end || errno || a > 0xFFFFu) {
                fprintf(stderr, "score: %s:%d: %s '%s' is not hex alarm bits\n", run->path, line_no, col_names[i], txt);
                return -1;
            }
            rw->alarms = (unsigned)a;
            continue;
        }
        errno = 0;
        rw->v[i] = strtod(txt, &end);
        if (!*txt || *end || errno || !isfinite(rw->v[i])) {
            fprintf(stderr, "score: %s:%d: %s '%s' is not a number\n", run->path, line_no, col_names[i], txt);
            return -1;
        }
    }
    rw->t = rw->v[C_T];
    return 0;
}

/* The rows after the header, time going forward; 0, or -1 (said on stderr). */
static int read_rows(FILE *in, run_t *run)
{
    char line[4096], *f[MAX_COLS];
    int line_no = 1;
    while (fgets(line, sizeof line, in)) {
        row_t *rw;
        line_no++;
        if (line[0] == '\n' || line[0] == '\r' || line[0] == 0)
            continue;
        if (split(line, f, MAX_COLS) != run->n_fields) {
            fprintf(stderr, "score: %s:%d: %d columns expected\n", run->path, line_no, run->n_fields);
            return -1;
        }
        if (run->n_rows == run->cap) {
            run->cap = run->cap ? run->cap * 2 : 4096;
            run->rows = realloc(run->rows, (size_t)run->cap * sizeof *run->rows);
            if (!run->rows) {
                fprintf(stderr, "score: out of memory\n");
                return -1;
            }
        }
        rw = &run->rows[run->n_rows];
        if (parse_row(run, line_no, f, rw) < 0)
            return -1;
        if (run->n_rows > 0 && !(rw->t > run->rows[run->n_rows - 1].t)) {
            fprintf(stderr, "score: %s:%d: time %.3f s does not follow %.3f s\n", run->path, line_no, rw->t,
                    run->rows[run->n_rows - 1].t);
            return -1;
        }
        run->n_rows++;
    }
    return 0;
}

/* The sample period: the rows' median spacing. */
static double sample_period(const run_t *run)
{
    double *gaps = malloc((size_t)(run->n_rows - 1) * sizeof *gaps), dt;
    int i;
    for (i = 1; i < run->n_rows; i++)
        gaps[i - 1] = run->rows[i].t - run->rows[i - 1].t;
    qsort(gaps, (size_t)(run->n_rows - 1), sizeof *gaps, cmp_double);
    dt = gaps[(run->n_rows - 1) / 2];
    free(gaps);
    return dt;
}

/* Row i into the metrics: its slice's distance, dose and pressure, its sample, its alarms. */
static void score_row(metrics_t *m, const run_t *run, int i, double dt_sample, double width_set, unsigned *prev_alarms)
{
    const int *col = run->col;
    const row_t *rw = &run->rows[i];
    double dt = i ? rw->t - run->rows[i - 1].t : (rw->t > 0 && rw->t < 1.5 * dt_sample ? rw->t : dt_sample);
    double v_kmh = speed_of(rw, col);
    /* the speed is the row's instant: the slice's distance by the trapezoid (the flows
     * are already means over the slice) */
    double v_slice = i ? 0.5 * (v_kmh + speed_of(&run->rows[i - 1], col)) : v_kmh;
    double work = col[C_VMEAS] >= 0 ? rw->v[C_VMEAS] : col[C_SPEED] >= 0 ? rw->v[C_SPEED] : v_kmh;
    double meas = col[C_FLOW] >= 0 ? rw->v[C_FLOW] : col[C_FLOWMEAS] >= 0 ? rw->v[C_FLOWMEAS] : rw->v[C_BOOM];
    double nozzle = col[C_BOOM] >= 0 ? rw->v[C_BOOM] : meas;
    double flow = col[C_FLOWTRUE] >= 0 ? rw->v[C_FLOWTRUE] : meas;
    double target = rw->v[C_TARGET];
    double ref = col[C_REF] >= 0 ? rw->v[C_REF] : target;
    double p = col[C_PBAR] >= 0 ? rw->v[C_PBAR] : col[C_PKPA] >= 0 ? rw->v[C_PKPA] / 100.0
             : col[C_PMPA] >= 0 ? rw->v[C_PMPA] * 10.0 : 0.0;
    int spray = col[C_SPRAY] >= 0 ? rw->v[C_SPRAY] != 0 : target > 0;
    /* the settings are states at the row's instant: the slice up to it had the previous row's */
    const row_t *st = i ? &run->rows[i - 1] : rw;
    double width = col[C_WIDTH] >= 0 ? st->v[C_WIDTH]
                 : col[C_OPEN] >= 0 ? st->v[C_OPEN] * param_v[P_SPACING] / 100.0 : width_set;
    double rate_now = col[C_RATE] >= 0 ? st->v[C_RATE] : param_v[P_RATE] * 0.1;
    unsigned rise = rw->alarms & ~*prev_alarms;
    uint8_t b;
    metrics_add(m, dt, v_slice / 3.6, nozzle, width, rate_now, p, spray);
    metrics_sample(m, ref, target, flow, work, spray);
    for (b = 0; b < 16; b++)
        if (rise & (1u << b)) {
            char code[24];
            const char *c = app_alarm_code(b);
            if (!c || !*c) {
                snprintf(code, sizeof code, "ALARM_%u", b);
                c = code;
            }
            metrics_alarm(m, rw->t, c, app_alarm_text(b));
        }
    *prev_alarms = rw->alarms;
}

int main(int argc, char **argv)
{
    const char *scn_path = NULL, *name = NULL, *zones_path = NULL;
    double rate = -1, nozzles = -1, spacing = -1;
    int i;
    char extra[700], clean[256];
    run_t run;
    FILE *in;
    scenario_t *s = NULL;
    metrics_t m;
    metrics_result_t r;
    double dt_sample, width_set;
    unsigned prev_alarms = 0;
    const arg_opt_t opts[] = {
        {"--scenario", ARG_TEXT, &scn_path, 0, 0, NULL},
        {"--zones", ARG_TEXT, &zones_path, 0, 0, NULL},
        {"--name", ARG_TEXT, &name, 0, 0, NULL},
        {"--rate", ARG_NUM, &rate, 10, 1000, NULL},
        {"--nozzles", ARG_NUM, &nozzles, 1, 96, NULL},
        {"--spacing-cm", ARG_NUM, &spacing, 10, 200, NULL},
    };

    memset(&run, 0, sizeof run);
    i = args_parse("score", argc, argv, opts, (int)(sizeof opts / sizeof opts[0]), &run.path, usage);
    if (i != ARGS_OK)
        return i == ARGS_HELP ? 0 : 2;
    if (!run.path) {
        usage(stderr);
        return 2;
    }
    if ((i = settings(scn_path, rate, nozzles, spacing, &s)) != 0)
        return i;
    width_set = param_v[P_NOZZLES] * param_v[P_SPACING] / 100.0;
    in = fopen(run.path, "r");
    if (!in) {
        fprintf(stderr, "score: cannot read %s: %s\n", run.path, strerror(errno));
        return 1;
    }
    if (read_header(in, &run) < 0 || read_rows(in, &run) < 0)
        return 1;
    fclose(in);
    if (run.n_rows < 2) {
        fprintf(stderr, "score: %s: %d rows: a run needs at least 2\n", run.path, run.n_rows);
        return 1;
    }
    dt_sample = sample_period(&run);
    metrics_init(&m, dt_sample);
    /* the simulator's first sample is at time 0, before its first row: at rest */
    if (run.rows[0].t > 0.5 * dt_sample && run.rows[0].t < 1.5 * dt_sample)
        metrics_sample(&m, 0.0, 0.0, 0.0, 0.0, 0);
    for (i = 0; i < run.n_rows; i++)
        score_row(&m, &run, i, dt_sample, width_set, &prev_alarms);
    metrics_finish(&m, &r);
    /* what a recording cannot tell: the valve's wear, and the dose error's split (it needs what
     * a meter true to its calibration reads and the valve's end stops, every millisecond) */
    r.valve_reversals = r.valve_reversals_per_min = r.valve_travel_strokes = NAN;
    r.dose_target_pct = r.dose_meter_pct = r.dose_ctl_pct = r.dose_ctl_stop_pct = r.dose_ctl_start_pct = NAN;
    snprintf(clean, sizeof clean, "%s", name ? name : run.path);
    for (i = 0; clean[i]; i++)
        if ((unsigned char)clean[i] < 32 || clean[i] == '\\' || clean[i] == '"')
            clean[i] = '?';
    snprintf(extra, sizeof extra,
             "\"scenario\":\"%s\",\"score_source\":\"%s\",\"score_rows\":%d,\"score_sample_s\":%.3f,",
             clean, run.col[C_VTRUE] >= 0 && run.col[C_BOOM] >= 0 ? "truth" : "measured", run.n_rows, dt_sample);
    if (zones_path && metrics_write_csv("score", zones_path, metrics_zones_csv, &m) < 0)
        return 1;
    metrics_json(stdout, &m, &r, extra, 0.0, 0.0);
    metrics_free(&m);
    free(run.rows);
    free(s);
    return 0;
}

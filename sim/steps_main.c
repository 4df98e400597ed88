/* steps_main.c: the step figures of a sampled series read from CSV, by the simulator's own metrics code. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "args.h"
#include "metrics.h"

#define MAX_COLS 64

static void usage(FILE *f)
{
    fputs("usage: steps SAMPLES.csv [--flow COLUMN] [--delay-samples N]\n"
          "  SAMPLES.csv: a header line, then one row every 0.1 s with the columns ref_lpm (the\n"
          "  reference target), target_lpm (the firmware's), flow_lpm (the flow), work (1: working\n"
          "  speed >= 4 km/h) and spray (1: the boom sprays), as `sim --samples` writes them.\n"
          "  Prints the step figures (docs/SCENARIOS.md) as one JSON object.\n"
          "  --flow COLUMN scores another column as the flow (e.g. target_lpm: a flow equal to the\n"
          "  target); --delay-samples N scores that column N samples late.\n", f);
}

/* Index of name in the header's comma-separated columns, -1 when absent. */
static int column(char **cols, int n, const char *name)
{
    int i;
    for (i = 0; i < n; i++)
        if (strcmp(cols[i], name) == 0)
            return i;
    return -1;
}

static int split(char *line, char **cols)
{
    int n = 0;
    char *p = line, *nl = strpbrk(line, "\r\n");
    if (nl)
        *nl = 0;
    while (n < MAX_COLS) {
        cols[n++] = p;
        p = strchr(p, ',');
        if (!p)
            break;
        *p++ = 0;
    }
    return n;
}

/* The series read so far, and the columns they come from. */
typedef struct {
    int i_ref, i_tgt, i_flow, i_work, i_spray;
    size_t cap, n;
    double *ref, *tgt, *flow;
    unsigned char *work, *spray;
} series_t;

/* Room for one more row; -1 when memory ran out. */
static int grow(series_t *r)
{
    if (r->n == r->cap) {
        r->cap = r->cap ? 2 * r->cap : 1024;
        r->ref = realloc(r->ref, r->cap * sizeof *r->ref);
        r->tgt = realloc(r->tgt, r->cap * sizeof *r->tgt);
        r->flow = realloc(r->flow, r->cap * sizeof *r->flow);
        r->work = realloc(r->work, r->cap);
        r->spray = realloc(r->spray, r->cap);
    }
    return r->ref && r->tgt && r->flow && r->work && r->spray ? 0 : -1;
}

/* A row's fields into the series; -1 when one is not a number. */
static int take_row(series_t *r, char **cols)
{
    char *end;
    size_t n = r->n;
    r->ref[n] = strtod(cols[r->i_ref], &end);
    if (*end)
        return -1;
    r->tgt[n] = strtod(cols[r->i_tgt], &end);
    if (*end)
        return -1;
    r->flow[n] = strtod(cols[r->i_flow], &end);
    if (*end)
        return -1;
    r->work[n] = (unsigned char)(strtol(cols[r->i_work], &end, 10) != 0);
    if (*end)
        return -1;
    r->spray[n] = (unsigned char)(strtol(cols[r->i_spray], &end, 10) != 0);
    if (*end)
        return -1;
    r->n++;
    return 0;
}

/* The file's header and rows into r; 0, or -1 (said on stderr). */
static int read_series(FILE *f, const char *path, const char *flow_col, series_t *r)
{
    char line[4096], *cols[MAX_COLS];
    int n_cols, lineno = 1;
    if (!fgets(line, sizeof line, f)) {
        fprintf(stderr, "steps: %s: empty file\n", path);
        return -1;
    }
    n_cols = split(line, cols);
    r->i_ref = column(cols, n_cols, "ref_lpm");
    r->i_tgt = column(cols, n_cols, "target_lpm");
    r->i_flow = column(cols, n_cols, flow_col);
    r->i_work = column(cols, n_cols, "work");
    r->i_spray = column(cols, n_cols, "spray");
    if (r->i_ref < 0 || r->i_tgt < 0 || r->i_flow < 0 || r->i_work < 0 || r->i_spray < 0) {
        fprintf(stderr, "steps: %s: the header needs ref_lpm, target_lpm, %s, work and spray\n", path, flow_col);
        return -1;
    }
    while (fgets(line, sizeof line, f)) {
        int nc;
        lineno++;
        if (line[0] == '\n' || line[0] == '\r' || line[0] == 0)
            continue;
        nc = split(line, cols);
        if (nc < n_cols) {
            fprintf(stderr, "steps: %s:%d: %d columns, the header has %d\n", path, lineno, nc, n_cols);
            return -1;
        }
        if (grow(r) < 0) {
            fprintf(stderr, "steps: out of memory\n");
            return -1;
        }
        if (take_row(r, cols) < 0) {
            fprintf(stderr, "steps: %s:%d: not a number\n", path, lineno);
            return -1;
        }
    }
    return 0;
}

int main(int argc, char **argv)
{
    const char *path = NULL, *flow_col = "flow_lpm";
    long delay = 0;
    int i;
    double *flow_d;
    series_t r;
    metrics_series_t s;
    FILE *f;
    const arg_opt_t opts[] = {
        {"--flow", ARG_TEXT, &flow_col, 0, 0, NULL},
        {"--delay-samples", ARG_WHOLE, &delay, 0, 100000, NULL},
    };

    i = args_parse("steps", argc, argv, opts, 2, &path, usage);
    if (i != ARGS_OK)
        return i == ARGS_HELP ? 0 : 2;
    if (!path) {
        usage(stderr);
        return 2;
    }
    f = fopen(path, "r");
    if (!f) {
        fprintf(stderr, "steps: cannot open %s: %s\n", path, strerror(errno));
        return 1;
    }
    memset(&r, 0, sizeof r);
    if (read_series(f, path, flow_col, &r) < 0)
        return 1;
    fclose(f);
    flow_d = malloc((r.n ? r.n : 1) * sizeof *flow_d);
    for (i = 0; i < (int)r.n; i++)
        flow_d[i] = r.flow[i - delay < 0 ? 0 : i - delay];
    s.ref = r.ref;
    s.target = r.tgt;
    s.flow = flow_d;
    s.work = r.work;
    s.spray = r.spray;
    s.n = (int)r.n;
    s.dt_s = 0.1;
    metrics_steps_json(stdout, &s);
    free(r.ref);
    free(r.tgt);
    free(r.flow);
    free(flow_d);
    free(r.work);
    free(r.spray);
    return 0;
}

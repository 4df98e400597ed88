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

int main(int argc, char **argv)
{
    const char *path = NULL, *flow_col = "flow_lpm";
    long delay = 0;
    char line[4096], *cols[MAX_COLS];
    int n_cols, i_ref, i_tgt, i_flow, i_work, i_spray, i, lineno = 1;
    size_t cap = 1024, n = 0;
    double *ref, *tgt, *flow, *flow_d;
    unsigned char *work, *spray;
    metrics_series_t s;
    FILE *f;

    {
        const arg_opt_t opts[] = {
            {"--flow", ARG_TEXT, &flow_col, 0, 0, NULL},
            {"--delay-samples", ARG_WHOLE, &delay, 0, 100000, NULL},
        };
        i = args_parse("steps", argc, argv, opts, 2, &path, usage);
        if (i != ARGS_OK)
            return i == ARGS_HELP ? 0 : 2;
    }
    if (!path) {
        usage(stderr);
        return 2;
    }
    f = fopen(path, "r");
    if (!f) {
        fprintf(stderr, "steps: cannot open %s: %s\n", path, strerror(errno));
        return 1;
    }
    if (!fgets(line, sizeof line, f)) {
        fprintf(stderr, "steps: %s: empty file\n", path);
        return 1;
    }
    n_cols = split(line, cols);
    i_ref = column(cols, n_cols, "ref_lpm");
    i_tgt = column(cols, n_cols, "target_lpm");
    i_flow = column(cols, n_cols, flow_col);
    i_work = column(cols, n_cols, "work");
    i_spray = column(cols, n_cols, "spray");
    if (i_ref < 0 || i_tgt < 0 || i_flow < 0 || i_work < 0 || i_spray < 0) {
        fprintf(stderr, "steps: %s: the header needs ref_lpm, target_lpm, %s, work and spray\n", path, flow_col);
        return 1;
    }
    ref = malloc(cap * sizeof *ref);
    tgt = malloc(cap * sizeof *tgt);
    flow = malloc(cap * sizeof *flow);
    work = malloc(cap);
    spray = malloc(cap);
    while (fgets(line, sizeof line, f)) {
        char *end;
        int nc;
        lineno++;
        if (line[0] == '\n' || line[0] == '\r' || line[0] == 0)
            continue;
        nc = split(line, cols);
        if (nc < n_cols) {
            fprintf(stderr, "steps: %s:%d: %d columns, the header has %d\n", path, lineno, nc, n_cols);
            return 1;
        }
        if (n == cap) {
            cap *= 2;
            ref = realloc(ref, cap * sizeof *ref);
            tgt = realloc(tgt, cap * sizeof *tgt);
            flow = realloc(flow, cap * sizeof *flow);
            work = realloc(work, cap);
            spray = realloc(spray, cap);
        }
        if (!ref || !tgt || !flow || !work || !spray) {
            fprintf(stderr, "steps: out of memory\n");
            return 1;
        }
        ref[n] = strtod(cols[i_ref], &end);
        if (*end) goto bad;
        tgt[n] = strtod(cols[i_tgt], &end);
        if (*end) goto bad;
        flow[n] = strtod(cols[i_flow], &end);
        if (*end) goto bad;
        work[n] = (unsigned char)(strtol(cols[i_work], &end, 10) != 0);
        if (*end) goto bad;
        spray[n] = (unsigned char)(strtol(cols[i_spray], &end, 10) != 0);
        if (*end) goto bad;
        n++;
        continue;
    bad:
        fprintf(stderr, "steps: %s:%d: not a number\n", path, lineno);
        return 1;
    }
    fclose(f);
    flow_d = malloc((n ? n : 1) * sizeof *flow_d);
    for (i = 0; i < (int)n; i++)
        flow_d[i] = flow[i - delay < 0 ? 0 : i - delay];
    s.ref = ref;
    s.target = tgt;
    s.flow = flow_d;
    s.work = work;
    s.spray = spray;
    s.n = (int)n;
    s.dt_s = 0.1;
    metrics_steps_json(stdout, &s);
    free(ref);
    free(tgt);
    free(flow);
    free(flow_d);
    free(work);
    free(spray);
    return 0;
}

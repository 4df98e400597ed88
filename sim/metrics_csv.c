/* metrics_csv.c: a run's metrics as CSV files: the series the step figures come from, the zones. */
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include "metrics.h"

void metrics_samples_csv(FILE *f, const metrics_t *m)
{
    int k;
    fputs("t_s,ref_lpm,target_lpm,flow_lpm,work,spray\n", f);
    for (k = 0; k < m->n_samples; k++)
        fprintf(f, "%.1f,%.17g,%.17g,%.17g,%d,%d\n", k * m->sample_dt_s, m->ref[k], m->target[k], m->flow[k],
                m->work[k], m->spray[k]);
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

int metrics_write_csv(const char *prog, const char *path, void (*write)(FILE *, const metrics_t *),
                      const metrics_t *m)
{
    FILE *f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "%s: cannot write %s: %s\n", prog, path, strerror(errno));
        return -1;
    }
    write(f, m);
    if (fclose(f) != 0) {
        fprintf(stderr, "%s: error writing %s: %s\n", prog, path, strerror(errno));
        return -1;
    }
    return 0;
}

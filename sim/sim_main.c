/* sim_main.c: the simulator program: run a scenario, write the trace, print the metrics as one JSON line last. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "sim.h"
#include "hal_host.h"
#include "pil_host.h"

static void usage(FILE *f)
{
    fputs("usage: sim --scenario FILE [--controller NAME] [--csv OUT.csv] [--seed N] [--trace-period S]\n"
          "           [--zones OUT.csv] [--samples OUT.csv] [--serial OUT.txt] [--drive-log OUT.txt]\n"
          "           [--pil IMAGE.ihx] [--input KEYS_AND_LINES.txt]\n"
          "  runs the firmware application against the sprayer model of FILE (scenarios/*.scn);\n"
          "  prints the metrics of docs/SCENARIOS.md as one JSON object on the last line.\n"
          "  NAME: pid, fuzzy_pid, bp_pid, ffmap or 'best' (the project's own), aog, raven. --seed replaces [run] seed.\n"
          "  --samples: the series the step figures are taken from (reference, target, flow every 0.1 s;\n"
          "  build/host/bin/steps reads it back).\n"
          "  --serial: what the controller sends on its RS232 link (tools/serial_log.py --replay reads it).\n"
          "  --input: operator input at given times ('t_s key K', 't_s serial TEXT' lines; sim/sim.h).\n"
          "  --drive-log: a line 'tick dir duty spray' whenever the valve drive or the boom valve changes.\n"
          "  --pil: the firmware runs inside s51 from IMAGE (make pil-image: build/pil/sprayer_pil.ihx),\n"
          "         in lock step with the plant; 'pil:' lines give its pass timing and stack.\n", f);
}

static int parse_u64(const char *s, unsigned long long *v)
{
    char *end;
    if (!*s || *s == '-' || *s == '+')
        return -1;
    errno = 0;
    *v = strtoull(s, &end, 10);
    return (*end || errno) ? -1 : 0;
}

/* Write one of the metrics' CSV files to path; -1 (said on stderr) when it cannot. */
static int write_out(const char *path, void (*write)(FILE *, const metrics_t *), const metrics_t *m)
{
    FILE *f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "sim: cannot write %s: %s\n", path, strerror(errno));
        return -1;
    }
    write(f, m);
    if (fclose(f) != 0) {
        fprintf(stderr, "sim: error writing %s: %s\n", path, strerror(errno));
        return -1;
    }
    return 0;
}

int main(int argc, char **argv)
{
    const char *scn_path = NULL, *controller = NULL, *csv_path = NULL, *zones_path = NULL, *samples_path = NULL;
    const char *serial_path = NULL, *drive_path = NULL, *pil_path = NULL;
    const char *input_path = NULL;
    FILE *serial = NULL, *drive_log = NULL;
    pil_t *pil = NULL;
    unsigned long long seed = 0;
    int have_seed = 0, i;
    double period = 0.1;
    char err[512];
    scenario_t *s;
    sim_t *sim;
    FILE *csv = NULL;
    metrics_result_t r;

    for (i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage(stdout);
            return 0;
        }
        if (!v) {
            fprintf(stderr, "sim: %s needs a value\n", a);
            usage(stderr);
            return 2;
        }
        if (!strcmp(a, "--scenario"))
            scn_path = v;
        else if (!strcmp(a, "--controller"))
            controller = v;
        else if (!strcmp(a, "--csv"))
            csv_path = v;
        else if (!strcmp(a, "--zones"))
            zones_path = v;
        else if (!strcmp(a, "--samples"))
            samples_path = v;
        else if (!strcmp(a, "--serial"))
            serial_path = v;
        else if (!strcmp(a, "--drive-log"))
            drive_path = v;
        else if (!strcmp(a, "--pil"))
            pil_path = v;
        else if (!strcmp(a, "--input"))
            input_path = v;
        else if (!strcmp(a, "--seed")) {
            if (parse_u64(v, &seed) < 0) {
                fprintf(stderr, "sim: --seed '%s' is not a whole number 0..2^64-1\n", v);
                return 2;
            }
            have_seed = 1;
        } else if (!strcmp(a, "--trace-period")) {
            char *end;
            period = strtod(v, &end);
            if (*end || !(period >= 0.001 && period <= 3600)) {
                fprintf(stderr, "sim: --trace-period '%s' is not a number of seconds 0.001..3600\n", v);
                return 2;
            }
        } else {
            fprintf(stderr, "sim: unknown option '%s'\n", a);
            usage(stderr);
            return 2;
        }
        i++;
    }
    if (!scn_path) {
        fprintf(stderr, "sim: --scenario FILE is required\n");
        usage(stderr);
        return 2;
    }
    s = malloc(sizeof *s);
    sim = malloc(sizeof *sim);
    if (!s || !sim) {
        fprintf(stderr, "sim: out of memory\n");
        return 1;
    }
    if (scenario_load(s, scn_path, err, sizeof err) < 0) {
        fprintf(stderr, "sim: %s\n", err);
        return 1;
    }
    if (controller && scenario_set_controller(s, controller, err, sizeof err) < 0) {
        fprintf(stderr, "sim: --controller: %s\n", err);
        return 1;
    }
    if (have_seed)
        s->seed = seed;
    if (csv_path) {
        csv = fopen(csv_path, "w");
        if (!csv) {
            fprintf(stderr, "sim: cannot write %s: %s\n", csv_path, strerror(errno));
            return 1;
        }
    }
    if (serial_path) {
        serial = fopen(serial_path, "w");
        if (!serial) {
            fprintf(stderr, "sim: cannot write %s: %s\n", serial_path, strerror(errno));
            return 1;
        }
    }
    if (drive_path) {
        drive_log = fopen(drive_path, "w");
        if (!drive_log) {
            fprintf(stderr, "sim: cannot write %s: %s\n", drive_path, strerror(errno));
            return 1;
        }
    }
    sim_init(sim, s);
    sim->drive_log = drive_log;
    if (input_path && sim_input_load(sim, input_path, err, sizeof err) < 0) {
        fprintf(stderr, "sim: --input: %s\n", err);
        return 1;
    }
    if (pil_path) {
        pil = pil_start(sim, pil_path, err, sizeof err);
        if (!pil) {
            fprintf(stderr, "sim: --pil: %s\n", err);
            return 1;
        }
    }
    if (csv)
        sim_trace_csv(sim, csv, period);
    if (serial) {
        /* run in 0.1 s slices and take what the UART sent in each (the host queue holds 4 KB) */
        double t;
        int b;
        for (t = 0.1; !sim_done(sim); t += 0.1) {
            sim_run(sim, t < s->duration_s ? t : s->duration_s);
            while ((b = hal_host_uart_tx_pop()) >= 0)
                fputc(b, serial);
        }
        if (fclose(serial) != 0) {
            fprintf(stderr, "sim: error writing %s: %s\n", serial_path, strerror(errno));
            return 1;
        }
    } else {
        sim_run(sim, s->duration_s);
    }
    if (pil && pil_finish(pil) < 0) {
        fprintf(stderr, "sim: --pil: the firmware in s51 stopped answering\n");
        return 1;
    }
    sim_finish(sim, &r);
    if (drive_log && fclose(drive_log) != 0) {
        fprintf(stderr, "sim: error writing %s: %s\n", drive_path, strerror(errno));
        return 1;
    }
    if (csv && fclose(csv) != 0) {
        fprintf(stderr, "sim: error writing %s: %s\n", csv_path, strerror(errno));
        return 1;
    }
    if ((zones_path && write_out(zones_path, metrics_zones_csv, &sim->metrics) < 0)
        || (samples_path && write_out(samples_path, metrics_samples_csv, &sim->metrics) < 0))
        return 1;
    printf("sim: %s: %.1f s simulated in %.3f s of wall time (%.0fx real time)\n", s->name, r.sim_s,
           sim->wall_s, sim->wall_s > 0 ? r.sim_s / sim->wall_s : 0.0);
    if (pil) {
        pil_report(pil, stdout);
        pil_free(pil);
    }
    sim_json(sim, &r, stdout);
    sim_free(sim);
    free(sim);
    free(s);
    return 0;
}

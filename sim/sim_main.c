/* sim_main.c: the simulator program: run a scenario, write the trace, print a summary and the metrics as one JSON line last. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include "args.h"
#include "sim.h"
#include "hal_host.h"
#include "pil_host.h"
#include "chip_host.h"
#include "ucsim/stc12_link.h"
#include "pty.h"
#include "link_crc.h"
#include "summary.h"
#include "progress.h"

static void usage(FILE *f)
{
    fputs("usage: sim --scenario FILE [--controller NAME] [--csv OUT.csv] [--seed N] [--trace-period S]\n"
          "           [--zones OUT.csv] [--samples OUT.csv] [--serial OUT.txt] [--drive-log OUT.txt]\n"
          "           [--pil IMAGE.ihx | --chip IMAGE.ihx [--s51 PATH]] [--input KEYS_AND_LINES.txt] [--pty [--pace X] [--wait S]]\n"
          "           [--fast | --tick-ms N [--idle-tick-ms M]] [--duration S]\n"
          "  runs the firmware application against the sprayer model of FILE (scenarios/*.scn);\n"
          "  prints a summary of the run's figures, then the metrics of docs/SCENARIOS.md as one JSON\n"
          "  object on the last line.\n"
          "  NAME: pid, fuzzy_pid, bp_pid, ffmap (the project's own), aog, raven. --seed replaces [run] seed.\n"
          "  --duration: the run ends at S seconds when FILE's ends later (the events after S dropped).\n"
          "  --samples: the series the step figures are taken from (reference, target, flow every 0.1 s;\n"
          "  build/host/bin/steps reads it back).\n"
          "  --serial: what the controller sends on its RS232 link (tools/serial_log.py --replay reads it).\n"
          "  --input: operator input at given times ('t_s key K', 't_s serial TEXT', 't_s frame HEX' lines; sim/sim.h).\n"
          "  --drive-log: a line 'tick dir duty spray' whenever the valve drive or the boom valve changes.\n"
          "  --pil: the firmware runs inside s51 from IMAGE (make pil-image: build/pil/sprayer_pil.ihx),\n"
          "         in lock step with the plant; 'pil:' lines give its pass timing and stack.\n"
          "  --chip: the field image (build/stc12/sprayer.ihx, its .map beside it) runs in the\n"
          "         STC12C5A60S2 model (--s51 PATH, default build/ucsim/s51; make chip), its pins on\n"
          "         the plant; 'chip:' lines give its passes and handlers in 1T clocks.\n"
          "         --chip-reset S: the reset pin pulsed at S; --chip-hang S: the main loop hangs at S\n"
          "         (interrupts still served) until a reset; --chip-wheel-sweep S: from S every wheel\n"
          "         edge falls 60 + 3k clocks before a PCA overflow (the capture race's window).\n"
          "  --pty: the link on a new pseudo-terminal (its name on stderr) that tools/monitor.py opens like a\n"
          "    port; the run starts when it is opened (--wait S, default 60), at X times real time (--pace,\n"
          "    default 1; 0 as fast as the reader takes it); commands sent to it reach the firmware, and\n"
          "    every 0.1 s a truth line 'SIM ...*HH' follows the firmware's (docs/MONITOR.md).\n"
          "  --tick-ms N: the plant steps and the firmware's passes every N ms (1..50, a divisor of 100;\n"
          "    1 is the model), every M ms while the valve is idle and the speed steady (--idle-tick-ms, a\n"
          "    longer multiple of N);\n"
          "    --fast is --tick-ms 5 --idle-tick-ms 10: an approximation whose metrics stay near the\n"
          "    1 ms run's (docs/PIL.md, the simulator's speed; tests/scripts/seed_spread.sh). Not with --pil.\n", f);
}

/* "SIM t_s v_true_kmh v_meas_kmh target_lpm ref_lpm flow_meas_lpm flow_true_lpm boom_lpm p_bar
 * p_meas_kpa valve_drive spray_on width_m rate_l_ha alarms*HH\r\n": the simulator's truth beside
 * the firmware's view, checksummed like the firmware's lines. */
static int sim_line(char *buf, size_t n, const sim_row_t *r)
{
    int len = snprintf(buf, n, "SIM %.3f %.4f %.2f %.2f %.4f %.2f %.4f %.4f %.4f %.0f %.4f %d %.3f %.0f %04X",
                       r->t_s, r->v_true_kmh, r->v_meas_kmh, r->target_lpm, r->ref_lpm, r->flow_meas_lpm,
                       r->flow_true_lpm, r->boom_lpm, r->p_bar, r->p_meas_kpa, r->valve_drive, r->spray_on,
                       r->width_m, r->rate_l_ha, r->alarms);
    return len + snprintf(buf + len, n - (size_t)len, "*%02X\r\n", link_crc8(buf, (size_t)len));
}

static double wall_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* The run on a pseudo-terminal: 0.1 s slices, commands in, the firmware's bytes and a truth line
 * out, paced to pace x real time; stops early when the PC closes the port. */
static int run_pty(sim_t *sim, const scenario_t *s, double pace, double wait_s)
{
    char name[256], line[256];
    uint8_t buf[4096];
    double t, w0;
    int fd = pty_open(name, sizeof name), b, len;
    sim_row_t row;
    if (fd < 0) {
        fprintf(stderr, "sim: %s\n", name);
        return -1;
    }
    fprintf(stderr, "sim: serial link on %s (waiting %.0f s for the PC to open it)\n", name, wait_s);
    if (pty_wait_peer(fd, wait_s) < 0) {
        fprintf(stderr, "sim: nobody opened %s in %.0f s\n", name, wait_s);
        close(fd);
        return -1;
    }
    w0 = wall_now();
    for (t = 0.1; !sim_done(sim); t += 0.1) {
        ssize_t got;
        size_t k;
        while ((got = read(fd, buf, sizeof buf)) > 0)
            for (k = 0; k < (size_t)got; k++)
                hal_host_uart_rx_push(buf[k]);
        sim_run(sim, t < s->duration_s ? t : s->duration_s);
        for (k = 0; k < sizeof buf && (b = hal_host_uart_tx_pop()) >= 0; k++)
            buf[k] = (uint8_t)b;
        sim_row(sim, &row);
        len = sim_line(line, sizeof line, &row);
        if (pty_write(fd, buf, k) < 0 || pty_write(fd, line, (size_t)len) < 0 || pty_peer_gone(fd)) {
            fprintf(stderr, "sim: the PC closed the link at %.1f s\n", sim_time_s(sim));
            break;
        }
        if (pace > 0) {
            double ahead = sim_time_s(sim) / pace - (wall_now() - w0);
            if (ahead > 0) {
                struct timespec d = { (time_t)ahead, (long)((ahead - (time_t)ahead) * 1e9) };
                nanosleep(&d, NULL);
            }
        }
    }
    if (pty_drain(fd, name, 10.0) < 0)
        fprintf(stderr, "sim: the PC did not read the last bytes of the link\n");
    close(fd);
    return 0;
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
    const char *input_path = NULL, *chip_path = NULL, *s51_path = "build/ucsim/s51";
    FILE *serial = NULL, *drive_log = NULL;
    pil_t *pil = NULL;
    progress_t prog;
    chip_t *chip = NULL;
    arg_nums_t chip_ev[3] = { { { 0 }, 0 } };   /* the times of --chip-reset, --chip-hang, --chip-wheel-sweep */
    static const int chip_ev_kind[3] = { STC12_EV_RESET, STC12_EV_HANG, STC12_EV_WHEEL_SWEEP };
    int j;
    unsigned long long seed = 0;
    int have_seed = 0, i, tick_ms = 1, idle_ms = 0, fast = 0;
    long tick_l = 0, idle_l = 0;
    double period = 0.1, pace = 1.0, wait_s = 60.0, cut_s = 0, speed;
    int use_pty = 0;
    char err[512];
    scenario_t *s;
    sim_t *sim;
    FILE *csv = NULL;
    metrics_result_t r;

    const arg_opt_t opts[] = {
        {"--scenario", ARG_TEXT, &scn_path, 0, 0, NULL},
        {"--controller", ARG_TEXT, &controller, 0, 0, NULL},
        {"--csv", ARG_TEXT, &csv_path, 0, 0, NULL},
        {"--zones", ARG_TEXT, &zones_path, 0, 0, NULL},
        {"--samples", ARG_TEXT, &samples_path, 0, 0, NULL},
        {"--serial", ARG_TEXT, &serial_path, 0, 0, NULL},
        {"--drive-log", ARG_TEXT, &drive_path, 0, 0, NULL},
        {"--pil", ARG_TEXT, &pil_path, 0, 0, NULL},
        {"--chip", ARG_TEXT, &chip_path, 0, 0, NULL},
        {"--s51", ARG_TEXT, &s51_path, 0, 0, NULL},
        {"--chip-reset", ARG_NUMS, &chip_ev[0], 0, 1e6, NULL},
        {"--chip-hang", ARG_NUMS, &chip_ev[1], 0, 1e6, NULL},
        {"--chip-wheel-sweep", ARG_NUMS, &chip_ev[2], 0, 1e6, NULL},
        {"--input", ARG_TEXT, &input_path, 0, 0, NULL},
        {"--pty", ARG_FLAG, &use_pty, 0, 0, NULL},
        {"--fast", ARG_FLAG, &fast, 0, 0, NULL},
        {"--seed", ARG_U64, &seed, 0, 0, &have_seed},
        {"--pace", ARG_NUM, &pace, 0, 1e6, NULL},
        {"--wait", ARG_NUM, &wait_s, 0, 1e6, NULL},
        {"--tick-ms", ARG_WHOLE, &tick_l, 1, SIM_TICK_MAX_MS, NULL},
        {"--idle-tick-ms", ARG_WHOLE, &idle_l, 1, SIM_TICK_MAX_MS, NULL},
        {"--duration", ARG_NUM, &cut_s, 0.001, 1e6, NULL},
        {"--trace-period", ARG_NUM, &period, 0.001, 3600, NULL},
    };
    i = args_parse("sim", argc, argv, opts, (int)(sizeof opts / sizeof opts[0]), NULL, usage);
    if (i != ARGS_OK)
        return i == ARGS_HELP ? 0 : 2;
    if (fast) {                     /* (a --tick-ms or --idle-tick-ms given too sets its own) */
        tick_ms = SIM_FAST_TICK_MS;
        idle_ms = SIM_FAST_IDLE_MS;
    }
    if (tick_l)
        tick_ms = (int)tick_l;
    if (idle_l)
        idle_ms = (int)idle_l;
    if (100 % tick_ms != 0 || (idle_ms && 100 % idle_ms != 0)) {
        fprintf(stderr, "sim: --tick-ms and --idle-tick-ms must divide 100\n");
        return 2;
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
    if (cut_s > 0)
        scenario_cut(s, cut_s, NULL, 0);        /* (checked above) */
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
    if ((tick_ms != 1 || idle_ms) && (pil_path || chip_path)) {
        fprintf(stderr, "sim: --fast/--tick-ms and --pil or --chip do not go together (s51 runs a millisecond a step)\n");
        return 2;
    }
    if (pil_path && chip_path) {
        fprintf(stderr, "sim: --pil and --chip: one firmware at a time\n");
        return 2;
    }
    sim_init(sim, s);
    if (sim_set_tick_ms(sim, tick_ms, idle_ms) < 0) {
        fprintf(stderr, "sim: ticks of %d ms, %d ms while idle: the idle tick must be a longer multiple of the tick\n",
                tick_ms, idle_ms);
        return 2;
    }
    sim->drive_log = drive_log;
    if (input_path && sim_input_load(sim, input_path, err, sizeof err) < 0) {
        fprintf(stderr, "sim: --input: %s\n", err);
        return 1;
    }
    for (i = 0; (pil_path || chip_path) && i < s->n_events; i++)
        if (s->events[i].kind == EV_POWER_CUT) {
            fprintf(stderr, "sim: %s: %s:%d: power_cut runs on the host build only\n", pil_path ? "--pil" : "--chip",
                    s->name, s->events[i].line);
            return 1;
        }
    if (chip_path) {
        chip = chip_start(sim, chip_path, s51_path, err, sizeof err);
        if (!chip) {
            fprintf(stderr, "sim: --chip: %s\n", err);
            return 1;
        }
        for (j = 0; j < 3; j++)
            for (i = 0; i < chip_ev[j].n; i++)
                if (chip_at(chip, chip_ev[j].v[i], chip_ev_kind[j], 60) < 0) {
                    fprintf(stderr, "sim: at most 8 --chip-* inputs\n");
                    return 2;
                }
    } else if (chip_ev[0].n + chip_ev[1].n + chip_ev[2].n) {
        fprintf(stderr, "sim: --chip-reset, --chip-hang, --chip-wheel-sweep go with --chip\n");
        return 2;
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
    if (use_pty && serial) {
        fprintf(stderr, "sim: --pty and --serial: one link at a time\n");
        return 2;
    }
    if (use_pty) {
        if (run_pty(sim, s, pace, wait_s) < 0)
            return 1;
    } else if (serial) {
        /* run in 0.1 s slices and take what the UART sent in each (the host queue holds 4 KB) */
        double t;
        int b;
        progress_start(&prog, pil ? "pil" : chip ? "chip" : "sim", s->duration_s);
        for (t = 0.1; !sim_done(sim); t += 0.1) {
            sim_run(sim, t < s->duration_s ? t : s->duration_s);
            while ((b = hal_host_uart_tx_pop()) >= 0)
                fputc(b, serial);
            progress_show(&prog, sim_time_s(sim));
        }
        progress_end(&prog);
        if (fclose(serial) != 0) {
            fprintf(stderr, "sim: error writing %s: %s\n", serial_path, strerror(errno));
            return 1;
        }
    } else {
        /* in 0.1 s slices, the same steps as at once, for the progress line; the link with
         * nobody on it: what the UART sends is gone, as a real line's */
        progress_start(&prog, pil ? "pil" : chip ? "chip" : "sim", s->duration_s);
        while (!sim_done(sim)) {
            sim_run(sim, sim_time_s(sim) + 0.1);
            while (hal_host_uart_tx_pop() >= 0)
                ;
            progress_show(&prog, sim_time_s(sim));
        }
        progress_end(&prog);
    }
    if (chip && chip_finish(chip) < 0) {
        fprintf(stderr, "sim: --chip: the model stopped answering\n");
        return 1;
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
    sim_summary(sim, &r, stdout);
    speed = sim->wall_s > 0 ? r.sim_s / sim->wall_s : 0.0;
    printf("sim: %s: %.1f s simulated in %.3f s of wall time (%.*fx real time)\n", s->name, r.sim_s,
           sim->wall_s, speed < 10 ? 2 : 0, speed);
    if (pil) {
        pil_report(pil, stdout);
        pil_free(pil);
    }
    if (chip) {
        chip_report(chip, stdout);
        chip_free(chip);
    }
    sim_json(sim, &r, stdout);
    sim_free(sim);
    free(sim);
    free(s);
    return 0;
}

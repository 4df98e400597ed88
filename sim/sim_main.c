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
#include "st7920_emu.h"
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
          "           [--zones OUT.csv] [--samples OUT.csv] [--serial OUT.txt] [--drive-log OUT.txt] [--lcd OUT.txt]\n"
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
          "  --lcd: the LCD's four text lines at the run's end (the emulated ST7920, host or --pil firmware).\n"
          "  --pil: the firmware runs inside s51 from IMAGE (make pil-image: build/pil/sprayer_pil.ihx),\n"
          "         in lock step with the plant; 'pil:' lines give its pass timing and stack.\n"
          "  --chip: the field image (build/stc12/sprayer.ihx, its .map beside it) runs in the\n"
          "         STC12C5A60S2 model (--s51 PATH, default build/ucsim/s51; make chip), its pins on\n"
          "         the plant; 'chip:' lines give its passes and handlers in 1T clocks.\n"
          "         --chip-reset S: the reset pin pulsed at S; --chip-hang S: the main loop hangs at S\n"
          "         (interrupts still served) until a reset; --chip-wheel-sweep S: from S every wheel\n"
          "         edge falls 3k clocks before the k-th PCA overflow (the capture race's window).\n"
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

/* The program's options, what it opened and the firmware it runs. */
typedef struct {
    const char *scn_path, *controller, *csv_path, *zones_path, *samples_path;
    const char *serial_path, *drive_path, *pil_path, *input_path, *chip_path, *s51_path, *lcd_path;
    arg_nums_t chip_ev[3];          /* the times of --chip-reset, --chip-hang, --chip-wheel-sweep */
    unsigned long long seed;
    int have_seed, tick_ms, idle_ms, fast, use_pty;
    long tick_l, idle_l;
    double period, pace, wait_s, cut_s;
    FILE *serial, *drive_log, *csv;
    pil_t *pil;
    chip_t *chip;
} opt_t;

/* The command line into o: -1 to run, or the exit status (help, a usage error). */
static int options(int argc, char **argv, opt_t *o)
{
    int i;
    const arg_opt_t opts[] = {
        {"--scenario", ARG_TEXT, &o->scn_path, 0, 0, NULL},
        {"--controller", ARG_TEXT, &o->controller, 0, 0, NULL},
        {"--csv", ARG_TEXT, &o->csv_path, 0, 0, NULL},
        {"--zones", ARG_TEXT, &o->zones_path, 0, 0, NULL},
        {"--samples", ARG_TEXT, &o->samples_path, 0, 0, NULL},
        {"--serial", ARG_TEXT, &o->serial_path, 0, 0, NULL},
        {"--drive-log", ARG_TEXT, &o->drive_path, 0, 0, NULL},
        {"--lcd", ARG_TEXT, &o->lcd_path, 0, 0, NULL},
        {"--pil", ARG_TEXT, &o->pil_path, 0, 0, NULL},
        {"--chip", ARG_TEXT, &o->chip_path, 0, 0, NULL},
        {"--s51", ARG_TEXT, &o->s51_path, 0, 0, NULL},
        {"--chip-reset", ARG_NUMS, &o->chip_ev[0], 0, 1e6, NULL},
        {"--chip-hang", ARG_NUMS, &o->chip_ev[1], 0, 1e6, NULL},
        {"--chip-wheel-sweep", ARG_NUMS, &o->chip_ev[2], 0, 1e6, NULL},
        {"--input", ARG_TEXT, &o->input_path, 0, 0, NULL},
        {"--pty", ARG_FLAG, &o->use_pty, 0, 0, NULL},
        {"--fast", ARG_FLAG, &o->fast, 0, 0, NULL},
        {"--seed", ARG_U64, &o->seed, 0, 0, &o->have_seed},
        {"--pace", ARG_NUM, &o->pace, 0, 1e6, NULL},
        {"--wait", ARG_NUM, &o->wait_s, 0, 1e6, NULL},
        {"--tick-ms", ARG_WHOLE, &o->tick_l, 1, SIM_TICK_MAX_MS, NULL},
        {"--idle-tick-ms", ARG_WHOLE, &o->idle_l, 1, SIM_TICK_MAX_MS, NULL},
        {"--duration", ARG_NUM, &o->cut_s, 0.001, 1e6, NULL},
        {"--trace-period", ARG_NUM, &o->period, 0.001, 3600, NULL},
    };
    memset(o, 0, sizeof *o);
    o->s51_path = "build/ucsim/s51";
    o->tick_ms = 1;
    o->period = 0.1;
    o->pace = 1.0;
    o->wait_s = 60.0;
    i = args_parse("sim", argc, argv, opts, (int)(sizeof opts / sizeof opts[0]), NULL, usage);
    if (i != ARGS_OK)
        return i == ARGS_HELP ? 0 : 2;
    if (o->fast) {                  /* (a --tick-ms or --idle-tick-ms given too sets its own) */
        o->tick_ms = SIM_FAST_TICK_MS;
        o->idle_ms = SIM_FAST_IDLE_MS;
    }
    if (o->tick_l)
        o->tick_ms = (int)o->tick_l;
    if (o->idle_l)
        o->idle_ms = (int)o->idle_l;
    if (100 % o->tick_ms != 0 || (o->idle_ms && 100 % o->idle_ms != 0)) {
        fprintf(stderr, "sim: --tick-ms and --idle-tick-ms must divide 100\n");
        return 2;
    }
    if (!o->scn_path) {
        fprintf(stderr, "sim: --scenario FILE is required\n");
        usage(stderr);
        return 2;
    }
    return -1;
}

/* path opened for writing into *f (none asked: NULL); -1 (said on stderr) when it cannot */
static int open_out(const char *path, FILE **f)
{
    if (!path)
        return 0;
    *f = fopen(path, "w");
    if (!*f) {
        fprintf(stderr, "sim: cannot write %s: %s\n", path, strerror(errno));
        return -1;
    }
    return 0;
}

/* The firmware in s51 or in the STC12 model when asked: 0, or the exit status. */
static int start_firmware(opt_t *o, sim_t *sim, const scenario_t *s)
{
    char err[512];
    static const int chip_ev_kind[3] = { STC12_EV_RESET, STC12_EV_HANG, STC12_EV_WHEEL_SWEEP };
    int i, j;
    for (i = 0; (o->pil_path || o->chip_path) && i < s->n_events; i++)
        if (s->events[i].kind == EV_POWER_CUT) {
            fprintf(stderr, "sim: %s: %s:%d: power_cut runs on the host build only\n", o->pil_path ? "--pil" : "--chip",
                    s->name, s->events[i].line);
            return 1;
        }
    if (o->chip_path) {
        o->chip = chip_start(sim, o->chip_path, o->s51_path, err, sizeof err);
        if (!o->chip) {
            fprintf(stderr, "sim: --chip: %s\n", err);
            return 1;
        }
        for (j = 0; j < 3; j++)
            for (i = 0; i < o->chip_ev[j].n; i++)
                if (chip_at(o->chip, o->chip_ev[j].v[i], chip_ev_kind[j], 0) < 0) {
                    fprintf(stderr, "sim: at most 8 --chip-* inputs\n");
                    return 2;
                }
    } else if (o->chip_ev[0].n + o->chip_ev[1].n + o->chip_ev[2].n) {
        fprintf(stderr, "sim: --chip-reset, --chip-hang, --chip-wheel-sweep go with --chip\n");
        return 2;
    }
    if (o->pil_path) {
        o->pil = pil_start(sim, o->pil_path, err, sizeof err);
        if (!o->pil) {
            fprintf(stderr, "sim: --pil: %s\n", err);
            return 1;
        }
    }
    return 0;
}

/* The run to its end: on a pseudo-terminal, into --serial's file, or with nobody on the link;
 * 0, or the exit status. */
static int run(opt_t *o, sim_t *sim, const scenario_t *s)
{
    progress_t prog;
    int b;
    if (o->use_pty && o->serial) {
        fprintf(stderr, "sim: --pty and --serial: one link at a time\n");
        return 2;
    }
    if (o->use_pty)
        return run_pty(sim, s, o->pace, o->wait_s) < 0 ? 1 : 0;
    /* in 0.1 s slices, the same steps as at once: what the UART sent in each into --serial's
     * file (the host queue holds 4 KB), or gone as on a line with nobody on it; the progress line */
    progress_start(&prog, o->pil ? "pil" : o->chip ? "chip" : "sim", s->duration_s);
    if (o->serial) {
        double t;
        for (t = 0.1; !sim_done(sim); t += 0.1) {
            sim_run(sim, t < s->duration_s ? t : s->duration_s);
            while ((b = hal_host_uart_tx_pop()) >= 0)
                fputc(b, o->serial);
            progress_show(&prog, sim_time_s(sim));
        }
    } else {
        while (!sim_done(sim)) {
            sim_run(sim, sim_time_s(sim) + 0.1);
            while (hal_host_uart_tx_pop() >= 0)
                ;
            progress_show(&prog, sim_time_s(sim));
        }
    }
    progress_end(&prog);
    if (o->serial && fclose(o->serial) != 0) {
        fprintf(stderr, "sim: error writing %s: %s\n", o->serial_path, strerror(errno));
        return 1;
    }
    return 0;
}

/* --lcd: the four text lines as the LCD shows them now, one a line; 0, or -1 (said why). */
static int write_lcd(const char *path)
{
    char line[17];
    uint8_t k;
    FILE *f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "sim: --lcd: %s: %s\n", path, strerror(errno));
        return -1;
    }
    for (k = 0; k < 4; k++) {
        st7920_emu_line(k, line);
        fprintf(f, "%s\n", line);
    }
    if (fclose(f) != 0) {
        fprintf(stderr, "sim: error writing %s: %s\n", path, strerror(errno));
        return -1;
    }
    return 0;
}

/* The firmware stopped, the files closed, the summary, the timing lines and the JSON printed;
 * 0, or the exit status. */
static int finish(opt_t *o, sim_t *sim, const scenario_t *s)
{
    metrics_result_t r;
    double speed;
    if (o->chip && chip_finish(o->chip) < 0) {
        fprintf(stderr, "sim: --chip: the model stopped answering\n");
        return 1;
    }
    if (o->pil && pil_finish(o->pil) < 0) {
        fprintf(stderr, "sim: --pil: the firmware in s51 stopped answering\n");
        return 1;
    }
    sim_finish(sim, &r);
    if (o->lcd_path && write_lcd(o->lcd_path) < 0)
        return 1;
    if (o->drive_log && fclose(o->drive_log) != 0) {
        fprintf(stderr, "sim: error writing %s: %s\n", o->drive_path, strerror(errno));
        return 1;
    }
    if (o->csv && fclose(o->csv) != 0) {
        fprintf(stderr, "sim: error writing %s: %s\n", o->csv_path, strerror(errno));
        return 1;
    }
    if ((o->zones_path && metrics_write_csv("sim", o->zones_path, metrics_zones_csv, &sim->metrics) < 0)
        || (o->samples_path && metrics_write_csv("sim", o->samples_path, metrics_samples_csv, &sim->metrics) < 0))
        return 1;
    sim_summary(sim, &r, stdout);
    speed = sim->wall_s > 0 ? r.sim_s / sim->wall_s : 0.0;
    printf("sim: %s: %.1f s simulated in %.3f s of wall time (%.*fx real time)\n", s->name, r.sim_s,
           sim->wall_s, speed < 10 ? 2 : 0, speed);
    if (o->pil) {
        pil_report(o->pil, stdout);
        pil_free(o->pil);
    }
    if (o->chip) {
        chip_report(o->chip, stdout);
        chip_free(o->chip);
    }
    sim_json(sim, &r, stdout);
    return 0;
}

int main(int argc, char **argv)
{
    opt_t o;
    char err[512];
    scenario_t *s;
    sim_t *sim;
    int rc = options(argc, argv, &o);
    if (rc >= 0)
        return rc;
    s = malloc(sizeof *s);
    sim = malloc(sizeof *sim);
    if (!s || !sim) {
        fprintf(stderr, "sim: out of memory\n");
        return 1;
    }
    if (scenario_load(s, o.scn_path, err, sizeof err) < 0) {
        fprintf(stderr, "sim: %s\n", err);
        return 1;
    }
    if (o.controller && scenario_set_controller(s, o.controller, err, sizeof err) < 0) {
        fprintf(stderr, "sim: --controller: %s\n", err);
        return 1;
    }
    if (o.have_seed)
        s->seed = o.seed;
    if (o.cut_s > 0)
        scenario_cut(s, o.cut_s, NULL, 0);      /* (checked above) */
    if (open_out(o.csv_path, &o.csv) < 0 || open_out(o.serial_path, &o.serial) < 0
        || open_out(o.drive_path, &o.drive_log) < 0)
        return 1;
    if ((o.tick_ms != 1 || o.idle_ms) && (o.pil_path || o.chip_path)) {
        fprintf(stderr, "sim: --fast/--tick-ms and --pil or --chip do not go together (s51 runs a millisecond a step)\n");
        return 2;
    }
    if (o.lcd_path && o.chip_path) {
        fprintf(stderr, "sim: --lcd and --chip: the chip model does not decode the LCD's pins (--pil does)\n");
        return 2;
    }
    if (o.pil_path && o.chip_path) {
        fprintf(stderr, "sim: --pil and --chip: one firmware at a time\n");
        return 2;
    }
    sim_init(sim, s);
    if (sim_set_tick_ms(sim, o.tick_ms, o.idle_ms) < 0) {
        fprintf(stderr, "sim: ticks of %d ms, %d ms while idle: the idle tick must be a longer multiple of the tick\n",
                o.tick_ms, o.idle_ms);
        return 2;
    }
    sim->drive_log = o.drive_log;
    if (o.input_path && sim_input_load(sim, o.input_path, err, sizeof err) < 0) {
        fprintf(stderr, "sim: --input: %s\n", err);
        return 1;
    }
    if (o.lcd_path) {
        st7920_emu_reset();
        hal_host_lcd_sink(st7920_emu_write);
    }
    if ((rc = start_firmware(&o, sim, s)) != 0)
        return rc;
    if (o.csv)
        sim_trace_csv(sim, o.csv, o.period);
    if ((rc = run(&o, sim, s)) != 0 || (rc = finish(&o, sim, s)) != 0)
        return rc;
    sim_free(sim);
    free(sim);
    free(s);
    return 0;
}

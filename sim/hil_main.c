/* hil_main.c: hardware in the loop, the PC's side: the plant model of a scenario drives a controller on the serial link, frame by frame. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include "args.h"
#include "sim.h"
#include "hal_host.h"
#include "hil.h"
#include "link_crc.h"
#include "params.h"
#include "app.h"
#include "target.h"
#include "ctl.h"
#include "pty.h"
#include "progress.h"

/* The simulator's firmware passes its main loop once a millisecond. After a settings change
 * its next step waits for the modules' constants, one a pass (app.c's app_prepare: 6 passes);
 * its alarms come in the third pass of its step (app.c: the step, its second pass, the alarms).
 * The PC keeps both instants, so that the figures are the simulator's: a frame after a change
 * goes at the step's instant, and the answer's alarms count from two milliseconds later. */
#define HIL_PREP_MS 6
#define HIL_DIAG_MS 2

/*
 * The simulator's loop (sim.c) with the firmware replaced by a board on the serial link
 * (docs/HIL.md): the board is set up with the scenario's settings (SET, then HIL ON), then at
 * every control period (100 ms of plant time) the plant's inputs as the firmware would take
 * them from the HAL (captures, PCA time, ADC, switches) go out as a sensor frame, and the
 * answer's outputs drive the plant (the valve after the reversal's dead time the answer
 * states) and stand for the firmware's status in the metrics. A frame that gets no good answer
 * is counted (the plant keeps the last outputs), and the run says so.
 */

typedef struct {
    int fd;
    double pace;                    /* x real time; 0: as fast as the board answers */
    double timeout_s;               /* for an answer */
    unsigned drop_every;            /* test: this frame number's multiples are never sent */
    unsigned corrupt_every;         /* test: ... are sent with a byte flipped */
    uint8_t seq;
    uint16_t wheel_total, meter_total;  /* running edge totals (hil.h) */
    uint8_t rejected_total;
    uint32_t next_ms;               /* the next control step */
    unsigned frames, answered, no_answer, dropped, corrupted;
    uint16_t board_lost;            /* the board's count, from its last answer */
    int pend;                       /* a valve output waiting for its dead time */
    int8_t pend_dir;
    uint8_t pend_duty;
    uint32_t pend_ms;
    hil_rx_t rx;
    double wall0;
    int failed;                     /* the link went away, or the controller refused a setting */
    uint16_t board_param[P_COUNT];  /* the settings the controller confirmed holding */
    int set_id;                     /* the setting in the frame awaiting its answer; -1: none */
    uint8_t param_gen;              /* param_generation when the last change was seen */
    uint32_t ready_ms;              /* the controller's step after that change, at the earliest */
    unsigned settings_sent, settings_waited;
    uint16_t alarms;                /* the last answer's alarm bits ... */
    uint32_t alarms_ms;             /* ... count from this millisecond */
} hil_pc_t;

static double wall_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

static void usage(FILE *f)
{
    fputs("usage: hil --scenario FILE --port DEV [--controller NAME] [--pace X] [--timeout S]\n"
          "           [--csv OUT.csv] [--drop-every N] [--corrupt-every N] [--duration S]\n"
          "  runs FILE's plant against the controller on DEV (a flashed board on /dev/ttyUSB0, or the\n"
          "  host build's stand-in `hilboard --pty`) frame by frame and prints the metrics JSON last,\n"
          "  as `sim` does, with hil_frames and hil_lost. --pace 1 (default): real time, the board's\n"
          "  own clock; 0: as fast as it answers. --drop-every / --corrupt-every N: every Nth sensor\n"
          "  frame is not sent / sent damaged (to see the loss counted). Exit 3 when frames were lost.\n"
          "  --duration: the run ends at S seconds when FILE's ends later (as sim --duration).\n", f);
}

/* a command line with its checksum; the reply that starts with want (other lines skipped) */
static int command(hil_pc_t *h, const char *cmd, const char *want, char *reply, size_t n)
{
    char line[96];
    size_t k = 0;
    double end = wall_now() + 3.0;
    snprintf(line, sizeof line, "%s*%02X\r\n", cmd, link_crc8(cmd, strlen(cmd)));
    if (pty_write(h->fd, line, strlen(line)) < 0)
        return -1;
    while (wall_now() < end) {
        uint8_t b;
        int got = link_read(h->fd, &b, 1, 0.1);
        if (got < 0)
            return -1;
        if (got == 0)
            continue;
        if (b == '\n') {
            reply[k] = 0;
            if (k && reply[k - 1] == '\r')
                reply[--k] = 0;
            if (!strncmp(reply, want, strlen(want)) || !strncmp(reply, "ERR", 3))
                return !strncmp(reply, want, strlen(want)) ? 0 : -1;
            k = 0;
        } else if (k + 1 < n) {
            reply[k++] = (char)b;
        }
    }
    snprintf(reply, n, "no answer in 3 s");
    return -1;
}

/* The frame's setting: the first the controller does not hold yet as the PC's firmware modules
 * hold it (a scenario's event changed it); one a frame, so a second change waits for the next.
 * Until an answer confirms it, each frame carries it again (setting it twice changes nothing). */
static void pick_setting(hil_pc_t *h, hil_in_t *in)
{
    int i, n = 0;
    h->set_id = -1;
    in->set_id = HIL_NO_SETTING;
    for (i = 0; i < P_COUNT; i++)
        if (param_v[i] != h->board_param[i] && n++ == 0) {
            h->set_id = i;
            in->set_id = (uint8_t)i;
            in->set_value = param_v[i];
        }
    if (n > 1)
        h->settings_waited++;
}

/* The sensor frame of this period: the pulses' running counts and last stamps, the conversions,
 * the sections, a setting to send. */
static void sensor_frame(hil_pc_t *h, hil_in_t *in)
{
    hal_capture_t c;
    memset(in, 0, sizeof *in);
    in->seq = ++h->seq;
    in->pca_now = hal_pca_now();
    hal_wheel_capture_take(&c);
    h->wheel_total = (uint16_t)(h->wheel_total + c.count);
    h->rejected_total = (uint8_t)(h->rejected_total + c.rejected);
    in->wheel_count = h->wheel_total;
    in->wheel_last = c.last;
    in->wheel_rejected = h->rejected_total;
    hal_flow_capture_take(&c);
    h->meter_total = (uint16_t)(h->meter_total + c.count);
    in->meter_count = h->meter_total;
    in->meter_last = c.last;
    /* the four conversions of each channel the controller's period takes (analog.c), in its
     * order, summed: the board's HAL gives them back as quarters of the sum */
    in->adc_pressure = 0;
    in->adc_level = 0;
    for (int i = 0; i < 4; i++)
        in->adc_pressure = (uint16_t)(in->adc_pressure + hal_adc_read(HAL_ADC_PRESSURE));
    for (int i = 0; i < 4; i++)
        in->adc_level = (uint16_t)(in->adc_level + hal_adc_read(HAL_ADC_LEVEL));
    in->sections = hal_sections();
    pick_setting(h, in);
}

/* The answer to frame seq within the timeout: 1, 0 when none came, -1 when the link failed. */
static int await_answer(hil_pc_t *h, uint8_t seq, hil_out_t *o)
{
    uint8_t buf[64];
    double end = wall_now() + h->timeout_s;
    int got, i, ok = 0;
    while (!ok && wall_now() < end) {
        got = link_read(h->fd, buf, sizeof buf, end - wall_now() > 0 ? end - wall_now() : 0);
        if (got < 0)
            return -1;
        for (i = 0; i < got; i++)
            if (hil_rx_byte(&h->rx, buf[i])) {
                hil_out_decode(h->rx.buf, o);
                if (o->seq == seq)
                    ok = 1;         /* an answer to an older frame (late) is dropped */
            }
    }
    return ok;
}

/* The board's answer: the setting's verdict, the outputs as the firmware's HAL would have set
 * them, the status it reports. */
static void apply_answer(sim_t *sim, hil_pc_t *h, const hil_in_t *in, const hil_out_t *o)
{
    h->answered++;
    h->board_lost = o->lost;
    if (h->set_id >= 0 && o->set_verdict == PARAM_OK) {
        h->board_param[h->set_id] = in->set_value;
        h->settings_sent++;
    } else if (h->set_id >= 0 && o->set_verdict != HIL_NO_SETTING) {
        fprintf(stderr, "hil: at %.1f s the controller refused %s = %u (parameter %d): %s\n", sim_time_s(sim),
                param_info((uint8_t)h->set_id)->name, in->set_value, h->set_id, param_why_text(o->set_verdict));
        h->failed = 2;
    }
    h->pend = 0;
    if (o->valve_delay_ms == 0) {
        hal_host_io.valve_dir = o->valve_dir;
        hal_host_io.valve_duty = o->valve_dir ? o->valve_duty : 0;
    } else {
        hal_host_io.valve_dir = HAL_VALVE_OFF;
        hal_host_io.valve_duty = 0;
        h->pend = 1;
        h->pend_dir = o->valve_dir;
        h->pend_duty = o->valve_duty;
        h->pend_ms = hal_ms() + o->valve_delay_ms;
    }
    hal_host_io.spray_on = o->relays & 1u;
    hal_host_io.buzzer = (o->relays >> 1) & 1u;
    hal_wheel_min_interval(o->wheel_min);
    app_status.in.speed_kmh_x100 = o->speed_kmh_x100;
    app_status.in.target_lpm_x100 = o->target_lpm_x100;
    app_status.in.flow_lpm_x100 = o->flow_lpm_x100;
    app_status.in.pressure_kpa = o->pressure_kpa;
    h->alarms = o->alarms;
    h->alarms_ms = hal_ms() + HIL_DIAG_MS;
    app_status.spraying = o->relays & 1u;
}

/* One sensor frame out, its answer in (or a count of why not). */
static void exchange(sim_t *sim, hil_pc_t *h)
{
    hil_in_t in;
    hil_out_t o;
    uint8_t f[HIL_IN_BYTES];
    int got;

    sensor_frame(h, &in);
    hil_in_encode(&in, f);
    h->frames++;
    if (h->drop_every && h->frames % h->drop_every == 0) {
        h->dropped++;
        h->no_answer++;             /* never sent: nothing can answer it */
        return;
    }
    if (h->corrupt_every && h->frames % h->corrupt_every == 0) {
        f[6] ^= 0x10;               /* the wheel count: the CRC must catch it */
        h->corrupted++;
    }
    if (pty_write(h->fd, f, sizeof f) < 0) {
        h->failed = 1;
        return;
    }
    got = await_answer(h, in.seq, &o);
    if (got < 0)
        h->failed = 1;
    else if (!got)
        h->no_answer++;
    else
        apply_answer(sim, h, &in, &o);
}

/* sim_step's step 5: the board instead of app_poll() */
static void pc_poll(sim_t *sim)
{
    hil_pc_t *h = sim->poll_ctx;
    uint32_t now = hal_ms();
    if ((int32_t)(now - h->alarms_ms) >= 0)
        app_status.alarms = h->alarms;
    if (h->pend && (int32_t)(now - h->pend_ms) >= 0) {
        hal_host_io.valve_dir = h->pend_dir;
        hal_host_io.valve_duty = h->pend_duty;
        h->pend = 0;
    }
    /* a setting changed: the firmware derives its modules' constants in the passes that follow
     * (one a millisecond in the simulator) and steps when done */
    if (param_generation != h->param_gen) {
        h->param_gen = param_generation;
        h->ready_ms = now + HIL_PREP_MS;
    }
    if (h->failed || (int32_t)(now - h->next_ms) < 0 || (int32_t)(now - h->ready_ms) < 0)
        return;
    h->next_ms += APP_PERIOD_MS;
    /* the reference target of the metrics reads the firmware's target module: keep it on the
     * switches as the board's step does */
    target_update(hal_sections());
    if (h->pace > 0) {
        double ahead = sim_time_s(sim) / h->pace - (wall_now() - h->wall0);
        if (ahead > 0) {
            struct timespec d = { (time_t)ahead, (long)((ahead - (time_t)ahead) * 1e9) };
            nanosleep(&d, NULL);
        }
    }
    exchange(sim, h);
}

/* 1 for the events a HIL run carries: the plant's (on the PC, as in the simulator) and the
 * settings' (in the frames). An event on the controller's own machine (its keypad, its serial
 * link, its supply) is not, nor is a kind this list does not know yet: such a run is refused. */
static int hil_carries(int kind)
{
    switch (kind) {
    case EV_SECTIONS_OPEN: case EV_RATE: case EV_PRESET: case EV_GIVEN_SPEED: case EV_PTO_RPM:
    case EV_METER_FAIL: case EV_METER_RESTORE: case EV_SPEED_FAIL: case EV_SPEED_RESTORE:
    case EV_PSENS_OPEN: case EV_PSENS_RESTORE: case EV_VALVE_STUCK: case EV_VALVE_FREE:
    case EV_BOUNCE: case EV_LEAK: case EV_CLOG: case EV_TANK:
    case EV_METER_K: case EV_P_OFFSET: case EV_P_DRIFT: case EV_LEVEL_OFFSET: case EV_WHEEL_MULT:
        return 1;
    default:
        return 0;
    }
}

/* The board given the scenario's settings, then HIL mode; -1 (said on stderr) when it refused. */
static int board_set_up(hil_pc_t *h, const scenario_t *s, const char *port)
{
    char reply[128], cmd[48];
    int i;
    for (i = 0; i < P_COUNT; i++) {
        char want[32];
        snprintf(cmd, sizeof cmd, "SET %d %u", i, s->param[i]);
        snprintf(want, sizeof want, "OK %d %u", i, s->param[i]);
        if (command(h, cmd, want, reply, sizeof reply) < 0) {
            fprintf(stderr, "hil: %s: '%s' got '%s' (a controller with this firmware, freshly reset?)\n", port,
                    cmd, reply);
            return -1;
        }
    }
    if (command(h, "HIL ON", "OK HIL", reply, sizeof reply) < 0) {
        fprintf(stderr, "hil: %s: 'HIL ON' got '%s'\n", port, reply);
        return -1;
    }
    return 0;
}

/* The link's figures, the warnings a run with lost frames or late settings gets, the metrics. */
static void report(const hil_pc_t *h, sim_t *sim, const scenario_t *s, const char *port, const metrics_result_t *r)
{
    char extra[768], name[256];
    size_t k;
    unsigned lost = h->no_answer;
    printf("hil: %s on %s: %u frames, %u answered, %u without a good answer (%u not sent, %u sent damaged), "
           "%u damaged answers; the controller counted %u lost or damaged; %u setting changes carried\n",
           s->name, port, h->frames, h->answered, lost, h->dropped, h->corrupted, h->rx.damaged, h->board_lost,
           h->settings_sent);
    if (h->settings_waited)
        printf("hil: SETTINGS LATE: %u frames had more than one setting change to carry (one a frame): the rest "
               "came a period later than in the simulator\n", h->settings_waited);
    if (lost || h->board_lost)
        printf("hil: FRAMES LOST: the plant held the last outputs %u times; the figures below are not those "
               "of a clean run\n", lost);
    snprintf(name, sizeof name, "%s", s->name);
    for (k = 0; name[k]; k++)
        if (name[k] == '"' || name[k] == '\\' || (unsigned char)name[k] < 32)
            name[k] = '?';
    snprintf(extra, sizeof extra,
             "\"scenario\":\"%s\",\"controller\":\"%s\",\"seed\":%llu,\"hil_frames\":%u,\"hil_answered\":%u,"
             "\"hil_lost\":%u,\"hil_lost_controller\":%u,\"hil_settings\":%u,",
             name, ctl_name((uint8_t)s->param[P_CONTROLLER]), (unsigned long long)s->seed, h->frames,
             h->answered, lost, h->board_lost, h->settings_sent);
    metrics_json(stdout, &sim->metrics, r, extra, sim->wall_s, sim->cpu_s);
}

/* The program's options (the link's go into h). */
typedef struct {
    const char *scn_path, *port, *controller, *csv_path;
    double cut_s;
} hil_opt_t;

/* The command line into o and h: -1 to run, or the exit status (help, a usage error). */
static int options(int argc, char **argv, hil_opt_t *o, hil_pc_t *h)
{
    long drop = 0, corrupt = 0;
    int i;
    const arg_opt_t opts[] = {
        {"--scenario", ARG_TEXT, &o->scn_path, 0, 0, NULL},
        {"--port", ARG_TEXT, &o->port, 0, 0, NULL},
        {"--controller", ARG_TEXT, &o->controller, 0, 0, NULL},
        {"--csv", ARG_TEXT, &o->csv_path, 0, 0, NULL},
        {"--pace", ARG_NUM, &h->pace, 0, 1000, NULL},
        {"--timeout", ARG_NUM, &h->timeout_s, 0.001, 60, NULL},
        {"--duration", ARG_NUM, &o->cut_s, 0.001, 1e6, NULL},
        {"--drop-every", ARG_WHOLE, &drop, 2, 1e6, NULL},
        {"--corrupt-every", ARG_WHOLE, &corrupt, 2, 1e6, NULL},
    };
    memset(o, 0, sizeof *o);
    memset(h, 0, sizeof *h);
    h->pace = 1.0;
    h->timeout_s = -1;
    i = args_parse("hil", argc, argv, opts, (int)(sizeof opts / sizeof opts[0]), NULL, usage);
    if (i != ARGS_OK)
        return i == ARGS_HELP ? 0 : 2;
    h->drop_every = (unsigned)drop;
    h->corrupt_every = (unsigned)corrupt;
    if (!o->scn_path || !o->port) {
        fprintf(stderr, "hil: --scenario FILE and --port DEV are required\n");
        usage(stderr);
        return 2;
    }
    /* the answer comes within the period in real time: 38400 baud, 50 bytes, the step */
    if (h->timeout_s < 0)
        h->timeout_s = h->pace > 0 ? 0.08 / h->pace : 2.0;
    return -1;
}

/* The scenario, its controller and duration as asked; -1 (said on stderr) when it cannot run
 * on a board. */
static int load(const hil_opt_t *o, scenario_t *s)
{
    char err[512];
    int i;
    if (scenario_load(s, o->scn_path, err, sizeof err) < 0) {
        fprintf(stderr, "hil: %s\n", err);
        return -1;
    }
    if (o->controller && scenario_set_controller(s, o->controller, err, sizeof err) < 0) {
        fprintf(stderr, "hil: --controller: %s\n", err);
        return -1;
    }
    if (o->cut_s > 0)
        scenario_cut(s, o->cut_s, NULL, 0);
    for (i = 0; i < s->n_events; i++)
        if (!hil_carries(s->events[i].kind)) {
            fprintf(stderr, "hil: %s:%d: event '%s' is not one a HIL run carries (the plant's and the settings' "
                    "are; a key, a serial line, a power cut act on the board itself): run it with sim\n", o->scn_path,
                    s->events[i].line, scenario_event_name(s->events[i].kind));
            return -1;
        }
    return 0;
}

int main(int argc, char **argv)
{
    hil_opt_t o;
    const char *port, *csv_path;
    char err[512];
    scenario_t *s;
    sim_t *sim;
    hil_pc_t h;
    progress_t prog;
    metrics_result_t r;
    FILE *csv = NULL;
    int rc = options(argc, argv, &o, &h);
    unsigned lost;

    if (rc >= 0)
        return rc;
    port = o.port;
    csv_path = o.csv_path;
    s = malloc(sizeof *s);
    sim = malloc(sizeof *sim);
    if (!s || !sim) {
        fprintf(stderr, "hil: out of memory\n");
        return 1;
    }
    if (load(&o, s) < 0)
        return 1;
    h.fd = tty_open(port, err, sizeof err);
    if (h.fd < 0) {
        fprintf(stderr, "hil: %s\n", err);
        return 1;
    }
    if (board_set_up(&h, s, port) < 0)
        return 1;
    if (csv_path && !(csv = fopen(csv_path, "w"))) {
        fprintf(stderr, "hil: cannot write %s: %s\n", csv_path, strerror(errno));
        return 1;
    }
    sim_init(sim, s);
    memcpy(h.board_param, s->param, sizeof h.board_param);    /* as set up above */
    h.param_gen = param_generation;
    h.ready_ms = 0;
    sim->poll = pc_poll;
    sim->poll_ctx = &h;
    h.next_ms = APP_PERIOD_MS;
    hil_rx_init(&h.rx, HIL_OUT_START);
    if (csv)
        sim_trace_csv(sim, csv, 0.1);
    h.wall0 = wall_now();
    progress_start(&prog, "hil", s->duration_s);
    while (!sim_done(sim) && !h.failed) {
        sim_run(sim, sim_time_s(sim) + 1.0);
        progress_show(&prog, sim_time_s(sim));
    }
    progress_end(&prog);
    if (h.failed == 2)
        return 1;
    if (h.failed) {
        fprintf(stderr, "hil: the link to %s went away at %.1f s\n", port, sim_time_s(sim));
        return 1;
    }
    sim_finish(sim, &r);
    if (csv && fclose(csv) != 0) {
        fprintf(stderr, "hil: error writing %s: %s\n", csv_path, strerror(errno));
        return 1;
    }
    lost = h.no_answer;
    report(&h, sim, s, port, &r);
    sim_free(sim);
    close(h.fd);
    return lost || h.board_lost ? 3 : 0;
}

/* sim.c: the lock-step loop: scenario events and driver, the plant, the host HAL, app_poll() and the metrics (the operator's input: sim_input.c; the trace and the JSON: sim_trace.c). */
#include <math.h>
#include <string.h>
#include <time.h>
#include "sim.h"
#include "hal_host.h"
#include "params.h"
#include "app.h"
#include "ctl.h"
#include "target.h"
#include "keypad.h"
#include "store.h"
#include "link_crc.h"
#include <stdlib.h>

static double now_s(clockid_t clock)
{
    struct timespec ts;
    clock_gettime(clock, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

static void sample(sim_t *sim, double flow_lpm);

/* A fast mode's long tick may start now: the valve's bridge off and its motor at rest, the
 * tractor at the driver's speed, no operator input in the run, on the long tick's grid (so that
 * it ends on the 100 ms grid of the control steps and samples) and not past the scenario's end. */
static int sim_idle(const sim_t *sim)
{
    return hal_host_io.valve_dir == HAL_VALVE_OFF && !sim->plant.moving && !sim->n_input && !sim->scn_input &&
           fabs(sim->plant.v_cmd_kmh - plant_speed_kmh(&sim->plant)) < SIM_IDLE_KMH &&
           sim->t_ns % sim->idle_tick_ns == 0 && sim->t_ns + sim->idle_tick_ns <= sim->end_ns;
}

/* valve_duty / 255.0 for each duty (no division a tick) */
static double duty_frac[256];

/* The ADC's conversions come from the plant of the running simulation (one a process). */
static plant_t *adc_plant;
static uint16_t adc_convert(uint8_t ch)
{
    return ch == HAL_ADC_PRESSURE || ch == HAL_ADC_LEVEL ? plant_adc_sample(adc_plant, ch) : 0;
}

static void apply_params(const scenario_t *s)
{
    uint8_t i;
    for (i = 0; i < P_COUNT; i++)
        param_put(i, s->param[i]);          /* range- and cross-checked by the reader */
}

/* The nozzles open: those of the switched-on sections, and once AgOpenGPS sends sections (its
 * relays in series with the switches) only those it has on too. */
static void boom_valves(sim_t *sim)
{
    int nps = scenario_nozzles_per_section(sim->scn), n = 0;
    uint8_t on = hal_host_io.sections & (sim->aog_sect_set ? sim->aog_sections : 0xFF);
    for (; on; on >>= 1)
        n += on & 1u;
    sim->plant.open_nozzles = n * nps;
}

static void set_sections(sim_t *sim, int open_nozzles)
{
    int nps = scenario_nozzles_per_section(sim->scn);
    int on = open_nozzles / nps;
    hal_host_io.sections = (uint8_t)((1u << on) - 1u);
    boom_valves(sim);
}

/* ---- AgOpenGPS (AgIO) and RateControl frames into the UART, built as their sources build them */
static void push_frame(const uint8_t *f, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++)
        hal_host_uart_rx_push(f[i]);
}

/* 80 81 7F pgn len data.. crc: the low byte of the sum of bytes 2 .. n-2 */
static void aog_frame(uint8_t pgn, const uint8_t *d, uint8_t len)
{
    uint8_t f[32];
    unsigned sum = 0;
    size_t i;
    f[0] = 0x80, f[1] = 0x81, f[2] = 0x7F, f[3] = pgn, f[4] = len;
    memcpy(f + 5, d, len);
    for (i = 2; i < 5u + len; i++)
        sum += f[i];
    f[5 + len] = (uint8_t)sum;
    push_frame(f, 6u + len);
}

/* AgOpenGPS's frames at the true ground speed (what the GPS measures), RateControl's 32500 every
 * 200 ms: the target units a minute for its rate over the open width at that speed (as the app
 * computes it), MasterOn and AutoOn, module 0 */
static void frames_step(sim_t *sim, uint64_t t1)
{
    const plant_t *pl = &sim->plant;
    double kmh = pl->v_mps * 3.6;
    if (sim->aog_period_ns && t1 >= sim->aog_next_ns) {
        unsigned v = (unsigned)floor(kmh * 10 + 0.5);
        uint8_t d254[8] = {(uint8_t)v, (uint8_t)(v >> 8), 1, 0, 0, 0x7D, sim->aog_sections, 0};
        uint8_t d239[8] = {0, (uint8_t)(v > 255 ? 255 : v), 0, 0, 0, 0, sim->aog_sections, 0};
        aog_frame(254, d254, 8);
        aog_frame(239, d239, 8);
        sim->aog_next_ns += sim->aog_period_ns;
    }
    if (sim->rc_rate > 0 && t1 >= sim->rc_next_ns) {
        uint32_t upm = (uint32_t)floor(sim->rc_rate * kmh * pl->open_nozzles * pl->p.spacing_m / 600.0 * 1000 + 0.5);
        uint8_t f[14] = {0xF4, 0x7E, 0, (uint8_t)upm, (uint8_t)(upm >> 8), (uint8_t)(upm >> 16), 0, 0, 0, 0x50, 0, 0, 0, 0};
        unsigned sum = 0, i;
        for (i = 0; i < 13; i++)
            sum += f[i];
        f[13] = (uint8_t)sum;
        push_frame(f, sizeof f);
        sim->rc_next_ns += 200000000ull;
    }
}

void sim_init(sim_t *sim, const scenario_t *s)
{
    int i;
    for (i = 0; i < 256; i++)
        duty_frac[i] = i / 255.0;
    memset(sim, 0, sizeof *sim);
    sim->tick_ns = SIM_TICK_NS;
    sim->slope_row = -1;
    sim->scn = s;
    sim->aog_sections = 0xFF;       /* until an aog_sections event: every section */
    sim->end_ns = (uint64_t)(s->duration_s * 1e9 + 0.5);
    hal_host_reset();
    plant_init(&sim->plant, &s->plant, s->seed);
    sim->plant.flow_edge = hal_host_flow_edge;
    sim->plant.wheel_edge = hal_host_wheel_edge;
    adc_plant = &sim->plant;
    hal_host_adc_source(adc_convert);
    set_sections(sim, s->plant.nozzles);
    hal_host_io.adc[HAL_ADC_PRESSURE] = sim->plant.adc_pressure;
    hal_host_io.adc[HAL_ADC_LEVEL] = sim->plant.adc_level;
    metrics_init(&sim->metrics, SIM_SAMPLE_S);
    sim->next_sample_ns = (uint64_t)(SIM_SAMPLE_S * 1e9 + 0.5);

    /* the firmware as at power-on, with the operator's settings */
    params_defaults();
    apply_params(s);
    hal_init();
    app_init();
    apply_params(s);
    for (i = 0; i < s->n_events; i++)
        sim->scn_input |= s->events[i].kind == EV_KEY || s->events[i].kind == EV_SERIAL || s->events[i].kind == EV_AOG_HZ
                          || s->events[i].kind == EV_RC_RATE;
    for (i = 0; i < s->n_events; i++)
        if (s->events[i].kind == EV_POWER_CUT) {
            store_save();           /* the operator's settings saved, so that a reboot finds them */
            break;
        }
    sim->fw_rate = target_rate_x10();
    sim->set_rate = sim->fw_rate * 0.1;
    /* sample k of the step series is at k * SIM_SAMPLE_S: the first one now */
    sample(sim, 0.0);
}

/* The supply fails for s seconds: the chip's outputs fall (the valve stays where it is), its RAM
 * is gone (app_status reads zero), nothing it would take is taken until it boots again. */
static void power_cut(sim_t *sim, double s)
{
    uint64_t back = sim->t_ns + (uint64_t)(s * 1e9 + 0.5);
    hal_host_io.valve_dir = HAL_VALVE_OFF;
    hal_host_io.valve_duty = 0;
    hal_host_io.spray_on = 0;
    hal_host_io.buzzer = 0;
    memset(&app_status, 0, sizeof app_status);
    if (back > sim->power_back_ns)
        sim->power_back_ns = back;
}

/* The supply is back: the host HAL as after a power-on reset, the firmware from its start. */
static void power_on(sim_t *sim)
{
    sim->power_back_ns = 0;
    sim->key_release_ns = 0;
    hal_host_power_on();
    params_defaults();
    hal_init();
    app_init();
    sim->fw_rate = target_rate_x10();   /* what the firmware loaded, not what the operator set */
}

/* The operator's nudge as the serial command does it (so that PIL runs it in s51 too): NUD
 * +, - or 0 (back to the preset), with its check. */
static void nudge_line(sim_t *sim, int dir)
{
    char line[16];
    snprintf(line, sizeof line, "NUD %c", dir > 0 ? '+' : dir < 0 ? '-' : '0');
    snprintf(line + 5, sizeof line - 5, "*%02X", link_crc8(line, 5));
    sim_event_text(sim, EV_SERIAL, line);
}

int sim_event(sim_t *sim, int kind, double v)
{
    plant_t *pl = &sim->plant;
    if (scenario_event_check(sim->scn, kind, v, NULL, 0) < 0)
        return -1;
    switch (kind) {
    case EV_SECTIONS_OPEN: set_sections(sim, (int)floor(v + 0.5)); break;
    case EV_RATE: param_set(P_RATE, (uint16_t)floor(v * 10 + 0.5)); break;
    case EV_PRESET: param_set(P_PRESET, (uint16_t)floor(v + 0.5) - 1u); break;
    case EV_NUDGE: nudge_line(sim, (int)floor(v + 0.5)); break;
    case EV_GIVEN_SPEED: param_set(P_GIVEN_SPEED, (uint16_t)floor(v * 10 + 0.5)); break;
    case EV_PTO_RPM: pl->pto_rpm = v; break;
    case EV_METER_FAIL: pl->meter_fail = 1; break;
    case EV_METER_RESTORE: pl->meter_fail = 0; break;
    case EV_SPEED_FAIL: pl->speed_fail = 1; break;
    case EV_SPEED_RESTORE: pl->speed_fail = 0; break;
    case EV_PSENS_OPEN: pl->psens_open = 1; break;
    case EV_PSENS_RESTORE: pl->psens_open = 0; break;
    case EV_VALVE_STUCK: pl->valve_stuck = 1; break;
    case EV_VALVE_FREE: pl->valve_stuck = 0; break;
    case EV_BOUNCE: pl->bounce_pct = v; break;
    case EV_LEAK: pl->leak_lpm = v; break;
    case EV_CLOG: pl->clogged = (int)floor(v + 0.5); break;
    case EV_TANK: pl->tank_v = v; break;
    case EV_METER_K: pl->p.meter_k_ppl = v; break;
    case EV_P_OFFSET: pl->psens_offset_bar = v; break;
    case EV_P_DRIFT: pl->psens_drift_bar_per_min = v; break;
    case EV_LEVEL_OFFSET: pl->level_offset_l = v; break;
    case EV_WHEEL_MULT: pl->wheel_mult = v; break;
    case EV_POWER_CUT: power_cut(sim, v); break;
    case EV_AOG_HZ:
        sim->aog_period_ns = v > 0 ? (uint64_t)floor(1e9 / v + 0.5) : 0;
        sim->aog_next_ns = sim->t_ns + sim->tick_ns;
        break;
    case EV_AOG_SECTIONS:
        sim->aog_sections = (uint8_t)((1u << (int)floor(v + 0.5) / scenario_nozzles_per_section(sim->scn)) - 1u);
        sim->aog_sect_set = 1;
        boom_valves(sim);
        break;
    case EV_RC_RATE:
        sim->rc_rate = v;
        sim->rc_next_ns = sim->t_ns + sim->tick_ns;
        break;
    default: return -1;
    }
    return 0;
}

int sim_event_name(sim_t *sim, const char *name, double value)
{
    int k;
    for (k = 0; k < EV_COUNT; k++)
        if (strcmp(name, scenario_event_name(k)) == 0)
            return sim_event(sim, k, value);
    return -1;
}

static const char *alarm_code(uint8_t bit, char *buf, size_t n)
{
    const char *c = app_alarm_code(bit);
    if (c && *c)
        return c;
    snprintf(buf, n, "ALARM_%u", bit);
    return buf;
}

double sim_reference_lpm(const sim_t *sim)
{
    const plant_t *pl = &sim->plant;
    double v = plant_speed_kmh(pl) * (1.0 + pl->p.wheel_slip_pct / 100.0) * 100.0;
    uint16_t vx = (uint16_t)(v > 65535.0 ? 65535.0 : v + 0.5);
    return target_flow_x100(target_speed_x100(vx)) / 100.0;
}

/* What a meter true to the firmware's calibration reads of the flow through it, L/min. */
static double meter_reads_lpm(sim_t *sim)
{
    const plant_t *pl = &sim->plant;
    if (param_v[P_METER_K] != sim->cal_param) {
        sim->cal_param = param_v[P_METER_K];
        sim->cal_inv = sim->cal_param > 0 ? 10.0 / sim->cal_param : 0.0;
    }
    return pl->q_meter * plant_meter_k(pl, pl->q_meter) * sim->cal_inv;
}

static void sample(sim_t *sim, double flow_lpm)
{
    metrics_sample(&sim->metrics, sim_reference_lpm(sim), app_status.in.target_lpm_x100 / 100.0, flow_lpm,
                   app_status.in.speed_kmh_x100 / 100.0, hal_host_io.spray_on);
}

/* The driver's command at t (time only moves forward): scenario_drive_kmh with a cursor. */
static double drive_kmh(sim_t *sim, double t)
{
    const scenario_t *s = sim->scn;
    const scn_drive_t *d = s->drive;
    int i;
    if (s->n_drive == 0)
        return 0.0;
    while (sim->drive_row + 1 < s->n_drive && d[sim->drive_row + 1].t_s <= t)
        sim->drive_row++;
    i = sim->drive_row;
    if (t < d[0].t_s || i + 1 >= s->n_drive)
        return d[i].kmh;
    if (i != sim->slope_row) {
        sim->slope_row = i;
        sim->drive_slope = (d[i + 1].kmh - d[i].kmh) / (d[i + 1].t_s - d[i].t_s);
    }
    return d[i].kmh + sim->drive_slope * (t - d[i].t_s);
}

/* The rate in force: the operator's, or a field computer's the firmware took (the host's
 * firmware; its state is not on the host under PIL) */
static double rate_now(const sim_t *sim)
{
    return !sim->pass && target_rate_remote() ? target_rate_x10() * 0.1 : sim->set_rate;
}

/* The operator is told: an alarm, a warning or a notice active on the firmware's screen (its
 * bits in app_status.alarms), or the screen dark while the power is cut. */
static int operator_told(const sim_t *sim)
{
    return sim->power_back_ns != 0 || app_status.alarms != 0;
}

/* The operator's view for silent_wrong, at a sample: the boom's mean flow over it, the truth. */
static void watch(sim_t *sim)
{
    const plant_t *pl = &sim->plant;
    metrics_watch_t w;
    int flowing = pl->open_nozzles - pl->clogged;
    w.boom_lpm = sim->boom_lpm;
    w.v_kmh = plant_speed_kmh(pl);
    w.width_m = (flowing > 0 ? flowing : 0) * pl->p.spacing_m;
    w.rate_l_ha = rate_now(sim);
    w.spraying = pl->spray_on;
    w.sections_on = pl->open_nozzles > 0;
    w.told = operator_told(sim);
    metrics_watch(&sim->metrics, SIM_SAMPLE_S, &w);
}

/* The firmware's pass of this tick (none while the power is off), and the rate it took. */
static void sim_firmware(sim_t *sim)
{
    if (sim->pass)
        sim->pass(sim->pass_ctx);
    else if (sim->poll)
        sim->poll(sim);
    else
        app_poll();
    if (target_rate_x10() != sim->fw_rate) {
        sim->fw_rate = target_rate_x10();   /* the operator set a rate (event, key or link) */
        sim->set_rate = sim->fw_rate * 0.1;
    }
}

/* What the tick ending at t1 (dt s long) left: the drive log, the alarms raised, the metrics,
 * the samples, the trace. */
static void sim_record(sim_t *sim, uint64_t t1, double dt)
{
    plant_t *pl = &sim->plant;
    if (sim->drive_log && (hal_host_io.valve_dir != sim->log_dir || hal_host_io.valve_duty != sim->log_duty ||
                           hal_host_io.spray_on != sim->log_spray)) {
        sim->log_dir = hal_host_io.valve_dir;
        sim->log_duty = hal_host_io.valve_duty;
        sim->log_spray = hal_host_io.spray_on;
        fprintf(sim->drive_log, "%llu %d %d %d\n", (unsigned long long)(t1 / SIM_TICK_NS), sim->log_dir,
                sim->log_duty, sim->log_spray);
    }

    if (app_status.alarms & ~sim->prev_alarms) {
        unsigned rise = app_status.alarms & ~sim->prev_alarms;
        uint8_t b;
        char buf[16];
        for (b = 0; b < 8 * sizeof app_status.alarms; b++)     /* every bit the firmware has */
            if (rise & (1u << b))
                metrics_alarm(&sim->metrics, t1 * 1e-9, alarm_code(b, buf, sizeof buf), app_alarm_text(b));
    }
    sim->prev_alarms = app_status.alarms;

    metrics_add(&sim->metrics, dt, pl->v_mps, pl->q_boom, pl->open_nozzles * pl->p.spacing_m,
                rate_now(sim), pl->p_bar, pl->spray_on);
    if (pl->spray_on && !sim->spray_on_ns)
        sim->spray_on_ns = t1 + 1;
    metrics_target(&sim->metrics, dt, pl->v_mps, meter_reads_lpm(sim), app_status.in.target_lpm_x100 * 0.01,
                   (pl->theta <= 0.0 || pl->theta >= 1.0 ? METRICS_AT_STOP : 0)
                       | (!sim->spray_on_ns || t1 < sim->spray_on_ns + SIM_START_NS ? METRICS_AT_START : 0));
    metrics_valve(&sim->metrics, dt, (double)pl->valve_reversals, pl->valve_travel, pl->spray_on);
    sim->acc_meter += pl->q_meter;
    sim->acc_boom += pl->q_boom;
    sim->acc_n++;
    if (t1 >= sim->next_sample_ns) {
        sim->flow_true_lpm = sim->acc_meter / sim->acc_n;
        sim->boom_lpm = sim->acc_boom / sim->acc_n;
        sim->acc_meter = sim->acc_boom = 0;
        sim->acc_n = 0;
        sample(sim, sim->flow_true_lpm);
        watch(sim);
        sim->next_sample_ns += (uint64_t)(SIM_SAMPLE_S * 1e9 + 0.5);
    }
    if (sim->csv && t1 >= sim->next_csv_ns) {
        sim_row_t r;
        sim_row(sim, &r);
        sim_csv_row(sim->csv, &r);
        sim->next_csv_ns += sim->csv_period_ns;
    }
}

void sim_step(sim_t *sim)
{
    const scenario_t *s = sim->scn;
    plant_t *pl = &sim->plant;
    uint32_t tick = sim->idle_tick_ns && sim_idle(sim) ? sim->idle_tick_ns : sim->tick_ns;
    uint64_t t1 = sim->t_ns + tick;
    double t1_ns = (double)(int64_t)t1;     /* t1 < 2^63: the signed conversion is exact and cheaper */
    plant_in_t in;
    double dt = tick * 1e-9;

    while (sim->next_event < s->n_events && s->events[sim->next_event].t_s * 1e9 <= t1_ns) {
        const scn_event_t *e = &s->events[sim->next_event++];
        if (e->kind == EV_KEY || e->kind == EV_SERIAL)
            sim_event_text(sim, e->kind, e->text);  /* checked when the file was read */
        else
            sim_event(sim, e->kind, e->value);
    }
    if (sim->n_input || sim->scn_input)
        sim_input_step(sim, t1);
    if (sim->aog_period_ns || sim->rc_rate > 0)
        frames_step(sim, t1);
    pl->v_cmd_kmh = drive_kmh(sim, t1_ns * 1e-9);
    in.drive = hal_host_io.valve_dir * duty_frac[hal_host_io.valve_duty];
    in.spray_on = hal_host_io.spray_on;

    hal_host_set_time_ns(t1);
    plant_step(pl, &in, tick);
    sim->t_ns = t1;

    if (sim->power_back_ns && t1 >= sim->power_back_ns)
        power_on(sim);
    if (!sim->power_back_ns)                /* a dead chip runs nothing; what arrives is gone at power_on */
        sim_firmware(sim);
    sim_record(sim, t1, dt);
}

void sim_run(sim_t *sim, double until_s)
{
    uint64_t until = until_s <= 0 ? 0 : (uint64_t)(until_s * 1e9 + 0.5);
    double w0 = now_s(CLOCK_MONOTONIC), c0 = now_s(CLOCK_PROCESS_CPUTIME_ID);
    if (until > sim->end_ns)
        until = sim->end_ns;
    while (sim->t_ns + sim->tick_ns <= until)
        sim_step(sim);
    sim->wall_s += now_s(CLOCK_MONOTONIC) - w0;
    sim->cpu_s += now_s(CLOCK_PROCESS_CPUTIME_ID) - c0;
}

int sim_set_tick_ms(sim_t *sim, int ms, int idle_ms)
{
    int period = (int)(SIM_SAMPLE_S * 1000 + 0.5);
    if (ms < 1 || ms > SIM_TICK_MAX_MS || period % ms != 0 || sim->t_ns != 0)
        return -1;
    if (idle_ms && (idle_ms <= ms || idle_ms > SIM_TICK_MAX_MS || period % idle_ms != 0 || idle_ms % ms != 0))
        return -1;
    sim->tick_ns = (uint32_t)ms * 1000000u;
    sim->idle_tick_ns = (uint32_t)idle_ms * 1000000u;
    return 0;
}

int sim_done(const sim_t *sim)
{
    return sim->t_ns + sim->tick_ns > sim->end_ns;
}

double sim_time_s(const sim_t *sim)
{
    return sim->t_ns * 1e-9;
}

void sim_free(sim_t *sim)
{
    free(sim->input);
    sim->input = NULL;
    metrics_free(&sim->metrics);
}

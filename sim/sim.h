/* sim.h: the simulator: the firmware application (app.h) in lock-step with the plant model, events, trace and metrics. */
#ifndef SIM_SIM_H
#define SIM_SIM_H

/*
 * How to use it (one simulation per process at a time: the firmware and the host HAL are
 * single instances):
 *
 *     scenario_t *s = malloc(sizeof *s);          // large (the drive table): not on a small stack
 *     char err[256];
 *     if (scenario_load(s, "scenarios/paper_dynamic_150.scn", err, sizeof err) < 0) { puts(err); exit(1); }
 *     sim_t *sim = malloc(sizeof *sim);
 *     sim_init(sim, s);                           // HAL reset, plant at rest, firmware params, app_init()
 *     sim_trace_csv(sim, csv_file, 0.1);          // optional: one CSV row every 0.1 s
 *     sim_run(sim, 60.0);                         // up to t = 60 s (or sim_step() tick by tick)
 *     sim_event(sim, EV_METER_FAIL, 0);           // apply an event now (scenario.h SCN_EVENTS)
 *     sim_run(sim, s->duration_s);
 *     metrics_result_t r; sim_finish(sim, &r);    // the metrics of docs/SCENARIOS.md
 *     sim_json(sim, &r, stdout);                  // ... as one JSON line
 *     sim_free(sim);
 *
 * One tick (SIM_TICK_NS = 1 ms) of sim_step, in this order:
 *   1. the scenario's events due at or before the tick's end are applied;
 *   2. the driver's command for the tick is read from [drive];
 *   3. the firmware's outputs in hal_host_io (valve_dir, valve_duty, spray_on) drive the plant;
 *   4. the plant advances one tick; the simulated clock (hal_host_set_time_ns) moves to the
 *      tick's end, then the pulse edges of the tick reach hal_host_flow_edge/_wheel_edge with
 *      their exact times, and hal_host_io.adc[HAL_ADC_PRESSURE], [HAL_ADC_LEVEL] are updated;
 *   5. app_poll() runs once (it does its control step when APP_PERIOD_MS has passed), or the
 *      firmware's pass in s51 (sim->pass, sim/pil_host.h);
 *   6. metrics and the trace take the tick.
 * A power cut (`power_cut S`) stops the firmware's passes for S seconds: the outputs fall as the
 * chip's do (relay, H-bridge and buzzer off, the valve stays where it is), app_status reads zero,
 * input is lost; the plant runs on. Then hal_host_power_on() and hal_init(), app_init() as at
 * power-up: the EEPROM holds what the firmware wrote (a scenario with a power cut starts with its
 * [config] saved there, as an operator's saved settings). Not in PIL or HIL runs.
 * Firmware parameters from [config] are set with param_set() before and again after app_init()
 * (so an app that loads its parameters from the erased EEPROM in app_init still gets them, and
 * param_generation says they changed). The section switches (hal_host_io.sections) start with
 * every section on; `sections_open N` switches on the first N / (nozzles / sections) sections.
 */

#include <stdint.h>
#include <stdio.h>
#include "scenario.h"
#include "plant.h"
#include "metrics.h"

#define SIM_TICK_NS 1000000u        /* plant step: 1 ms */
#define SIM_START_NS 5000000000u    /* the start's share of the loop's: until 5 s after the boom first opened */
#define SIM_TICK_MAX_MS 50          /* the longest tick sim_set_tick_ms allows (fast modes) */
#define SIM_FAST_TICK_MS 5          /* sim --fast: the tick */
#define SIM_FAST_IDLE_MS 10         /* ... and the tick while the valve is idle */
#define SIM_IDLE_KMH 0.05           /* idle also means the tractor within this of the driver's speed */
#define SIM_SAMPLE_S 0.1            /* target/flow samples for the step metrics (= APP_PERIOD_MS) */

/* Everything the trace holds at one instant: the truth, the firmware's view, the controller. */
typedef struct {
    double t_s;
    double v_cmd_kmh, v_true_kmh;   /* driver's command, true ground speed */
    double v_meas_kmh;              /* firmware: app_status.in.speed_kmh_x100 */
    double target_lpm;              /* firmware: target boom flow */
    double flow_meas_lpm;           /* firmware: measured flow */
    double flow_true_lpm;           /* truth: through the meter (nozzles + leak), mean over the last sample period */
    double boom_lpm;                /* truth: out of the nozzles, mean over the last sample period */
    double pump_lpm, bypass_lpm, relief_lpm;  /* truth, this tick */
    double p_bar;                   /* truth: line pressure at the boom */
    double p_meas_kpa;              /* firmware: app_status.in.pressure_kpa */
    int adc_pressure, adc_level;    /* what the ADC reads now */
    double valve_pos;               /* truth: bypass valve 0 closed .. 1 open */
    double valve_drive;             /* HAL output as the plant takes it: [-1, 1], + opens the bypass */
    double ctl_drive;               /* firmware: controller output, + = more boom flow, [-1, 1) */
    double kp, ki, kd;              /* firmware: gains of the last step */
    double tank_l;                  /* truth */
    double tank_meas_l;             /* firmware: app_status.tank_l */
    double pto_rpm;
    int spray_on;                   /* master boom valve as the firmware set it */
    int open_nozzles;               /* truth: nozzles in the open sections */
    int sections;                   /* switch bits the firmware reads */
    unsigned alarms;                /* firmware: app_status.alarms */
    double ref_lpm;                 /* the metrics' reference target: the settings at the true wheel speed */
    double rate_l_ha;               /* the set rate now */
    double width_m;                 /* the open boom's width */
} sim_row_t;

typedef struct sim {
    const scenario_t *scn;          /* must outlive the simulation */
    plant_t plant;
    metrics_t metrics;
    uint64_t t_ns;                  /* simulated time (= hal_host_io.time_ns) */
    uint64_t end_ns;                /* duration_s of the scenario */
    uint32_t tick_ns;               /* SIM_TICK_NS, or a fast mode's longer tick (sim_set_tick_ms) */
    uint32_t idle_tick_ns;          /* a fast mode's tick while the valve is idle (0: tick_ns) */
    int next_event;                 /* index into scn->events */
    int drive_row;                  /* the last [drive] row at or before now (a cursor) */
    unsigned prev_alarms;
    uint64_t spray_on_ns;           /* when the boom first opened, +1 (0: not yet; the start's share) */
    /* mean flows over the current sample period */
    double acc_meter, acc_boom;
    uint32_t acc_n;
    double flow_true_lpm, boom_lpm; /* the last period's means */
    uint16_t cal_param;             /* the meter's calibration parameter cal_inv was computed for */
    double cal_inv;                 /* litres a pulse by the firmware's calibration (0: none) */
    int slope_row;                  /* the [drive] row drive_slope is for (-1: none) */
    double drive_slope;             /* km/h per s from that row to the next */
    uint64_t next_sample_ns;
    /* trace */
    FILE *csv;
    uint64_t csv_period_ns, next_csv_ns;
    double wall_s;                  /* wall time spent in sim_step so far */
    double cpu_s;                   /* the process's CPU time over the same (no other load in it) */
    /* the firmware's pass of a tick: app_poll() here, or (pass set) the same firmware elsewhere
     * (hal/pil: inside s51), which leaves its outputs in hal_host_io and app_status */
    void (*pass)(void *ctx);
    void *pass_ctx;
    /* the valve drive sequence: a line "tick dir duty spray" whenever one of them changes */
    FILE *drive_log;
    int log_dir, log_duty, log_spray;
    /* operator input (sim_input_load): key presses and serial command lines at given times */
    struct sim_input *input;
    int n_input, next_input;
    uint64_t key_release_ns;        /* the key held now is let go at this time (0: none held) */
    int scn_input;                  /* the scenario's [events] hold key or serial input */
    uint64_t power_back_ns;         /* a power cut: the supply comes back at this time (0: on) */
    /* AgOpenGPS and RateControl on the serial link (events aog_hz, aog_sections, rc_rate_l_ha) */
    uint64_t aog_period_ns, aog_next_ns;    /* 254 and 239 every period (0: none) */
    uint8_t aog_sections;           /* the sections they carry (bit 0 = section 1) */
    int aog_sect_set;               /* an aog_sections event came: the boom's valves follow them */
    double rc_rate;                 /* L/ha RateControl asks for (0: no frames) */
    uint64_t rc_next_ns;            /* its next 32500 */
    uint16_t fw_rate;               /* the firmware's rate in use (L/ha x10) the last tick it ran ... */
    double set_rate;                /* ... and the rate the operator last set (a reboot's reload is not one) */
    /* step 5 of sim_step: app_poll() when NULL; the HIL program (sim/hil_main.c) puts a board
     * on the serial link there instead */
    void (*poll)(struct sim *sim);
    void *poll_ctx;
} sim_t;

/* One timed operator input: a key held SIM_KEY_HOLD_MS, or a line sent to the serial link. */
typedef struct sim_input {
    double t_s;
    char key;                       /* keypad character, or 0 for a serial line or frame */
    char line[72];                  /* the line without its end; "\r\n" is added */
    uint8_t n_bytes;                /* a frame: its bytes in line[], as they are (0: a line) */
} sim_input_t;
#define SIM_KEY_HOLD_MS 100

/* Read operator input for the run from a text file, one event a line, times ascending:
 *     t_s key K         hold keypad key K (0-9 A-D * #) for SIM_KEY_HOLD_MS
 *     t_s serial TEXT   the characters of TEXT and "\r\n" arrive at the UART
 *     t_s frame HEX..   the bytes (two hex digits each, spaces between allowed) arrive at the
 *                       UART as they are: a PGN frame (docs/PGN.md)
 * ('#' starts a comment where a line starts with it). 0, or -1 with "file:line: reason" in err.
 * Call after sim_init(). */
int sim_input_load(sim_t *sim, const char *path, char *err, size_t n);
/* The operator's inputs due by t1 (ns): keys pressed and let go, lines into the UART
 * (sim_input.c, for sim_step). */
void sim_input_step(sim_t *sim, uint64_t t1);
/* The reference target, L/min: what the firmware's settings give for the true wheel speed (slip
 * included), so that the firmware's own measurement noise can neither hide nor invent a hold. */
double sim_reference_lpm(const sim_t *sim);

/* Start a simulation of scenario s at time 0 (resets the host HAL and the firmware). */
void sim_init(sim_t *sim, const scenario_t *s);
/* One plant tick of SIM_TICK_NS and one app_poll(). */
void sim_step(sim_t *sim);
/* A fast mode: the plant steps and the firmware's passes every ms milliseconds instead of every
 * one (1..SIM_TICK_MAX_MS, a divisor of the 100 ms sample period, so that the control steps and
 * the samples stay on their grid), and every idle_ms (0: ms; a multiple of ms, a divisor of 100)
 * while the plant is idle (the valve's bridge off and motor at rest, the tractor at the driver's
 * speed; no operator input in the run); before the first step only. An approximation, not the model (docs/PIL.md, the simulator's speed): the
 * pressure's implicit step over a longer tick takes the pump's pulsation averaged over it, the
 * firmware sees its inputs in tick-long slices. 0, or -1 for ticks it does not allow. */
int sim_set_tick_ms(sim_t *sim, int ms, int idle_ms);
/* Step until the simulated time reaches until_s (never past the scenario's end). */
void sim_run(sim_t *sim, double until_s);
/* 1 once the scenario's duration is over. */
int sim_done(const sim_t *sim);
double sim_time_s(const sim_t *sim);
/* Apply an event now (kinds and values as in [events]); -1 when the value is not valid for
 * this scenario (nothing changes), 0 when applied. */
int sim_event(sim_t *sim, int kind, double value);
/* A key or serial event now (EV_KEY: text is the key; EV_SERIAL: the line); -1 when the text
 * is not valid for it (nothing happens), 0 when applied. */
int sim_event_text(sim_t *sim, int kind, const char *text);
/* The same by the event's name ("meter_fail", "leak_lpm", ...); -1 for an unknown name too. */
int sim_event_name(sim_t *sim, const char *name, double value);
/* Fill a trace row with the state now. */
void sim_row(const sim_t *sim, sim_row_t *row);
/* Write the CSV header now and one row every period_s from here on (f == NULL stops). */
void sim_trace_csv(sim_t *sim, FILE *f, double period_s);
void sim_csv_header(FILE *f);
void sim_csv_row(FILE *f, const sim_row_t *r);
/* The metrics of the run so far (steps, zones, dose...). */
void sim_finish(sim_t *sim, metrics_result_t *r);
/* The metrics as one JSON line, with the scenario's name, controller and seed first. */
void sim_json(const sim_t *sim, const metrics_result_t *r, FILE *f);
void sim_free(sim_t *sim);

#endif

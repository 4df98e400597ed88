/* app.c: the main loop: every APP_PERIOD_MS measure, target, control, drive the valve, diagnose, log; the watchdog fed while healthy. */
#if defined(__SDCC)
#pragma stackauto           /* locals on the stack, not each its own XRAM (docs/MEMORY.md) */
#endif
#include "hal.h"
#include "params.h"
#include "ctl.h"
#include "app.h"
#include "speed.h"
#include "flow.h"
#include "analog.h"
#include "target.h"
#include "valve.h"
#include "diag.h"
#include "diag_wheel.h"
#include "ops.h"
#include "totals.h"
#include "serial.h"
#include "pgn.h"
#include "hil.h"
#include "store.h"
#include "console.h"
#include "drive.h"

/*
 * One control step every APP_PERIOD_MS, in passes of its own: app_step (measure: speed.c,
 * flow.c, analog.c; target: target.c; spray: sections on, tank above its minimum, moving;
 * drive: drive.c), then app_after (totals, the RAM check, the watchdog), app_diag (alarms,
 * buzzer) and diag_after_fit; a log line every 1000 ms (serial.c). A step late by a period or
 * more does not kick the watchdog and skips the periods it missed (the totals count them).
 * The I/O test (ops_io) hands the relay, the buzzer and the jog to the technician.
 */
#define APP_LOG_PERIODS (1000u / APP_PERIOD_MS)
/* periods after power-up before over-pressure is an alarm even if the pressure never fell under
 * P max (the pump may push against a bypass left closed while the slowest valve opens) */
#define APP_P_WAIT 150u
/* The totals are saved this long after the boom shuts: not in the step that switches the
 * relay off, when its coil's energy and the supply's dip meet the IAP erase's current. */
#define APP_SAVE_WAIT_PERIODS (1000u / APP_PERIOD_MS)
/* A changed setting is saved this long after the change was first seen (the changes made
 * meanwhile go with it); the totals every minute of spraying. The EEPROM's erase budget
 * (store.h) bounds what any sequence of changes can cost. */
#define APP_SET_SAVE_PERIODS (2000u / APP_PERIOD_MS)
#define APP_TOTALS_SAVE_PERIODS (60000u / APP_PERIOD_MS)
#define IO_ON (ops_io & OPS_IO_ON)

static struct {
    uint32_t next_ms;
    uint16_t overruns;              /* steps late by a period or more */
    uint8_t ctl_id;                 /* P_CONTROLLER the controller was selected for */
    uint8_t was_manual;
    uint8_t log_div;
    uint8_t internal;
    uint8_t p_watch;                /* APP_P_WAIT: the pressure was under P max once spraying or parked since power-up, or APP_P_WAIT passed */
    uint8_t save_wait;              /* periods until the totals are saved after a shut (0: none due) */
    uint8_t set_wait;               /* periods until changed settings are saved (0: none counting) */
    uint16_t sprayed;               /* periods sprayed since the app last asked for a save */
    uint8_t save;                   /* the save is due: app_poll runs it in a pass of its own */
    uint8_t prep;                   /* next module app_prepare derives for ... */
    uint8_t prep_gen;               /* ... this param_generation (all done when it is current) */
    uint8_t periods;                /* periods this step covers (more than 1: it was late) */
    uint8_t after;                  /* APP_AFTER_*: the step's second pass is due (app_after) */
    uint8_t diag;                   /* APP_DIAG_*: flags app_account leaves for app_diag */
    int16_t q_model;                /* the nozzle model's flow at the pressure (app_measure) */
} ap;
#define APP_AFTER_DUE 1u
#define APP_AFTER_KICK 2u           /* the step ran on time: the watchdog is fed after the RAM check */
#define APP_DIAG_DUE 1u
#define APP_DIAG_SETTLED 2u         /* diag_step's settled */
#define APP_DIAG_P_WATCH 4u         /* and p_watch */

/* The control chain from rest, as at power-on (app_init, and the first frame of HIL mode). */
static void app_start(void)
{
    hal_valve_out(HAL_VALVE_OFF, 0);
    hal_spray_enable(0);
    hal_buzzer(0);
    speed_init();
    flow_init();
    analog_init();
    target_init();
    valve_init();
    diag_init();
    /* manual mode never survives a power-up: the valve left where a jog put it would spray a
     * dose nobody follows (the record keeps it until the next save) */
    param_put(P_MODE, 0);
    ap.ctl_id = (uint8_t)param_v[P_CONTROLLER];
    ctl_select(ap.ctl_id);
    ap.overruns = 0;
    drive_init();
    ops_init();
    ap.was_manual = 0;
    ap.log_div = 0;
    ap.internal = 0;
    ap.p_watch = 0;
    ap.save_wait = 0;
    ap.set_wait = 0;
    ap.sprayed = 0;
    ap.save = 0;
    ap.prep = 0;
    ap.prep_gen = param_generation;
    ap.after = 0;
    ap.diag = 0;
    ap.next_ms = hal_ms() + APP_PERIOD_MS;
}

void app_init(void)
{
    totals_init();
    store_load();                   /* the EEPROM's parameters and lifetime totals, or the defaults and a message */
    serial_init();
#if FW_PGN
    pgn_init();
#endif
#if FW_HIL
    hil_init();                     /* out of the HIL mode, as at power-on */
#endif
    app_start();
    console_init();
}

#if FW_HIL
/* HIL mode: the outputs of the step just run, as the output frame (hil.h). */
static void app_hil_answer(void) __reentrant
{
    hil_out_t o;
    o.valve_delay_ms = valve_pending(&o.valve_dir, &o.valve_duty);
    o.relays = (uint8_t)((app_status.spraying ? 1u : 0u) | (app_status.alarms_unacked ? 2u : 0u));
    o.alarms = app_status.alarms;
    o.speed_kmh_x100 = app_status.in.speed_kmh_x100;
    o.target_lpm_x100 = app_status.in.target_lpm_x100;
    o.flow_lpm_x100 = app_status.in.flow_lpm_x100;
    o.pressure_kpa = app_status.in.pressure_kpa;
    serial_hil_send(&o);
}
#endif

/* Every parameter inside its range, or RAM is not what it should be. */
static uint8_t params_sane(void)
{
    uint8_t i;
    for (i = 0; i < P_COUNT; i++)
        if (!param_in_range(i, param_v[i]))
            return 0;
    return 1;
}

/* Measure: speed, flow, pressure, level, the sections; the target (eq. (1), Table 1, or 0 with
 * the boom's sections off) and the flow the loop follows: the meter, or the nozzle model when
 * the meter is lost or reads under a quarter of what the nozzles pass (a dead meter read as no
 * flow closed the bypass for a whole second and took the line to the relief valve); the alarm
 * waits 1 s to be sure, the loop does not. Into app_status. */
static void app_measure(void)
{
    uint16_t v_meas, p;
    int16_t q_meter, q_used;
    uint8_t open, meter_lost;

    v_meas = pgn_speed(speed_step());   /* the wheel's, or the GPS's (Speed src) */
#if FW_PGN
    diag_set_frames(pgn_frames());
#endif
    q_meter = flow_step();
    analog_step();
    p = analog_pressure_kpa();
    target_update(pgn_sections(hal_sections()));
    open = target_open_nozzles();
    diag_set_nozzles(open);
    ops_set_speed(target_speed_x100(v_meas));
    ops_set_target(open ? target_flow_x100(app_status.in.speed_kmh_x100) : 0);
    ops_set_manual(param_v[P_MODE] != 0);
    /* the flow the loop follows (above); a live meter that reads low is a clog (diag.c), and
     * the loop stays on the meter */
    meter_lost = (diag_alarms() >> AL_METER_LOST) & 1u;
    q_used = q_meter;
    ap.q_model = diag_nozzle_flow_x100(p, open);
    if ((meter_lost || diag_meter_suspect()) && analog_pressure_ok())
        q_used = ap.q_model;
    ops_set_flow(q_used);
    ops_set_pressure(p);
    ops_set_open_nozzles(open);
}

/* Spray or not: sections on, the tank above its minimum, the machine moving (in manual mode
 * too: a boom open at a standstill floods one spot), no internal fault. Opening starts the
 * start-up closing; shutting saves the lifetime totals.
 * Back to auto: bumpless from the drive now. */
static void app_spray(void)
{
    uint8_t manual = app_status.manual;
    uint8_t want = app_status.open_nozzles
                   && !(diag_alarms() & ((1u << AL_TANK_LOW) | (1u << AL_PUMP_DRY)))
                   && app_status.in.speed_kmh_x100 > 0 && !ap.internal && !IO_ON;
    /* after power-up the boom waits, shown, while the line is over P max (a fixed PTO's pump
     * against a bypass still opening) and the nozzles would spray over twice the target there,
     * until APP_P_WAIT (under twice the target is no further from it than a shut boom) */
    ops_set_boom_wait(want && !app_status.spraying && !manual && ap.p_watch < APP_P_WAIT && drive_overp()
                      && (uint16_t)ap.q_model > ((uint16_t)app_status.in.target_lpm_x100 << 1));
    want &= !app_status.boom_wait;
    if (want != app_status.spraying) {
        ops_set_spraying(want);
        hal_spray_enable(want);
        if (!want)
            ap.save_wait = APP_SAVE_WAIT_PERIODS;   /* keep the lifetime totals, a while later */
        if (want)
            drive_spray_on(manual);
    }
    if (IO_ON)
        hal_spray_enable((ops_io & OPS_IO_RELAY) && !ap.internal);   /* never against an internal fault */
    if (manual != ap.was_manual) {
        ap.was_manual = manual;
        if (!manual)
            ctl_reset(app_status.drive);    /* bumpless: the loop starts from the drive now */
        ops_jog_cancel();
    }
}

/* The saves (each in a pass of its own: app_save): the totals APP_SAVE_WAIT_PERIODS after a shut
 * (spraying again cancels it) and every APP_TOTALS_SAVE_PERIODS of spraying; changed settings
 * APP_SET_SAVE_PERIODS after the change was first seen. */
static void app_save_when_due(void)
{
    if (app_status.spraying) {
        ap.save_wait = 0;
        if (++ap.sprayed >= APP_TOTALS_SAVE_PERIODS)
            ap.save = 1;
    } else if (ap.save_wait && --ap.save_wait == 0) {
        ap.save = 1;
    }
    if (store_generation() == param_generation)
        ap.set_wait = 0;
    else if (!ap.set_wait)
        ap.set_wait = APP_SET_SAVE_PERIODS;
    else if (--ap.set_wait == 0)
        ap.save = 1;                /* (still unsaved a wait later: counted again) */
}

/* The save app_save_when_due asked for (store_poll carries it out over the next passes); one
 * already running writes the values and totals of its time; a low supply refuses it: the
 * shut's tried again a wait later, the others when next due. */
static void app_save(void)
{
    ap.save = 0;
    if (store_busy())
        return;
    ap.sprayed = 0;
    if (!store_save_start(0))
        ap.save_wait = APP_SAVE_WAIT_PERIODS;
}

/* Totals and saves, the alarms' flags (app_diag); once a second the display's divisions and a
 * log line. */
static void app_account(void)
{
    uint8_t on = app_status.spraying;
    uint16_t v = 0, w = 0;
    int16_t q = 0;

    /* every period since the last step, a late step's missed ones too (the same figures for
     * each: nothing in the loop changes them) */
    if (on) {
        v = app_status.in.speed_kmh_x100;
        w = target_width_cm();
        q = app_status.in.flow_lpm_x100;
    }
    do
        totals_step(v, w, q);
    while (--ap.periods);
    app_save_when_due();

    /* over-pressure is an alarm while spraying or parked open, once the pressure was under P max
     * there after power-up (or after APP_P_WAIT) */
    if (ap.p_watch < APP_P_WAIT
        && (++ap.p_watch >= APP_P_WAIT || (!drive_overp() && (on || drive_parked()))))
        ap.p_watch = APP_P_WAIT;
    ap.diag = (uint8_t)(APP_DIAG_DUE | (on && !drive_priming() ? APP_DIAG_SETTLED : 0)
                        | ((on || drive_parked()) && ap.p_watch >= APP_P_WAIT ? APP_DIAG_P_WATCH : 0));
    /* once a second the display values and the log line: in a pass of their own (app_poll) */
    if (++ap.log_div >= APP_LOG_PERIODS)
        ap.log_div = APP_LOG_PERIODS;
}

/* The alarms of the step just run (diag.c, with its figures): the step's longest part, in the
 * pass after it, before anything else of that pass (the valve's poll included), so that they
 * read what the step left. */
static void app_diag(void)
{
    diag_step(&app_status, (ap.diag & APP_DIAG_SETTLED) != 0, (ap.diag & APP_DIAG_P_WATCH) != 0);
    ap.diag = 0;
    ops_alarms_step();              /* (a call of its own: off diag_step's deep call chain) */
}

/* After a settings change every module derives its constants again (divides, some thousands
 * of cycles each): one module a pass here, so that neither these passes nor the next control
 * step carry them all (the rate target's for the sections now: the step derives it again only
 * when they change). Returns 1 while work was done. */
static uint8_t app_prepare(void)
{
    if (ap.prep_gen == param_generation && ap.prep == 0)
        return 0;
    if (ap.prep_gen != param_generation) {
        ap.prep_gen = param_generation;
        ap.prep = 0;                /* a change during the round starts it again */
    }
    switch (ap.prep++) {
    case 0: speed_prepare(); break;
    case 1: flow_prepare(); break;
    case 2: analog_kpa_of_sum(0); break;            /* derives the scale when it is stale */
    case 3: diag_set_nozzles(target_open_nozzles()); break;
    case 4: valve_prepare(); break;
    default:                        /* (both here: as many passes as before the target's came) */
        target_update(pgn_sections(hal_sections()));
        ctl_prepare();
        ap.prep = 0;
        break;
    }
    return 1;
}

/* Once a second: the divisions of the display values, and the log line. */
static void app_second(void)
{
    ap.log_div = 0;
    ops_show_totals();
    serial_log_request();
}

/* The save the step asked for, then the once-a-second work, each a pass; 1 when one ran. */
static uint8_t app_after_step(void)
{
    if (ap.save)
        app_save();
    else if (ap.log_div >= APP_LOG_PERIODS)
        app_second();
    else
        return 0;
    return 1;
}

/* The step's first pass: from the inputs to the valve's drive, and the status. */
static void app_step(void)
{
    if ((uint8_t)param_v[P_CONTROLLER] != ap.ctl_id) {     /* the controller the operator chose */
        ap.ctl_id = (uint8_t)param_v[P_CONTROLLER];
        ctl_select(ap.ctl_id);
        ctl_reset(app_status.drive);
    }
    app_measure();
    app_spray();
    drive_step();
    ops_show_step();
}

/* The step's second pass, first thing in the pass after it: what no output of the step waits
 * for (the wheel's learning, the totals and saves), the RAM check (every parameter in its
 * range: else the internal fault, and the next step sprays nothing), then the watchdog. */
static void app_after(void)
{
    uint8_t kick = ap.after & APP_AFTER_KICK;
    ap.after = 0;
    speed_learn_now();
    app_account();
    if (!params_sane()) {
        ap.internal = 1;
        diag_internal_fault();
    }
    if (kick && !ap.internal)
        hal_wdt_kick();
}

/* The step's later passes, one a pass, first thing in it, each with the serial link: app_after;
 * the alarms (before the valve's poll: they read what the step left, the next step sees them);
 * the nozzle model's constant after a fit. Returns 1 when one ran. */
static uint8_t app_step_rest(void)
{
    uint8_t diag = ap.diag && !ap.after;
    if (ap.after)
        app_after();
    else if (!diag && !diag_after_fit())
        return 0;
    serial_poll(1);
    if (diag)
        app_diag();
    return 1;
}

void app_poll(void)
{
    uint32_t now = hal_ms();
    uint8_t late, due, rest;

    rest = app_step_rest();
    valve_poll(now);
    if (rest)
        return;
#if FW_HIL
    if (hil_active()) {
        /* one step a sensor frame, on its inputs; none without one (never on stale inputs:
         * when the frames stop, so do the steps, and the watchdog resets the chip); the PC
         * waits for the answer, so the step takes its constants, save and log with it */
        serial_poll(1);
        console_poll();
        while (store_poll())
            ;                       /* a save they asked for, whole */
        if (!hil_due())
            return;
        if (hil_first())
            app_start();
        while (app_prepare())
            ;
        app_step();
        ap.after = APP_AFTER_DUE;
        app_after();
        app_diag();
        if (ap.save)
            app_save();
        while (store_poll())
            ;
        if (ap.log_div >= APP_LOG_PERIODS)
            app_second();
        app_hil_answer();
        if (!ap.internal)
            hal_wdt_kick();
        return;
    }
#endif
    /* One heavy job a pass: the modules' constants after a change (no command taken meanwhile:
     * a flood of changes never holds a due step); the step; a save, the second's work; else the
     * console, or in odd ms a save's part. The serial link in every pass but the step's. */
    due = (int32_t)(now - ap.next_ms) >= 0;
    if (app_prepare()) {
        serial_poll(!due);
        return;
    }
    if (!due) {
        if (app_after_step())
            serial_poll(1);
        else if (!serial_poll(1) && !((now & 1u) && store_poll()))
            console_poll();
        return;
    }
    /* a step late by a period or more (a held CPU, a stall) skips the periods it missed, so
     * the schedule stays on its grid, and counts them into the totals */
    ap.periods = 0;
    do {
        ap.next_ms += APP_PERIOD_MS;
        if (ap.periods < 255)
            ap.periods++;
    } while ((int32_t)(now - ap.next_ms) >= 0);
    late = ap.periods > 1;
    if (late)
        ap.overruns++;
    app_step();
    ap.after = late ? APP_AFTER_DUE : APP_AFTER_DUE | APP_AFTER_KICK;
}

#if FW_PROBES
const char *app_alarm_code(uint8_t bit)
{
    return diag_code(bit);
}

const char *app_alarm_text(uint8_t bit)
{
    return diag_text(bit);
}

uint16_t app_overruns(void)
{
    return ap.overruns;
}
#endif

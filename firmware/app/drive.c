/* drive.c: what the valve is driven with each period: the start-up closing, the controller, a shut boom's bypass held or parked, over-pressure, manual jogs. */
#if defined(__SDCC)
#pragma stackauto           /* locals on the stack, not each its own XRAM (docs/MEMORY.md) */
#endif
#include <stddef.h>
#include "hal.h"
#include "params.h"
#include "ctl.h"
#include "analog.h"
#include "valve.h"
#include "target.h"
#include "ops.h"
#include "drive.h"

#define APP_PRIME_MAX_PERIODS 100u  /* start-up closing gives up after 10 s */
#define APP_PRIME_SHIFT 3           /* ... and stops once the meter reads the target less this share */
#define APP_JOG_DRIVE Q15(0.6)      /* a jog (OPS_JOG_PERIODS) at 60 % duty */
#define APP_RELIEVE_DRIVE Q15(0.5)  /* over-pressure: open the bypass at 50 % */
#define APP_HOLD_KPA 5u             /* a shut boom holds the spraying pressure within this (+1/16) */
#define APP_P_AHEAD 12u             /* no closing while this many periods more of the pressure's
                                     * last rise would take it over P max (drive_overp_soon) */
#define APP_NEAR_P_SHIFT 2u         /* above P max less P max >> this (3.6 of 4.8 bar) a closing
                                     * drive is at most twice Min duty (drive_step) */
#define IO_ON (ops_io & OPS_IO_ON)

static struct {
    uint8_t prime;                  /* periods of start-up closing left (0: done) */
    uint8_t parked;                 /* boom shut and the bypass found at its open stop, or held */
    uint16_t p_hold;                /* kPa the boom sprayed at (filtered), 0: park open */
} dv;
/* x100 L/min: the meter's flow a period ago, while the start-up closing runs (drive_auto; the
 * direct RAM, as XRAM is at its floor) */
static __data int16_t prime_flow_last;

/* 1: the meter read half the target since the boom opened in auto (drive_starved) */
static __bit flowed;
/* kPa: the pressure a period ago (drive_overp_soon; the direct RAM, as XRAM is at its floor) */
static __data uint16_t p_last;

void drive_init(void)
{
    dv.prime = 0;
    dv.parked = 0;
    dv.p_hold = 0;
}

/* The boom opens: the start-up closing at full duty while the line is under P start (the
 * paper's start) unless a shut boom held the bypass at the spraying pressure; the controller
 * from rest. */
void drive_spray_on(uint8_t manual)
{
    dv.prime = (!manual && !dv.p_hold && analog_pressure_ok()
                && app_status.in.pressure_kpa < param_v[P_P_MIN]) ? APP_PRIME_MAX_PERIODS : 0;
    if (dv.prime)
        prime_flow_last = app_status.in.flow_lpm_x100;
    flowed = 0;
    ctl_reset(0);
}

uint8_t drive_priming(void)
{
    return dv.prime;
}

uint8_t drive_parked(void)
{
    return dv.parked;
}

/* The pressure above P max (the sensor working). */
uint8_t drive_overp(void)
{
    return analog_pressure_ok() && app_status.in.pressure_kpa > param_v[P_P_MAX];
}

/* The pump stopped under a spraying boom: a pump on the wheels of a tractor that halts while the
 * minimum-flow rule holds the target. The flow the meter read falls under half the target,
 * below P start, under MinQ speed; closing the bypass then makes no flow, and the tractor's
 * restart would find it shut, the line at the relief valve while a slow valve reopens. So
 * nothing closes (as over P max) until the flow, the pressure or the speed comes back. Not
 * before the meter has read half the target since the boom opened: a line still filling (the
 * bypass held at a low pressure, a start at a crawl) needs the loop to close. */
static uint8_t drive_starved(void)
{
    int16_t half = app_status.in.target_lpm_x100 >> 1;
    if (app_status.in.flow_lpm_x100 >= half)
        flowed = 1;
    return flowed && app_status.in.flow_lpm_x100 < half && analog_pressure_ok()
           && app_status.in.pressure_kpa < param_v[P_P_MIN]
           && !target_working_speed(app_status.in.speed_kmh_x100);
}

/* Over P max soon: the pressure rising so fast that APP_P_AHEAD periods more of this period's
 * rise would take it over P max. A fast valve closing toward a target near P max turns once the
 * meter shows the target, and its coast, its backlash and the meter's lag carry the pressure on
 * past P max (the family's OVERPRESSURE runs: 1.5-2 s valves told 4 s, 141-149 L/ha, the target
 * at 4.0-4.4 bar); the pressure shows the flow's rise at once, the meter a few periods late. So
 * the closing stops that far ahead, as over P max; the loop may still open. */
static uint8_t drive_overp_soon(void)
{
    uint16_t p = app_status.in.pressure_kpa;
    int16_t dp = (int16_t)(p - p_last);
    p_last = p;
    return dp > 0 && analog_pressure_ok()
           && (dp >= 1024 || p + (uint16_t)dp * APP_P_AHEAD > param_v[P_P_MAX]);
}

/* The drive of a spraying boom in auto: the start-up closing at full duty until the line
 * reaches P_P_MIN (the paper's start) or the meter reads 7/8 of the target a period ahead (the
 * flow as it is plus its last period's rise: the valve coasts, the line fills and the meter
 * lags, so a closing that stops once the flow is there leaves it past the target), then the
 * controller, which closes nothing over P max, soon over it, or with the pump stopped. */
static q15_t drive_auto(uint8_t overp)
{
    q15_t drive = 0;
    int16_t rise;
    if (dv.prime) {
        dv.prime--;
        rise = app_status.in.flow_lpm_x100 - prime_flow_last;
        prime_flow_last = app_status.in.flow_lpm_x100;
        if (rise < 0)
            rise = 0;
        if (app_status.in.pressure_kpa >= param_v[P_P_MIN] || (valve_limit() & CTL_AT_CLOSED) || !analog_pressure_ok()
            || app_status.in.flow_lpm_x100
                   >= app_status.in.target_lpm_x100 - (app_status.in.target_lpm_x100 >> APP_PRIME_SHIFT) - rise)
            dv.prime = 0;
        else
            drive = Q15_MAX;
        if (!dv.prime)
            ctl_reset(drive);           /* (p_hold: 0 since the boom opened, drive_spray_on) */
    }
    if (!dv.prime) {
        ops_set_valve_limit(valve_limit() | (overp || drive_starved() ? CTL_NO_CLOSE : 0));
        drive = ctl_step(&app_status.in);
    }
    return drive;
}

/* The pressure the boom sprays at, filtered over about 8 periods, once the start-up closing is
 * done: what a shut boom holds the bypass to. */
static void drive_hold_learn(void)
{
    int16_t d = (int16_t)(app_status.in.pressure_kpa - dv.p_hold);
    if (!dv.prime)
        dv.p_hold = dv.p_hold ? (uint16_t)(dv.p_hold + ((d + 4) >> 3)) : app_status.in.pressure_kpa;
}

/* A shut boom: the bypass opens until the pressure is no higher than the boom sprayed at (the
 * pump circulates at a pressure the operator chose, not through the relief valve), and the
 * valve stays there, so that spraying again starts near where it left off, from below (the
 * boom's opening lowers the pressure). Without a spraying pressure to hold (power-up, the valve
 * moved by hand, the pressure sensor failed) the bypass is parked at its open stop. */
static q15_t drive_park(void)
{
    uint16_t h = dv.p_hold;
    if ((valve_limit() & CTL_AT_OPEN)
        || (valve_position() != VALVE_POS_UNKNOWN && valve_position() >= (uint16_t)Q15(0.9))) {
        dv.parked = 1;                      /* open enough (or at the stop): stay, no retries */
    } else if (h) {
        /* held within h/16 + APP_HOLD_KPA of the spraying pressure; once held, opened again
         * beyond twice that (the pump sped up) */
        h = (h >> 4) + APP_HOLD_KPA;
        dv.parked = app_status.in.pressure_kpa <= dv.p_hold + (dv.parked ? 2 * h : h);
    }
    return dv.parked ? 0 : -Q15_MAX;
}

/* Drive the valve: manual mode only jogs; a spraying boom in auto as drive_auto; a shut boom
 * as drive_park; over-pressure never closes further and opens the bypass. The controller hears
 * what the valve got. */
void drive_step(void)
{
    uint8_t manual = app_status.manual;
    uint8_t overp = drive_overp(), soon = drive_overp_soon();   /* (the pressure's rise: every period) */
    q15_t drive = 0;
    if (manual || IO_ON) {
        int8_t dir = ops_jog_take();
        if (dir)
            drive = dir > 0 ? APP_JOG_DRIVE : -APP_JOG_DRIVE;
    } else if (app_status.spraying) {
        drive = drive_auto(overp | soon);
        drive_hold_learn();
    } else {
        if (dv.prime) {
            dv.prime = 0;                   /* shut while priming: nothing sprayed to hold */
            dv.p_hold = 0;
        }
        drive = drive_park();
    }
    if (manual || IO_ON || !analog_pressure_ok()) {
        dv.p_hold = 0;                      /* the valve moved by hand, or no pressure to hold on; */
        prime_flow_last = 0;                /* a start-up closing resumed after it takes its flow as
                                             * risen from nothing */
    }
    if (manual || IO_ON)
        flowed = 0;                         /* back in auto the loop may have to close first */
    if (app_status.spraying || manual || IO_ON)
        dv.parked = 0;
    /* Near P max a closing drive is held to twice Min duty (every controller's): a fast valve
     * told it is slower, turned after a rest by a pulse worth its backlash, carried the flow a
     * tenth and the pressure 0.7 bar past in 0.8 s with its motor's coast, over P max before
     * the rule above could stop it (a target at 4.5 bar). Min
     * duty, not a fixed duty: a valve stiffer than the cap would never close there. */
    if (!manual && !IO_ON && app_status.spraying && drive > 0 && analog_pressure_ok()
        && app_status.in.pressure_kpa > param_v[P_P_MAX] - (param_v[P_P_MAX] >> APP_NEAR_P_SHIFT)
        && (drive >> 1) > ctl_stiction)
        drive = ctl_stiction << 1;          /* (Min duty under a half here: no overflow) */
    if (overp && drive > -APP_RELIEVE_DRIVE)
        drive = -APP_RELIEVE_DRIVE;         /* never close further; open the bypass */
    valve_set(drive);
    ctl_applied(valve_applied(), valve_limit());   /* what the valve got, overrides included */
}


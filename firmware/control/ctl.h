/* ctl.h: the one interface of the flow controllers: init, bumpless reset, step(setpoint, measured) -> valve drive. */
#ifndef CTL_H
#define CTL_H

#include "fixed.h"

/* The controllers, chosen by P_CONTROLLER (keypad), the serial link or a scenario's `controller =`. */
enum { CTL_PID = 0, CTL_FUZZY_PID = 1, CTL_BP_PID = 2, CTL_FFMAP = 3, CTL_AOG = 4, CTL_RAVEN = 5, CTL_COUNT };

/* What a controller sees each control period (APP_PERIOD_MS). Flows in L/min x100. */
typedef struct {
    int16_t target_lpm_x100;        /* setpoint: the boom flow the dose needs now */
    int16_t flow_lpm_x100;          /* measured boom flow */
    uint16_t speed_kmh_x100;        /* ground speed (the target already follows it) */
    uint16_t pressure_kpa;          /* boom pressure (reacts before the meter does) */
    uint8_t valve_limit;            /* CTL_AT_* bits: the valve sits at an end stop */
} ctl_in_t;
#define CTL_AT_OPEN 1               /* bypass fully open: no more "less flow" */
#define CTL_AT_CLOSED 2             /* bypass fully closed: no more "more flow" */
#define CTL_NO_CLOSE 4              /* closing refused (over-pressure, a stopped pump) with the valve
                                     * NOT at a stop: like CTL_AT_CLOSED for anti-windup, but no
                                     * end-stop calibration */
#define CTL_CLOSE_BLOCKED (CTL_AT_CLOSED | CTL_NO_CLOSE)

/* The output: valve drive for the next period, Q15 signed duty. Positive = more boom flow,
 * i.e. drive the bypass valve toward closed; negative opens it. */

/* Min duty (P_VALVE_BRK), Q15: the valve's break-away as the operator told it. */
extern int16_t ctl_stiction;

/* Select a controller (0 when id is unknown and nothing changes) and start it from rest. */
uint8_t ctl_select(uint8_t id);
uint8_t ctl_selected(void);
/* Byte i of what ffmap learnt of the valve, for the EEPROM (store.h STORE_LEARN_CTL); with another
 * controller selected, the record's as it was. */
uint8_t ctl_learnt_byte(uint8_t i);
/* Bumpless transfer: the loop (re)starts from the drive the valve has now (manual -> auto). */
void ctl_reset(q15_t drive_now);
/* What the valve really got this period, after the application's overrides (over-pressure
 * relief, manual jog, priming, parking) and the stop logic, and the stops it is at (CTL_AT_*
 * from the valve's own estimate, not over-pressure): called every period, stepping or not. A
 * controller that estimates the valve's position (ffmap) integrates this drive, not its own
 * demand, and calibrates at the stops; without the call it assumes its demand was applied. */
void ctl_applied(q15_t drive, uint8_t limit) __reentrant;
/* One control step on the inputs `in` (in XRAM: the application's status block, ops.h
 * app_status.in, or a test's own); the controllers read them through this pointer on every
 * target, and nothing else of the caller's.
 * The budget of any controller: ctl_step plus ctl_applied in at most
 * CTL_STEP_BUDGET_CYCLES machine cycles of classic 12-clock timing as s51 counts them (the 1T
 * STC12 runs this code about six times faster: about 5.4 ms of the 100 ms period); tt_ctl fails
 * a controller over it, `make bench` prints each one's worst. */
#ifndef CTL_STEP_BUDGET_CYCLES          /* a lower one on the command line proves the check fails */
#define CTL_STEP_BUDGET_CYCLES 30000UL
#endif
q15_t ctl_step(const __xdata ctl_in_t *in);
/* Derive the constants of changed parameters now, so that the next step need not. */
void ctl_prepare(void);
/* The gain (0 kp, 1 ki, 2 kd) the controller used in its last step, Q12, for logs and traces. */
int16_t ctl_gain(uint8_t i);
/* Name of a controller for the console and the logs ("pid", "fuzzy_pid", "bp_pid", "ffmap", "aog", "raven"). */
const __code char *ctl_name(uint8_t id);

#endif

/* status.h: the status block ops owns (ops.h its operations): what the application measured and decided in its last control step. */
#ifndef STATUS_H
#define STATUS_H

#include "compiler.h"
#include "ctl.h"

/* What the application measured and decided in its last control step: the console, the
 * serial log and the simulator's trace read it. ops owns it and alone writes it: its reset
 * (ops_init), the alarms raised and acknowledged, the totals shown, and the figures the
 * application publishes through ops.h's ops_set_*. The control step's inputs are its block
 * `in` (ctl.h ctl_in_t: target and measured flow, ground speed used for the target, boom line
 * pressure, the valve's CTL_AT_* and CTL_NO_CLOSE), passed to ctl_step, not copied. The
 * totals are totals_get()'s, the gains ctl_gain()'s (no copies here). */
typedef struct {
    ctl_in_t in;                    /* the control step's inputs (ctl.h) */
    uint16_t tank_l;                /* tank contents from the level sensor */
    uint16_t applied_l_ha_x10;      /* dose applied over the job so far */
    int16_t drive;                  /* Q15 valve drive from the controller (+ = more flow) */
    uint16_t alarms;                /* active alarm bits */
    uint16_t alarms_unacked;        /* alarm bits raised and not yet acknowledged */
    uint8_t spraying;               /* master boom valve open */
    uint8_t manual;                 /* manual mode (operator jogs the valve) */
    uint8_t open_nozzles;           /* nozzles in the switched-on sections */
    uint8_t boom_wait;              /* the boom kept shut after power-up: the line over P max */
    uint32_t job_area_m2;           /* the job's area, taken once a second (a divide) */
} app_status_t;

extern app_status_t app_status;

#endif

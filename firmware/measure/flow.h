/* flow.h: boom flow from the turbine meter's pulse periods, averaged over the control period. */
#ifndef FLOW_H
#define FLOW_H

#include "compiler.h"

/*
 * Each period: n edges, newest at t; flow = 60 * n / (K * (t - t_prev_newest)): the mean over
 * the whole pulse intervals that ended in this period (about the period itself: at 18 L/min
 * and 380 p/L, 11 or 12 intervals of 8.8 ms), with no quantisation by the window.
 * A window whose mean period is shorter than the meter can pulse (FLOW_MAX_X100, twice the
 * LWGYA-20's 150 L/min) is a glitch: rejected (the last good value is held) and counted.
 * When pulses stop the flow can be at most one pulse over the time since the last edge; after
 * FLOW_ZERO_PERIODS without a pulse it is zero. K is P_METER_K (0.1 p/L); the tank method
 * counts flow_pulses() while a measured volume V is sprayed: P_METER_K = 10 * pulses / V.
 */
#define FLOW_MAX_X100 30000         /* 300 L/min */
#define FLOW_ZERO_PERIODS 10u       /* 1 s without a pulse: no flow (0.16 L/min at 380 p/L) */
#define FLOW_STALE_PERIODS 100u

void flow_init(void);
/* One control period: take the meter edges, return L/min x100. */
int16_t flow_step(void) __reentrant;
/* Derive the constants of changed parameters now, so that the next step need not. */
void flow_prepare(void);
int16_t flow_lpm_x100(void);
uint32_t flow_pulses(void);
uint16_t flow_glitches(void);
uint16_t flow_quiet_periods(void);

#endif

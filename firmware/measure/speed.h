/* speed.h: ground speed from the wheel pulses by timing their periods (PCA time stamps), not by counting in a window. */
#ifndef SPEED_H
#define SPEED_H

#include "compiler.h"

/*
 * Each control period takes the edges that arrived (count n, PCA time of the newest) and
 * measures v = distance_per_pulse * n / (t_newest - t_previous_newest): the mean speed over
 * the last n whole pulse intervals, whatever the window. Resolution: the PCA tick (1.085 us)
 * against a pulse interval of 0.128 s at 11 km/h is 1e-5, below the 0.01 km/h of the
 * result and the 2e-4 of um_muldiv. Latency: the estimate is the mean over the last pulse
 * interval(s), so it describes the instant half an interval before the newest edge, plus up
 * to one control period (at 4 km/h with the default wheel: 0.35 s intervals, ~0.3 s mean);
 * a change of speed is fully seen once one whole interval at the new speed has ended.
 * When pulses stop, the speed can be at most what the pulse that has not come yet allows
 * (one pulse distance over the time since the last edge), so it falls as 1/t; below
 * SPEED_ZERO_X100 it is zero (standstill), i.e. 2.8 s after the last pulse with the default
 * 0.3927 m a pulse. A window whose mean period means more than SPEED_MAX_X100 is a glitch
 * (bounce, interference): rejected and counted. Rises are limited to SPEED_SLEW_X100 for
 * each period since the last measurement (3 m/s^2, six times what a tractor does) so a single extra edge cannot kick the
 * target; falls are not limited (the 1/t bound is physical).
 * The pulses come from P_WHEEL_PPR elements a turn that are never evenly spaced: each
 * element's offset from its even place is learnt at steady speed (the same element's edge
 * one turn apart gives the turn's time, against which the span since the previous edge reads
 * the two offsets' difference) and taken out of every span, so one period measures the speed
 * as a whole turn would. Until they are learnt (the first turns, and after every restart of the
 * learning) the speed is a tracker's (speed.c speed_track): an alpha-beta-gamma filter on the
 * edges' positions, whose spacing errors are white within a turn, carried on between edges at
 * the acceleration it reads (which decays over about 1.6 s: a tractor levels off) and never past
 * the speed at which the next edge would have come. It starts on the expanding-memory gains (the
 * least-squares quadratic through the edges so far) and settles on SPEED_TK_*'s; a speed taken
 * over a window of spans lags by half the window, which at a start from standstill left the
 * target 5-14 % under the truth for a second and a half. On its steady gains an edge a whole
 * pulse off its place is a pulse missed or extra and only the rest of it counts; two such edges
 * in a row are the tracker's rate off by a pulse a span, and it starts again from the span. A
 * pulse sooner than a quarter of the period at 1.5 times the speed (the estimate's, or the last
 * span's where that is faster: the estimate's rise is slewed; at standstill none) is dropped by
 * the HAL (bounce, interference) and counted as a glitch.
 * The distance per pulse is P_WHEEL (0.1 mm); its 100 m calibration counts
 * speed_pulses() over a measured 100 m: P_WHEEL = 1000000 / pulses.
 */
#define SPEED_ZERO_X100 50u         /* 0.5 km/h: below this, standstill */
#define SPEED_MAX_X100 6000u        /* 60 km/h: faster pulses are glitches */
#define SPEED_SLEW_X100 108u        /* 3 m/s^2 over 100 ms = 1.08 km/h */
/* This many measured periods in a row, each a quarter over the estimate before them and over the
 * rise SPEED_SLEW_X100 a period allows since (8 -> 12 km/h held 0.3 s, a doubling 8 -> 16), are
 * a wheel sending pulses a tractor cannot make: a second magnet or sensor, a loose one doubling
 * the edges (speed_jumped). 3 m/s^2 is 0.3 g: beyond what a tractor drawing a sprayer reaches in
 * a field (the plant's tractor: 0.5 m/s^2); a bounce doubles one period's span, a spacing error
 * moves one by a quarter at most. Not from rest (the first spans of a start). */
#define SPEED_JUMP_PERIODS 3u
#define SPEED_STALE_PERIODS 100u    /* 10 s without a pulse: the old edge is forgotten */
#define SPEED_LOST_X100 200u        /* pulses that stop above 2 km/h: a lost sensor, not a stop */
#define SPEED_TK_ALPHA 166          /* the tracker (speed.c, offsets unlearnt): position gain 0.65, /256 */
#define SPEED_TK_BETA 77            /* ... rate gain 0.30, /256 */
#define SPEED_TK_GAMMA 492          /* ... acceleration gain 0.03, x16384 (speed.c's units) */
#define SPEED_TK_T_MAX 7200u        /* ... a span over 2 s (PCA/256): it starts again */
#define SPEED_TK_DECAY 4u           /* ... the acceleration decays by 1/2^this a period (1.6 s) */
#define SPEED_TK_FILL_N 6u          /* ... the steady gains from this many edges tracked (speed.c
                                     * tk_gain: the first fit's before) */
#define SPEED_TK_OUT_N 3u           /* ... its speed used from this many edges (the span's before) */
#define SPEED_TK_V_MAX 60000u       /* ... the rate's range: 103 pulses a second (146 km/h on the
                                     * default wheel; beyond it the span's speed) */
#define SPEED_TK_NEXT 4352u         /* unlearnt, the next edge may come up to 1/16 of a spacing past
                                     * its even place: the speed between edges stays under the
                                     * speed at which it would have come */
#define SPEED_FIRST_TURN 0x80u      /* speed.c: the first turn of offsets was just learnt */
#define SPEED_STEADY_SH 8u          /* a steady turn: its time within 1/2^this of the last one's
                                     * (at 1/512 a wheel was learnt only at 28-72 s in some dynamic
                                     * runs; at 1/128 offsets learnt while the tractor still gained
                                     * speed held part of that gain: docs/CONTROLLERS.md) */
#define SPEED_BAD_TURNS 3u          /* steady turns with an edge off its learnt place: relearn */
#define SPEED_AHEAD_MAX 4u          /* speed_ahead moves the speed by at most 1/2^this of it */
#define SPEED_TEETH_MAX 16u         /* most wheel pulses a turn (P_WHEEL_PPR) */
#define SPEED_SPAN_MAX 2048         /* a span this far (1/4096 of a spacing) from where the learnt
                                     * offsets put it is a missed or an extra pulse (a whole spacing
                                     * off), not learnt; a wheel's own spans differ by up to a
                                     * quarter (4 % spacing: 5.7 % a span, 27 % seen in the family) */
#define SPEED_LEARN_DRIFT 16        /* an edge this far (1/4096 of a spacing) from its learnt place:
                                     * the speed changed, no offset is learnt from it (at 128 the
                                     * start of a change inside a turn timed steady was learnt) */

void speed_init(void);
/* One control period: take the wheel edges, return the speed in km/h x100. */
uint16_t speed_step(void) __reentrant;
/* The wheel's spacing errors learnt from the step's newest span: in the pass after the step
 * (app.c), as nothing of this step reads them; the next speed_step runs it first when no one
 * has. */
void speed_learn_now(void) __reentrant;
/* 1: the speed without speed_ahead's lead on a change (speed.c), for a flow that follows the
 * speed by itself. Read only: the flow controller asks for it through speed_set_plain
 * (speed_plain.c; ffmap.c: a pump on the wheels learns no speed feed-forward); 0 after power-up
 * and when another controller is selected (ctl.c). */
extern __bit speed_plain;
void speed_set_plain(uint8_t plain) __reentrant;
/* 1: the wheel's spacing errors are learnt: the speed no longer steps by them at each pulse
 * (ffmap.c: until then a small change of the target teaches the feed-forward nothing while it is off) */
extern __bit speed_learnt;
/* Derive the constants of changed parameters now, so that the next step need not. */
void speed_prepare(void);
uint16_t speed_kmh_x100(void);
/* Wheel pulses since start (calibration), glitch windows since start. */
uint32_t speed_pulses(void);
uint16_t speed_glitches(void);
/* Control periods since the last wheel pulse (saturates at 65535). */
uint16_t speed_quiet_periods(void);
/* 1 from a jump a tractor cannot make (SPEED_JUMP_PERIODS) until the speed is zero again. */
uint8_t speed_jumped(void);
/* The speed measured when the last pulse came (for the speed-sensor-lost rule). */
uint16_t speed_at_last_pulse_x100(void);

#endif

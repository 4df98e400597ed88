/* valve.h: the bypass valve's H-bridge drive: direction, PWM duty, dead time on reversal, end stops from an estimated position. */
#ifndef VALVE_H
#define VALVE_H

#include "fixed.h"

/*
 * Drive: Q15 signed, + = more boom flow = bypass toward closed (HAL_VALVE_CLOSE), duty =
 * |drive| >> 7. A reversal first switches both half bridges off for VALVE_DEAD_MS (the motor
 * stops, no shoot-through), counted in milliseconds by valve_poll() from the main loop.
 * End stops (the valve has no limit switches): the position is estimated by integrating
 * the drive that moves the motor (|duty| >= VALVE_MOVE_Q15, below it stiction holds it) over
 * each period divided by the full-stroke time P_VALVE_TRAVEL. The valve is at a stop when
 *  - it has been driven one way by more than VALVE_ONEWAY_Q15 (3.6 strokes) since it last
 *    moved the other way (a valve up to 3 times slower than Valve time says gets to its stop
 *    first: believed too soon, a stop parks the bypass part open and holds the loop back), or
 *  - its estimated position is known (after a stop was found once) and it has been driven
 *    VALVE_OVER_Q15 (0.15 stroke) past the estimated end.
 * It is then not driven that way any more (valve_limit() reports CTL_AT_CLOSED/CTL_AT_OPEN
 * to the controller); a drive the other way frees it at once. After VALVE_RETRY_PERIODS the
 * stop is forgotten with VALVE_RETRY_Q15 (0.1 stroke) of travel left to try again, in case
 * the estimate ran ahead of the valve (stiction, a valve that stuck for a while): at full
 * duty 4 periods in 24 against a stop that is real, and a valve whose estimate was wrong
 * gets back 0.1 stroke every 2.4 s.
 */
#define VALVE_DEAD_MS 20u
#define VALVE_MOVE_Q15 Q15(0.15)
#define VALVE_ONEWAY_Q15 117965L    /* 3.6 strokes */
#define VALVE_OVER_Q15 4915L        /* 0.15 stroke */
#define VALVE_RETRY_Q15 3277L       /* 0.1 stroke */
#define VALVE_RETRY_PERIODS 20u     /* 2 s */
#define VALVE_POS_UNKNOWN 0xFFFFu

void valve_init(void);
/* Once a period: the drive for the next period (the previous one is integrated first). */
void valve_set(q15_t drive) __reentrant;
/* Derive the constants of changed parameters now, so that the next valve_set need not. */
void valve_prepare(void);
/* From the main loop as often as it turns: ends the dead time. */
void valve_poll(uint32_t now_ms) __reentrant;
/* CTL_AT_* bits. */
uint8_t valve_limit(void);
/* The drive actually applied after the stop logic, Q15. */
q15_t valve_applied(void);
/* Estimated position, Q15 of the stroke, 0 = closed; VALVE_POS_UNKNOWN before a stop was found. */
uint16_t valve_position(void);
/* 1 when the valve was driven open by q15 strokes (Q15) or more since it last moved toward closed. */
uint8_t valve_opened_by(uint16_t q15);
/* What the bridge is to drive (dir, duty) and in how many ms: the rest of a reversal's dead
 * time, 0 when it drives it now (hardware in the loop tells the PC's plant). */
#if FW_HIL
uint8_t valve_pending(int8_t *dir, uint8_t *duty) __reentrant;
#endif

#endif

/* target.h: the target boom flow, eq. (1), from the open nozzles, the minimum-flow rule of Table 1, and the speed used. */
#ifndef TARGET_H
#define TARGET_H

#include "compiler.h"

/*
 * q1 [L/min] = C * v * d * m / 60000 (eq. 1): C = the rate in use, target_rate_x10 (the
 * preset, or the rate a field computer set, nudged by the operator), v km/h, d = P_SPACING cm,
 * m = the nozzles of the switched-on sections. P_NOZZLES are split over P_SECTIONS as
 * evenly as they go (the first N % S sections carry one more); section switch bits at or
 * beyond P_SECTIONS are ignored.
 * Table 1: above 0 and below P_MINF_SPEED the target is the flow of P_MINF_SPEED; at
 * standstill it is 0. P_GIVEN_SPEED > 0 replaces the wheel sensor (bench tests, sensor lost).
 * Per period: one 32x16 product; the constants are recomputed when a parameter or the
 * section switches change.
 */
void target_init(void);
/* Pick up parameter and section-switch changes (call once a period before the others). */
void target_update(uint8_t sections) __reentrant;
/* The speed the target follows: the given speed when set, else the measured one. */
uint16_t target_speed_x100(uint16_t measured_x100) __reentrant;
uint8_t target_speed_given(void);
/* 1 at working speed: P_MINF_SPEED or more (the alarm rules judge there; below it Table 1's
 * rule sets the target). One copy of the product and compare for diag.c's and drive.c's. */
uint8_t target_working_speed(uint16_t speed_x100) __reentrant;
/* Eq. (1) with Table 1's rule, L/min x100 (saturates at 327.67). */
int16_t target_flow_x100(uint16_t speed_x100) __reentrant;
uint8_t target_open_nozzles(void);
/* What a loop set on the whole boom multiplies its gain by with o of the n nozzles open, in
 * quarters: (n / o + 1) / 2 (4: all open; n / o floored to halves), at most TARGET_NOZ_MAX,
 * and TARGET_NOZ_MAX with none open (ffmap.c ffmap_gain_at_p says why). */
#define TARGET_NOZ_MAX 16u
extern __data uint8_t target_noz_q;
extern __bit target_noz_new;        /* 1: the nozzles open changed (read only: target_noz_take) */
/* 1 once after the nozzles open changed (ffmap.c's hold), and the change taken. */
uint8_t target_noz_take(void) __reentrant;
/* Nozzles of section s (0-based), for the console. */
uint8_t target_section_nozzles(uint8_t s) __reentrant;
/* Working width of the open sections, cm. */
uint16_t target_width_cm(void);
/* A rate from a field computer (serial Remote), L/ha x10, in place of the preset in use: taken
 * (1) when P_REMOTE is on and it is within P_REMOTE_WIN % of that preset (and at least 10 L/ha);
 * refused (0) otherwise, and counted. It holds until Remote is switched off or a new preset
 * (its value, or the other one chosen) or window leaves it outside. */
uint8_t target_remote_rate(uint16_t rate_x10) __reentrant;
/* The rate in use, L/ha x10: the preset in use (P_PRESET: Rate 1 or Rate 2) or the field
 * computer's rate in its place, times (100 + the operator's nudge) / 100; the one set rate of
 * the target, the alarms, the log and the link. 1 when it came from the field computer. */
uint16_t target_rate_x10(void);
uint16_t target_preset_x10(void);
/* The operator's nudge: dir > 0 up, < 0 down by P_RATE_STEP %, 0 back to the preset; bounded
 * to +-TARGET_NUDGE_MAX %; the offset now in %. An offset of the rate in use: it stays over a
 * change of preset or of the field computer's rate. */
#define TARGET_NUDGE_MAX 50
int8_t target_nudge(int8_t dir) __reentrant;
int8_t target_nudge_pct(void);
uint8_t target_rate_remote(void);
/* Remote rates refused since start (wraps at 256), for the LCD. */
uint8_t target_remote_refusals(void);

#endif

/* diag_line.h: the rules judged on the line and the tank (diag_line.c), each a period, for diag_step. */
#ifndef DIAG_LINE_H
#define DIAG_LINE_H

#include "compiler.h"
#include "status.h"

#define DIAG_DRY_PERIODS 10u        /* pump dry from the line: under P start, under a quarter of the target metered (then PUMP_DRY's own periods: 1.9 s) */
#define DIAG_ZERO_PERIODS 50u       /* pressure zero: 5 s shut and standing with the reading steady ... */
#define DIAG_ZERO_STEADY_KPA 12u    /* ... within this (the ADC's noise, a few LSB of a 16 bar sensor) */
#define DIAG_ZERO_KPA 25u           /* ... and the line at rest: a reading above this is off its zero */
#define DIAG_ZERO_OPEN_Q15 3277u    /* ... with the bypass open by a tenth of its stroke or more */
#define DIAG_BAL_MIN_X100 1500      /* tank balance: metered flow in the turbine's full range only */
#define DIAG_BAL_PCT 5u             /* ... a meter off the level's fall by more than this % (ISO 16122-2) */
#define DIAG_BAL_WAIT 30u           /* ... not for 3 s after a step of the level (its 0.4 s filter) */
#define DIAG_BAL_STRETCH 100u       /* ... over stretches of 10 s or more in range */

void diag_line_init(void);
/* The period's inputs of every rule (diag.c's and these), set once a period by diag_period
 * (diag_step's first act; a test of these rules alone calls it after measuring): the status
 * block and `settled` as diag_step takes them, kept as ctl.c keeps ctl_in; and the facts the
 * rules ask the same way, judged once: the speed a working one (target_working_speed), the
 * pressure and the level sensors good (analog.h), meter pulses this period (flow.h
 * flow_quiet_periods() == 0). */
extern const __xdata app_status_t *__data diag_in;
extern __bit diag_settled, diag_working, diag_psens, diag_lsens, diag_metering;
void diag_period(const __xdata app_status_t *in, uint8_t settled) __reentrant;
/* 1 while the line says the pump ran dry (held as diag_line.c says). */
uint8_t diag_dry_line(void) __reentrant;
/* 1 while the pressure sensor read off its zero at the last rest. */
uint8_t diag_zero(void) __reentrant;
/* The tank balance this period: */
#define DIAG_BAL_NONE 0u            /* not judged (too little fallen yet) */
#define DIAG_BAL_ON 1u              /* the meter agrees with the level */
#define DIAG_BAL_OFF 2u             /* it does not: Meter K is wrong */
#define DIAG_BAL_ANEW 3u            /* a new Meter K or Tank size: started anew */
uint8_t diag_balance(void) __reentrant;

#endif

/* diag_wheel.h: the wheel against the pump and the minimum-flow warning (diag_wheel.c), each a period, for diag_step. */
#ifndef DIAG_WHEEL_H
#define DIAG_WHEEL_H

#include "compiler.h"
#include "status.h"

#define DIAG_PUMP_PERIODS 30u       /* 3 s of line pressure at a wheel standstill on a sprayer
                                     * whose pump stops with the wheels: SPEED_LOST */
#define DIAG_PUMP_RUN_KPA 50u       /* ... the pump turns: the line holds this or more */
#define DIAG_PUMP_STOP_KPA 10u      /* ... the pump stands: the line under this at a standstill */
#define DIAG_PUMP_OPEN_Q15 16384u   /* ... through the bypass opened half a stroke (a line trapped
                                     * by the check valves holds with the pump standing) */

/* The link's AgOpenGPS frames this period (the application sets them, FW_PGN): those in use
 * stopped (SPEED_LOST), Speed src both finding the wheel off the GPS (WHEEL_NOISE), the GPS's
 * speed in use (a SPEED_LOST clears without wheel pulses). */
#define DIAG_FRAMES_LOST 1u
#define DIAG_FRAMES_SPEED_OFF 2u
#define DIAG_FRAMES_GPS 4u
#if FW_PGN
void diag_set_frames(uint8_t frames);
uint8_t diag_frames(void);
#define DIAG_FRAMES(bit) (diag_frames() & (bit))
#else
#define DIAG_FRAMES(bit) 0          /* no frames: the rules' frame terms drop out at compile time */
#endif

void diag_wheel_init(void);
/* 1 while the pump says the wheels turn at a standstill the wheel reports (SPEED_LOST); reads
 * the period's inputs (diag_line.h diag_period). */
uint8_t diag_pump(void) __reentrant;

#endif

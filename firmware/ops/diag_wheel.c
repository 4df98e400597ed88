/* diag_wheel.c: the wheel against the pump (SPEED_LOST at a standstill the wheel reports), the link's frames (SPEED_LOST, WHEEL_NOISE) and the minimum-flow warning, for diag_step. */
#include "params.h"
#include "analog.h"
#include "speed.h"
#include "target.h"
#include "valve.h"
#include "mul.h"
#include "diag_line.h"
#include "diag_wheel.h"

static struct {
    uint8_t pump_stops;             /* the line fell under DIAG_PUMP_STOP_KPA at a wheel standstill:
                                     * the pump is on the wheels (a coupled PTO) */
    uint8_t pump_cnt;               /* periods of the pump's evidence, of one kind ... */
    uint8_t pump_still;             /* ... that kind: 1 the line standing, 0 the pump delivering */
} dw;

#if FW_PGN
static uint8_t dw_frames;           /* DIAG_FRAMES_* this period */

void diag_set_frames(uint8_t frames)
{
    dw_frames = frames;
}

uint8_t diag_frames(void)
{
    return dw_frames;
}
#endif

void diag_wheel_init(void)
{
    dw.pump_stops = 0;
    dw.pump_cnt = dw.pump_still = 0;
}

/* The pump against the wheel. At a standstill the wheel reports (no given speed), the boom
 * shut: the line under DIAG_PUMP_STOP_KPA for DIAG_PUMP_PERIODS says the pump stands with the
 * wheels (a coupled PTO: learnt until power-off). On such a sprayer, once the wheel has measured
 * a speed, the line held at DIAG_PUMP_RUN_KPA or more as long with the sections on, the bypass opened
 * by DIAG_PUMP_OPEN_Q15 (the shut boom's hold), says the pump delivers: the wheels turn, 1,
 * the wheel sensor is lost. (Check valves and a shut bypass trap a line's pressure with the
 * pump standing, until the bypass opens; a fixed PTO's pump runs at a standstill: nothing is
 * learnt.) */
uint8_t diag_pump(void) __reentrant
{
    uint16_t p = diag_in->in.pressure_kpa;
    uint8_t run = p >= DIAG_PUMP_RUN_KPA && valve_opened_by(DIAG_PUMP_OPEN_Q15), still = p < DIAG_PUMP_STOP_KPA;
    if (diag_in->in.speed_kmh_x100 || diag_in->spraying || target_speed_given() || !diag_psens
        || !(still || (run && dw.pump_stops && diag_in->open_nozzles && speed_at_last_pulse_x100()))) {
        dw.pump_cnt = 0;
        return 0;
    }
    if (still != dw.pump_still) {   /* the other kind of evidence: its own count */
        dw.pump_still = still;
        dw.pump_cnt = 0;
    }
    if (++dw.pump_cnt < DIAG_PUMP_PERIODS)
        return 0;
    dw.pump_cnt = DIAG_PUMP_PERIODS;
    if (still)
        dw.pump_stops = 1;
    return run;
}

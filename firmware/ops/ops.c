/* ops.c: what the operator can do from the keypad or the serial link: jog, acknowledge, reset totals. */
#include "hal.h"
#include "speed.h"
#include "flow.h"
#include "totals.h"
#include "analog.h"
#include "valve.h"
#include "ops.h"
#include "diag.h"

app_status_t app_status;
static struct {
    uint8_t periods;                /* periods of jog left (0: none) */
    int8_t dir;                     /* +1 more boom flow, -1 less */
} jog;
__data uint8_t ops_io;

void ops_init(void)
{
    __xdata uint8_t *p = (__xdata uint8_t *)&app_status;
    uint8_t n = sizeof app_status;
    do
        *p++ = 0;
    while (--n);
    jog.periods = 0;
    jog.dir = 0;
    ops_io = 0;
}

void ops_set_speed(uint16_t kmh_x100) __reentrant
{
    app_status.in.speed_kmh_x100 = kmh_x100;
}

void ops_set_target(int16_t lpm_x100) __reentrant
{
    app_status.in.target_lpm_x100 = lpm_x100;
}

void ops_set_flow(int16_t lpm_x100) __reentrant
{
    app_status.in.flow_lpm_x100 = lpm_x100;
}

void ops_set_pressure(uint16_t kpa) __reentrant
{
    app_status.in.pressure_kpa = kpa;
}

void ops_set_valve_limit(uint8_t limit) __reentrant
{
    app_status.in.valve_limit = limit;
}

void ops_set_manual(uint8_t manual) __reentrant
{
    app_status.manual = manual;
}

void ops_set_open_nozzles(uint8_t open) __reentrant
{
    app_status.open_nozzles = open;
}

void ops_set_spraying(uint8_t spraying) __reentrant
{
    app_status.spraying = spraying;
}

void ops_set_boom_wait(uint8_t wait) __reentrant
{
    app_status.boom_wait = wait;
}

void ops_show_step(void)
{
    app_status.tank_l = analog_tank_l();
    app_status.drive = valve_applied();
}

void ops_show_totals(void)
{
    app_status.job_area_m2 = totals_job_m2();
    app_status.applied_l_ha_x10 = totals_applied_l_ha_x10();
}

/* the buzzer: the I/O test's switch, else while an alarm is unacknowledged */
static void ops_buzzer(void)
{
    hal_buzzer((ops_io & OPS_IO_ON) ? (ops_io & OPS_IO_BUZZER) : app_status.alarms_unacked != 0);
}

void ops_alarms_step(void)
{
    uint16_t g = diag_alarms(), quiet = DIAG_QUIET_BITS | (app_status.manual ? 1u << AL_OFFRATE : 0u);
    app_status.alarms_unacked |= g & (uint16_t)~app_status.alarms & (uint16_t)~quiet;
    app_status.alarms = g;
    ops_buzzer();
}

#if FW_IOTEST
void ops_io_test(uint8_t flags) __reentrant
{
    ops_io = (flags & OPS_IO_ON) ? flags : 0;
    hal_spray_enable((ops_io & OPS_IO_ON) ? (ops_io & OPS_IO_RELAY) : app_status.spraying);
    ops_buzzer();
    if (!(ops_io & OPS_IO_ON))
        jog.periods = 0;
}
#endif

void ops_jog(int8_t dir) __reentrant
{
    if (!(app_status.manual || (ops_io & OPS_IO_ON)) || dir == 0)
        return;
    jog.dir = dir;
    jog.periods = OPS_JOG_PERIODS;
}

int8_t ops_jog_take(void)
{
    if (!jog.periods)
        return 0;
    jog.periods--;
    return jog.dir;
}

void ops_jog_cancel(void)
{
    jog.periods = 0;
}


void ops_alarm_ack_bits(uint16_t bits) __reentrant
{
    app_status.alarms_unacked &= (uint16_t)~bits;
    ops_buzzer();
}

void ops_totals_reset(void)
{
    totals_job_reset();
    app_status.job_area_m2 = 0;
    app_status.applied_l_ha_x10 = 0;
}

uint32_t ops_wheel_pulses(void)
{
    return speed_pulses();
}

uint32_t ops_flow_pulses(void)
{
    return flow_pulses();
}

/* ops.c: what the operator can do from the keypad or the serial link: jog, acknowledge, reset totals. */
#include "hal.h"
#include "speed.h"
#include "flow.h"
#include "totals.h"
#include "ops.h"

app_status_t app_status;
ops_jog_t ops_jog_req;
__data uint8_t ops_io;

void ops_init(void)
{
    ops_jog_req.periods = 0;
    ops_jog_req.dir = 0;
    ops_io = 0;
}

void ops_io_test(uint8_t flags) __reentrant
{
    ops_io = (flags & OPS_IO_ON) ? flags : 0;
    hal_spray_enable((ops_io & OPS_IO_ON) ? (ops_io & OPS_IO_RELAY) : app_status.spraying);
    hal_buzzer((ops_io & OPS_IO_ON) ? (ops_io & OPS_IO_BUZZER) : app_status.alarms_unacked != 0);
    if (!(ops_io & OPS_IO_ON))
        ops_jog_req.periods = 0;
}

void ops_jog(int8_t dir) __reentrant
{
    if (!(app_status.manual || (ops_io & OPS_IO_ON)) || dir == 0)
        return;
    ops_jog_req.dir = dir;
    ops_jog_req.periods = OPS_JOG_PERIODS;
}

void ops_alarm_ack_bits(uint16_t bits) __reentrant
{
    app_status.alarms_unacked &= (uint16_t)~bits;
    hal_buzzer(app_status.alarms_unacked != 0);
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

/* pil_main.c: the firmware's entry in s51 (instead of firmware/app/main.c): main.c's loop, one app_poll() a host tick, each pass timed. */
#include <8051.h>
#include "hal.h"
#include "pil.h"
#include "pil_proto.h"
#include "params.h"
#include "app.h"
#include "ctl.h"

#define STACK_MARK 0x5A

static __data uint8_t stack_start, a;
static uint8_t generation;          /* param_generation the host last saw */
static uint16_t alarms;             /* the alarms the host last saw */   /* __data: the scans must not touch the stack they scan */

/* the settings of a PIL_CONFIG or PIL_TICK frame: a count, then (id, value) pairs */
static void settings(void)
{
    uint8_t n = pil_get8(), id;
    uint16_t v;
    while (n--) {
        id = pil_get8();
        v = pil_get16();
        param_set(id, v);
    }
}

static void expect(uint8_t b)
{
    while (pil_get8() != b)
        ;
}

static void status(uint16_t v)
{
    pil_put16(v);
}

int main(void)
{
    uint32_t c;
    /* every idata byte above the stack pointer gets a mark: what is still marked at the end was
     * never used by the stack */
    stack_start = SP;
    for (a = (uint8_t)(SP + 1); a != 0; a++)
        *(__idata uint8_t *)a = STACK_MARK;

    /* as the simulator starts the firmware (sim_init): defaults, the operator's settings,
     * hal_init, app_init, the settings again */
    pil_put(PIL_HELLO);
    expect(PIL_CONFIG);
    params_defaults();
    settings();
    hal_init();
    app_init();
    pil_put(PIL_READY);
    expect(PIL_CONFIG);
    settings();
    generation = (uint8_t)(param_generation + 1);   /* the first pass sends its status */

    for (;;) {
        uint8_t f = pil_get8();
        if (f == PIL_QUIT)
            break;
        if (f != PIL_TICK)
            continue;
        pil_tick_inputs();
        settings();
        pil_measured = 0;
        pil_cycles_start();
        app_poll();
        c = pil_cycles_stop();
        pil_put(PIL_DONE);
        pil_put16((uint16_t)c);
        pil_put16((uint16_t)(c >> 16));
        if (!pil_measured && generation == param_generation && alarms == app_status.alarms) {
            pil_put(0);             /* nothing the status shows can have changed */
            continue;
        }
        pil_put(pil_measured ? 3 : generation != param_generation ? 1 : 4);
        generation = param_generation;
        alarms = app_status.alarms; /* (the pass after a step finds them: app_diag) */
        status(app_status.in.speed_kmh_x100);
        status((uint16_t)app_status.in.target_lpm_x100);
        status((uint16_t)app_status.in.flow_lpm_x100);
        status(app_status.in.pressure_kpa);
        status(app_status.tank_l);
        status((uint16_t)app_status.drive);
        status((uint16_t)ctl_gain(0));
        status((uint16_t)ctl_gain(1));
        status((uint16_t)ctl_gain(2));
        status(app_status.alarms);
        status(param_v[P_RATE]);
        status(param_v[P_METER_K]);
    }
    /* the stack's high-water mark: the highest byte no longer marked */
    for (a = 0xFF; a > stack_start && *(__idata uint8_t *)a == STACK_MARK; a--)
        ;
    pil_put(PIL_REPORT);
    pil_put(a);
    pil_put(stack_start);
    *(volatile __xdata uint8_t *)0xFFFF = 's';     /* simif: stop the simulation */
    for (;;)
        ;
}

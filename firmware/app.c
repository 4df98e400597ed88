/* app.c: the main loop's scheduler: one control step every APP_PERIOD_MS, the watchdog fed while it runs. */
#include "hal.h"
#include "app.h"

static uint32_t next_ms;

void app_init(void)
{
    hal_valve_out(HAL_VALVE_OFF, 0);
    hal_spray_enable(0);
    next_ms = hal_ms() + APP_PERIOD_MS;
}

void app_poll(void)
{
    uint32_t now = hal_ms();
    if ((int32_t)(now - next_ms) < 0)
        return;
    next_ms += APP_PERIOD_MS;
    hal_wdt_kick();
}

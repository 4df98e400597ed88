/* app.h: the application: measurement -> rate target -> controller -> valve, console and alarms. */
#ifndef APP_H
#define APP_H

#include "compiler.h"

/* The control period: every measurement, target and controller step runs once per period.
 * 100 ms: the BP-PID step must fit in 25 % of it on a classic 12-clock 8051 (23040 cycles). */
#define APP_PERIOD_MS 100

/* The status the application writes each period (app_status, ops.h: the console, the serial
 * link and the simulator read it). */
#include "ops.h"

/* Alarm bits of app_status.alarms (codes and LCD texts from app_alarm_code/_text). */
#define APP_ALARM_BITS OPS_ALARM_BITS

void app_init(void);
/* Call as often as possible: runs whatever is due (control step, keypad, display, serial). */
void app_poll(void);
/* Short code ("TANK_LOW") and LCD text (at most 16 characters) of an alarm bit. */
const char *app_alarm_code(uint8_t bit);
const char *app_alarm_text(uint8_t bit);
/* Control steps that ran a whole period or more late, since start. */
uint16_t app_overruns(void);

#endif

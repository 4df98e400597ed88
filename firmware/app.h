/* app.h: the application: measurement -> rate target -> controller -> valve, console and alarms. */
#ifndef APP_H
#define APP_H

#include "compiler.h"

/* The control period: every measurement, target and controller step runs once per period. */
#define APP_PERIOD_MS 100

void app_init(void);
/* Call as often as possible: runs whatever is due (control step, keypad, display, serial). */
void app_poll(void);

#endif

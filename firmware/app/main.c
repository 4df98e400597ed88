/* main.c: the controller's entry on the chip: start the HAL, then the application's loop forever. */
#include "hal.h"
#include "app.h"

int main(void)
{
    hal_init();
    app_init();
    for (;;)
        app_poll();
}

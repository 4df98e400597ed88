/* pwm.c: the valve's H-bridge: PCA module 1's PWM on its enable, the direction on IN_A and IN_B. */
#include <stc12.h>
#include "hal.h"
#include "stc12_int.h"
#include "pins.h"

/* ---- PWM: PCA module 1, 8 bits at SYSCLK/12/256 = 3.6 kHz ------------------------------------- */
void hal_valve_out(int8_t dir, uint8_t duty) __reentrant
{
#if FW_HIL
    if (stc12_hil)
        dir = HAL_VALVE_OFF;        /* the PC's plant gets the drive in a frame */
#endif
    if (dir == HAL_VALVE_OFF || duty == 0) {
        PCA_PWM1 = 0x03;            /* EPC1H/L: output stays low */
        CCAP1H = 0xFF;
        PIN_VALVE_A = 0;
        PIN_VALVE_B = 0;
        return;
    }
    /* the PWM output is high while CL >= CCAP1L: duty/256 of the period */
    PCA_PWM1 = 0;
    CCAP1H = (uint8_t)(0u - duty);
    PIN_VALVE_A = dir > 0;
    PIN_VALVE_B = dir < 0;
}

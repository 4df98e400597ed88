/* adc.c: the 10-bit ADC (pressure and tank level). */
#include <stc12.h>
#include "hal.h"
#include "stc12_int.h"

/* ---- ADC: 10 bits, result high 8 bits in ADC_RES, low 2 in ADC_RESL (ADRJ = 0) ----------- */
#define ADC_SPEED_90 0x60
#define ADC_FLAG 0x10
#define ADC_START 0x08

uint16_t hal_adc_read(uint8_t ch) __reentrant
{
    uint8_t n = 0;
#if FW_HIL
    if (stc12_hil) {
        /* the frame's sum of four conversions: four reads in a row return its quarters, which
         * add up to it (analog.c reads four a period) */
        static uint8_t k;
        return ch < 2 ? (uint16_t)((stc12_hil->adc[ch] + (k++ & 3u)) >> 2) : 0;
    }
#endif
    ADC_CONTR = ADC_POWER | ADC_SPEED_90 | ADC_START | (ch & 7);
    NOP(); NOP(); NOP(); NOP();     /* the flag is valid four clocks after the start */
    /* a conversion takes 90 clocks; a converter that never finishes reads 0, an open
     * 4-20 mA loop, so the sensor fault alarms instead of the loop hanging until the watchdog */
    while (!(ADC_CONTR & ADC_FLAG))
        if (++n == 0)
            return 0;
    ADC_CONTR &= (unsigned char)~ADC_FLAG;
    return (uint16_t)ADC_RES << 2 | (ADC_RESL & 3);
}

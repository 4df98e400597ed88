/* tick.c: the millisecond count, read off the PCA counter when timer 0 wakes it. */
#include <stc12.h>
#include "hal.h"
#include "stc12_int.h"
#include "isr.h"

/* ---- milliseconds from the PCA counter ---------------------------------------------------- */
/*
 * Timer 0 only wakes the count about once a millisecond; the milliseconds themselves are read
 * off the PCA counter (921.6 ticks each: 921 and 3/5), which the hardware clocks without a
 * stop or a reload. A reload that stops the timer loses the clocks of every instruction
 * between the stop and the start (the compiler's, not a constant), and an IAP erase holds the
 * CPU for longer than a timer period. Only the counter's 16 bits are compared (a signed
 * difference: no overflow count, no 32-bit temporaries in the handler), so a held CPU or a
 * late interrupt up to 35 ms (32768 ticks) is caught up with whole milliseconds here; an
 * erase holds it about 21 ms. The PCA is clocked from SYSCLK, not the CPU: it counts on while
 * IAP holds the CPU (checked at bring-up, docs/bringup.md: the LOG time stamps against the
 * PC's clock across saves).
 */
volatile uint32_t tick_ms;          /* stc12_int.h: hal_init starts them */
uint16_t tick_next_pca;             /* PCA count (low 16 bits) of the next millisecond */
uint8_t tick_fifths;                /* fifths of a PCA tick carried */

void stc12_timer0_isr(void) __interrupt(1)
{
    uint16_t t;                     /* one 16-bit value: in registers (two bytes took XRAM) */
    TL0 = (uint8_t)(65536u - 11059u);   /* about a millisecond; its exactness does not matter */
    TH0 = (uint8_t)((65536u - 11059u) >> 8);
    for (;;) {
        do {
            t = (uint16_t)CH << 8;
            t |= CL;
        } while ((uint8_t)(t >> 8) != CH);
        if ((int16_t)(t - tick_next_pca) < 0)
            break;
        tick_ms++;
        tick_next_pca += 921u;
        tick_fifths += 3u;
        if (tick_fifths >= 5u) {
            tick_fifths -= 5u;
            tick_next_pca++;
        }
    }
}

uint32_t hal_ms(void)
{
    uint32_t t;
    uint8_t ea;
    IRQ_OFF(ea);
    t = tick_ms;
    IRQ_RESTORE(ea);
    return t;
}

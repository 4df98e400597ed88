/* pil.h: what pil_main.c uses of the processor-in-the-loop backend beyond hal.h. */
#ifndef PIL_H
#define PIL_H

#include "compiler.h"

void pil_put(uint8_t b);
void pil_put16(uint16_t v);
uint8_t pil_get8(void);            /* waits for the host's next byte (the cycle counter paused) */
uint16_t pil_get16(void);
void pil_tick_inputs(void);        /* the rest of a PIL_TICK frame up to its settings */
void pil_cycles_start(void);       /* timer 0 counts machine cycles from 0 */
uint32_t pil_cycles_stop(void);
extern uint8_t pil_measured;       /* set by the HAL when a pass reads the ADC or a capture */
void pil_timer0_isr(void) __interrupt(1);

#endif

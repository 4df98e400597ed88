/* tt.h: output of the target tests: the same program prints the same text from s51 and from the host. */
#ifndef TT_H
#define TT_H

#include "compiler.h"

void tt_begin(void);                /* prints TT-BEGIN */
void tt_end(void);                  /* prints TT-END and stops the simulator */
void tt_putc(char c);
void tt_puts(const char *s);
void tt_hex8(uint8_t v);
void tt_hex16(uint16_t v);
void tt_hex32(uint32_t v);
void tt_dec32(int32_t v);
/* Machine-cycle stopwatch (timer 0 of the simulated 8051; 0 on the host). */
void tt_cycles_start(void);
uint32_t tt_cycles_stop(void);
/* A benchmark line "#cycles <name> <n>": the comparison skips lines that start with '#'. */
void tt_bench(const char *name, uint32_t cycles);
/* 1 in the s51 build, 0 on the host. */
uint8_t tt_on_target(void);
/* A 16-bit pseudo-random sequence both builds draw the same vectors from (xorshift). */
uint16_t tt_rand16(void);

#if defined(__SDCC) && defined(HAL_UCSIM)
/* SDCC wants the handler's prototype where main() is: every test includes this header. */
void tt_ucsim_timer0_isr(void) __interrupt(1);
#endif

#endif

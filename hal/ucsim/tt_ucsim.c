/* tt_ucsim.c: the target tests' I/O inside s51: the simif byte at xdata 0xFFFF, timer 0 as a cycle counter. */
#include <8051.h>
#include "tt.h"

/* uCsim's simulator interface: write 'p' then a character to print it, 's' to stop. */
static volatile __xdata __at(0xFFFF) unsigned char simif;
static volatile uint16_t t0_overflows;

void tt_ucsim_timer0_isr(void) __interrupt(1)
{
    t0_overflows++;
}

void tt_putc(char c)
{
    simif = 'p';
    simif = (unsigned char)c;
}

void tt_end(void)
{
    tt_puts("TT-END\n");
    simif = 's';
    for (;;)
        ;
}

/* Timer 0 counts machine cycles (12 clocks each on the classic core s51 models). */
void tt_cycles_start(void)
{
    EA = 0;
    TR0 = 0;
    TMOD = (TMOD & 0xF0) | 0x01;
    TH0 = 0;
    TL0 = 0;
    TF0 = 0;
    t0_overflows = 0;
    ET0 = 1;
    EA = 1;
    TR0 = 1;
}

uint32_t tt_cycles_stop(void)
{
    uint16_t lo;
    TR0 = 0;
    lo = (uint16_t)TH0 << 8 | TL0;
    if (TF0) {                       /* an overflow not yet serviced */
        TF0 = 0;
        t0_overflows++;
    }
    /* the stopwatch itself: the call into tt_cycles_stop and the TR0 = 0 before the read */
    return ((uint32_t)t0_overflows << 16 | lo);
}

/* The target tests' chip has a blank EEPROM (the controllers read their learnt figures back). */
uint8_t hal_eeprom_read(uint16_t addr)
{
    (void)addr;
    return 0xFFu;
}

uint8_t tt_on_target(void)
{
    return 1;
}

/* isr_cycles.c: machine cycles of each interrupt handler of hal/stc12, on its longest path, measured in s51 (make bench). */
#include <stc12.h>
#include "hal.h"
#include "isr.h"

/* uCsim's simulator interface: 'p' prints the next byte, 's' stops */
static volatile __xdata __at(0xFFFF) unsigned char simif;

typedef void (*handler_t)(void);

static void out_c(char c)
{
    simif = 'p';
    simif = (unsigned char)c;
}

static void out_s(const char *s)
{
    while (*s)
        out_c(*s++);
}

static void out_u(uint16_t v)
{
    char b[6];
    uint8_t n = 0;
    do {
        b[n++] = (char)('0' + v % 10u);
        v /= 10u;
    } while (v);
    while (n)
        out_c(b[--n]);
}

static void nothing(void)
{
}

/* timer 1 counts the machine cycles of one call of h */
static uint16_t timed(handler_t h)
{
    TR1 = 0;
    TH1 = 0;
    TL1 = 0;
    TR1 = 1;
    h();
    TR1 = 0;
    return (uint16_t)TH1 << 8 | TL1;
}

/* A handler as the chip runs it: the call's own overhead taken out (what `nothing` costs
 * beyond its LCALL and RET), the vector's LJMP added (RETI costs what RET does). */
static void report(const char *name, handler_t h, uint16_t base)
{
    out_s(name);
    out_c(' ');
    out_u((uint16_t)(timed(h) - base + 4u + 2u));
    out_c('\n');
}

void main(void)
{
    uint16_t base;
    EA = 0;                         /* the handlers run only when called here */
    TMOD = (TMOD & 0x0F) | 0x10;    /* timer 1: 16-bit, counting machine cycles */
    base = timed(nothing);
    out_s("TT-BEGIN\n");
    report("timer0_tick", (handler_t)stc12_timer0_isr, base);
    IE0 = 1;
    report("int0_wheel", (handler_t)stc12_int0_isr, base);
    CCF0 = 1;                       /* a capture and a counter overflow together: the longest path */
    CF = 1;
    report("pca_flow_and_overflow", (handler_t)stc12_pca_isr, base);
    hal_uart_put('a');              /* the first byte goes to SBUF, the second waits in the queue */
    hal_uart_put('b');
    RI = 1;                         /* a byte received and one sent together */
    TI = 1;
    report("uart_rx_and_tx", (handler_t)stc12_uart_isr, base);
    out_s("TT-END\n");
    simif = 's';
    for (;;)
        ;
}

/* tt_common.c: formatting for the target tests, shared by the s51 and host builds. */
#include "tt.h"

static const __code char hexdig[] = "0123456789abcdef";

void tt_puts(const char *s)
{
    while (*s)
        tt_putc(*s++);
}

void tt_hex8(uint8_t v)
{
    tt_putc(hexdig[v >> 4]);
    tt_putc(hexdig[v & 15]);
}

void tt_hex16(uint16_t v)
{
    tt_hex8((uint8_t)(v >> 8));
    tt_hex8((uint8_t)v);
}

void tt_hex32(uint32_t v)
{
    tt_hex16((uint16_t)(v >> 16));
    tt_hex16((uint16_t)v);
}

void tt_dec32(int32_t v)
{
    char buf[11];
    uint8_t n = 0;
    uint32_t u;
    if (v < 0) {
        tt_putc('-');
        u = (uint32_t)(-(v + 1)) + 1u;
    } else {
        u = (uint32_t)v;
    }
    do {
        buf[n++] = (char)('0' + u % 10u);
        u /= 10u;
    } while (u);
    while (n)
        tt_putc(buf[--n]);
}

void tt_begin(void)
{
    tt_puts("TT-BEGIN\n");
}

void tt_bench(const char *name, uint32_t cycles)
{
    if (!tt_on_target())
        return;
    tt_puts("#cycles ");
    tt_puts(name);
    tt_putc(' ');
    tt_dec32((int32_t)cycles);
    tt_putc('\n');
}

static uint16_t rnd = 0xACE1u;

uint16_t tt_rand16(void)
{
    rnd ^= (uint16_t)(rnd << 7);
    rnd ^= (uint16_t)(rnd >> 9);
    rnd ^= (uint16_t)(rnd << 8);
    return rnd;
}

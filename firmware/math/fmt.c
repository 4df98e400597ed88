/* fmt.c: the one number formatter: unsigned decimal with an optional fixed point, by subtraction. */
#if defined(__SDCC)
#pragma stackauto           /* locals on the stack, not each its own XRAM (docs/MEMORY.md) */
#endif
#include "fmt.h"

static const __code uint32_t pow10[10] = {
    1000000000UL, 100000000UL, 10000000UL, 1000000UL, 100000UL, 10000UL, 1000UL, 100UL, 10UL, 1UL
};

uint8_t fmt_u32(__idata char *out, uint32_t v, uint8_t decimals, uint8_t trim) __reentrant
{
    uint8_t i, d, n = 0, started = 0;
    uint32_t p;
    /* digit i is the one of 10^(9 - i); the point goes before digit 10 - decimals, and the
     * digits start at 9 - decimals at the latest ("0.05") */
    for (i = 0; i < 10; i++) {
        d = 0;
        p = pow10[i];
        while (v >= p) {
            v -= p;
            d++;
        }
        if (decimals && i == 10 - decimals)
            out[n++] = '.';
        if (d || started || i + decimals >= 9) {
            out[n++] = (char)('0' + d);
            started = 1;
        }
    }
    if (trim && decimals) {
        while (out[n - 1] == '0')
            n--;
        if (out[n - 1] == '.')
            n--;
    }
    out[n] = 0;
    return n;
}

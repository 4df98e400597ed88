/* umath.c: unsigned arithmetic for the per-period work without a divide: a*n/d by a table reciprocal, 32x16 products, square root. */
#include "umath.h"
#include "mul.h"

/* recip_tab[i] = 2^22 / (128 + i), rounded: 2^30 / m for the mantissa m = (128 + i) * 256. */
static const __code uint16_t recip_tab[129] = {
    32768, 32514, 32264, 32018, 31775, 31536, 31301, 31069,
    30840, 30615, 30394, 30175, 29959, 29747, 29537, 29331,
    29127, 28926, 28728, 28533, 28340, 28150, 27962, 27777,
    27594, 27414, 27236, 27060, 26887, 26715, 26546, 26379,
    26214, 26052, 25891, 25732, 25575, 25420, 25267, 25116,
    24966, 24818, 24672, 24528, 24385, 24245, 24105, 23967,
    23831, 23697, 23564, 23432, 23302, 23173, 23046, 22920,
    22795, 22672, 22550, 22429, 22310, 22192, 22075, 21960,
    21845, 21732, 21620, 21509, 21400, 21291, 21183, 21077,
    20972, 20867, 20764, 20662, 20560, 20460, 20361, 20262,
    20165, 20068, 19973, 19878, 19784, 19692, 19600, 19508,
    19418, 19329, 19240, 19152, 19065, 18979, 18893, 18809,
    18725, 18641, 18559, 18477, 18396, 18316, 18236, 18157,
    18079, 18001, 17924, 17848, 17772, 17697, 17623, 17549,
    17476, 17404, 17332, 17261, 17190, 17120, 17050, 16981,
    16913, 16845, 16777, 16710, 16644, 16578, 16513, 16448,
    16384,
};

/* Shift x (not 0) left until its bit 31 is set; returns the shift. x is on the stack of the
 * reentrant caller: an __idata pointer, no generic pointer calls. */
static uint8_t norm32(__idata uint32_t *x) __reentrant
{
    uint32_t v = *x;
    uint8_t s = 0;
    while (!(v & 0xFF000000UL)) {
        v <<= 8;
        s += 8;
    }
    while (!(v & 0x80000000UL)) {
        v <<= 1;
        s++;
    }
    *x = v;
    return s;
}

uint32_t um_mul32x16_shr16(uint32_t a, uint16_t b) __reentrant
{
    uint32_t hi = UMUL(a >> 16, b);             /* both factors fit 16 bits: < 2^32 */
    uint32_t lo = UMUL(a, b);                   /* (the low 16 bits of a) */
    uint32_t r = hi + ((lo + 0x8000u) >> 16);
#if defined(__SDCC) && FX_SABOTAGE == 12
    r |= 1;                                     /* wrong bits on purpose (mul.h) */
#endif
    return r < hi ? 0xFFFFFFFFUL : r;
}

uint32_t um_muldiv(uint32_t a, uint16_t n, uint32_t d) __reentrant
{
    uint32_t p, q;
    uint16_t m, r16;
    uint8_t i, f;
    int8_t e;

    if (a == 0 || n == 0)
        return 0;
    if (d == 0)
        return 0xFFFFFFFFUL;
#if defined(__SDCC) && FX_SABOTAGE == 13
    a += a >> 8;                                /* wrong bits on purpose (mul.h) */
#endif
    p = a;
    e = -(int8_t)norm32((__idata uint32_t *)&p);    /* a = (p >> 16) * 2^(16 + e) */
    p = UMUL(p >> 16, n);                       /* < 2^32, not 0 */
    e -= (int8_t)norm32((__idata uint32_t *)&p);    /* a * n = (p >> 16) * 2^(32 + e) */
    q = d;
    e += (int8_t)norm32((__idata uint32_t *)&q);    /* d = (q >> 16) * 2^(16 - sd) */
    m = (uint16_t)(q >> 16);                    /* 32768 .. 65535 */
    i = (uint8_t)((m >> 8) - 128u);
    f = (uint8_t)m;
    /* the table's steps are below 256 (254 at most): an 8 x 8 product, MUL AB, no call */
    r16 = recip_tab[i] - (uint16_t)(((uint16_t)((uint8_t)(recip_tab[i] - recip_tab[i + 1]) * f) + 128u) >> 8);
    p = UMUL(p >> 16, r16);                     /* (a n / d) * 2^(14 - e) */
    e -= 14;
    if (e >= 0) {
        while (e > 0) {
            if (p & 0x80000000UL)
                return 0xFFFFFFFFUL;
            p <<= 1;
            e--;
        }
        return p;
    }
    if (e < -31)
        return 0;
    e = -e;
    return (p + (1UL << (e - 1))) >> e;
}

uint32_t um_scaled_div(uint32_t num, uint16_t m, uint32_t d) __reentrant
{
    uint32_t q = num / d;                       /* (the remainder without a remainder routine) */
#if defined(__SDCC) && FX_SABOTAGE == 14
    return (q * m + ((num - q * d) * m + d / 2u) / d) | 1u;     /* wrong bits on purpose (mul.h) */
#else
    return q * m + ((num - q * d) * m + d / 2u) / d;
#endif
}

uint16_t um_sqrt32(uint32_t x) __reentrant
{
    /* the root's bits from the top, each kept while its square stays within x: a 16 x 16
     * product a bit (MUL AB) where the shift-and-subtract form moved 32-bit values on the stack */
    uint16_t r = 0, b = 0x8000u, t;
    do {
        t = r | b;
        if (UMUL(t, t) <= x)
            r = t;
        b >>= 1;
    } while (b);
    return r;
}

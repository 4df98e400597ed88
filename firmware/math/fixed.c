/* fixed.c: saturating fixed-point arithmetic and table-driven tanh; same bits on SDCC and gcc. */
#include "fixed.h"

int16_t fx_sat16(int32_t x)
{
    if (x > 32767L)
        return 32767;
    if (x < -32768L)
        return -32768;
    return (int16_t)x;
}

int16_t fx_add_sat(int16_t a, int16_t b)
{
    return fx_sat16((int32_t)a + b);
}

int16_t fx_sub_sat(int16_t a, int16_t b)
{
    return fx_sat16((int32_t)a - b);
}

int32_t fx_mul32(int16_t a, int16_t b)
{
    return (int32_t)a * b;
}

int16_t fx_mul_shift(int16_t a, int16_t b, uint8_t shift)
{
    int32_t p = (int32_t)a * b;
#ifdef FX_SABOTAGE
    /* deliberately different bits (truncation): only for the test that proves the s51
     * comparison can fail; never in a real build */
    if (shift)
        p = p >> shift;
#else
    if (shift)
        p = (p + (1L << (shift - 1))) >> shift;
#endif
    return fx_sat16(p);
}

/* constant shifts: SDCC turns them into byte moves, a variable shift is a loop of ~30 cycles a bit */
q15_t q15_mul(q15_t a, q15_t b)
{
    return fx_sat16(((int32_t)a * b + 0x4000L) >> 15);
}

q12_t q12_mul(q12_t a, q12_t b)
{
    return fx_sat16(((int32_t)a * b + 0x0800L) >> 12);
}

q15_t fx_tanh(q12_t x)
{
    uint16_t ax;            /* |x| in Q12 */
    uint16_t i;             /* table interval, 1/64 wide */
    int16_t y;              /* Q15 */
    int16_t d;              /* Q15 rise over the interval: 0 .. 512 since tanh' <= 1 */

    ax = x < 0 ? (uint16_t)(-(int32_t)x) : (uint16_t)x;   /* -(-32768) = 32768 fits uint16 */
    if (ax >= (uint16_t)((FX_TANH_N - 1) * 64)) {
        y = 32767;
    } else {
        i = ax >> 6;
        y = fx_tanh_tab[i];
        d = fx_tanh_tab[i + 1] - y;
        /* d * frac <= 512 * 63 = 32256: a 16-bit multiply is enough */
        y += (int16_t)((d * (int16_t)(ax & 63u) + 32) >> 6);
    }
    return x < 0 ? (q15_t)-y : (q15_t)y;
}

q15_t fx_sigmoid(q12_t x)
{
    /* (32768 + tanh) / 2 rounded to nearest; tanh = 32767 would round to 32768: saturate */
    return fx_sat16((32769L + fx_tanh(x)) >> 1);
}

/* fxops.c: general fixed-point products, (1+tanh)/2, saturating sum and difference; in the library archive, linked only where called. */
#include "fixed.h"
#include "mul.h"

/*
 * The control steps use MUL (mul.h) with their own constant shifts; these general forms are
 * the fixed-point API the tests check against double-precision twins (test_fixed, tt_fixed).
 * The firmware image links this file only if something in it calls one of them.
 */

int32_t fx_mul32(int16_t a, int16_t b)
{
    return MUL(a, b);
}

int16_t fx_mul_shift(int16_t a, int16_t b, uint8_t shift)
{
    int32_t p = (int32_t)a * b;
    if (shift)
        p = (p + (1L << (shift - 1))) >> shift;
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

q15_t fx_sigmoid(q12_t x)
{
    /* (32768 + tanh) / 2 rounded to nearest; tanh = 32767 would round to 32768: saturate */
    return fx_sat16((32769L + fx_tanh(x)) >> 1);
}

/* Saturating sum and difference: the reference of the 8051's assembly (hal/mcs51/addsub_sat.c);
 * the target tests compare the two bit for bit. */
#if !defined(__SDCC)
int16_t fx_add_sat(int16_t a, int16_t b)
{
    return fx_sat16((int32_t)a + b);
}

int16_t fx_sub_sat(int16_t a, int16_t b)
{
    return fx_sat16((int32_t)a - b);
}
#endif

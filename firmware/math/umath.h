/* umath.h: unsigned arithmetic for the per-period work without a divide (a divide costs ~1000 cycles on the 8051). */
#ifndef UMATH_H
#define UMATH_H

#include "compiler.h"

/* Reentrant: their locals live on the stack for the moment they run instead of taking XRAM
 * for good (SDCC does not overlay the large model's xdata locals). */

/* (a * b) >> 16, rounded to nearest; saturates at 0xFFFFFFFF. Two 16x16 products. */
uint32_t um_mul32x16_shr16(uint32_t a, uint16_t b) __reentrant;
/* a * n / d by normalised mantissas and a 129-entry reciprocal table with linear
 * interpolation: relative error below 2e-4 (tests/math/test_umath.c measures it), saturates at
 * 0xFFFFFFFF, d = 0 gives 0xFFFFFFFF, a or n = 0 gives 0. Three 16x16 products, no divide. */
uint32_t um_muldiv(uint32_t a, uint16_t n, uint32_t d) __reentrant;
/* (num * m + d / 2) / d exactly (rounded; d > 0) where num * m may pass 32 bits: the whole
 * quotient num / d times m, plus the remainder's share, (r * m + d / 2) / d, which must fit 32
 * bits ((d - 1) m + d / 2 < 2^32). Two divides: for derivations when a parameter changes
 * (flow.c's meter constant, target.c's eq. (1) constant, ctl.c's and valve.c's duties in Q15),
 * one copy for all. */
uint32_t um_scaled_div(uint32_t num, uint16_t m, uint32_t d) __reentrant;
/* floor(sqrt(x)), bit by bit: a 16 x 16 product and a compare each. */
uint16_t um_sqrt32(uint32_t x) __reentrant;

#endif

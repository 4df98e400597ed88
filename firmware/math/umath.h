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
/* floor(sqrt(x)), bit by bit: shifts, adds and compares only. */
uint16_t um_sqrt32(uint32_t x) __reentrant;

#endif

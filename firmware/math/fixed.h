/* fixed.h: the fixed-point formats of the firmware, saturating arithmetic, tanh and (1+tanh)/2 from tables. */
#ifndef FIXED_H
#define FIXED_H

#include "compiler.h"

/*
 * Formats (one typedef each; a variable's format also stands in a trailing comment):
 *   q15_t  int16, 15 fraction bits: [-1, 1 - 2^-15]
 *   q12_t  int16, 12 fraction bits: [-8, 8 - 2^-12]   (network weights and activations' inputs)
 *   q8_t   int16,  8 fraction bits: [-128, 128 - 2^-8]
 *   q16_t  int32, 16 fraction bits: [-32768, 32768)   (accumulators)
 *
 * Overflow policy: every routine here saturates to the format's limits, it never wraps.
 * Rounding policy: products round to nearest (add half an LSB, then an arithmetic right shift,
 * which gcc and SDCC both do for signed operands: the target tests check that they agree).
 * Nothing here divides or uses floating point.
 */
typedef int16_t q15_t;
typedef int16_t q12_t;
typedef int16_t q8_t;
typedef int32_t q16_t;

#define Q15_MAX ((q15_t)32767)
#define Q15_MIN ((q15_t)-32768)
#define Q15_ONE 32768L

/* Constants through macros only (folded by the compiler: no float reaches the code). */
#define Q15(x) ((q15_t)((x) >= 0.999969482421875 ? 32767 : (x) * 32768.0 + ((x) >= 0 ? 0.5 : -0.5)))
#define Q12(x) ((q12_t)((x) * 4096.0 + ((x) >= 0 ? 0.5 : -0.5)))
#define Q8(x)  ((q8_t)((x) * 256.0 + ((x) >= 0 ? 0.5 : -0.5)))
#define Q16(x) ((q16_t)((x) * 65536.0 + ((x) >= 0 ? 0.5 : -0.5)))

/* tanh tables (tools/gen_tanh.py): FX_TANH_N points of tanh(i / 64) in Q15, i.e. x in
 * [0, 5.34]; from the last point on tanh is 32767. Points 0..FX_TANH_J in fx_tanh_tab, points
 * FX_TANH_J..FX_TANH_N - 1 (within 255 of 32767) as 32767 - tanh in a byte each. */
#define FX_TANH_N 343
#define FX_TANH_J 178
extern const FX_CODE q15_t fx_tanh_tab[FX_TANH_J + 1];
extern const FX_CODE uint8_t fx_tanh_tail[FX_TANH_N - FX_TANH_J];

/* FX_NAKED: an assembly routine on the 8051 that leaves R0-R7 alone (callers keep theirs). */
#if defined(__SDCC)
#define FX_NAKED __naked
#else
#define FX_NAKED
#endif
/* Saturate a 32-bit value to int16. */
int16_t fx_sat16(int32_t x) FX_NAKED;
/* a + b saturated (any int16 format: both operands in the same one). */
int16_t fx_add_sat(int16_t a, int16_t b) FX_NAKED;
/* a - b saturated. */
int16_t fx_sub_sat(int16_t a, int16_t b) FX_NAKED;
/* (a * b) >> shift rounded to nearest and saturated to int16: q15*q15 with shift 15 is Q15, and so on. */
int16_t fx_mul_shift(int16_t a, int16_t b, uint8_t shift);
/* Q15 x Q15 -> Q15, rounded, saturated (-1 * -1 gives 32767). */
q15_t q15_mul(q15_t a, q15_t b);
/* Q12 x Q12 -> Q12, rounded, saturated. */
q12_t q12_mul(q12_t a, q12_t b);
/* tanh of a Q12 argument, Q15 result; linear interpolation in the table; |error| < 2 LSB (1.53 measured). */
q15_t fx_tanh(q12_t x) __reentrant;
/* (1 + tanh(x)) / 2 of a Q12 argument as Q15 in [0, 1), |error| < 2 LSB: the network's non-negative output. */
q15_t fx_sigmoid(q12_t x);

#endif

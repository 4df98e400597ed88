/* mul.h: the 16x16 -> 32 signed multiply of the control steps, and the dot product of the network. */
#ifndef MUL_H
#define MUL_H

#include "compiler.h"

/*
 * On the 8051 (mul.c, assembly): four MUL AB (about 60 machine cycles against about 230 for
 * SDCC's general 32-bit multiply), the operands, product and sum in direct RAM. The routines
 * are __naked and touch only A, B, DPTR and PSW (dot_ab saves what else it uses), and their
 * declarations say so: a caller keeps its live values in R0-R7 across the call. On the host the
 * same exact products in C. Every product of the controllers goes through MUL, MAC or DOT; a
 * build with -DFX_SABOTAGE makes mul_ab's products odd on the 8051 only (the test that proves
 * the s51 comparison can fail).
 *   MUL(a, b)     a * b, int16 operands, int32 product
 *   MAC(a, b)     mul_acc += a * b
 *   DOT(w, x, n)  mul_acc += w[0] * x[0] + ... + w[n-1] * x[n-1], w and x int16 arrays in xdata
 */
#if defined(__SDCC)
extern __data int16_t mul_a, mul_b;
extern __data int32_t mul_r;
extern __data int32_t mul_acc;
int32_t mul_ab(void) __naked;
void mac_ab(void) __naked;
void dot_ab(uint8_t n) __naked;
#define MUL(a, b) (mul_a = (a), mul_b = (b), mul_ab())
#define MAC(a, b) do { mul_a = (a); mul_b = (b); mac_ab(); } while (0)
#define DOT(w, x, n) do { mul_a = (int16_t)(uint16_t)(w); mul_b = (int16_t)(uint16_t)(x); dot_ab(n); } while (0)
#else
extern int32_t mul_acc;
void dot_c(const int16_t *w, const int16_t *x, uint8_t n);
#define DOT(w, x, n) dot_c(w, x, n)
#define MUL(a, b) ((int32_t)(int16_t)(a) * (int16_t)(b))
#define MAC(a, b) (mul_acc += (int32_t)(int16_t)(a) * (int16_t)(b))
#endif

/* The full 16x16 -> 32 product as a function (MUL through a call): the target tests' vectors. */
int32_t fx_mul32(int16_t a, int16_t b);

#endif

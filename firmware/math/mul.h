/* mul.h: the 16x16 -> 32 signed multiply of the control steps; the network's dot product and learning row. */
#ifndef MUL_H
#define MUL_H

#include "compiler.h"

#ifndef FX_SABOTAGE
#define FX_SABOTAGE 0
#endif

/*
 * On the 8051 (hal/mcs51/mul.c, acc.c, upd.c, mul_round.c: assembly): four MUL AB (about 60 machine cycles against about 230 for
 * SDCC's general 32-bit multiply), the operands, product and sum in direct RAM. The routines
 * are __naked and touch only A, B, DPTR and PSW (dot_ab saves what else it uses), and their
 * declarations say so: a caller keeps its live values in R0-R7 across the call. On the host the
 * same exact products in C. Every product of the controllers goes through MUL, MAC or DOT.
 * -DFX_SABOTAGE=n (tools/run_tests.sh only, never a real build) gives one routine the
 * controllers compute with wrong bits on the 8051 only, so that the s51 comparison is shown to
 *  catch each: 1 mul_ab, 2 mac_ab, 3 dot_ab, 4 upd_ab, 5 umul_ab, 6 mul_r15, 7 mul_r12,
 * 8 acc_shr15, 9 acc_shr12 (hal/mcs51/mul.c, acc.c, upd.c, mul_round.c), 10 fx_sat16 (hal/mcs51/sat16.c), 11 fx_tanh (fixed.c),
 * 12 um_mul32x16_shr16, 13 um_muldiv, 14 um_scaled_div (umath.c).
 *   MUL(a, b)     a * b, int16 operands, int32 product
 *   ACC_START(r)  mul_acc = 2^(r-1): the rounding of the sum's >> r (r = 12 or 15), where a
 *                 MAC or DOT sum starts
 *   MAC(a, b)     mul_acc += a * b
 *   DOT(w, x, n)  mul_acc += w[0] * x[0] + ... + w[n-1] * x[n-1], int16 arrays: w in xdata, x in
 *                 idata (a reentrant caller's locals, on the stack)
 *   UMUL(a, b)    a * b, uint16 operands, uint32 product (one expression holds at most one)
 *   MUL_R15(a, b), MUL_R12(a, b)   (a * b + 2^14) >> 15, (a * b + 2^11) >> 12: rounded, int32
 *   ACC_SHR15(), ACC_SHR12()       mul_acc >> 15, >> 12 (arithmetic), int32
 *   UPD(w, dw, x, eg, lim, n, s)   one row of a network's learning step (below)
 *
 * UPD, for j = 0 .. n-1 (w int16 and dw int8 arrays in xdata, x int16 in idata; s = 1 or 4):
 *   d     = (eg * x[j] + 2^(15-s)) >> (16-s)      eg * x rounded (x Q15: s = 1, x Q12: s = 4)
 *   d    += (dw[j] >> 4) - (dw[j] >> 6) + (dw[j] >> 8)    the momentum term, 0.0508 dw
 *   w[j]  = w[j] + d, held within +-lim
 *   dw[j] = the change made, held within +-127
 * The caller keeps (eg * x[j]) >> (16-s) within int16 and w[j] within +-lim (nothing else
 * saturates); the host's C and the 8051's assembly give the same bits (tt_ctl).
 */
#if defined(__SDCC)
extern __data int16_t mul_a, mul_b;
extern __data int32_t mul_r;
extern __data int32_t mul_acc;
int32_t mul_ab(void) __naked;
void acc_start(uint8_t hi) __naked;
void mac_ab(void) __naked;
void dot_ab(uint8_t n) __naked;
extern __data int16_t upd_eg, upd_lim;
extern __data uint16_t upd_dw;
void upd_ab(uint16_t n_s) __naked;
#define MUL(a, b) (mul_a = (a), mul_b = (b), mul_ab())
int32_t mul_r15(void) __naked;
int32_t mul_r12(void) __naked;
int32_t acc_shr15(void) __naked;
int32_t acc_shr12(void) __naked;
uint32_t umul_ab(void) __naked;
#define UMUL(a, b) (mul_a = (int16_t)(uint16_t)(a), mul_b = (int16_t)(uint16_t)(b), umul_ab())
#define MUL_R15(a, b) (mul_a = (a), mul_b = (b), mul_r15())
#define MUL_R12(a, b) (mul_a = (a), mul_b = (b), mul_r12())
#define ACC_SHR15() acc_shr15()
#define ACC_SHR12() acc_shr12()
#define MAC(a, b) do { mul_a = (a); mul_b = (b); mac_ab(); } while (0)
#define DOT(w, x, n) do { mul_a = (int16_t)(uint16_t)(w); mul_b = (int16_t)(uint16_t)(x); dot_ab(n); } while (0)
#define UPD(w, dw, x, eg, lim, n, s)                                                          \
    do {                                                                                     \
        mul_a = (int16_t)(uint16_t)(w);                                                      \
        upd_dw = (uint16_t)(dw);                                                             \
        mul_b = (int16_t)(uint16_t)(x);                                                      \
        upd_eg = (eg);                                                                       \
        upd_lim = (lim);                                                                     \
        upd_ab((uint16_t)(((uint16_t)(s) << 8) | (n)));                                      \
    } while (0)
#else
extern int32_t mul_acc;
void acc_start(uint8_t hi);
void dot_c(const int16_t *w, const int16_t *x, uint8_t n);
#define DOT(w, x, n) dot_c(w, x, n)
void upd_c(int16_t *w, int8_t *dw, const int16_t *x, int16_t eg, int16_t lim, uint8_t n, uint8_t s);
#define UPD(w, dw, x, eg, lim, n, s) upd_c(w, dw, x, eg, lim, n, s)
#define MUL(a, b) ((int32_t)(int16_t)(a) * (int16_t)(b))
#define UMUL(a, b) ((uint32_t)(uint16_t)(a) * (uint16_t)(b))
#define MUL_R15(a, b) ((MUL(a, b) + 16384) >> 15)
#define MUL_R12(a, b) ((MUL(a, b) + 2048) >> 12)
#define ACC_SHR15() (mul_acc >> 15)
#define ACC_SHR12() (mul_acc >> 12)
void mac_c(int16_t a, int16_t b);
#define MAC(a, b) mac_c((int16_t)(a), (int16_t)(b))
#endif

#define ACC_START(r) acc_start((uint8_t)(1u << ((r) - 9)))   /* 2^(r-1): its byte 1 */

/* The full 16x16 -> 32 product as a function (MUL through a call): the target tests' vectors. */
int32_t fx_mul32(int16_t a, int16_t b);

#endif

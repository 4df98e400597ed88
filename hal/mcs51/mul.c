/* mul.c: the 16x16 -> 32 signed multiply on the 8051 (MUL AB); the host's C is firmware/math/mul.c. */
#include "mul.h"

__data int16_t mul_a, mul_b;
__data int32_t mul_r;

/* mul_r = mul_a * mul_b, also returned (dpl, dph, b, a); FX_SABOTAGE (mul.h): wrong bits on
 * purpose, only for the test that proves the s51 comparison can fail */
int32_t mul_ab(void) __naked
{
    __asm
        lcall _mul_u            ; the unsigned product (mul_round.c), then the signs
        mov a,(_mul_a + 1)
        jnb acc.7,00001$
        clr c
        mov a,(_mul_r + 2)
        subb a,_mul_b
        mov (_mul_r + 2),a
        mov a,(_mul_r + 3)
        subb a,(_mul_b + 1)
        mov (_mul_r + 3),a
00001$:
        mov a,(_mul_b + 1)
        jnb acc.7,00002$
        clr c
        mov a,(_mul_r + 2)
        subb a,_mul_a
        mov (_mul_r + 2),a
        mov a,(_mul_r + 3)
        subb a,(_mul_a + 1)
        mov (_mul_r + 3),a
00002$:
#if FX_SABOTAGE == 1
        orl _mul_r,#1           ; the product made odd (wrong bits on purpose)
#endif
        mov dpl,_mul_r
        mov dph,(_mul_r + 1)
        mov b,(_mul_r + 2)
        mov a,(_mul_r + 3)
        ret
    __endasm;
}

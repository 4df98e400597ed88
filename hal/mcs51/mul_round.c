/* mul_round.c: the unsigned product UMUL (whose first part mul_ab shares) and the rounded Q15 product MUL_R15 (mul.h; the Q12 one and the sum's shifts, bp_pid's, are acc.c's), in assembly on the 8051 (the host's are C macros). */
#include "mul.h"

/* Like mul_ab these touch only A, B, DPTR and PSW (and mul_r), so a caller keeps R0-R7; each
 * replaces the rounding add and long shift SDCC writes out at every use. */
/* mul_r = mul_a * mul_b unsigned, also returned (dpl, dph, b, a): UMUL. Its first part,
 * _mul_u (the unsigned product into mul_r, its top byte in A), is mul_ab's too. */
uint32_t umul_ab(void) __naked
{
    __asm
        lcall _mul_u
        mov dpl,_mul_r
        mov dph,(_mul_r + 1)
        mov b,(_mul_r + 2)
#if FX_SABOTAGE == 5
        orl dpl,#1              ; the product made odd (wrong bits on purpose)
#endif
        ret
_mul_u::
        mov a,_mul_a
        mov b,_mul_b
        mul ab
        mov _mul_r,a
        mov (_mul_r + 1),b
        mov a,(_mul_a + 1)
        mov b,_mul_b
        mul ab
        add a,(_mul_r + 1)
        mov (_mul_r + 1),a
        mov a,b
        addc a,#0
        mov (_mul_r + 2),a
        mov a,_mul_a
        mov b,(_mul_b + 1)
        mul ab
        add a,(_mul_r + 1)
        mov (_mul_r + 1),a
        mov a,b
        addc a,(_mul_r + 2)
        mov (_mul_r + 2),a
        clr a
        rlc a
        mov (_mul_r + 3),a
        mov a,(_mul_a + 1)
        mov b,(_mul_b + 1)
        mul ab
        add a,(_mul_r + 2)
        mov (_mul_r + 2),a
        mov a,b
        addc a,(_mul_r + 3)
        mov (_mul_r + 3),a
        ret
    __endasm;
}

/* (mul_a * mul_b + 2^14) >> 15, returned (dpl, dph, b, a): the rounded Q15 product without the
 * long shift SDCC writes out at each use */
int32_t mul_r15(void) __naked
{
    __asm
        lcall _mul_ab
        mov a,(_mul_r + 1)
        add a,#0x40
        mov (_mul_r + 1),a
        clr a
        addc a,(_mul_r + 2)
        mov (_mul_r + 2),a
        clr a
        addc a,(_mul_r + 3)
        mov (_mul_r + 3),a
        mov a,(_mul_r + 1)
        rlc a                   ; C = bit 15
        mov a,(_mul_r + 2)
        rlc a
        mov dpl,a               ; bits 15..22
        mov a,(_mul_r + 3)
        rlc a
        mov dph,a               ; bits 23..30, C = the sign
        subb a,acc              ; 0x00 or 0xff
        mov b,a
#if FX_SABOTAGE == 6
        orl dpl,#1              ; the result made odd (wrong bits on purpose)
#endif
        ret
    __endasm;
}

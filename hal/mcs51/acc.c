/* acc.c: the products only bp_pid takes, on the 8051 (MUL AB): the accumulate, the dot product,
 * the sum's shifts and the rounded Q12 product (mul.h MAC, DOT, ACC_SHR15, ACC_SHR12, MUL_R12;
 * the learning row is upd.c's): a module of their own, so that an image without bp_pid links
 * none of them; the host's C is firmware/math/mul.c. */
#include "mul.h"

__data int32_t mul_acc;

/* mul_acc += mul_a * mul_b */
void mac_ab(void) __naked
{
    __asm
        lcall _mul_ab
        mov a,_mul_acc
        add a,_mul_r
        mov _mul_acc,a
        mov a,(_mul_acc + 1)
        addc a,(_mul_r + 1)
        mov (_mul_acc + 1),a
        mov a,(_mul_acc + 2)
        addc a,(_mul_r + 2)
        mov (_mul_acc + 2),a
        mov a,(_mul_acc + 3)
        addc a,(_mul_r + 3)
        mov (_mul_acc + 3),a
#if FX_SABOTAGE == 2
        xrl (_mul_acc + 2),#1   ; the sum 2^16 off (wrong bits on purpose)
#endif
        ret
    __endasm;
}
/* mul_acc += the sum of n products w[j] * x[j]: w at the xdata address in mul_a, x at the idata
 * address in mul_b's low byte (int16 each, contiguous); the registers it uses are saved */
void dot_ab(uint8_t n) __naked
{
    (void)n;
    __asm
        ar0 = 0x00              ; bank 0 register addresses for push / pop
        ar1 = 0x01
        ar2 = 0x02
        ar3 = 0x03
        ar4 = 0x04
        ar5 = 0x05
        ar6 = 0x06
        ar7 = 0x07
        push ar0
        push ar1
        push ar2
        push ar3
        push ar4
        push ar5
        push ar6
        push ar7
        mov _mul_r,dpl
00010$:
        mov r0,_mul_b           ; x[j] from the internal RAM
        mov a,@r0
        mov r6,a
        inc r0
        mov a,@r0
        mov r7,a
        inc r0
        mov _mul_b,r0
        mov dpl,_mul_a          ; w[j] from the XRAM
        mov dph,(_mul_a + 1)
        movx a,@dptr
        mov r0,a
        inc dptr
        movx a,@dptr
        mov r1,a
        inc dptr
        mov _mul_a,dpl
        mov (_mul_a + 1),dph
        mov a,r0
        mov b,r6
        mul ab
        mov r2,a
        mov r3,b
        mov a,r1
        mov b,r6
        mul ab
        add a,r3
        mov r3,a
        clr a
        addc a,b
        mov r4,a
        mov a,r0
        mov b,r7
        mul ab
        add a,r3
        mov r3,a
        mov a,b
        addc a,r4
        mov r4,a
        clr a
        rlc a
        mov r5,a
        mov a,r1
        mov b,r7
        mul ab
        add a,r4
        mov r4,a
        mov a,b
        addc a,r5
        mov r5,a
        mov a,r1
        jnb acc.7,00011$
        clr c
        mov a,r4
        subb a,r6
        mov r4,a
        mov a,r5
        subb a,r7
        mov r5,a
00011$:
        mov a,r7
        jnb acc.7,00012$
        clr c
        mov a,r4
        subb a,r0
        mov r4,a
        mov a,r5
        subb a,r1
        mov r5,a
00012$:
        mov a,r2
        add a,_mul_acc
        mov _mul_acc,a
        mov a,r3
        addc a,(_mul_acc + 1)
        mov (_mul_acc + 1),a
        mov a,r4
        addc a,(_mul_acc + 2)
        mov (_mul_acc + 2),a
        mov a,r5
        addc a,(_mul_acc + 3)
        mov (_mul_acc + 3),a
        djnz _mul_r,00010$
#if FX_SABOTAGE == 3
        xrl (_mul_acc + 2),#1   ; the sum 2^16 off (wrong bits on purpose)
#endif
        pop ar7
        pop ar6
        pop ar5
        pop ar4
        pop ar3
        pop ar2
        pop ar1
        pop ar0
        ret
    __endasm;
}

/* mul_acc >> 15 (its rounding added beforehand) */
int32_t acc_shr15(void) __naked
{
    __asm
        mov a,(_mul_acc + 1)
        rlc a                   ; C = bit 15
        mov a,(_mul_acc + 2)
        rlc a
        mov dpl,a
        mov a,(_mul_acc + 3)
        rlc a
        mov dph,a
        subb a,acc
        mov b,a
#if FX_SABOTAGE == 8
        orl dpl,#1              ; the result made odd (wrong bits on purpose)
#endif
        ret
    __endasm;
}
/* mul_acc >> 12 (its rounding added beforehand) */
int32_t acc_shr12(void) __naked
{
    __asm
        mov a,(_mul_acc + 1)
        swap a
        anl a,#0x0f
        mov dpl,a
        mov a,(_mul_acc + 2)
        swap a
        mov b,a
        anl a,#0xf0
        orl dpl,a
        mov a,b
        anl a,#0x0f
        mov dph,a
        mov a,(_mul_acc + 3)
        swap a
        mov b,a
        anl a,#0xf0
        orl dph,a
        mov a,b
        anl a,#0x0f
        jnb acc.3,00041$
        orl a,#0xf0
00041$:
        mov b,a
        rlc a
        subb a,acc
#if FX_SABOTAGE == 9
        orl dpl,#1              ; the result made odd (wrong bits on purpose)
#endif
        ret
    __endasm;
}
/* (mul_a * mul_b + 2^11) >> 12 */
int32_t mul_r12(void) __naked
{
    __asm
        lcall _mul_ab
        mov a,(_mul_r + 1)
        add a,#0x08
        mov (_mul_r + 1),a
        clr a
        addc a,(_mul_r + 2)
        mov (_mul_r + 2),a
        clr a
        addc a,(_mul_r + 3)
        mov (_mul_r + 3),a
        mov a,(_mul_r + 1)
        swap a
        anl a,#0x0f
        mov dpl,a
        mov a,(_mul_r + 2)
        swap a
        mov b,a
        anl a,#0xf0
        orl dpl,a               ; bits 12..19
        mov a,b
        anl a,#0x0f
        mov dph,a
        mov a,(_mul_r + 3)
        swap a
        mov b,a
        anl a,#0xf0
        orl dph,a               ; bits 20..27
        mov a,b
        anl a,#0x0f
        jnb acc.3,00040$
        orl a,#0xf0             ; bits 28..35, the sign extended
00040$:
        mov b,a
        rlc a
        subb a,acc
#if FX_SABOTAGE == 7
        orl dpl,#1              ; the result made odd (wrong bits on purpose)
#endif
        ret
    __endasm;
}

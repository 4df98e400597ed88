/* mul.c: the 16x16 -> 32 signed multiply the controllers use: four MUL AB on the 8051, C on the host. */
#include "mul.h"

#if defined(__SDCC)
__data int16_t mul_a, mul_b;
__data int32_t mul_r;
__data int32_t mul_acc;

/* mul_r = mul_a * mul_b, also returned (dpl, dph, b, a); -DFX_SABOTAGE: deliberately wrong bits,
 * only for the test that proves the s51 comparison can fail, never in a real build */
int32_t mul_ab(void) __naked
{
    __asm
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
#ifdef FX_SABOTAGE
        orl _mul_r,#1           ; the product made odd (wrong bits on purpose)
#endif
        mov dpl,_mul_r
        mov dph,(_mul_r + 1)
        mov b,(_mul_r + 2)
        mov a,(_mul_r + 3)
        ret
    __endasm;
}
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
        ret
    __endasm;
}
/* mul_acc += the sum of n products w[j] * x[j]: w at the xdata address in mul_a, x at the one in
 * mul_b (int16 each, contiguous); the registers it uses are saved */
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
        mov dpl,_mul_a
        mov dph,(_mul_a + 1)
        movx a,@dptr
        mov r0,a
        inc dptr
        movx a,@dptr
        mov r1,a
        inc dptr
        mov _mul_a,dpl
        mov (_mul_a + 1),dph
        mov dpl,_mul_b
        mov dph,(_mul_b + 1)
        movx a,@dptr
        mov r6,a
        inc dptr
        movx a,@dptr
        mov r7,a
        inc dptr
        mov _mul_b,dpl
        mov (_mul_b + 1),dph
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
#else
int32_t mul_acc;

void dot_c(const int16_t *w, const int16_t *x, uint8_t n)
{
    while (n--)
        mul_acc += (int32_t)*w++ * *x++;
}
#endif

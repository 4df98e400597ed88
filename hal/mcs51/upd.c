/* upd.c: one row of a network's learning step on the 8051 (mul.h UPD), bp_pid's alone, with its
 * operands in the direct RAM; the host's C is firmware/math/mul.c. */
#include "mul.h"

__data int16_t upd_eg, upd_lim;
__data uint16_t upd_dw;

/* One row of a network's learning step (mul.h, UPD): w at the xdata address in mul_a, x at the
 * idata address in mul_b's low byte, dw at the xdata address upd_dw; eg and lim in upd_eg,
 * upd_lim; n in dpl, s in dph. The product is dot_ab's; the registers it uses are saved. */
void upd_ab(uint16_t n_s) __naked
{
    (void)n_s;
    __asm
        ar0 = 0x00              ; bank 0 register addresses for push / pop
        ar1 = 0x01
        ar2 = 0x02
        ar3 = 0x03
        ar4 = 0x04
        ar5 = 0x05
        ar6 = 0x06
        ar7 = 0x07
#if FX_SABOTAGE == 4
        xrl (_upd_eg + 1),#1    ; the error 256 off (wrong bits on purpose)
#endif
        push ar0
        push ar1
        push ar2
        push ar3
        push ar4
        push ar5
        push ar6
        push ar7
        mov _mul_r,dpl              ; n
        mov (_mul_r + 1),dph        ; s
        mov b,dph
        mov a,#0x80
00020$:
        rr a
        djnz b,00020$
        mov (_mul_r + 2),a          ; the rounding 2^(15-s), as a byte above the lowest
        mov r1,(_upd_eg + 1)
00021$:
        ; x[j] -> r7:r6, from the internal RAM (r0 its pointer, then the low byte of eg)
        mov r0,_mul_b
        mov a,@r0
        mov r6,a
        inc r0
        mov a,@r0
        mov r7,a
        inc r0
        mov _mul_b,r0
        mov r0,_upd_eg
        ; r5:r4:r3:r2 = eg * x, signed
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
        jnb acc.7,00022$
        clr c
        mov a,r4
        subb a,r6
        mov r4,a
        mov a,r5
        subb a,r7
        mov r5,a
00022$:
        mov a,r7
        jnb acc.7,00023$
        clr c
        mov a,r4
        subb a,r0
        mov r4,a
        mov a,r5
        subb a,r1
        mov r5,a
00023$:
        ; rounded, then d = r5:r4 = bits 16-s .. 31-s (shifted left s times)
        mov a,(_mul_r + 2)
        add a,r3
        mov r3,a
        clr a
        addc a,r4
        mov r4,a
        clr a
        addc a,r5
        mov r5,a
        mov b,(_mul_r + 1)
00024$:
        mov a,r3
        add a,r3
        mov r3,a
        mov a,r4
        rlc a
        mov r4,a
        mov a,r5
        rlc a
        mov r5,a
        djnz b,00024$
        ; r3 = (dw >> 4) - (dw >> 6) + (dw >> 8), arithmetic shifts of the int8 dw[j]
        mov dpl,_upd_dw
        mov dph,(_upd_dw + 1)
        movx a,@dptr
        mov r2,a
        swap a
        anl a,#0x0F
        jnb acc.3,00025$
        orl a,#0xF0
00025$:
        mov r3,a
        mov a,r2
        rl a
        rl a
        anl a,#0x03
        jnb acc.1,00026$
        orl a,#0xFC
00026$:
        xch a,r3
        clr c
        subb a,r3
        mov r3,a
        mov a,r2
        jnb acc.7,00027$
        dec r3
00027$:
        ; d += r3, sign-extended
        mov a,r3
        add a,r4
        mov r4,a
        mov a,r3
        jb acc.7,00028$
        clr a
        sjmp 00029$
00028$:
        mov a,#0xFF
00029$:
        addc a,r5
        mov r5,a
        ; r7:r6 = w[j]; r3:r2 = w[j] + d, held within +-lim
        mov dpl,_mul_a
        mov dph,(_mul_a + 1)
        movx a,@dptr
        mov r6,a
        inc dptr
        movx a,@dptr
        mov r7,a
        mov a,r6
        add a,r4
        mov r2,a
        mov a,r7
        addc a,r5
        mov r3,a
        jnb ov,00030$
        mov a,r5                    ; beyond int16: beyond the bound the way d went
        jb acc.7,00032$
        sjmp 00031$
00030$:
        jb acc.7,00033$
        clr c                       ; sum >= 0: above lim?
        mov a,_upd_lim
        subb a,r2
        mov a,(_upd_lim + 1)
        subb a,r3
        jnc 00034$
00031$:
        mov r2,_upd_lim
        mov r3,(_upd_lim + 1)
        sjmp 00034$
00033$:
        mov a,r2                    ; sum < 0: sum + lim < 0?
        add a,_upd_lim
        mov a,r3
        addc a,(_upd_lim + 1)
        jnb acc.7,00034$
00032$:
        clr c
        clr a
        subb a,_upd_lim
        mov r2,a
        clr a
        subb a,(_upd_lim + 1)
        mov r3,a
00034$:
        mov dpl,_mul_a
        mov dph,(_mul_a + 1)
        mov a,r2
        movx @dptr,a
        inc dptr
        mov a,r3
        movx @dptr,a
        inc dptr
        mov _mul_a,dpl
        mov (_mul_a + 1),dph
        ; dw[j] = the change made, held within +-127
        clr c
        mov a,r2
        subb a,r6
        mov r2,a
        mov a,r3
        subb a,r7
        jb acc.7,00035$
        jnz 00036$
        mov a,r2
        jnb acc.7,00037$
00036$:
        mov r2,#0x7F
        sjmp 00037$
00035$:
        cpl a
        jnz 00038$
        mov a,r2
        add a,#0x7F
        jc 00037$
00038$:
        mov r2,#0x81
00037$:
        mov dpl,_upd_dw
        mov dph,(_upd_dw + 1)
        mov a,r2
        movx @dptr,a
        inc dptr
        mov _upd_dw,dpl
        mov (_upd_dw + 1),dph
        djnz _mul_r,00039$          ; the loop is longer than a relative jump
        sjmp 00040$
00039$:
        ljmp 00021$
00040$:
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

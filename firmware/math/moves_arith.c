/* moves_arith.c: the shared copies of SDCC's 32- and 16-bit compares, sums, differences and shifts (tools/share_moves.py, as moves.c). */
#include "compiler.h"

/*
 * As in moves.c: each routine _mv_NAME is exactly the instructions of share_moves.py's
 * MOVES["NAME"], then RET. The x_ set: the sequences the modules outside the
 * controllers still wrote out most often, each used often enough to pay for its routine
 * (compares and differences with a local, SDCC's signed compare of a negation, shifts by 1, 2 and 4). The host build has no such code.
 */
#if defined(__SDCC)
void mv_arith_routines(void) __naked
{
    __asm
        ar4 = 0x04              ; bank 0 register addresses, as the modules calling them use them
        ar5 = 0x05
        ar6 = 0x06
_mv_x_sbc_ii3::
        subb a,@r0
        inc r1
        mov a,@r1
        inc r0
        subb a,@r0
        inc r1
        mov a,@r1
        inc r0
        subb a,@r0
        ret
_mv_x_cmp_r4567_i::
        clr c
        mov a,r4
        subb a,@r0
        mov a,r5
        inc r0
        subb a,@r0
        mov a,r6
        inc r0
        subb a,@r0
        mov a,r7
        inc r0
        subb a,@r0
        ret
_mv_x_cmp_ffff_r4567::
        clr c
        mov a,#0xff
        subb a,r4
        mov a,#0xff
        subb a,r5
        clr a
        subb a,r6
        clr a
        subb a,r7
        ret
_mv_x_neg_scmp_r45::
        mov ar4,r6
        mov ar5,r7
        clr c
        clr a
        subb a,r4
        mov a,#(0x00^0x80)
        mov b,r5
        ret
_mv_x_shl4_r67_i::
        mov @r0,ar5
        mov a,r6
        swap a
        xch a,@r0
        swap a
        anl a,#0x0f
        xrl a,@r0
        xch a,@r0
        anl a,#0x0f
        xch a,@r0
        xrl a,@r0
        xch a,@r0
        inc r0
        mov @r0,a
        mov a,r7
        swap a
        anl a,#0xf0
        orl a,@r0
        mov @r0,a
        mov a,r7
        swap a
        anl a,#0x0f
        inc r0
        mov @r0,a
        inc r0
        ret
_mv_x_cmp_i_r2367::
        clr c
        mov a,@r0
        subb a,r2
        inc r0
        mov a,@r0
        subb a,r3
        inc r0
        mov a,@r0
        subb a,r6
        inc r0
        mov a,@r0
        subb a,r7
        ret
_mv_x_shl1_r4567::
        mov a,r4
        add a,r4
        mov r4,a
        mov a,r5
        rlc a
        mov r5,a
        mov a,r6
        rlc a
        mov r6,a
        mov a,r7
        rlc a
        mov r7,a
        ret
_mv_x_sbc_r45_i::
        subb a,r4
        mov r4,a
        inc r0
        mov a,@r0
        subb a,r5
        mov r5,a
        inc r0
        mov a,@r0
        ret
_mv_x_shl4_r2367::
        xch a,r6
        swap a
        anl a,#0xf0
        xch a,r6
        swap a
        xch a,r6
        xrl a,r6
        xch a,r6
        anl a,#0xf0
        xch a,r6
        xrl a,r6
        mov r7,a
        mov a,r2
        swap a
        anl a,#0x0f
        orl a,r6
        mov r6,a
        mov a,r2
        swap a
        anl a,#0xf0
        mov r3,a
        mov r2,#0x00
        ret
_mv_x_sub_i_r4567::
        clr c
        subb a,r4
        mov @r0,a
        inc r0
        mov a,@r0
        subb a,r5
        mov @r0,a
        inc r0
        mov a,@r0
        subb a,r6
        mov @r0,a
        inc r0
        mov a,@r0
        subb a,r7
        mov @r0,a
        ret
_mv_x_shr1_r4567::
        clr c
        rrc a
        mov r7,a
        mov a,r6
        rrc a
        mov r6,a
        mov a,r5
        rrc a
        mov r5,a
        mov a,r4
        rrc a
        ret
_mv_x_cmp_ii4::
        mov a,_bp
        add a,#0x18
        mov r0,a
        mov a,_bp
        add a,#0x1c
        mov r1,a
        clr c
        mov a,@r0
        subb a,@r1
        inc r0
        mov a,@r0
        inc r1
        subb a,@r1
        inc r0
        mov a,@r0
        inc r1
        subb a,@r1
        inc r0
        mov a,@r0
        inc r1
        subb a,@r1
        ret
_mv_x_shr1_i4_r67::
        inc r0
        inc r0
        inc r0
        mov a,@r0
        clr c
        rrc a
        mov r7,a
        dec r0
        mov a,@r0
        rrc a
        mov r6,a
        dec r0
        mov a,@r0
        rrc a
        ret
_mv_x_add_fp1_r45::
        mov r0,_bp
        inc r0
        mov a,r4
        add a,@r0
        mov r4,a
        mov a,r5
        inc r0
        addc a,@r0
        mov r5,a
        ret
_mv_x_dptr_a_r67::
        add a,r6
        mov dpl,a
        clr a
        addc a,r7
        mov dph,a
        ret
_mv_x_shl1_r56::
        mov a,r5
        add a,r5
        mov r5,a
        mov a,r6
        rlc a
        mov r6,a
        ret
_mv_x_add_i_r23::
        mov a,r2
        add a,@r0
        mov r2,a
        mov a,r3
        inc r0
        addc a,@r0
        mov r3,a
        ret
_mv_x_neg_scmp_r67::
        clr c
        clr a
        subb a,r6
        mov a,#(0x00^0x80)
        mov b,r7
        ret
_mv_x_cmp_r67_100::
        clr c
        mov a,r6
        subb a,#0x64
        mov a,r7
        subb a,#0x00
        ret
_mv_x_add_ii4_r4567::
        mov a,@r1
        add a,@r0
        mov r4,a
        inc r1
        mov a,@r1
        inc r0
        addc a,@r0
        mov r5,a
        inc r1
        mov a,@r1
        inc r0
        addc a,@r0
        mov r6,a
        inc r1
        mov a,@r1
        inc r0
        addc a,@r0
        mov r7,a
        ret
_mv_x_sbc_i_r67::
        mov a,r6
        inc r0
        subb a,@r0
        mov r6,a
        mov a,r7
        inc r0
        subb a,@r0
        mov r7,a
        ret
_mv_x_orl_i3::
        inc r0
        orl a,@r0
        inc r0
        orl a,@r0
        inc r0
        orl a,@r0
        ret
_mv_x_sbc_r67_i::
        subb a,r6
        mov r6,a
        inc r0
        mov a,@r0
        subb a,r7
        mov r7,a
        ret
_mv_x_shr2_i::
        anl a,#0x03
        mov c,acc.0
        xch a,@r0
        rrc a
        xch a,@r0
        rrc a
        mov c,acc.0
        xch a,@r0
        rrc a
        xch a,@r0
        rrc a
        xch a,@r0
        inc r0
        mov @r0,a
        ret
_mv_x_sbc_r567_0::
        subb a,r5
        clr a
        subb a,r6
        clr a
        subb a,r7
        ret
_mv_x_add_a_r67::
        add a,r6
        mov r6,a
        clr a
        addc a,r7
        mov r7,a
        ret
_mv_x_cmp_r67_r45::
        clr c
        mov a,r6
        subb a,r4
        mov a,r7
        subb a,r5
        ret
_mv_x_addc_b_dph::
        addc a,b
        mov dph,a
        ret
_mv_x_sub_i_r4763::
        mov a,@r0
        clr c
        subb a,r4
        mov r4,a
        inc r0
        mov a,@r0
        subb a,r7
        mov r7,a
        inc r0
        mov a,@r0
        subb a,r6
        mov r6,a
        inc r0
        mov a,@r0
        subb a,r3
        mov r3,a
        ret
_mv_x_shl2_r45::
        mov c,acc.7
        xch a,r4
        rlc a
        xch a,r4
        rlc a
        mov c,acc.7
        xch a,r4
        rlc a
        xch a,r4
        rlc a
        xch a,r4
        anl a,#0x03
        mov r5,a
        ret
_mv_x_shl2_r67::
        mov c,acc.7
        xch a,r6
        rlc a
        xch a,r6
        rlc a
        mov c,acc.7
        xch a,r6
        rlc a
        xch a,r6
        rlc a
        xch a,r6
        anl a,#0x03
        mov r7,a
        ret
_mv_x_cmp_fp1_r3467::
        mov r0,_bp
        inc r0
        clr c
        mov a,r3
        subb a,@r0
        mov a,r4
        inc r0
        subb a,@r0
        mov a,r6
        inc r0
        subb a,@r0
        mov a,r7
        inc r0
        subb a,@r0
        ret
_mv_x_sbc_i3_0::
        subb a,@r0
        clr a
        inc r0
        subb a,@r0
        clr a
        inc r0
        subb a,@r0
        ret
_mv_x_rlc_r67::
        mov a,r6
        rlc a
        mov r6,a
        mov a,r7
        rlc a
        mov r7,a
        ret
    __endasm;
}
#endif

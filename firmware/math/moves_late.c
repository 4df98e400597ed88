/* moves_late.c: the shared copies of the z_ set of SDCC's moves (tools/share_moves.py, as moves.c). */
#include "compiler.h"

/*
 * As in moves.c: each routine _mv_NAME is exactly the instructions of share_moves.py's
 * MOVES["NAME"], then RET. The z_ set: the sequences the modules outside the
 * controllers still wrote out most often once every set before had been shared (a second pass
 * of the tool, after those), each used often enough to pay for its routine (DPTR from a pair of
 * locals, frame offsets, 16-bit loads, stores and sums, compares, shifts). None sets _bp or SP.
 * The host build has no such code.
 */
#if defined(__SDCC)
void mv_late_routines(void) __naked
{
    __asm
        ar3 = 0x03              ; bank 0 register addresses, as the modules calling them use them
        ar4 = 0x04
        ar5 = 0x05
        ar6 = 0x06
        ar7 = 0x07
_mv_z_ar_i2::
        mov dpl,@r0
        inc r0
        mov dph,@r0
        ret
_mv_z_mul_b2::
        mov b,#0x02
        mul ab
        ret
_mv_z_fp_r0_14::
        mov a,_bp
        add a,#0x14
        mov r0,a
        ret
_mv_z_sbc_i3_r67::
        inc r0
        subb a,@r0
        mov a,r6
        inc r0
        subb a,@r0
        mov a,r7
        inc r0
        subb a,@r0
        ret
_mv_z_neg_scmp_r23::
        clr c
        clr a
        subb a,r2
        mov a,#(0x00^0x80)
        mov b,r3
        ret
_mv_z_st_1a1a::
        inc dptr
        movx @dptr,a
        inc dptr
        movx @dptr,a
        ret
_mv_z_ar_r34::
        mov dpl,r3
        mov dph,r4
        ret
_mv_z_c_dpl::
        clr a
        rlc a
        mov dpl,a
        ret
_mv_z_rrc_r67::
        rrc a
        xch a,r6
        rrc a
        xch a,r6
        mov r7,a
        ret
_mv_z_sbc_0_r67::
        subb a,#0x00
        mov a,r6
        subb a,#0x00
        mov a,r7
        subb a,#0x00
        ret
_mv_z_ld_fp1_r34::
        mov r0,_bp
        inc r0
        mov ar3,@r0
        inc r0
        mov ar4,@r0
        ret
_mv_z_rv_r567a::
        mov r5,dph
        mov r6,b
        mov r7,a
        ret
_mv_z_fp_r1_09::
        mov a,_bp
        add a,#0x09
        mov r1,a
        ret
_mv_z_shl4_r45::
        swap a
        anl a,#0xf0
        xch a,r4
        swap a
        xch a,r4
        xrl a,r4
        xch a,r4
        anl a,#0xf0
        xch a,r4
        xrl a,r4
        mov r5,a
        ret
_mv_z_shr2_orl_i::
        mov a,r5
        rr a
        rr a
        anl a,#0x3f
        dec r0
        orl a,@r0
        mov @r0,a
        dec r0
        dec r0
        mov @r0,ar4
        mov a,r5
        ret
_mv_z_shl1_r23::
        mov a,r2
        add a,r2
        mov r2,a
        mov a,r3
        rlc a
        mov r3,a
        ret
_mv_z_ld_r5a::
        movx a,@dptr
        mov r5,a
        inc dptr
        movx a,@dptr
        ret
_mv_z_ar_r56::
        mov dpl,r5
        mov dph,r6
        ret
_mv_z_ar_r76::
        mov dpl,r7
        mov dph,r6
        ret
_mv_z_cld_r3a::
        clr a
        movc a,@a+dptr
        mov r3,a
        inc dptr
        clr a
        movc a,@a+dptr
        ret
_mv_z_sub_ii_r67::
        inc r1
        mov @r1,a
        inc r0
        mov a,@r0
        subb a,r6
        inc r1
        mov @r1,a
        inc r0
        mov a,@r0
        subb a,r7
        inc r1
        mov @r1,a
        ret
_mv_z_add_a_r45::
        add a,r4
        mov r4,a
        clr a
        addc a,r5
        mov r5,a
        ret
_mv_z_ld_r47::
        movx a,@dptr
        mov r4,a
        inc dptr
        movx a,@dptr
        mov r7,a
        ret
_mv_z_fp1_r7a::
        mov r7,a
        mov r0,_bp
        inc r0
        ret
_mv_z_sub_r67_r45::
        mov a,r6
        clr c
        subb a,r4
        mov r4,a
        mov a,r7
        subb a,r5
        mov r5,a
        ret
_mv_z_scmp_0_r2::
        clr c
        mov a,#(0x00^0x80)
        mov b,r2
        ret
_mv_z_cmp_ffff_r3456::
        clr c
        mov a,#0xff
        subb a,r3
        mov a,#0xff
        subb a,r4
        clr a
        subb a,r5
        clr a
        subb a,r6
        ret
_mv_z_st_a_r56::
        movx @dptr,a
        mov a,r5
        inc dptr
        movx @dptr,a
        mov a,r6
        inc dptr
        movx @dptr,a
        ret
_mv_z_shr1_r4::
        clr c
        rrc a
        xch a,r4
        rrc a
        xch a,r4
        ret
_mv_z_add_a_r23::
        add a,r2
        mov r2,a
        clr a
        addc a,r3
        mov r3,a
        ret
_mv_z_ld_ir4567_r1::
        mov ar4,@r1
        inc r1
        mov ar5,@r1
        inc r1
        mov ar6,@r1
        inc r1
        mov ar7,@r1
        ret
_mv_z_i3_clr::
        inc r0
        inc r0
        inc r0
        mov a,@r0
        clr c
        ret
_mv_z_fp_r0_0a::
        mov a,_bp
        add a,#0x0a
        mov r0,a
        ret
    __endasm;
}
#endif

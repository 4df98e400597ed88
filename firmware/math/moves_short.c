/* moves_short.c: the shared copies of SDCC's shorter moves (tools/share_moves.py, as moves.c). */
#include "compiler.h"

/*
 * As in moves.c: each routine _mv_NAME is exactly the instructions of share_moves.py's
 * MOVES["NAME"], then RET. These sequences are 4 to 15 bytes long (a register pair to or from
 * DPTR, 16-bit moves through @R0 and @R1, SDCC's signed compare, 32-bit sums and differences
 * with a local, carries, sign extensions, shifts by 4): each is here because it is used often
 * enough to pay for its routine. The host build has no such code.
 */
#if defined(__SDCC)
void mv_short_routines(void) __naked
{
    __asm
        ar2 = 0x02              ; bank 0 register addresses, as the modules calling them use them
        ar3 = 0x03
        ar4 = 0x04
        ar5 = 0x05
        ar6 = 0x06
        ar7 = 0x07
_mv_ar_r67::
        mov dpl,r6
        mov dph,r7
        ret
_mv_ar_r45::
        mov dpl,r4
        mov dph,r5
        ret
_mv_ar_r23::
        mov dpl,r2
        mov dph,r3
        ret
_mv_rv_r67::
        mov r6,dpl
        mov r7,dph
        ret
_mv_rv_r45::
        mov r4,dpl
        mov r5,dph
        ret
_mv_rv_r23::
        mov r2,dpl
        mov r3,dph
        ret
_mv_rv_r3456::
        mov r3,dpl
        mov r4,dph
        mov r5,b
        mov r6,a
        ret
_mv_st_i2::
        mov a,@r0
        movx @dptr,a
        inc r0
        mov a,@r0
        inc dptr
        movx @dptr,a
        ret
_mv_cp_ii2::
        mov @r1,a
        inc r0
        mov a,@r0
        inc r1
        mov @r1,a
        ret
_mv_ld_ir23::
        mov ar2,@r0
        inc r0
        mov ar3,@r0
        ret
_mv_ld_ir45::
        mov ar4,@r0
        inc r0
        mov ar5,@r0
        ret
_mv_ld_ir67::
        mov ar6,@r0
        inc r0
        mov ar7,@r0
        ret
_mv_st_ir23::
        mov @r0,ar2
        inc r0
        mov @r0,ar3
        ret
_mv_st_ir67::
        mov @r0,ar6
        inc r0
        mov @r0,ar7
        ret
_mv_st_ir3456::
        mov @r0,ar3
        inc r0
        mov @r0,ar4
        inc r0
        mov @r0,ar5
        inc r0
        mov @r0,ar6
        ret
_mv_ld_r56::
        movx a,@dptr
        mov r5,a
        inc dptr
        movx a,@dptr
        mov r6,a
        ret
_mv_st_r23::
        mov a,r2
        movx @dptr,a
        mov a,r3
        inc dptr
        movx @dptr,a
        ret
_mv_st_00::
        clr a
        movx @dptr,a
        inc dptr
        movx @dptr,a
        ret
_mv_ld_fp1a::
        mov r0,_bp
        inc r0
        mov a,@r0
        ret
_mv_r67_0::
        mov r6,#0x00
        mov r7,#0x00
        ret
_mv_inc_dptr5::
        inc dptr
        inc dptr
        inc dptr
        inc dptr
        inc dptr
        ret
_mv_scmp_b::
        xrl b,#0x80
        subb a,b
        ret
_mv_sub_i_r2367::
        mov a,@r0
        clr c
        subb a,r2
        mov r2,a
        inc r0
        mov a,@r0
        subb a,r3
        mov r3,a
        inc r0
        mov a,@r0
        subb a,r6
        mov r6,a
        inc r0
        mov a,@r0
        subb a,r7
        ret
_mv_add_i_r4567::
        mov a,@r0
        add a,r4
        mov r4,a
        inc r0
        mov a,@r0
        addc a,r5
        mov r5,a
        inc r0
        mov a,@r0
        addc a,r6
        mov r6,a
        inc r0
        mov a,@r0
        addc a,r7
        ret
_mv_adc_r67::
        clr a
        addc a,r6
        mov r6,a
        clr a
        addc a,r7
        mov r7,a
        ret
_mv_sext_r67::
        rlc a
        subb a,acc
        mov r6,a
        mov r7,a
        ret
_mv_shr4_r4::
        swap a
        xch a,r4
        swap a
        anl a,#0x0f
        xrl a,r4
        xch a,r4
        anl a,#0x0f
        xch a,r4
        xrl a,r4
        xch a,r4
        ret
_mv_shr4_r6::
        swap a
        xch a,r6
        swap a
        anl a,#0x0f
        xrl a,r6
        xch a,r6
        anl a,#0x0f
        xch a,r6
        xrl a,r6
        xch a,r6
        ret
    __endasm;
}
#endif

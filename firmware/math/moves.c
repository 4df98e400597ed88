/* moves.c: the shared copies of SDCC's long moves (tools/share_moves.py calls them in place of the sequences). */
#include "compiler.h"

/*
 * Each routine _mv_NAME is exactly the instructions share_moves.py's MOVES["NAME"] replaces,
 * then RET: the registers, DPTR, A and the flags end as the sequence left them. No C calls
 * them; the assembly of the firmware's modules does (the library archive links this module
 * where one is used). The host build has no such code.
 */
#if defined(__SDCC)
void mv_routines(void) __naked
{
    __asm
        ar4 = 0x04              ; bank 0 register addresses, as the modules calling them use them
        ar5 = 0x05
        ar6 = 0x06
        ar7 = 0x07
_mv_ld_i4::
        movx a,@dptr
        mov @r0,a
        inc dptr
        movx a,@dptr
        inc r0
        mov @r0,a
        inc dptr
        movx a,@dptr
        inc r0
        mov @r0,a
        inc dptr
        movx a,@dptr
        inc r0
        mov @r0,a
        ret
_mv_st_i4::
        mov a,@r0
        movx @dptr,a
        inc r0
        mov a,@r0
        inc dptr
        movx @dptr,a
        inc r0
        mov a,@r0
        inc dptr
        movx @dptr,a
        inc r0
        mov a,@r0
        inc dptr
        movx @dptr,a
        ret
_mv_ld_r4567::
        movx a,@dptr
        mov r4,a
        inc dptr
        movx a,@dptr
        mov r5,a
        inc dptr
        movx a,@dptr
        mov r6,a
        inc dptr
        movx a,@dptr
        mov r7,a
        ret
_mv_ld_r2367::
        movx a,@dptr
        mov r2,a
        inc dptr
        movx a,@dptr
        mov r3,a
        inc dptr
        movx a,@dptr
        mov r6,a
        inc dptr
        movx a,@dptr
        mov r7,a
        ret
_mv_ld_r2345::
        movx a,@dptr
        mov r2,a
        inc dptr
        movx a,@dptr
        mov r3,a
        inc dptr
        movx a,@dptr
        mov r4,a
        inc dptr
        movx a,@dptr
        mov r5,a
        ret
_mv_st_r4567::
        mov a,r4
        movx @dptr,a
        mov a,r5
        inc dptr
        movx @dptr,a
        mov a,r6
        inc dptr
        movx @dptr,a
        mov a,r7
        inc dptr
        movx @dptr,a
        ret
_mv_st_r2367::
        mov a,r2
        movx @dptr,a
        mov a,r3
        inc dptr
        movx @dptr,a
        mov a,r6
        inc dptr
        movx @dptr,a
        mov a,r7
        inc dptr
        movx @dptr,a
        ret
_mv_st_r2345::
        mov a,r2
        movx @dptr,a
        mov a,r3
        inc dptr
        movx @dptr,a
        mov a,r4
        inc dptr
        movx @dptr,a
        mov a,r5
        inc dptr
        movx @dptr,a
        ret
_mv_rrc_i3::
        rrc a
        mov @r0,a
        dec r0
        mov a,@r0
        rrc a
        mov @r0,a
        dec r0
        mov a,@r0
        rrc a
        mov @r0,a
        ret
_mv_addc_i67::
        mov a,r6
        inc r0
        addc a,@r0
        mov r6,a
        mov a,r7
        inc r0
        addc a,@r0
        mov r7,a
        ret
_mv_ar_i4a::
        mov r0,a
        mov dpl,@r0
        inc r0
        mov dph,@r0
        inc r0
        mov b,@r0
        inc r0
        mov a,@r0
        ret
_mv_st_a000::
        movx @dptr,a
        clr a
        inc dptr
        movx @dptr,a
        inc dptr
        movx @dptr,a
        inc dptr
        movx @dptr,a
        ret
_mv_rv_i4::
        mov @r0,dpl
        inc r0
        mov @r0,dph
        inc r0
        mov @r0,b
        inc r0
        mov @r0,a
        ret
_mv_cld_r67::
        clr a
        movc a,@a+dptr
        mov r6,a
        inc dptr
        clr a
        movc a,@a+dptr
        mov r7,a
        ret
_mv_ar_i4::
        mov dpl,@r0
        inc r0
        mov dph,@r0
        inc r0
        mov b,@r0
        inc r0
        mov a,@r0
        ret
_mv_st_ir4567::
        mov @r0,ar4
        inc r0
        mov @r0,ar5
        inc r0
        mov @r0,ar6
        inc r0
        mov @r0,ar7
        ret
_mv_st_1a00::
        inc dptr
        movx @dptr,a
        clr a
        inc dptr
        movx @dptr,a
        inc dptr
        movx @dptr,a
        ret
_mv_st_aaaa::
        movx @dptr,a
        inc dptr
        movx @dptr,a
        inc dptr
        movx @dptr,a
        inc dptr
        movx @dptr,a
        ret
_mv_ld_dptr::
        movx a,@dptr
        mov r6,a
        inc dptr
        movx a,@dptr
        mov dpl,r6
        mov dph,a
        ret
_mv_ld_r67::
        movx a,@dptr
        mov r6,a
        inc dptr
        movx a,@dptr
        mov r7,a
        ret
_mv_ld_r45::
        movx a,@dptr
        mov r4,a
        inc dptr
        movx a,@dptr
        mov r5,a
        ret
_mv_ld_r23::
        movx a,@dptr
        mov r2,a
        inc dptr
        movx a,@dptr
        mov r3,a
        ret
_mv_st_r67::
        mov a,r6
        movx @dptr,a
        mov a,r7
        inc dptr
        movx @dptr,a
        ret
_mv_st_r45::
        mov a,r4
        movx @dptr,a
        mov a,r5
        inc dptr
        movx @dptr,a
        ret
_mv_ld_fp1::
        mov r0,_bp
        inc r0
        mov dpl,@r0
        inc r0
        mov dph,@r0
        ret
_mv_rv_r4567::
        mov r4,dpl
        mov r5,dph
        mov r6,b
        mov r7,a
        ret
_mv_ar_r4567::
        mov dpl,r4
        mov dph,r5
        mov b,r6
        mov a,r7
        ret
_mv_gp_r67::
        mov r5,#0x80
        mov dpl,r6
        mov dph,r7
        mov b,r5
        ret
_mv_fp_r0_03::
        mov a,_bp
        add a,#0x03
        mov r0,a
        ret
_mv_fp_r0_04::
        mov a,_bp
        add a,#0x04
        mov r0,a
        ret
_mv_fp_r0_05::
        mov a,_bp
        add a,#0x05
        mov r0,a
        ret
_mv_fp_r0_07::
        mov a,_bp
        add a,#0x07
        mov r0,a
        ret
_mv_fp_r0_09::
        mov a,_bp
        add a,#0x09
        mov r0,a
        ret
_mv_fp_r0_0b::
        mov a,_bp
        add a,#0x0b
        mov r0,a
        ret
_mv_fp_r0_0d::
        mov a,_bp
        add a,#0x0d
        mov r0,a
        ret
_mv_fp_r0_0f::
        mov a,_bp
        add a,#0x0f
        mov r0,a
        ret
_mv_fp_r0_11::
        mov a,_bp
        add a,#0x11
        mov r0,a
        ret
_mv_fp_r0_fc::
        mov a,_bp
        add a,#0xfc
        mov r0,a
        ret
_mv_fp_r0_fd::
        mov a,_bp
        add a,#0xfd
        mov r0,a
        ret
_mv_fp_r1_05::
        mov a,_bp
        add a,#0x05
        mov r1,a
        ret
_mv_fp_r0_06::
        mov a,_bp
        add a,#0x06
        mov r0,a
        ret
_mv_fp_r0_13::
        mov a,_bp
        add a,#0x13
        mov r0,a
        ret
_mv_fp_r0_15::
        mov a,_bp
        add a,#0x15
        mov r0,a
        ret
    __endasm;
}
#endif

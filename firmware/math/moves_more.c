/* moves_more.c: the shared copies of SDCC's further moves (tools/share_moves.py, as moves.c). */
#include "compiler.h"

/*
 * As in moves.c: each routine _mv_NAME is exactly the instructions of share_moves.py's
 * MOVES["NAME"], then RET. The x_ set: the sequences the modules outside the
 * controllers still wrote out most often, each used often enough to pay for its routine
 * (register triples to and from DPTR, frame offsets, 16-bit loads and stores). The host build has no such code.
 */
#if defined(__SDCC)
void mv_more_routines(void) __naked
{
    __asm
        ar4 = 0x04              ; bank 0 register addresses, as the modules calling them use them
        ar5 = 0x05
        ar6 = 0x06
_mv_x_rv_r567::
        mov r5,dpl
        mov r6,dph
        mov r7,b
        ret
_mv_x_ar_r564::
        mov dpl,r5
        mov dph,r6
        mov b,r4
        ret
_mv_x_fp_r0_02::
        mov r0,_bp
        inc r0
        inc r0
        ret
_mv_x_ld_r45_add::
        movx a,@dptr
        mov r6,a
        inc dptr
        movx a,@dptr
        mov r4,a
        mov ar5,r6
        clr a
        mov r6,a
        mov r7,a
        mov a,#0xf0
        add a,r6
        mov r6,a
        mov a,#0x3f
        addc a,r7
        mov r7,a
        clr a
        addc a,r5
        mov r5,a
        clr a
        addc a,r4
        mov r4,a
        ret
_mv_x_fp_x05::
        xch a,r0
        mov a,_bp
        add a,#0x05
        xch a,r0
        ret
_mv_x_ar_r567::
        mov dpl,r5
        mov dph,r6
        mov b,r7
        ret
_mv_x_st_i00::
        inc r0
        mov @r0,#0x00
        inc r0
        mov @r0,#0x00
        ret
_mv_x_ld_r6a::
        movx a,@dptr
        mov r6,a
        inc dptr
        movx a,@dptr
        ret
_mv_x_fp1_st00::
        mov r0,_bp
        inc r0
        clr a
        mov @r0,a
        inc r0
        mov @r0,a
        ret
_mv_x_rv_r3467::
        mov r3,dpl
        mov r4,dph
        mov r6,b
        mov r7,a
        ret
_mv_x_mv_r45_r67::
        mov ar4,r6
        mov ar5,r7
        ret
_mv_x_st_r56::
        mov a,r5
        movx @dptr,a
        mov a,r6
        inc dptr
        movx @dptr,a
        ret
_mv_x_st_r34::
        mov a,r3
        movx @dptr,a
        mov a,r4
        inc dptr
        movx @dptr,a
        ret
_mv_x_ld_r2a::
        movx a,@dptr
        mov r2,a
        inc dptr
        movx a,@dptr
        ret
_mv_x_fp_r0_fa::
        mov a,_bp
        add a,#0xfa
        mov r0,a
        ret
_mv_x_rv_r56::
        mov r5,dpl
        mov r6,dph
        ret
_mv_x_st_1a010::
        inc dptr
        movx @dptr,a
        mov a,#0x01
        inc dptr
        movx @dptr,a
        clr a
        inc dptr
        movx @dptr,a
        ret
_mv_x_cld_r45::
        clr a
        movc a,@a+dptr
        mov r4,a
        inc dptr
        clr a
        movc a,@a+dptr
        mov r5,a
        ret
_mv_x_ld_i2::
        movx a,@dptr
        mov @r0,a
        inc dptr
        movx a,@dptr
        inc r0
        mov @r0,a
        ret
_mv_x_ld_r34::
        movx a,@dptr
        mov r3,a
        inc dptr
        movx a,@dptr
        mov r4,a
        ret
_mv_x_st_ir45::
        mov @r0,ar4
        inc r0
        mov @r0,ar5
        ret
    __endasm;
}
#endif

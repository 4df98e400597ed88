/* moves.c: the shared copies of SDCC's long moves (tools/share_moves.py calls them in place of the sequences). */
#include "compiler.h"

/*
 * Each routine is exactly the instructions share_moves.py replaces, then RET: the registers,
 * DPTR, A and the flags end as the sequence left them. No C calls them; the assembly of the
 * firmware's modules does (the library archive links this module where one is used). The
 * host build has no such code.
 */
#if defined(__SDCC)
void mv_ld_i4(void) __naked
{
    __asm
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
    __endasm;
}

void mv_st_i4(void) __naked
{
    __asm
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
    __endasm;
}

void mv_ld_r4567(void) __naked
{
    __asm
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
    __endasm;
}

void mv_ld_r2367(void) __naked
{
    __asm
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
    __endasm;
}

void mv_ld_r2345(void) __naked
{
    __asm
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
    __endasm;
}

void mv_st_r4567(void) __naked
{
    __asm
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
    __endasm;
}

void mv_st_r2367(void) __naked
{
    __asm
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
    __endasm;
}

void mv_st_r2345(void) __naked
{
    __asm
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
    __endasm;
}

void mv_ar_i4a(void) __naked
{
    __asm
        mov r0,a
        mov dpl,@r0
        inc r0
        mov dph,@r0
        inc r0
        mov b,@r0
        inc r0
        mov a,@r0
        ret
    __endasm;
}

void mv_st_a000(void) __naked
{
    __asm
        movx @dptr,a
        clr a
        inc dptr
        movx @dptr,a
        inc dptr
        movx @dptr,a
        inc dptr
        movx @dptr,a
        ret
    __endasm;
}

void mv_rv_i4(void) __naked
{
    __asm
        mov @r0,dpl
        inc r0
        mov @r0,dph
        inc r0
        mov @r0,b
        inc r0
        mov @r0,a
        ret
    __endasm;
}

void mv_cld_r67(void) __naked
{
    __asm
        clr a
        movc a,@a+dptr
        mov r6,a
        inc dptr
        clr a
        movc a,@a+dptr
        mov r7,a
        ret
    __endasm;
}

void mv_ar_i4(void) __naked
{
    __asm
        mov dpl,@r0
        inc r0
        mov dph,@r0
        inc r0
        mov b,@r0
        inc r0
        mov a,@r0
        ret
    __endasm;
}

void mv_st_ir4567(void) __naked
{
    __asm
        ar4 = 0x04              ; bank 0 register addresses, as the modules calling it use them
        ar5 = 0x05
        ar6 = 0x06
        ar7 = 0x07
        mov @r0,ar4
        inc r0
        mov @r0,ar5
        inc r0
        mov @r0,ar6
        inc r0
        mov @r0,ar7
        ret
    __endasm;
}

void mv_st_1a00(void) __naked
{
    __asm
        inc dptr
        movx @dptr,a
        clr a
        inc dptr
        movx @dptr,a
        inc dptr
        movx @dptr,a
        ret
    __endasm;
}

void mv_st_aaaa(void) __naked
{
    __asm
        movx @dptr,a
        inc dptr
        movx @dptr,a
        inc dptr
        movx @dptr,a
        inc dptr
        movx @dptr,a
        ret
    __endasm;
}

void mv_ld_r67(void) __naked
{
    __asm
        movx a,@dptr
        mov r6,a
        inc dptr
        movx a,@dptr
        mov r7,a
        ret
    __endasm;
}

void mv_ld_r45(void) __naked
{
    __asm
        movx a,@dptr
        mov r4,a
        inc dptr
        movx a,@dptr
        mov r5,a
        ret
    __endasm;
}

void mv_ld_r23(void) __naked
{
    __asm
        movx a,@dptr
        mov r2,a
        inc dptr
        movx a,@dptr
        mov r3,a
        ret
    __endasm;
}

void mv_st_r67(void) __naked
{
    __asm
        mov a,r6
        movx @dptr,a
        mov a,r7
        inc dptr
        movx @dptr,a
        ret
    __endasm;
}

void mv_st_r45(void) __naked
{
    __asm
        mov a,r4
        movx @dptr,a
        mov a,r5
        inc dptr
        movx @dptr,a
        ret
    __endasm;
}

void mv_rv_r4567(void) __naked
{
    __asm
        mov r4,dpl
        mov r5,dph
        mov r6,b
        mov r7,a
        ret
    __endasm;
}

void mv_ar_r4567(void) __naked
{
    __asm
        mov dpl,r4
        mov dph,r5
        mov b,r6
        mov a,r7
        ret
    __endasm;
}

void mv_fp_r0_03(void) __naked
{
    __asm
        mov a,_bp
        add a,#0x03
        mov r0,a
        ret
    __endasm;
}

void mv_fp_r0_04(void) __naked
{
    __asm
        mov a,_bp
        add a,#0x04
        mov r0,a
        ret
    __endasm;
}

void mv_fp_r0_05(void) __naked
{
    __asm
        mov a,_bp
        add a,#0x05
        mov r0,a
        ret
    __endasm;
}

void mv_fp_r0_07(void) __naked
{
    __asm
        mov a,_bp
        add a,#0x07
        mov r0,a
        ret
    __endasm;
}

void mv_fp_r0_09(void) __naked
{
    __asm
        mov a,_bp
        add a,#0x09
        mov r0,a
        ret
    __endasm;
}

void mv_fp_r0_0b(void) __naked
{
    __asm
        mov a,_bp
        add a,#0x0b
        mov r0,a
        ret
    __endasm;
}

void mv_fp_r0_0d(void) __naked
{
    __asm
        mov a,_bp
        add a,#0x0d
        mov r0,a
        ret
    __endasm;
}

void mv_fp_r0_0f(void) __naked
{
    __asm
        mov a,_bp
        add a,#0x0f
        mov r0,a
        ret
    __endasm;
}

void mv_fp_r0_11(void) __naked
{
    __asm
        mov a,_bp
        add a,#0x11
        mov r0,a
        ret
    __endasm;
}

void mv_fp_r0_fc(void) __naked
{
    __asm
        mov a,_bp
        add a,#0xfc
        mov r0,a
        ret
    __endasm;
}

void mv_fp_r0_fd(void) __naked
{
    __asm
        mov a,_bp
        add a,#0xfd
        mov r0,a
        ret
    __endasm;
}

void mv_fp_r1_05(void) __naked
{
    __asm
        mov a,_bp
        add a,#0x05
        mov r1,a
        ret
    __endasm;
}
#endif

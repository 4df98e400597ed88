/* divulong.c: SDCC's 32-bit unsigned divide (__divulong) for the large model, in registers. */
#include "compiler.h"

/*
 * SDCC calls __divulong for every uint32_t / and (its callers') remainder: x in DPL, DPH, B, A,
 * y in the XRAM parameter __divulong_PARM_2, x / y back in DPL, DPH, B, A. The library's
 * large-model routine is its C version: x, the remainder and the count in 9 more bytes of XRAM
 * for good, each of its 32 steps reading and writing them there. This is the library's own
 * shift-and-subtract of its small stack-auto model (the same quotient, bit for bit, and the
 * same 0xFFFFFFFF for y = 0), with y copied to R1 and the stack: the firmware's archive comes
 * before SDCC's libraries on the link line, so the image takes this one. tt_fixed checks its
 * quotients against the host's.
 */
void divulong_routine(void) __naked
{
    __asm
        .area XSEG (XDATA)
__divulong_PARM_2::
        .ds 4
        .area CSEG (CODE)
        ar0 = 0x00
        ar4 = 0x04
        ar5 = 0x05
__divulong::
        mov r3,a                ; x3 (x0 .. x2 stay in DPL, DPH, B)
        mov r4,dpl              ; DPTR reads y: x0, x1 aside
        mov r5,dph
        mov dptr,#__divulong_PARM_2
        movx a,@dptr
        mov r1,a                ; y0
        inc dptr
        movx a,@dptr
        push acc                ; y1
        inc dptr
        movx a,@dptr
        push acc                ; y2
        inc dptr
        movx a,@dptr
        push acc                ; y3
        mov dpl,r4
        mov dph,r5
        mov a,sp
        add a,#0xfe
        mov r0,a                ; R0 points to y1
        mov r2,#32              ; count
        clr a
        mov r4,a                ; the remainder, R7:R4
        mov r5,a
        mov r6,a
        mov r7,a
00001$:                         ; until the first 1 is shifted out of x
        mov a,dpl               ; x <<= 1
        add a,dpl
        mov dpl,a
        mov a,dph
        rlc a
        mov dph,a
        mov a,b
        rlc a
        mov b,a
        mov a,r3
        rlc a
        mov r3,a
        jc 00003$
        djnz r2,00001$
        sjmp 00005$
00002$:
        mov a,dpl               ; x <<= 1
        add a,dpl
        mov dpl,a
        mov a,dph
        rlc a
        mov dph,a
        mov a,b
        rlc a
        mov b,a
        mov a,r3
        rlc a
        mov r3,a
00003$:
        mov a,r4                ; remainder <<= 1, the bit from x fed in
        rlc a
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
        mov a,r4                ; remainder - y (the carry is clear: it never overflows)
        subb a,r1
        mov a,r5
        subb a,@r0
        mov a,r6
        inc r0
        subb a,@r0
        mov a,r7
        inc r0
        subb a,@r0
        dec r0
        dec r0
        jc 00004$               ; remainder >= y: subtract, a 1 into x
        mov a,r4
        subb a,r1
        mov r4,a
        mov a,r5
        subb a,@r0
        mov r5,a
        mov a,r6
        inc r0
        subb a,@r0
        mov r6,a
        mov a,r7
        inc r0
        subb a,@r0
        mov r7,a
        dec r0
        dec r0
        orl dpl,#1
00004$:
        djnz r2,00002$
00005$:
        dec sp                  ; y1 .. y3 off the stack
        dec sp
        dec sp
        mov a,r3
        ret
    __endasm;
}

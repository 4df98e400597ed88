/* sat16.c: fx_sat16 (fixed.h) in assembly on the 8051; the C reference is firmware/math/fixed.c. */
#include "fixed.h"

/* The saturating basic: it touches only A, B, DPTR and PSW, and fixed.h declares it __naked, so
 * a caller keeps its registers across the call. fx_add_sat and fx_sub_sat, in the same style,
 * are in addsub_sat.c (linked only where called). */
int16_t fx_sat16(int32_t x) __naked
{
    (void)x;
    __asm
        jb acc.7,00010$         ; x in dpl, dph, b, a (msb)
        orl a,b
        jnz 00011$              ; >= 65536: above the top
        mov a,dph
        jb acc.7,00011$         ; 32768 .. 65535: above the top
#if FX_SABOTAGE == 10
        orl dpl,#1              ; in range, made odd (wrong bits on purpose, mul.h)
#endif
        ret
00011$:
        mov dptr,#0x7fff
        ret
00010$:
        anl a,b
        cpl a
        jnz 00012$              ; < -65536: below the bottom
        mov a,dph
        jnb acc.7,00012$        ; -65536 .. -32769: below the bottom
        ret
00012$:
        mov dptr,#0x8000
        ret
    __endasm;
}

/* addsub_sat.c: fx_add_sat and fx_sub_sat (fixed.h) in assembly on the 8051; their C reference is firmware/math/fxops.c. */
#include "fixed.h"

int16_t fx_add_sat(int16_t a, int16_t b) __naked
{
    (void)a;
    (void)b;
    __asm
        mov b,dpl               ; a in dpl, dph; b in its xdata parameter
        push dph
        mov dptr,#_fx_add_sat_PARM_2
        movx a,@dptr
        add a,b
        mov b,a
        inc dptr
        movx a,@dptr
        mov dpl,b
        pop b
        addc a,b
        mov dph,a
        jnb ov,00020$
        jb acc.7,00021$         ; overflow: the sign flipped; negative means above the top
        mov dptr,#0x8000
        ret
00021$:
        mov dptr,#0x7fff
00020$:
        ret
    __endasm;
}

int16_t fx_sub_sat(int16_t a, int16_t b) __naked
{
    (void)a;
    (void)b;
    __asm
        mov b,dpl               ; a in dpl, dph; b in its xdata parameter
        push dph
        mov dptr,#_fx_sub_sat_PARM_2
        movx a,@dptr
        xch a,b
        clr c
        subb a,b
        mov b,a
        inc dptr
        movx a,@dptr
        mov dpl,b
        mov b,a
        pop acc
        subb a,b
        mov dph,a
        jnb ov,00030$
        jb acc.7,00031$
        mov dptr,#0x8000
        ret
00031$:
        mov dptr,#0x7fff
00030$:
        ret
    __endasm;
}

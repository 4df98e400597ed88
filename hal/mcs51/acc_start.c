/* acc_start.c: a multiply-accumulate's start on the 8051, a module of its own: linked only into the images whose controllers use it (bp_pid); the host's C is firmware/math/mul.c. */
#include "mul.h"

/* mul_acc = hi << 8: the rounding a sum starts from (ACC_START, mul.h) */
void acc_start(uint8_t hi) __naked
{
    hi;
    __asm
        mov (_mul_acc + 1),dpl
        clr a
        mov _mul_acc,a
        mov (_mul_acc + 2),a
        mov (_mul_acc + 3),a
        ret
    __endasm;
}

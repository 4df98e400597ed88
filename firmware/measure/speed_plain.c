/* speed_plain.c: whether the speed leads a change (speed.h speed_plain), as the flow controller asks. */
#include "compiler.h"
#include "speed.h"

/*
 * A module of its own: the controller sets the mode (a layer above, calling down), the wheel's
 * speed (speed.c) reads it, and a test of the controllers links it without the wheel and its HAL.
 */
__bit speed_plain;

void speed_set_plain(uint8_t plain) __reentrant
{
    if (plain)
        speed_plain = 1;
    else
        speed_plain = 0;
}

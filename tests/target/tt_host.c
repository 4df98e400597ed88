/* tt_host.c: the target tests' output on the host: stdout, no cycle counter. */
#include <stdio.h>
#include "tt.h"

void tt_putc(char c)
{
    putchar(c);
}

void tt_end(void)
{
    tt_puts("TT-END\n");
    fflush(stdout);
}

void tt_cycles_start(void)
{
}

uint32_t tt_cycles_stop(void)
{
    return 0;
}

uint8_t tt_on_target(void)
{
    return 0;
}

/* ctl_peer.c: what the peers (aog, raven) share: their dead bands and brake points on the target. */
#if defined(__SDCC)
#pragma stackauto           /* locals on the stack, not each its own XRAM (docs/MEMORY.md) */
#endif
#include "ctl_int.h"

/* The peers alone call this: a module of its own, linked only into the images that carry them
 * (the research image), not with the output stage bp_pid shares with pid. */
int16_t ctl_of_target(int16_t frac)
{
    return (int16_t)(MUL(ctl_in->target_lpm_x100, frac) >> 15);
}

/* ctl_out.c: the output stage pid, fuzzy_pid, bp_pid and the peers share: pulse accumulation, limits, clamps, D term. */
#if defined(__SDCC)
#pragma stackauto           /* locals on the stack, not each its own XRAM (docs/MEMORY.md) */
#endif
#include "ctl_int.h"

/*
 * The common output stage (pid, fuzzy_pid, bp_pid; ffmap has its own servo but the same limit
 * and end-stop rules, CTL_CLIP and CTL_STOP): the valve does not move below the break-away duty
 * (Min duty, 20 % by default), so increments smaller than that are accumulated and sent as one
 * pulse when they add up (pulse accumulation, as floating-valve controllers do): the valve gets
 * the movement the law asked for, later. Requests beyond full duty are cut (anti-windup: the
 * valve is the integrator, the excess is dropped, never stored), and nothing is asked or
 * accumulated against an end stop that valve_limit reports. The error clamp and du to drive,
 * which ffmap uses too, are ctl_drive.c's: an image with ffmap alone links none of this module.
 */

int16_t ctl_clamp16(int16_t x, int16_t lo, int16_t hi)
{
    return x < lo ? lo : x > hi ? hi : x;
}

int16_t ctl_d2(int16_t x, int16_t x1, int16_t x2)
{
    return fx_sat16((int32_t)x - 2 * (int32_t)x1 + x2);
}

q15_t ctl_out(int32_t d, uint8_t limit)
{
    d += ctl_carry;
    CTL_CLIP(d);
    CTL_STOP(d, limit, CTL_AT_CLOSED);
    if (d < CTL_STICTION && d > -CTL_STICTION) {
        ctl_carry = (q15_t)d;
        d = 0;
    } else {
        ctl_carry = 0;
    }
    ctl_last = (q15_t)d;
    return (q15_t)d;
}

/* ctl_out.c: the output stage the controllers share: error clamp, du to drive, pulse accumulation, limits. */
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
 * accumulated against an end stop that valve_limit reports.
 */

int16_t ctl_clamp_e(int16_t e)
{
    if (e > CTL_E_MAX)
        return CTL_E_MAX;
    if (e < -CTL_E_MAX)
        return -CTL_E_MAX;
    return e;
}

int16_t ctl_of_target(int16_t frac)
{
    return (int16_t)(MUL(ctl_in->target_lpm_x100, frac) >> 15);
}

int16_t ctl_clamp16(int16_t x, int16_t lo, int16_t hi)
{
    return x < lo ? lo : x > hi ? hi : x;
}

int32_t ctl_du_to_drive(int32_t du)
{
    int16_t s4 = fx_sat16((du + 128) >> 8);        /* du in Q4 */
    return (MUL(s4, ctl_kf) + 128) >> 8;
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

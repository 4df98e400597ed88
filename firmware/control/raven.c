/* raven.c: the valve logic of Raven's SCS consoles (a peer for comparison), from their valve calibration. */
#include "ctl_int.h"
#include "params.h"
#include "umath.h"

/*
 * Raven's valve calibration is a four-digit number (P_RAVEN_CAL), one digit each for
 *   backlash B  the length of the first correction pulse after the correction changes direction
 *               (1-9; 0: none, a fast valve's three-digit cal);
 *   speed S     standard valve 1 slow .. 9 fast; a fast valve 0 fast .. 9 slow;
 *   brake P     how far from the target the valve starts to turn slower (0 = 5 %, 1 = 10 % ..
 *               9 = 90 %), so as not to overshoot;
 *   dead band D the difference allowed, 1-9 %.
 * Raven recommends 2123 for a standard valve and 743 for a fast valve. Our reading:
 *  - a cal under 1000 (backlash digit 0, as 743) is a fast valve, the others standard;
 *  - the speed digit sets the drive of a correction beyond the brake point: (S + 1) / 10 of full
 *    duty for a standard valve (1 -> 0.2 .. 9 -> 1.0), (10 - S) / 10 for a fast one;
 *  - inside the brake point the drive falls with the error: speed x |e| / (brake x target);
 *  - within the dead band the valve is not driven;
 *  - the first correction after a change of direction gets B x 10 ms of full drive more (the
 *    backlash pulse), in the 100 ms period of its first drive;
 *  - the drive goes through the output stage the other controllers share (ctl_out.c): what is
 *    below the valve's Min duty is accumulated into one pulse, full duty and the end stops cut.
 */

void rv_derive(void)
{
    rv_state_t *r = &ctl_st.rv;
    uint16_t c = param_v[P_RAVEN_CAL];
    uint8_t b = (uint8_t)(c / 1000u), s = (uint8_t)(c / 100u % 10u), p = (uint8_t)(c / 10u % 10u);
    uint8_t d = (uint8_t)(c % 10u);
    r->fast = b == 0;
    r->speed = (int16_t)(3277u * (r->fast ? 10u - s : s + 1u));
    if (r->speed < 0)
        r->speed = 32767;           /* 10 x 3277 wraps: full duty */
    r->brake = (int16_t)(p ? 3277u * p : 1638u);
    r->band = (int16_t)(((uint32_t)d * 32768u + 50u) / 100u);
    r->pulse = (int16_t)(RV_PULSE_Q15 * b);
}

q15_t rv_step(void) CTL_SHARED
{
    rv_state_t *r = &ctl_st.rv;
    int16_t t = ctl_in->target_lpm_x100;
    int16_t e = ctl_clamp_e((int16_t)fx_sat16((int32_t)t - ctl_in->flow_lpm_x100));
    int16_t ae = e < 0 ? -e : e;
    int32_t m, bk;
    int8_t dir;

    ctl_first = 0;
    ctl_sat = 0;
    if (t <= 0 || (int32_t)ae <= (MUL(t, r->band) >> 15)) {
        ctl_carry = 0;              /* within the dead band: the valve is not driven */
        ctl_last = 0;
        return 0;
    }
    bk = MUL(t, r->brake) >> 15;
    m = r->speed;
    if ((int32_t)ae < bk)
        m = (int32_t)um_muldiv((uint32_t)ae, (uint16_t)r->speed, (uint32_t)bk);
    dir = e > 0 ? 1 : -1;
    if (dir != r->dir) {
        if (r->dir)
            m += r->pulse;          /* the backlash pulse */
        ctl_carry = 0;              /* a pulse the other way is not owed any more */
        r->dir = dir;
    }
    return ctl_out(dir > 0 ? m : -m, ctl_in->valve_limit);
}

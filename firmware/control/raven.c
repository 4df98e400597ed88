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

void rv_derive(void) CTL_SHARED
{
    static const __code uint16_t p10[3] = {1000u, 100u, 10u};
    static const __code int16_t band[10] = {0, 328, 655, 983, 1311, 1638, 1966, 2294, 2621, 2949};  /* d % */
    uint16_t c = param_v[P_RAVEN_CAL];
    uint8_t d[4], i;
    for (i = 0; i < 3u; i++)        /* the digits, without a divide */
        for (d[i] = 0; c >= p10[i]; d[i]++)
            c -= p10[i];
    d[3] = (uint8_t)c;
    ctl_st.rv.fast = d[0] == 0;
    c = 3277u * (ctl_st.rv.fast ? 10u - d[1] : d[1] + 1u);
    ctl_st.rv.speed = c > 32767u ? 32767 : (int16_t)c;     /* 10 x 3277: full duty */
    ctl_st.rv.brake = (int16_t)(d[2] ? 3277u * d[2] : 1638u);
    ctl_st.rv.band = band[d[3]];
    ctl_st.rv.pulse = (int16_t)(RV_PULSE_Q15 * d[0]);
}

q15_t rv_step(void) CTL_SHARED
{
    int16_t t = ctl_in->target_lpm_x100;
    int16_t e = ctl_clamp_e((int16_t)fx_sat16((int32_t)t - ctl_in->flow_lpm_x100));
    int16_t ae = e < 0 ? -e : e;
    int32_t m;
    int16_t bk;
    int8_t dir;

    if (ctl_first)                  /* (re)started: from rest */
        ctl_st.rv.dir = 0;
    ctl_first = 0;
    ctl_sat = 0;
    if (t <= 0 || ae <= ctl_of_target(ctl_st.rv.band)) {
        ctl_carry = 0;              /* within the dead band: the valve is not driven */
        ctl_last = 0;
        return 0;
    }
    bk = ctl_of_target(ctl_st.rv.brake);
    m = ctl_st.rv.speed;
    if (ae < bk)
        m = (int32_t)um_muldiv((uint32_t)ae, (uint16_t)ctl_st.rv.speed, (uint32_t)bk);
    dir = e > 0 ? 1 : -1;
    if (dir != ctl_st.rv.dir) {
        if (ctl_st.rv.dir)
            m += ctl_st.rv.pulse;          /* the backlash pulse */
        ctl_carry = 0;              /* a pulse the other way is not owed any more */
        ctl_st.rv.dir = dir;
    }
    return ctl_out(dir > 0 ? m : -m, ctl_in->valve_limit);
}

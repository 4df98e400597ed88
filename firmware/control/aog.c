/* aog.c: AgOpenGPS Rate Control's valve loop (a peer for comparison), from its published description. */
#include "ctl_int.h"
#include "params.h"

/*
 * The open-source AgOpenGPS Rate Control module, valve mode, as its documentation describes it:
 * every 50 ms, error = target - actual limited to +-target; outside a 4 % dead band the
 * integral accumulates ki x error and the output is
 *     min PWM + kp x SF x error + integral + kd x (last actual - actual),
 * its magnitude held between min PWM and max PWM x SF, the sign kept; SF = 1 beyond the 20 %
 * brake point and 0.75 inside it; inside the dead band the valve is not driven.
 * Our reading, where the description leaves a choice:
 *  - min PWM carries the error's sign (added unsigned it would drive a small negative error
 *    the wrong way); the output's sign is the sum's (the error's when the sum is 0);
 *  - the settings are the user's, in AgOpenGPS's units: PWM counts of 255, errors in L/min of
 *    boom flow, gains per 50 ms loop. This loop runs every 100 ms (APP_PERIOD_MS), so each
 *    period counts as two of AgOpenGPS's loops: the integral adds 2 ki x error, and the
 *    derivative, whose flow change spans two loops, is kd / 2 of it; a drive held for 100 ms
 *    moves the valve as two 50 ms loops with the same drive do;
 *  - the integral is held within +-max PWM (anti-windup, which the description does not
 *    mention; without it the integral of a valve at its end stop grows without bound);
 *  - the drive goes through the output stage the other controllers share (ctl_out.c): what is
 *    below the valve's Min duty is accumulated into one pulse, full duty and the end stops cut.
 */

/* (v * m + d / 2) / d, the settings' scaling */
static int16_t ag_scale(uint16_t v, uint16_t m, uint16_t d) CTL_SHARED
{
    return (int16_t)(((uint32_t)v * m + d / 2u) / d);
}

/* The settings to Q formats (once a parameter changes, ctl.c): 255 counts = 32767; kp in Q7,
 * ki in Q8 of the integral's Q23 a period (twice the 50 ms loop's), kd in Q8 (half the loop's). */
void ag_derive(void) CTL_SHARED
{
    ctl_st.ag.kp = ag_scale(param_v[P_AOG_KP], 16448u, 1000u);     /* 32767 * 128 / 255 / 1000 */
    ctl_st.ag.ki = ag_scale(param_v[P_AOG_KI], 32896u, 5000u);     /* 2 * 32767 * 256 / 255 / 10000 */
    ctl_st.ag.kd = ag_scale(param_v[P_AOG_KD], 16448u, 1000u);     /* 32767 * 256 / 255 / 2000 */
    ctl_st.ag.min = ag_scale(param_v[P_AOG_MIN], 32767u, 255u);
    ctl_st.ag.max = ag_scale(param_v[P_AOG_MAX], 32767u, 255u);
    if (ctl_st.ag.max < ctl_st.ag.min)
        ctl_st.ag.max = ctl_st.ag.min;
}

q15_t ag_step(void) CTL_SHARED
{
    int16_t t = ctl_in->target_lpm_x100, y = ctl_in->flow_lpm_x100;
    int16_t e, v, lim;
    int32_t o;
    uint8_t far, neg;

    if (t < 0)
        t = 0;
    e = ctl_clamp16(ctl_clamp_e((int16_t)fx_sat16((int32_t)t - y)), -t, t);
    if (ctl_first) {                /* (re)started: from rest */
        ctl_st.ag.y1 = y;
        ctl_st.ag.integ = 0;
        ctl_first = 0;
    }
    v = e < 0 ? -e : e;
    ctl_sat = 0;
    if (t == 0 || v <= ctl_of_target(AG_DB_Q15)) {
        ctl_st.ag.y1 = y;           /* inside the dead band: the valve is not driven */
        ctl_carry = 0;
        ctl_last = 0;
        return 0;
    }
    far = v > ctl_of_target(AG_BRAKE_Q15);
    lim = ctl_st.ag.max;
    o = ctl_st.ag.integ + MUL(e, ctl_st.ag.ki);
    if (o > ((int32_t)lim << 8))
        o = (int32_t)lim << 8;
    if (o < -((int32_t)lim << 8))
        o = -((int32_t)lim << 8);
    ctl_st.ag.integ = o;
    o = MUL(e, ctl_st.ag.kp);
    if (!far) {
        o -= o >> 2;                /* SF 0.75 inside the brake point */
        lim -= lim >> 2;
    }
    o = (o >> 7) + (ctl_st.ag.integ >> 8) + (MUL(fx_sat16((int32_t)ctl_st.ag.y1 - y), ctl_st.ag.kd) >> 8);
    ctl_st.ag.y1 = y;
    o += e > 0 ? ctl_st.ag.min : -ctl_st.ag.min;
    v = fx_sat16(o);
    if (v < -32767)
        v = -32767;
    neg = v < 0 || (v == 0 && e < 0);   /* the sign kept (the error's when the sum is 0) */
    if (neg)
        v = -v;
    if (v < ctl_st.ag.min)
        v = ctl_st.ag.min;
    if (v > lim)
        v = lim;
    return ctl_out(neg ? -v : v, ctl_in->valve_limit);
}

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

/* The settings to Q formats (once a parameter changes, ctl.c): 255 counts = 32767; kp in Q7,
 * ki in Q8 of the integral's Q23 a period (twice the 50 ms loop's), kd in Q8 (half the loop's). */
void ag_derive(void)
{
    ag_state_t *a = &ctl_st.ag;
    a->kp = (int16_t)(((uint32_t)param_v[P_AOG_KP] * 16448u + 500u) / 1000u);   /* 32767 * 128 / 255 / 1000 */
    a->ki = (int16_t)(((uint32_t)param_v[P_AOG_KI] * 65791u + 5000u) / 10000u); /* 2 * 32767 * 256 / 255 / 10000 */
    a->kd = (int16_t)(((uint32_t)param_v[P_AOG_KD] * 16448u + 500u) / 1000u);   /* 32767 * 256 / 255 / 2000 */
    a->min = (int16_t)(((uint32_t)param_v[P_AOG_MIN] * 32767u + 127u) / 255u);
    a->max = (int16_t)(((uint32_t)param_v[P_AOG_MAX] * 32767u + 127u) / 255u);
    if (a->max < a->min)
        a->max = a->min;
}

q15_t ag_step(void) CTL_SHARED
{
    ag_state_t *a = &ctl_st.ag;
    int16_t t = ctl_in->target_lpm_x100, y = ctl_in->flow_lpm_x100;
    int16_t e, ae, lim;
    int32_t o, p, top;
    uint8_t far;

    if (t < 0)
        t = 0;
    e = ctl_clamp16(ctl_clamp_e((int16_t)fx_sat16((int32_t)t - y)), -t, t);
    if (ctl_first) {
        a->y1 = y;
        ctl_first = 0;
    }
    ae = e < 0 ? -e : e;
    ctl_sat = 0;
    if ((int32_t)ae <= (MUL(t, AG_DB_Q15) >> 15)) {
        a->y1 = y;                  /* inside the dead band: the valve is not driven */
        ctl_carry = 0;
        ctl_last = 0;
        return 0;
    }
    far = (int32_t)ae > (MUL(t, AG_BRAKE_Q15) >> 15);
    top = (int32_t)a->max << 8;
    a->integ += MUL(e, a->ki);
    if (a->integ > top)
        a->integ = top;
    if (a->integ < -top)
        a->integ = -top;
    p = MUL(e, a->kp);
    if (!far)
        p -= p >> 2;                /* SF 0.75 inside the brake point */
    o = (p >> 7) + (a->integ >> 8) + (MUL(fx_sat16((int32_t)a->y1 - y), a->kd) >> 8);
    o += e > 0 ? a->min : -a->min;
    a->y1 = y;
    lim = far ? a->max : a->max - (a->max >> 2);
    if (o == 0)
        o = e > 0 ? 1 : -1;
    if (o > 0) {
        if (o < a->min)
            o = a->min;
        if (o > lim)
            o = lim;
    } else {
        if (o > -a->min)
            o = -a->min;
        if (o < -lim)
            o = -lim;
    }
    return ctl_out(o, ctl_in->valve_limit);
}

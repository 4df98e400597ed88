/* aog.c: the valve PID of SK21's RateControl module, as AgOpenGPS users run it (a peer for comparison; docs/PEERS.md names the release and files). */
#include "ctl_int.h"
#include "params.h"
#include "umath.h"

/*
 * The module's valve loop (PIDvalve), every PID time (150 ms by default):
 *   reference = the highest target since the loop started (closing sections keeps the gain);
 *   error = target - actual; the integral is cleared when the error crosses to the other side
 *   of the target beyond the dead band; within the dead band (1.5 % of the target) no drive and
 *   no integral; else, the error limited to +-target, f = error / reference, authority = max
 *   PWM - min PWM, and with "near" = |f| within the brake point:
 *     near: integral += f x Ki x authority (at most MaxIntegral a run), held within +-authority;
 *     change = f x Kp x (near ? slow adjust : 1) x authority + integral;
 *     drive = sign(change) x (|change| + min PWM) held within min .. max PWM (0 when |change|
 *     is under 0.1 count).
 * Kp and Ki as the app sets them (the module divides by 100). Our reading where it leaves a
 * choice: this loop runs every 100 ms (APP_PERIOD_MS) where the module's default is 150 ms; the
 * drive is a level the module holds between its runs, so only the integral's step (and its
 * limit of 25 counts a run) is scaled by 100 / 150. The drive goes through the output stage the
 * other controllers share (ctl_out.c).
 */

/* Each derived setting: (setting x m + d / 2) / d, into ag_state_t's kp, ki, min, max, brake,
 * kps (the slow adjust's Q15, then made kp x it) in that order */
static const __code uint8_t ag_id[6] = {P_AOG_KP, P_AOG_KI, P_AOG_MIN, P_AOG_MAX, P_AOG_BRAKE, P_AOG_SLOW};
static const __code uint16_t ag_m[6] = {2048u, 2048u, 32767u, 32767u, 32768u, 32767u};
static const __code uint16_t ag_d[6] = {100u, 150u, 255u, 255u, 1000u, 100u};

/* The settings in Q formats (once a parameter changes, ctl.c) */
void ag_derive(void) CTL_SHARED
{
    uint8_t i;
    uint16_t d;
    int16_t *q = &ctl_st.ag.kp;
    for (i = 0; i < 6u; i++) {
        d = ag_d[i];
        *q++ = (int16_t)((UMUL(param_v[ag_id[i]], ag_m[i]) + (d >> 1)) / d);
    }
    ctl_st.ag.kps = (int16_t)((MUL(ctl_st.ag.kp, ctl_st.ag.kps) + 16384) >> 15);
    if (ctl_st.ag.max < ctl_st.ag.min)
        ctl_st.ag.max = ctl_st.ag.min;
}

/* |e| x authority x k (Q11) / reference: Q15 duty, with its sign (one rounding) */
static int32_t ag_gain(int16_t e, int16_t k) CTL_SHARED
{
    uint32_t m = um_muldiv(UMUL(e < 0 ? -e : e, ctl_st.ag.max - ctl_st.ag.min), (uint16_t)k,
                           (uint32_t)ctl_st.ag.ref << 11);
    return e < 0 ? -(int32_t)m : (int32_t)m;
}

/* no drive: the valve rests, nothing kept back */
static q15_t ag_rest(void) CTL_SHARED
{
    ctl_carry = 0;
    ctl_last = 0;
    return 0;
}

q15_t ag_step(void) CTL_SHARED
{
    int16_t t = ctl_in->target_lpm_x100, e, band;
    int32_t c;
    uint8_t near;

    if (t <= 0 || ctl_first) {      /* (re)started, or nothing to spray: from rest */
        ctl_st.ag.integ = 0;
        ctl_st.ag.ref = 0;
        ctl_st.ag.pos = 1;
        ctl_first = 0;
    }
    if (t > ctl_st.ag.ref)
        ctl_st.ag.ref = t;
    e = (int16_t)fx_sat16((int32_t)t - ctl_in->flow_lpm_x100);
    band = ctl_of_target(AG_DB_Q15);
    if ((e > band && !ctl_st.ag.pos) || (e < -band && ctl_st.ag.pos)) {
        ctl_st.ag.pos ^= 1;         /* past the target beyond the dead band: the integral cleared */
        ctl_st.ag.integ = 0;
    }
    ctl_sat = 0;
    if (t <= 0 || (e <= band && e >= -band)) {
        ctl_st.ag.integ = 0;        /* inside the dead band: the valve is not driven */
        return ag_rest();
    }
    e = ctl_clamp16(e, -t, t);
    /* |f| = |e| / reference (|e| <= target <= reference) within the brake point (one UMUL an
     * expression, mul.h) */
    c = (int32_t)UMUL(ctl_st.ag.brake, ctl_st.ag.ref);
    near = UMUL(e < 0 ? -e : e, 32768u) <= (uint32_t)c;
    if (near) {
        c = ag_gain(e, ctl_st.ag.ki);
        c = ctl_clamp16((int16_t)fx_sat16(c), -AG_MAXI_Q15, AG_MAXI_Q15) + (int32_t)ctl_st.ag.integ;
        ctl_st.ag.integ = ctl_clamp16((int16_t)fx_sat16(c), (int16_t)(ctl_st.ag.min - ctl_st.ag.max),
                                      (int16_t)(ctl_st.ag.max - ctl_st.ag.min));
    }
    if (!ctl_st.ag.ki)
        ctl_st.ag.integ = 0;
    c = ag_gain(e, near ? ctl_st.ag.kps : ctl_st.ag.kp) + ctl_st.ag.integ;
    if (c < AG_ZERO_Q15 && c > -AG_ZERO_Q15)
        return ag_rest();
    e = (int16_t)fx_sat16((c < 0 ? -c : c) + ctl_st.ag.min);
    e = ctl_clamp16(e, ctl_st.ag.min, ctl_st.ag.max);
    return ctl_out(c < 0 ? -e : e, ctl_in->valve_limit);
}

/* pid.c: pid (the paper's eq. (7)) and fuzzy_pid (the classic self-tuning fuzzy PID), one law. */
#include "ctl_int.h"

/* ---- pid: eq. (7) ------------------------------------------------------------------------- */
/* du of eq. (7) with the gains of ctl_k (Q12) and the history of pid (fuzzy_pid has the same
 * layout); e, e1, e2 in x100 L/min. Shifts the history. */
static int32_t pid_law(int16_t e) CTL_SHARED
{
    int16_t d2e = ctl_d2(e, ctl_st.pid.e1, ctl_st.pid.e2);
    int16_t de = (int16_t)(e - ctl_st.pid.e1);      /* |e| <= CTL_E_MAX: no overflow */
    int32_t du = MUL(ctl_k[0], de);
    du += MUL(ctl_k[1], e);
    du += MUL(ctl_k[2], d2e);
    ctl_st.pid.e2 = ctl_st.pid.e1;
    ctl_st.pid.e1 = e;
    return du;
}

q15_t pid_step(void) CTL_SHARED
{
    int16_t e = ctl_clamp_e(ctl_in->target_lpm_x100 - ctl_in->flow_lpm_x100);
    int32_t du;

    if (ctl_first) {
        ctl_st.pid.e1 = e;
        ctl_st.pid.e2 = e;
        ctl_first = 0;
    }
    ctl_k[0] = PID_KP;
    ctl_k[1] = PID_KI;
    ctl_k[2] = PID_KD;
    du = pid_law(e);
    return ctl_out(ctl_du_to_drive(du), ctl_in->valve_limit);
}

/* ---- fuzzy_pid: the classic self-tuning fuzzy PID ----------------------------------------
 * Error e and its change ec, each on seven levels NB NM NS ZO PS PM PB (-3..3) with triangular
 * memberships; product inference and singleton outputs, so the centroid is the bilinear blend
 * of the four active rules (the weights add up to 1: no divide). */
#define NB -3
#define NM -2
#define NS -1
#define ZO 0
#define PS 1
#define PM 2
#define PB 3
const __code int8_t fz_tab[3][7][7] = {
    {   /* dKp */
        {PB, PB, PM, PM, PS, ZO, ZO}, {PB, PB, PM, PS, PS, ZO, NS}, {PM, PM, PM, PS, ZO, NS, NS},
        {PM, PM, PS, ZO, NS, NM, NM}, {PS, PS, ZO, NS, NS, NM, NM}, {PS, ZO, NS, NM, NM, NM, NB},
        {ZO, ZO, NM, NM, NM, NB, NB}},
    {   /* dKi */
        {NB, NB, NM, NM, NS, ZO, ZO}, {NB, NB, NM, NS, NS, ZO, ZO}, {NB, NM, NS, NS, ZO, PS, PS},
        {NM, NM, NS, ZO, PS, PM, PM}, {NM, NS, ZO, PS, PS, PM, PB}, {ZO, ZO, PS, PS, PM, PB, PB},
        {ZO, ZO, PS, PM, PM, PB, PB}},
    {   /* dKd */
        {PS, NS, NB, NB, NB, NM, PS}, {PS, NS, NB, NM, NM, NS, ZO}, {ZO, NS, NM, NM, NS, NS, ZO},
        {ZO, NS, NS, NS, NS, NS, ZO}, {ZO, ZO, ZO, ZO, ZO, ZO, ZO}, {PB, NS, PS, PS, PS, PS, PB},
        {PB, PM, PM, PM, PS, PS, PB}},
};

/* Level position of x (x100 L/min) at `unit` per level, Q8, 0 .. 6*256 (NB .. PB). */
static uint16_t fz_level(int16_t x, int16_t unit) CTL_SHARED
{
    int32_t q = ctl_clamp16(x, -3 * unit, 3 * unit);
    int16_t l;
    /* x * 256 / unit without a divide: unit is 100 or 50 -> x * 2.56 or 5.12, Q16 constants */
    if (unit == FZ_E_LEVEL)
        l = (int16_t)((q * 167772L + 32768L) >> 16);    /* 2.56 * 65536 */
    else
        l = (int16_t)((q * 335544L + 32768L) >> 16);    /* 5.12 * 65536 */
    l += 3 * 256;
    if (l < 0)
        l = 0;
    if (l > 6 * 256)
        l = 6 * 256;
    return (uint16_t)l;
}

q15_t fz_step(void) CTL_SHARED
{
    int16_t e = ctl_clamp_e(ctl_in->target_lpm_x100 - ctl_in->flow_lpm_x100);
    uint16_t le, lc;
    uint8_t i, j, t;
    uint16_t fe, fc;
    int16_t r0, r1;
    int32_t d;
    static const __code int16_t k0[3] = {PID_KP, PID_KI, PID_KD};
    static const __code int16_t qk[3] = {FZ_QP, FZ_QI, FZ_QD};

    if (ctl_first) {
        ctl_st.fz.e1 = e;
        ctl_st.fz.e2 = e;
        ctl_first = 0;
    }
    le = fz_level(e, FZ_E_LEVEL);
    lc = fz_level((int16_t)(e - ctl_st.fz.e1), FZ_EC_LEVEL);
    i = (uint8_t)(le >> 8);
    fe = le & 255u;
    if (i == 6) {                   /* PB itself: the last interval at its end */
        i = 5;
        fe = 256;
    }
    j = (uint8_t)(lc >> 8);
    fc = lc & 255u;
    if (j == 6) {
        j = 5;
        fc = 256;
    }
    for (t = 0; t < 3; t++) {
        /* blend along ec on rows i and i+1, then along e: level in Q16 */
        r0 = (int16_t)fz_tab[t][i][j] * (int16_t)(256 - fc) + (int16_t)fz_tab[t][i][j + 1] * (int16_t)fc;
        r1 = (int16_t)fz_tab[t][i + 1][j] * (int16_t)(256 - fc) + (int16_t)fz_tab[t][i + 1][j + 1] * (int16_t)fc;
        d = MUL(r0, (int16_t)(256 - fe)) + MUL(r1, (int16_t)fe);    /* level, Q16 */
        d = (MUL(fx_sat16((d + 128) >> 8), qk[t]) + 128) >> 8;  /* Q12 gain change */
        ctl_k[t] = fx_sat16(k0[t] + d);
        if (ctl_k[t] < 0)
            ctl_k[t] = 0;
    }
    d = pid_law(e);
    return ctl_out(ctl_du_to_drive(d), ctl_in->valve_limit);
}

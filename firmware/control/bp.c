/* bp.c: bp_pid, the paper's neural network tuning the PID gains, its work spread over BP_PHASES periods. */
#include "ctl_int.h"

/*
 * The paper's network: inputs target, measured flow, error and a bias; 5 tanh hidden nodes;
 * kp, ki, kd = (1 + tanh)/2 of 3 outputs; cost E = e^2 / 2; gradients through the incremental
 * law with sgn(dy/du) = +1; eta 0.2, momentum 0.05; weights from a seeded xorshift16. Deviations
 * for a real plant and a small CPU: normalised inputs, bounded weights (BP_WMAX), an 8-bit
 * momentum memory, learning frozen at a limit or stop, and the work spread over BP_PHASES
 * periods. docs/CONTROLLERS.md has each one and why.
 */
static uint16_t bp_rng;

static uint16_t bp_rand(void)
{
    bp_rng ^= (uint16_t)(bp_rng << 7);
    bp_rng ^= (uint16_t)(bp_rng >> 9);
    bp_rng ^= (uint16_t)(bp_rng << 8);
    return bp_rng;
}

void bp_init(void)
{
    uint8_t i, j;
    bp_rng = BP_SEED;
    for (i = 0; i < BP_HID; i++)
        for (j = 0; j < BP_IN; j++) {
            ctl_st.bp.w[i][j] = (int16_t)(bp_rand() & 0x0FFFu) - 2048;
            ctl_st.bp.dw[i][j] = 0;
        }
    for (i = 0; i < BP_OUT; i++)
        for (j = 0; j < BP_HID; j++) {
            ctl_st.bp.v[i][j] = (int16_t)(bp_rand() & 0x0FFFu) - 2048;
            ctl_st.bp.dv[i][j] = 0;
        }
    for (i = 0; i < BP_OUT; i++)
        ctl_st.bp.k[i] = 16384;     /* g(0) = 0.5 until the first forward pass */
    ctl_st.bp.phase = 0;
}

/* One row of weights: w += eta*delta*input + momentum, bounded; dw keeps the change made.
 * layer 0: output row `row` (inputs: the hidden outputs, Q15); 1: hidden row (inputs x, Q12).
 * 16-bit arithmetic wherever the ranges allow it (|w| <= BP_WMAX, |momentum| <= 8), one
 * 16x16 multiply a weight, pointers walked: ~300 machine cycles a weight. */
static void bp_upd_row(uint8_t layer, uint8_t row, int16_t eg) CTL_SHARED
{
    uint8_t n;
    int16_t d, mom, w0, nw, dd;
    /* in direct RAM: the large model would give these 10 B of the nearly full XRAM */
    static __data int32_t p;
    static __xdata int16_t *__data w, *__data xin;
    static __xdata int8_t *__data dw;
    if (layer) {
        n = BP_IN;
        w = &ctl_st.bp.w[row][0];
        dw = &ctl_st.bp.dw[row][0];
        xin = ctl_st.bp.x;
    } else {
        n = BP_HID;
        w = &ctl_st.bp.v[row][0];
        dw = &ctl_st.bp.dv[row][0];
        xin = ctl_st.bp.oh;
    }
    while (n--) {
        p = MUL(eg, *xin++);
        if (layer) {
            p = (p + 2048) >> 12;
            d = p > 32767 ? 32767 : p < -32768L ? -32768 : (int16_t)p;
        } else {
            d = (int16_t)((p + 16384) >> 15);
        }
        mom = *dw;
        mom = (int16_t)((mom >> 4) - (mom >> 6) + (mom >> 8));   /* alpha * dw, 0.0508 */
        if (mom > 0 && d > 32767 - mom)
            d = 32767;
        else if (mom < 0 && d < -32767 - 1 - mom)
            d = -32768;
        else
            d += mom;
        w0 = *w;
        if (d >= 0)
            nw = w0 > BP_WMAX - d ? BP_WMAX : w0 + d;
        else
            nw = w0 < -BP_WMAX - d ? -BP_WMAX : w0 + d;
        dd = nw > w0 + 127 ? 127 : nw < w0 - 127 ? -127 : nw - w0;
        *w++ = nw;
        *dw++ = (int8_t)dd;
    }
}

/* ---- the control step, in named steps (each inlined into bp_step) ------------------------- */

/* Forward: the hidden layer on phase 0, the output layer (new gains) on phase 1; the gains
 * are held in between. n: the normalised error (Q12). */
CTL_STEP void bp_forward(int16_t n) CTL_SHARED
{
    __xdata bp_state_t *b = &ctl_st.bp;
    __xdata int16_t *x = b->xs;     /* Q12 */
    __xdata int16_t *wp;
    int16_t eg;
    uint8_t i;
    if (b->phase == 0) {
        x[0] = 4096;
        x[1] = (int16_t)((MUL(ctl_clamp16(ctl_in->target_lpm_x100, 0, CTL_E_MAX), BP_Q_NORM) + 16384) >> 15);
        x[2] = (int16_t)((MUL(ctl_clamp16(ctl_in->flow_lpm_x100, 0, CTL_E_MAX), BP_Q_NORM) + 16384) >> 15);
        x[3] = n;
        wp = &b->w[0][0];
        for (i = 0; i < BP_HID; i++) {
            mul_acc = 2048;             /* rounding of the >> 12 */
            DOT(wp, x, BP_IN);
            wp += BP_IN;
            b->o[i] = fx_tanh(fx_sat16(mul_acc >> 12));
        }
    } else if (b->phase == 1) {
        wp = &b->v[0][0];
        for (i = 0; i < BP_OUT; i++) {
            mul_acc = 16384;
            DOT(wp, b->o, BP_HID);
            wp += BP_HID;
            /* (1 + tanh)/2 rounded, saturated (fx_sigmoid, inlined): (32769 + t) >> 1 in 16 bits */
            eg = fx_tanh(fx_sat16(mul_acc >> 15));
            b->k[i] = eg == 32767 ? 32767 : (int16_t)((uint16_t)((uint16_t)eg + 32769u) >> 1);
        }
    }
    for (i = 0; i < BP_OUT; i++)
        ctl_k[i] = (b->k[i] + 4) >> 3;
}

/* The incremental law of pid with the network's gains, through the output stage. */
CTL_STEP q15_t bp_law(int16_t e) CTL_SHARED
{
    __xdata bp_state_t *b = &ctl_st.bp;
    __xdata int16_t *de = b->de;
    int32_t du;
    uint8_t i;
    de[0] = (int16_t)(e - b->e1);
    de[1] = e;
    de[2] = fx_sat16((int32_t)e - 2 * (int32_t)b->e1 + b->e2);
    du = 0;
    for (i = 0; i < BP_OUT; i++)
        du += (MUL(b->k[i], de[i]) + 4) >> 3;       /* Q15 * x100 -> Q12 x100 */
    return ctl_out(ctl_du_to_drive(du), ctl_in->valve_limit);
}

/* Phase 1 of learning: the output deltas of this sample; its inputs and hidden outputs kept
 * for the update. */
CTL_STEP void bp_deltas(int16_t n) CTL_SHARED
{
    __xdata bp_state_t *b = &ctl_st.bp;
    __xdata int16_t *dn = b->dn;
    uint8_t i, j;
    dn[0] = n - b->n1;
    dn[1] = n;
    dn[2] = fx_sat16((int32_t)n - 2 * (int32_t)b->n1 + b->n2);
    for (i = 0; i < BP_OUT; i++) {
        /* delta_l = e * sgn * d(du)/dK_l * g'(net_l), g' = 2K(1-K) */
        int16_t gp = (int16_t)((MUL(b->k[i], (int16_t)(32767 - b->k[i])) + 8192) >> 14);   /* Q15 */
        int16_t t = fx_sat16((MUL(n, dn[i]) + 2048) >> 12);                                  /* Q12 */
        b->dl[i] = fx_sat16((MUL(t, gp) + 16384) >> 15);                                    /* Q12 */
    }
    for (j = 0; j < BP_IN; j++)
        b->x[j] = b->xs[j];
    for (j = 0; j < BP_HID; j++)
        b->oh[j] = b->o[j];
}

/* Phases 2..5 of learning: two units a period, units 0-2 the output rows, 3-7 the hidden rows
 * (their deltas with the output weights just updated, as the reference code does). */
CTL_STEP void bp_update(void) CTL_SHARED
{
    __xdata bp_state_t *b = &ctl_st.bp;
    int16_t eg;                     /* Q12: eta * delta */
    uint8_t i, j;
    j = (uint8_t)((b->phase - 2) << 1);
    for (i = j; i < j + 2; i++) {
        if (i < BP_OUT) {
            eg = (int16_t)((MUL(b->dl[i], BP_ETA) + 2048) >> 12);
            bp_upd_row(0, i, eg);
        } else {
            uint8_t h = (uint8_t)(i - BP_OUT), l;
            int16_t one_m = (int16_t)(32767 - ((MUL(b->oh[h], b->oh[h]) + 16384) >> 15));   /* Q15 1 - O^2 */
            mul_acc = 2048;
            for (l = 0; l < BP_OUT; l++)
                MAC(b->dl[l], b->v[l][h]);
            eg = fx_sat16((MUL(fx_sat16(mul_acc >> 12), one_m) + 16384) >> 15);
            eg = (int16_t)((MUL(eg, BP_ETA) + 2048) >> 12);
            bp_upd_row(1, h, eg);
        }
    }
}

/* Learning, frozen while saturated or at an end stop; one update spread over BP_PHASES periods.
 * A frozen update is dropped, the next one starts afresh; the forward pass goes on. */
CTL_STEP void bp_learn(int16_t n) CTL_SHARED
{
    __xdata bp_state_t *b = &ctl_st.bp;
    if (ctl_sat || ctl_in->valve_limit) {
        b->phase = b->phase == 0 ? 1 : 0;
    } else if (b->phase == 0) {
        b->phase = 1;
    } else if (b->phase == 1) {
        bp_deltas(n);
        b->phase = 2;
    } else {
        bp_update();
        b->phase = b->phase == BP_PHASES - 1 ? 0 : (uint8_t)(b->phase + 1);
    }
}

q15_t bp_step(void) CTL_SHARED
{
    __xdata bp_state_t *b = &ctl_st.bp;
    int16_t e = ctl_clamp_e(ctl_in->target_lpm_x100 - ctl_in->flow_lpm_x100);
    int16_t n;
    q15_t out;

    n = (int16_t)((MUL(ctl_clamp16(e, -BP_E_CLAMP, BP_E_CLAMP), BP_E_NORM) + 1024) >> 11);
    if (ctl_first) {                /* from rest: no kick, no learning from stale history */
        b->e1 = b->e2 = e;
        b->n1 = b->n2 = n;
        b->phase = 0;
        ctl_first = 0;
    }
    bp_forward(n);
    out = bp_law(e);
    bp_learn(n);
    b->e2 = b->e1;
    b->e1 = e;
    b->n2 = b->n1;
    b->n1 = n;
    return out;
}

/* bp.c: bp_pid, the paper's neural network tuning the PID gains: forward pass and learning every period. */
#include "ctl_int.h"

/*
 * The paper's network (eqs. 8-14), as its MATLAB reference runs it, every sample k: inputs
 * target, measured flow, error and a bias; 5 tanh hidden nodes; kp, ki, kd = (1 + tanh)/2 of 3
 * outputs; the incremental law with those gains; then the cost E = e(k)^2 / 2 back-propagated
 * through the law (sgn(dy/du) = +1) to every weight, eta 0.2, momentum 0.05: the output rows
 * first, then the hidden rows with the output weights just updated. Weights from a seeded
 * xorshift16 in [-0.5, 0.5). Deviations a real plant needs: normalised inputs, bounded weights
 * (BP_WMAX), learning frozen while the drive is cut or the valve at an end stop; and for the
 * 1 KB of XRAM an 8-bit momentum memory. docs/CONTROLLERS.md has each one and why.
 */
static uint16_t bp_rng;
#if !defined(__SDCC)
int16_t bp_o_seen[BP_HID];
#define BP_SEEN_O(i, v) (bp_o_seen[i] = (v))
#else
#define BP_SEEN_O(i, v)
#endif

static uint16_t bp_rand(void)
{
    bp_rng ^= (uint16_t)(bp_rng << 7);
    bp_rng ^= (uint16_t)(bp_rng >> 9);
    bp_rng ^= (uint16_t)(bp_rng << 8);
    return bp_rng;
}

void bp_init(void)
{
    /* the weights in row order, each array walked flat (no index pair kept in the direct RAM) */
    __xdata int16_t *w = &ctl_st.bp.w[0][0], *v = &ctl_st.bp.v[0][0];
    __xdata int8_t *dw = &ctl_st.bp.dw[0][0], *dv = &ctl_st.bp.dv[0][0];
    uint8_t i;
    bp_rng = BP_SEED;
    for (i = 0; i < BP_HID * BP_IN; i++) {
        w[i] = (int16_t)(bp_rand() & 0x0FFFu) - 2048;
        dw[i] = 0;
    }
    for (i = 0; i < BP_OUT * BP_HID; i++) {
        v[i] = (int16_t)(bp_rand() & 0x0FFFu) - 2048;
        dv[i] = 0;
    }
    for (i = 0; i < BP_OUT; i++)
        ctl_st.bp.k[i] = 16384;     /* g(0) = 0.5 until the first forward pass */
}

/* ---- the control step, in named steps (each inlined into bp_step) ------------------------- */

/* Forward pass (eqs. 8-13): this period's inputs x (Q12), the hidden layer o (Q15), the gains.
 * n: the normalised error (Q12). x and o are bp_step's (idata, where DOT and UPD read them). */
CTL_STEP void bp_forward(int16_t n, __idata int16_t *x, __idata int16_t *o) CTL_SHARED
{
    __xdata bp_state_t *b = &ctl_st.bp;
    __xdata int16_t *wp;
    int16_t t;
    uint8_t i;
    x[0] = 4096;
    x[1] = (int16_t)MUL_R15(ctl_clamp16(ctl_in->target_lpm_x100, 0, CTL_E_MAX), BP_Q_NORM);
    x[2] = (int16_t)MUL_R15(ctl_clamp16(ctl_in->flow_lpm_x100, 0, CTL_E_MAX), BP_Q_NORM);
    x[3] = n;
    wp = &b->w[0][0];
    for (i = 0; i < BP_HID; i++) {
        ACC_START(12);
        DOT(wp, x, BP_IN);
        wp += BP_IN;
        o[i] = fx_tanh(fx_sat16(ACC_SHR12()));
        BP_SEEN_O(i, o[i]);
    }
    wp = &b->v[0][0];
    for (i = 0; i < BP_OUT; i++) {
        ACC_START(15);
        DOT(wp, o, BP_HID);
        wp += BP_HID;
        /* (1 + tanh)/2 rounded, saturated (fx_sigmoid, inlined): (32769 + t) >> 1 in 16 bits */
        t = fx_tanh(fx_sat16(ACC_SHR15()));
        b->k[i] = t == 32767 ? 32767 : (int16_t)((uint16_t)((uint16_t)t + 32769u) >> 1);
#if FW_PROBES                        /* the gains in Q12 for ctl_gain: nothing reads them on the chip */
        ctl_k[i] = (b->k[i] + 4) >> 3;
#endif
    }
}

/* The incremental law of pid with the network's gains, through the output stage. */
CTL_STEP q15_t bp_law(int16_t e) CTL_SHARED
{
    __xdata bp_state_t *b = &ctl_st.bp;
    int16_t de[BP_OUT];             /* e - e1, e, e - 2e1 + e2 (x100): on bp_step's stack */
    int32_t du;
    uint8_t i;
    de[0] = (int16_t)(e - b->e1);
    de[1] = e;
    de[2] = ctl_d2(e, b->e1, b->e2);
    du = 0;
    for (i = 0; i < BP_OUT; i++)
        du += (MUL(b->k[i], de[i]) + 4) >> 3;       /* Q15 * x100 -> Q12 x100 */
    return ctl_out(ctl_du_to_drive(du), ctl_in->valve_limit);
}

/* Back-propagation of this period's error (E = n^2 / 2) to every weight, with momentum
 * (UPD, mul.h: |eta * delta| <= 0.2 * 8 and |input| <= 3.2 keep its products in range).
 * Output rows: delta_l = n * d(du)/dK_l * g'(net_l), g' = 2K(1-K); dv = eta delta_l O_i.
 * Hidden rows, with the output weights just updated (the reference code's order):
 * delta_i = (1 - O_i^2) sum_l delta_l v_li; dw = eta delta_i x_j. */
CTL_STEP void bp_learn(int16_t n, __idata int16_t *x, __idata int16_t *o) CTL_SHARED
{
    __xdata bp_state_t *b = &ctl_st.bp;
    int16_t dn[BP_OUT];             /* the same of the normalised error (Q12) */
    int16_t dl[BP_OUT];             /* Q12 output deltas of this period */
    int16_t eg, one_m;              /* Q12: n * dn, then eta * delta; Q15: 1 - O^2 */
    uint8_t i, l;
    dn[0] = n - b->n1;
    dn[1] = n;
    dn[2] = ctl_d2(n, b->n1, b->n2);
    for (l = 0; l < BP_OUT; l++) {
        int16_t gp = (int16_t)((MUL(b->k[l], (int16_t)(32767 - b->k[l])) + 8192) >> 14);   /* Q15 */
        eg = fx_sat16(MUL_R12(n, dn[l]));                                                   /* Q12 */
        dl[l] = fx_sat16(MUL_R15(eg, gp));                                                  /* Q12 */
        eg = (int16_t)MUL_R12(dl[l], BP_ETA);
        UPD(&b->v[l][0], &b->dv[l][0], o, eg, BP_WMAX, BP_HID, 1);
    }
    for (i = 0; i < BP_HID; i++) {
        one_m = (int16_t)(32767 - MUL_R15(o[i], o[i]));
        ACC_START(12);
        for (l = 0; l < BP_OUT; l++)
            MAC(dl[l], b->v[l][i]);
        eg = fx_sat16(MUL_R15(fx_sat16(ACC_SHR12()), one_m));
        eg = (int16_t)MUL_R12(eg, BP_ETA);
        UPD(&b->w[i][0], &b->dw[i][0], x, eg, BP_WMAX, BP_IN, 4);
    }
}

q15_t bp_step(void) CTL_SHARED
{
    __xdata bp_state_t *b = &ctl_st.bp;
    int16_t e = ctl_clamp_e(ctl_in->target_lpm_x100 - ctl_in->flow_lpm_x100);
    int16_t n;
    q15_t out;
    int16_t x[BP_IN];               /* Q12 this period's inputs, on the stack (idata) */
    int16_t o[BP_HID];              /* Q15 this period's hidden outputs */

    n = (int16_t)((MUL(ctl_clamp16(e, -BP_E_CLAMP, BP_E_CLAMP), BP_E_NORM) + 1024) >> 11);
    if (ctl_first) {                /* from rest: no kick, no learning from stale history */
        b->e1 = b->e2 = e;
        b->n1 = b->n2 = n;
        ctl_first = 0;
    }
    bp_forward(n, (__idata int16_t *)x, (__idata int16_t *)o);
    out = bp_law(e);
    /* learning frozen while the drive was cut or the valve sits at an end stop: the error
     * there says nothing about the gains */
    if (!ctl_sat && !ctl_in->valve_limit)
        bp_learn(n, (__idata int16_t *)x, (__idata int16_t *)o);
    b->e2 = b->e1;
    b->e1 = e;
    b->n2 = b->n1;
    b->n1 = n;
    return out;
}

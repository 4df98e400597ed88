/* flow.c: boom flow from the flow meter's pulse periods, with glitch rejection. */
#include "hal.h"
#include "params.h"
#include "umath.h"
#include "flow.h"

/* the cross-check that keeps every boom within the meter's range (params.c) checks this ceiling */
typedef char flow_max_is_the_cross_checks[(FLOW_MAX_X100 == PARAM_FLOW_MAX_X100) ? 1 : -1];

static struct {
    uint32_t k;             /* L/min x100 * PCA ticks a pulse: 5.5296e10 / P_METER_K */
    uint32_t last_pca;
    uint32_t pulses;
    uint16_t q_x100;
    uint16_t quiet;
    uint16_t glitches;
    uint8_t have_edge;
    uint8_t gen;
} fl;

static void flow_derive(void) __reentrant
{
    /* q[L/min x100] = 100 * 60 * 921600 * 10 / (kk[0.1 p/L] * dt) = 5.5296e10 / (kk dt), kk
     * = P_METER_K; 5.5296e10 = 1382400000 * 40, split so nothing overflows 32 bits (kk < 65536) */
    fl.k = um_scaled_div(1382400000UL, 40u, param_v[P_METER_K]);
    fl.gen = param_generation;
}

void flow_prepare(void)
{
    if (fl.gen != param_generation)
        flow_derive();
}

void flow_init(void)
{
    uint8_t i;
    for (i = 0; i < sizeof fl; i++)     /* all as at power-up (what flow_derive sets, it sets) */
        ((__xdata uint8_t *)&fl)[i] = 0;
    fl.quiet = 0xFFFF;                  /* no pulse yet */
    flow_derive();
}

int16_t flow_step(void) __reentrant
{
    hal_capture_t c;
    uint32_t q, dt;

    if (fl.gen != param_generation)
        flow_derive();
    hal_flow_capture_take((__idata hal_capture_t *)&c);   /* on the stack: idata */
    if (c.count) {
        fl.pulses += c.count;
        fl.quiet = 0;
        if (fl.have_edge) {
            dt = c.last - fl.last_pca;
            q = um_muldiv(fl.k, c.count, dt);
            if (!dt || q > FLOW_MAX_X100)
                fl.glitches++;
            else
                fl.q_x100 = (uint16_t)q;
        }
        fl.last_pca = c.last;
        fl.have_edge = 1;
    } else {
        if (fl.quiet < 0xFFFF)
            fl.quiet++;
        if (fl.have_edge && fl.quiet < FLOW_ZERO_PERIODS) {
            q = um_muldiv(fl.k, 1, hal_pca_now() - fl.last_pca);
            if (q < fl.q_x100)
                fl.q_x100 = (uint16_t)q;
        } else {
            fl.q_x100 = 0;
        }
        if (fl.quiet >= FLOW_STALE_PERIODS)
            fl.have_edge = 0;
    }
    return (int16_t)fl.q_x100;
}

int16_t flow_lpm_x100(void)
{
    return (int16_t)fl.q_x100;
}

uint32_t flow_pulses(void)
{
    return fl.pulses;
}

uint16_t flow_glitches(void)
{
    return fl.glitches;
}

uint16_t flow_quiet_periods(void)
{
    return fl.quiet;
}

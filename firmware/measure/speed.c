/* speed.c: ground speed from wheel pulse periods, decaying as 1/t when pulses stop. */
#include "hal.h"
#include "params.h"
#include "umath.h"
#include "speed.h"

static struct {
    uint32_t k;             /* km/h x100 * PCA ticks a pulse: P_WHEEL * 33177.6 */
    uint32_t last_pca;      /* PCA time of the newest edge */
    uint32_t pulses;
    uint16_t v_x100;
    uint16_t v_pulse_x100;  /* speed at the last pulse */
    uint16_t quiet;         /* periods since the last pulse */
    uint8_t since;          /* periods since the estimate was last measured (slew allowance) */
    uint16_t glitches;
    uint8_t have_edge;
    uint8_t gen;
} sp;

static void speed_derive(void) __reentrant
{
    uint32_t w = param_v[P_WHEEL];
    /* v[km/h x100] = w[0.1 mm] * 1e-4 m * 3.6 * 100 * 921600 / dt[ticks] = w * 33177.6 / dt */
    sp.k = w * 33177u + (w * 3u + 2u) / 5u;
    sp.gen = param_generation;
}

void speed_prepare(void)
{
    if (sp.gen != param_generation)
        speed_derive();
}

void speed_init(void)
{
    sp.last_pca = 0;
    sp.pulses = 0;
    sp.v_x100 = 0;
    sp.v_pulse_x100 = 0;
    sp.quiet = 0xFFFF;
    sp.glitches = 0;
    sp.have_edge = 0;
    sp.since = 0;
    speed_derive();
}

uint16_t speed_step(void) __reentrant
{
    hal_capture_t c;
    uint32_t v;

    if (sp.gen != param_generation)
        speed_derive();
    hal_wheel_capture_take(&c);
    if (sp.since < 255)
        sp.since++;
    if (c.count) {
        sp.pulses += c.count;
        sp.quiet = 0;
        if (sp.have_edge) {
            v = um_muldiv(sp.k, c.count, c.last - sp.last_pca);
            if (c.last == sp.last_pca || v > SPEED_MAX_X100) {
                sp.glitches++;
            } else {
                /* the rise allowed since the last measurement, period by period */
                if (v > (uint32_t)sp.v_x100 + (uint32_t)SPEED_SLEW_X100 * sp.since)
                    v = (uint32_t)sp.v_x100 + (uint32_t)SPEED_SLEW_X100 * sp.since;
                sp.v_x100 = (uint16_t)v;
                sp.since = 0;
            }
        }
        sp.last_pca = c.last;
        sp.have_edge = 1;
        sp.v_pulse_x100 = sp.v_x100;
    } else {
        if (sp.quiet < 0xFFFF)
            sp.quiet++;
        if (sp.have_edge) {
            v = um_muldiv(sp.k, 1, hal_pca_now() - sp.last_pca);
            if (v < sp.v_x100)
                sp.v_x100 = (uint16_t)v;
            if (sp.quiet >= SPEED_STALE_PERIODS)
                sp.have_edge = 0;   /* before the 32-bit PCA time can wrap */
        } else {
            sp.v_x100 = 0;
        }
    }
    if (sp.v_x100 < SPEED_ZERO_X100)
        sp.v_x100 = 0;
    return sp.v_x100;
}

uint16_t speed_kmh_x100(void)
{
    return sp.v_x100;
}

uint32_t speed_pulses(void)
{
    return sp.pulses;
}

uint16_t speed_glitches(void)
{
    return sp.glitches;
}

uint16_t speed_quiet_periods(void)
{
    return sp.quiet;
}

uint16_t speed_at_last_pulse_x100(void)
{
    return sp.v_pulse_x100;
}

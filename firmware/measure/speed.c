/* speed.c: ground speed from wheel pulse periods, decaying as 1/t when pulses stop. */
#include "hal.h"
#include "params.h"
#include "umath.h"
#include "speed.h"

static struct {
    uint32_t k;             /* km/h x100 * PCA ticks a pulse: P_WHEEL * 33177.6 */
    uint32_t last_pca;      /* PCA time of the newest edge */
    uint32_t pulses;
    uint32_t t_rev_last;    /* the last turn's time measured, PCA ticks (0: none) */
    uint16_t v_x100;
    uint16_t v_pulse_x100;  /* speed at the last pulse */
    uint16_t quiet;         /* periods since the last pulse */
    uint16_t glitches;
    uint8_t since;          /* periods since the estimate was last measured (slew allowance) */
    uint8_t have_edge;
    uint8_t gen;
    uint8_t n;              /* elements a turn (P_WHEEL_PPR) */
    uint8_t idx;            /* element of the newest edge */
    uint8_t learnt;         /* offsets learnt since they were forgotten (saturates) */
    int16_t off[SPEED_TEETH_MAX];   /* each element's position offset, 1/4096 of a spacing */
    uint32_t t_el[SPEED_TEETH_MAX]; /* PCA time of each element's last edge seen alone */
    uint8_t stamp[SPEED_TEETH_MAX]; /* low byte of `pulses` at that edge */
} sp;

static void speed_forget_offsets(void) __reentrant
{
    uint8_t i;
    for (i = 0; i < SPEED_TEETH_MAX; i++) {
        sp.off[i] = 0;
        sp.stamp[i] = (uint8_t)(sp.pulses + 128u);   /* never exactly a turn ago */
    }
    sp.t_rev_last = 0;
    sp.learnt = 0;
}

static void speed_derive(void) __reentrant
{
    uint32_t w = param_v[P_WHEEL];
    /* v[km/h x100] = w[0.1 mm] * 1e-4 m * 3.6 * 100 * 921600 / dt[ticks] = w * 33177.6 / dt */
    sp.k = w * 33177u + (w * 3u + 2u) / 5u;
    if (sp.n != (uint8_t)param_v[P_WHEEL_PPR]) {
        sp.n = (uint8_t)param_v[P_WHEEL_PPR];
        sp.idx = 0;
        speed_forget_offsets();
    }
    sp.gen = param_generation;
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
    sp.n = 0;
    speed_derive();
}

/* Learn the new edge's offset against the old one's from the turn that ends with it: the same
 * element's edge exactly one turn ago gives the turn's time T, and the span dt of `count`
 * pulses should then be (count + off[new] - off[old]) T_end / n, T_end the turn time at the
 * span: the turn's time is that of its middle, half a turn before, so T_end = T + n d / 2 with
 * d how much T changed since the last edge's turn (a steady acceleration). Not while the
 * speed changes by more than 1/512 a pulse. */
static void speed_learn(uint8_t count, uint32_t t_new, uint32_t dt, uint8_t old, uint8_t nw) __reentrant
{
    uint32_t t_rev, t_end, seen;
    int32_t err, d;
    uint8_t stamp = sp.stamp[nw];
    t_rev = t_new - sp.t_el[nw];
    sp.t_el[nw] = t_new;
    sp.stamp[nw] = (uint8_t)sp.pulses;
    if ((uint8_t)((uint8_t)sp.pulses - stamp) != sp.n)
        return;
    d = (int32_t)(t_rev - sp.t_rev_last);
    if (sp.t_rev_last == 0 || d > (int32_t)(sp.t_rev_last >> 9) || -d > (int32_t)(sp.t_rev_last >> 9)) {
        sp.t_rev_last = t_rev;
        return;
    }
    sp.t_rev_last = t_rev;
    t_end = (uint32_t)((int32_t)t_rev + d * (int32_t)sp.n / 2);
    /* where the new edge sits against the old one, in 1/4096 of a spacing: dt n 4096 / T_end */
    seen = um_muldiv(dt, (uint16_t)sp.n * 2048u, t_end) << 1;
    err = (int32_t)seen - ((int32_t)count << 12) - ((int32_t)sp.off[nw] - sp.off[old]);
    if (err > 1024 || err < -1024)
        return;                 /* a quarter of a spacing: a missed or extra pulse, not an offset */
    /* only the new edge's offset moves, towards the old one's plus what the span saw: round a
     * turn the spans add up to the turn, so the chain closes on itself. The first turn takes
     * what it sees, then a mean growing to about 16 turns. */
    err /= sp.learnt < sp.n ? 1 : sp.learnt < 2u * sp.n ? 2 : sp.learnt < 4u * sp.n ? 4 : sp.learnt < 8u * sp.n ? 8 : 16;
    if (sp.learnt < 255)
        sp.learnt++;
    sp.off[nw] += (int16_t)err;
    if (nw == 0 && sp.off[0] != 0) {
        /* only differences count: element 0 is the zero, so the offsets cannot drift away */
        int16_t o0 = sp.off[0];
        uint8_t i;
        for (i = 0; i < sp.n; i++)
            sp.off[i] -= o0;
    }
}

uint16_t speed_step(void) __reentrant
{
    hal_capture_t c;
    uint32_t v;

    if (sp.gen != param_generation)
        speed_derive();
    hal_wheel_capture_take(&c);
    if (c.rejected)
        sp.glitches += c.rejected;
    if (sp.since < 255)
        sp.since++;
    if (c.count) {
        uint8_t old = sp.idx, nw = (uint8_t)((sp.idx + c.count) % sp.n);
        sp.pulses += c.count;
        sp.quiet = 0;
        if (sp.have_edge) {
            uint32_t dt = c.last - sp.last_pca;
            /* the distance the span covers, in 1/4096 of a pulse spacing: each element's
             * learnt offset takes the wheel's spacing error out of the period */
            uint32_t dist = c.count < 15u ? ((uint32_t)c.count << 12) + sp.off[nw] - sp.off[old]
                                          : (uint32_t)c.count << 12;
            v = c.count < 15u ? (um_muldiv(sp.k, (uint16_t)dist, dt) + 2048u) >> 12
                              : um_muldiv(sp.k, c.count, dt);
            if (c.last == sp.last_pca || v > SPEED_MAX_X100) {
                sp.glitches++;
            } else {
                /* the rise allowed since the last measurement, period by period */
                if (v > (uint32_t)sp.v_x100 + (uint32_t)SPEED_SLEW_X100 * sp.since)
                    v = (uint32_t)sp.v_x100 + (uint32_t)SPEED_SLEW_X100 * sp.since;
                sp.v_x100 = (uint16_t)v;
                sp.since = 0;
                if (sp.n > 1 && c.count < 15u)
                    speed_learn((uint8_t)c.count, c.last, dt, old, nw);
            }
        }
        sp.idx = nw;
        sp.last_pca = c.last;
        sp.have_edge = 1;
        sp.v_pulse_x100 = sp.v_x100;
    } else {
        if (sp.quiet < 0xFFFF)
            sp.quiet++;
        if (sp.have_edge) {
            /* the next element is (1 + its offset - this one's) spacings away */
            uint8_t nx = (uint8_t)((sp.idx + 1u) % sp.n);
            v = (um_muldiv(sp.k, (uint16_t)(4096 + sp.off[nx] - sp.off[sp.idx]), hal_pca_now() - sp.last_pca)
                 + 2048u) >> 12;
            if (v < sp.v_x100)
                sp.v_x100 = (uint16_t)v;
            if (sp.quiet >= SPEED_STALE_PERIODS) {
                sp.have_edge = 0;   /* before the 32-bit PCA time can wrap */
                if (sp.v_pulse_x100 >= SPEED_LOST_X100)
                    speed_forget_offsets();     /* pulses stopped at speed: which element is next is lost */
            }
        } else {
            sp.v_x100 = 0;
        }
    }
    if (sp.v_x100 < SPEED_ZERO_X100)
        sp.v_x100 = 0;
    /* a pulse sooner than a quarter of the period at 1.5 times this speed is not a pulse */
    hal_wheel_min_interval(sp.v_x100 ? um_muldiv(sp.k, 1, (uint32_t)sp.v_x100 * 6u) : sp.k / (SPEED_MAX_X100 * 4u));
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

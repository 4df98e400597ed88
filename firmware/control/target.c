/* target.c: eq. (1) target flow from the open nozzles and the speed, Table 1's minimum flow below P_MINF_SPEED. */
#include "params.h"
#include "umath.h"
#include "target.h"
#include "mul.h"

static struct {
    uint32_t k_q16;                 /* L/min x100 per km/h x100, Q16: C d m / 600000 (C in L/ha x10) */
    uint16_t remote_x10;            /* L/ha x10 from a field computer, 0: none (the preset) */
    int8_t nudge_pct;               /* the operator's offset on it, +-TARGET_NUDGE_MAX % */
    uint8_t refusals;               /* remote rates refused since start (wraps) */
    uint8_t open;                   /* the nozzles of the sections switched on */
    uint8_t sections;
    uint8_t gen;
} tg;
static __bit tg_valid;              /* tg derived from the sections and settings it holds */
__data uint8_t target_noz_q = 4;
__bit target_noz_new;               /* the nozzles open changed (ffmap.c's hold) */

uint8_t target_noz_take(void) __reentrant
{
    if (!target_noz_new)
        return 0;
    target_noz_new = 0;
    return 1;
}

uint8_t target_section_nozzles(uint8_t s) __reentrant
{
    uint8_t n = (uint8_t)param_v[P_NOZZLES], ns = (uint8_t)param_v[P_SECTIONS];
    if (s >= ns || ns == 0)
        return 0;
    return (uint8_t)(n / ns + (s < n % ns ? 1 : 0));
}

/* The preset in use (Rate 1 or Rate 2), L/ha x10. */
uint16_t target_preset_x10(void)
{
    return param_v[param_v[P_PRESET] ? P_RATE2 : P_RATE];
}

/* 1 when rate_x10 (L/ha x10) is at least the presets' least (10 L/ha) and within the operator's
 * window (P_REMOTE_WIN % of the preset in use) around it. */
static uint8_t target_rate_window(uint16_t rate_x10) __reentrant
{
    uint16_t job = target_preset_x10(), d = rate_x10 >= job ? rate_x10 - job : job - rate_x10;
    uint32_t lim;
    if (rate_x10 < 100u)            /* P_RATE's least, 10 L/ha (the window's top is 2 x Dose) */
        return 0;
    lim = UMUL(job, param_v[P_REMOTE_WIN]);
    return UMUL(d, 100u) <= lim;
}

uint16_t target_rate_x10(void)
{
    uint16_t base = tg.remote_x10 ? tg.remote_x10 : target_preset_x10();
    if (!tg.nudge_pct)
        return base;
    /* base (<= 10000) x (100 + offset) / 100 rounded, offset within +-50: under 2^16 */
    return (uint16_t)um_scaled_div(base, (uint16_t)(100 + tg.nudge_pct), 100u);
}

int8_t target_nudge_pct(void)
{
    return tg.nudge_pct;
}

int8_t target_nudge(int8_t dir) __reentrant
{
    int8_t step = (int8_t)param_v[P_RATE_STEP], n;   /* |offset| + step <= 100: within int8 */
    n = dir ? (int8_t)(tg.nudge_pct + (dir > 0 ? step : -step)) : 0;
    if (n > TARGET_NUDGE_MAX)
        n = TARGET_NUDGE_MAX;
    else if (n < -TARGET_NUDGE_MAX)
        n = -TARGET_NUDGE_MAX;
    if (n != tg.nudge_pct) {
        tg.nudge_pct = n;
        tg_valid = 0;               /* derived again at the next update */
    }
    return n;
}

uint8_t target_rate_remote(void)
{
    return tg.remote_x10 != 0;
}

uint8_t target_remote_rate(uint16_t rate_x10) __reentrant
{
    if (!param_v[P_REMOTE] || !target_rate_window(rate_x10)) {
        tg.refusals++;
        return 0;
    }
    tg.remote_x10 = rate_x10;
    tg_valid = 0;                   /* derived again at the next update */
    return 1;
}

uint8_t target_remote_refusals(void)
{
    return tg.refusals;
}

/* (n / o + 1) / 2 for o of the n nozzles open, in quarters: 2 + n / o in halves, at most
 * TARGET_NOZ_MAX (P_NOZZLES <= 96; by subtraction: no divide routine for it) */
static void target_noz(void)
{
    static __data uint8_t w;
    uint8_t o = tg.open, f;
    w = (uint8_t)param_v[P_NOZZLES] << 1;
    for (f = 2; w >= o && f < TARGET_NOZ_MAX; f++)
        w -= o;
    target_noz_q = f;
}

static void target_derive(void) __reentrant
{
    uint8_t s, m, o = tg.open;
    uint32_t cdm;
    tg.open = 0;
    for (s = 0, m = tg.sections; s < 8u; s++, m >>= 1)
        if (m & 1u)
            tg.open += target_section_nozzles(s);
    if (tg.open != o)
        target_noz_new = 1;
    target_noz();
    if (tg.remote_x10 && (!param_v[P_REMOTE] || !target_rate_window(tg.remote_x10)))
        tg.remote_x10 = 0;          /* Remote off, or a new preset or window leaves it outside */
    cdm = UMUL(target_rate_x10(), param_v[P_SPACING]) * tg.open;       /* <= 1.92e8 */
    /* cdm * 65536 / 600000 = cdm * 4096 / 37500, rounded (the same bits as C in L/ha / 60000) */
    tg.k_q16 = um_scaled_div(cdm, 4096u, 37500u);
    tg.gen = param_generation;
    tg_valid = 1;
}

void target_init(void)
{
    tg_valid = 0;
    tg.remote_x10 = 0;
    tg.nudge_pct = 0;
    tg.refusals = 0;
    tg.sections = 0;
    target_derive();
}

void target_update(uint8_t sections) __reentrant
{
    if (!tg_valid || sections != tg.sections || tg.gen != param_generation) {
        tg.sections = sections;
        target_derive();
    }
}

uint8_t target_speed_given(void)
{
    return param_v[P_GIVEN_SPEED] != 0;
}

uint16_t target_speed_x100(uint16_t measured_x100) __reentrant
{
    return param_v[P_GIVEN_SPEED] ? param_v[P_GIVEN_SPEED] * 10u : measured_x100;
}

uint8_t target_working_speed(uint16_t speed_x100) __reentrant
{
    return speed_x100 >= param_v[P_MINF_SPEED] * 10u;
}

int16_t target_flow_x100(uint16_t speed_x100) __reentrant
{
    uint16_t vmin = param_v[P_MINF_SPEED] * 10u;
    uint32_t q;
    if (speed_x100 == 0)
        return 0;
    if (speed_x100 < vmin)
        speed_x100 = vmin;
    q = um_mul32x16_shr16(tg.k_q16, speed_x100);
    return q > 32767u ? 32767 : (int16_t)q;
}

uint8_t target_open_nozzles(void)
{
    return tg.open;
}

uint16_t target_width_cm(void)
{
    return (uint16_t)tg.open * param_v[P_SPACING];
}

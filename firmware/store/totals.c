/* totals.c: job and lifetime area and volume, the applied dose. */
#if defined(__SDCC)
#pragma stackauto           /* locals on the stack, not each its own XRAM (docs/MEMORY.md) */
#endif
#include "umath.h"
#include "totals.h"
#include "mul.h"

totals_t totals;

static struct {
    uint16_t dm2_frac;              /* area below one dm^2, Q11 */
    uint16_t life_dm2;              /* dm^2 of the life total not yet a whole m^2 */
    uint32_t ml_frac;               /* volume below one ml, Q20 */
} to;

void totals_init(void)
{
    totals.job_dm2 = totals.job_ml = totals.life_m2 = totals.life_ml = 0;
    to.dm2_frac = 0;
    to.life_dm2 = 0;
    to.ml_frac = 0;
}

void totals_job_reset(void)
{
    totals.job_dm2 = 0;
    totals.job_ml = 0;
}

void totals_step(uint16_t speed_x100, uint16_t width_cm, int16_t flow_x100) __reentrant
{
    uint32_t a;
    if (speed_x100 && width_cm) {
        /* 0.1 s at v[km/h x100] covers v * 0.0277778 cm; times the width in cm is cm^2, and
         * / 100 dm^2: a * 2.777778e-4 dm^2 = a * 0.568889 in Q11 (37282 / 65536) */
        a = um_mul32x16_shr16(UMUL(speed_x100, width_cm), 37282u) + to.dm2_frac;
        to.dm2_frac = (uint16_t)(a & 0x7FFu);
        a >>= 11;
        totals.job_dm2 += a;
        to.life_dm2 += (uint16_t)a;             /* a <= 16000 dm^2 a period */
        while (to.life_dm2 >= 100u) {
            to.life_dm2 -= 100u;
            totals.life_m2++;
        }
    }
    if (flow_x100 > 0) {
        /* ml in 0.1 s = q[L/min x100] / 60; Q20: 2^20 / 60 = 17476.27 */
        to.ml_frac += MUL(flow_x100, 17476);   /* both positive, below 2^15 */
        a = to.ml_frac >> 20;
        to.ml_frac &= 0xFFFFFUL;
        totals.job_ml += a;
        totals.life_ml += a;
    }
}

void totals_set_life(uint32_t m2, uint32_t ml)
{
    totals.life_m2 = m2;
    totals.life_ml = ml;
}

void totals_set_job(uint32_t dm2, uint32_t ml)
{
    totals.job_dm2 = dm2;
    totals.job_ml = ml;
}

uint32_t totals_job_m2(void)
{
    return totals.job_dm2 / 100u;
}

uint16_t totals_applied_l_ha_x10(void) __reentrant
{
    uint32_t ml = totals.job_ml, dm2 = totals.job_dm2, r;
    if (dm2 < 100u)
        return 0;
    /* L/ha x10 = ml * 10000 / dm^2; scale both down until the product fits */
    while (ml > 429496UL) {
        ml >>= 1;
        dm2 >>= 1;
    }
    r = ml * 10000UL / dm2;
    return r > 65535UL ? 65535u : (uint16_t)r;
}

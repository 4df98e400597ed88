/* target.c: eq. (1) target flow from the open nozzles and the speed, Table 1's minimum flow below P_MINF_SPEED. */
#include "params.h"
#include "umath.h"
#include "target.h"

static struct {
    uint32_t k_q16;                 /* L/min x100 per km/h x100, Q16: C d m / 60000 */
    uint16_t width_cm;
    uint8_t open;
    uint8_t sections;
    uint8_t gen;
    uint8_t valid;
} tg;

uint8_t target_section_nozzles(uint8_t s) __reentrant
{
    uint8_t n = (uint8_t)param_v[P_NOZZLES], ns = (uint8_t)param_v[P_SECTIONS];
    if (s >= ns || ns == 0)
        return 0;
    return (uint8_t)(n / ns + (s < n % ns ? 1 : 0));
}

static void target_derive(void) __reentrant
{
    uint8_t s;
    uint32_t cdm;
    tg.open = 0;
    for (s = 0; s < 8u; s++)
        if (tg.sections & (1u << s))
            tg.open += target_section_nozzles(s);
    tg.width_cm = (uint16_t)tg.open * param_v[P_SPACING];
    cdm = (uint32_t)param_v[P_RATE] * param_v[P_SPACING] * tg.open;     /* <= 1.92e7 */
    tg.k_q16 = ((cdm / 60000u) << 16) + ((cdm % 60000u) * 65536UL + 30000u) / 60000u;
    tg.gen = param_generation;
    tg.valid = 1;
}

void target_init(void)
{
    tg.valid = 0;
    tg.sections = 0;
    target_derive();
}

void target_update(uint8_t sections) __reentrant
{
    if (!tg.valid || sections != tg.sections || tg.gen != param_generation) {
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
    return tg.width_cm;
}

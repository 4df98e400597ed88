/* params.c: the parameter table, its defaults and range checks. */
#include <stddef.h>
#include "umath.h"
#include "params.h"

#define PARAM_ROW(id, name, unit, dec, lo, hi, def) {name, unit, dec, lo, hi, def},
static const __code param_info_t table[P_COUNT] = { PARAM_TABLE(PARAM_ROW) };
#undef PARAM_ROW

uint16_t param_v[P_COUNT];
uint8_t param_generation;

void params_defaults(void)
{
    uint8_t i;
    for (i = 0; i < P_COUNT; i++)
        param_v[i] = table[i].def;
    param_generation++;
}

uint8_t param_in_range(uint8_t id, uint16_t v)
{
    return id < P_COUNT && v >= table[id].min && v <= table[id].max;
}

uint8_t param_put(uint8_t id, uint16_t v) __reentrant
{
    if (!param_in_range(id, v))
        return 0;
    if (param_v[id] != v) {
        param_v[id] = v;
        param_generation++;
    }
    return 1;
}

/* The meter's pulse rate at the largest flow the boom can pass: every nozzle at P max
 * (q = Q3 sqrt(P / 300 kPa)); Hz = K[0.1 p/L] / 10 * Q[L/min x100] / 100 / 60. */
static uint32_t meter_hz_max(uint16_t k, uint16_t nozzles, uint16_t q3_x100, uint16_t p_max) __reentrant
{
    uint16_t root_q8 = um_sqrt32(((uint32_t)p_max << 16) / 300u);   /* sqrt(P/300) x 256 */
    uint32_t q_x100 = ((uint32_t)nozzles * q3_x100 * root_q8) >> 8;
    return um_muldiv(q_x100, k, 60000UL);
}

uint8_t param_cross(uint8_t id, uint16_t v) __reentrant
{
#define V(i) ((i) == id ? v : param_v[i])
    if (V(P_TANK_MIN) >= V(P_TANK_L))
        return PARAM_X_TANK;
    if (V(P_P_MIN) >= V(P_P_MAX))
        return PARAM_X_PRESSURE;
    if (meter_hz_max(V(P_METER_K), V(P_NOZZLES), V(P_NOZZLE_Q3), V(P_P_MAX)) > PARAM_METER_HZ_MAX)
        return PARAM_X_METER;
    return PARAM_OK;
#undef V
}

uint8_t param_try(uint8_t id, uint16_t v) __reentrant
{
    uint8_t why;
    if (!param_in_range(id, v))
        return PARAM_E_RANGE;
    why = param_cross(id, v);
    if (why == PARAM_OK)
        param_put(id, v);
    return why;
}

uint8_t param_set(uint8_t id, uint16_t v) __reentrant
{
    return param_try(id, v) == PARAM_OK;
}

static const char __code *const __code why_texts[] = {
    "", "Out of range", "Tank min>=size", "P start>=P max", "Meter K:too fast"
};

const char *param_why_text(uint8_t why) __reentrant
{
    return why <= PARAM_X_METER ? why_texts[why] : "";
}

const param_info_t *param_info(uint8_t id)
{
    return id < P_COUNT ? &table[id] : NULL;
}

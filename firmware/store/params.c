/* params.c: the parameter table, its defaults and range checks. */
#if defined(__SDCC)
#pragma stackauto           /* locals on the stack, not each its own XRAM (docs/MEMORY.md) */
#endif
#include <stddef.h>
#include "umath.h"
#include "params.h"
#include "mul.h"

#define PARAM_ROW(id, name, unit, dec, lo, hi, def) {name, unit, dec, lo, hi, def},
static const __code param_info_t table[P_COUNT] = { PARAM_TABLE(PARAM_ROW) };
#undef PARAM_ROW

uint16_t param_v[P_COUNT];
__data uint8_t param_generation;

void params_defaults(void)
{
    uint8_t i;
    for (i = 0; i < P_COUNT; i++)
        param_v[i] = table[i].def;
    param_generation++;
}

uint8_t param_in_range(uint8_t id, uint16_t v)
{
    if (id >= P_COUNT || v < table[id].min || v > table[id].max)
        return 0;
    if (id == P_RAVEN_CAL) {
        /* the dead band digit is 1-9: v % 10 (v <= 9999 here) by subtraction, no remainder
         * routine in the image for this one use */
        while (v >= 1000u)
            v -= 1000u;
        while (v >= 100u)
            v -= 100u;
        while (v >= 10u)
            v -= 10u;
        return v != 0;
    }
    return 1;
}

/* a value a record of version ver may hold: in its range in this version's units, or Remote =
 * AgOpenGPS, which an image without the frames refuses to set (the record loads all the same
 * there, Remote at its default, off) */
uint8_t param_stored_ok(uint8_t ver, uint8_t id, uint16_t v) __reentrant
{
    return param_in_range(id, param_of_version(ver, id, v)) || (id == P_REMOTE && v == REMOTE_PGN);
}

uint8_t param_put(uint8_t id, uint16_t v)
{
    if (!param_in_range(id, v))
        return 0;
    if (param_v[id] != v) {
        param_v[id] = v;
        param_generation++;
    }
    return 1;
}

/* The meter's pulse rate with every nozzle open is f3 = K[0.1 p/L] n Q3[L/min x100] / 60000 Hz
 * at 3 bar, f3 sqrt(P / 300 kPa) at P max: within the budget when f3 <= HZ and
 * f3^2 P / 2048 <= HZ^2 300 / 2048 (the square then fits 32 bits). The flow itself, n Q3 at 3 bar
 * and n Q3 sqrt(P / 300 kPa) at P max, in eighths (n Q3 / 8 < 2^15: its square fits 32 bits):
 * (n Q3 / 8)^2 P / 2048 <= (MAX / 8)^2 300 / 2048. */
uint8_t params_cross(void)
{
    uint32_t f3;
    if (param_v[P_TANK_MIN] >= param_v[P_TANK_L])
        return PARAM_X_TANK;
    if (param_v[P_P_MIN] >= param_v[P_P_MAX])
        return PARAM_X_PRESSURE;
    f3 = um_muldiv(UMUL(param_v[P_METER_K], param_v[P_NOZZLES]), param_v[P_NOZZLE_Q3], 60000UL);
    if (f3 > PARAM_METER_HZ_MAX     /* (then f3 and the flow in eighths below: 16 bits) */
        || um_mul32x16_shr16(UMUL((uint16_t)f3, (uint16_t)f3), (uint16_t)(param_v[P_P_MAX] << 5))
           > PARAM_METER_HZ_MAX * PARAM_METER_HZ_MAX * 300u / 2048u)
        return PARAM_X_METER;
    f3 = UMUL(param_v[P_NOZZLES], param_v[P_NOZZLE_Q3]) >> 3;
    if (um_mul32x16_shr16(UMUL((uint16_t)f3, (uint16_t)f3), (uint16_t)(param_v[P_P_MAX] << 5))
        > (PARAM_FLOW_MAX_X100 / 8u) * (PARAM_FLOW_MAX_X100 / 8u) * 300u / 2048u)
        return PARAM_X_FLOW;
    return PARAM_OK;
}

uint8_t param_try(uint8_t id, uint16_t v)
{
    uint16_t old;
    uint8_t why;
    if (!param_in_range(id, v))
        return PARAM_E_RANGE;
    old = param_v[id];              /* the set with v in it, checked; kept only when it passes */
    param_v[id] = v;
    why = params_cross();
    if (why != PARAM_OK)
        param_v[id] = old;
    else if (old != v)
        param_generation++;
    return why;
}

#if FW_PROBES
uint8_t param_set(uint8_t id, uint16_t v)
{
    return param_try(id, v) == PARAM_OK;
}
#endif

static const char __code *const __code why_texts[] = {
    "", "Out of range", "Tank min>=size", "P start>=P max", "Meter K:too fast", "Boom Q>300L/min"
};

const __code char *param_why_text(uint8_t why)
{
    return why <= PARAM_X_FLOW ? why_texts[why] : "";
}

const __code uint8_t params_version_count[PARAMS_VERSION - 1u] = {
    PARAMS_V2_COUNT, PARAMS_V3_COUNT, PARAMS_V4_COUNT, PARAMS_V8_COUNT, PARAMS_V8_COUNT, PARAMS_V8_COUNT,
    PARAMS_V8_COUNT, PARAMS_V9_COUNT, PARAMS_V10_COUNT, P_COUNT};
typedef char params_version_counts[(PARAMS_VERSION == 11) ? 1 : -1];   /* a new version: its count here */

uint16_t param_of_version(uint8_t ver, uint8_t id, uint16_t v)
{
    if (id == P_RATE && ver < 10u)
        return v > 1000u ? 0 : v * 10u;
    return v;
}

const __code param_info_t *param_info(uint8_t id)
{
    return id < P_COUNT ? &table[id] : NULL;
}

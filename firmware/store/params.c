/* params.c: the parameter table, its defaults and range checks. */
#if defined(__SDCC)
#pragma stackauto           /* locals on the stack, not each its own XRAM (docs/MEMORY.md) */
#endif
#include <stddef.h>
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

uint8_t param_set(uint8_t id, uint16_t v)
{
    if (!param_in_range(id, v))
        return 0;
    if (param_v[id] != v) {
        param_v[id] = v;
        param_generation++;
    }
    return 1;
}

const param_info_t *param_info(uint8_t id)
{
    return id < P_COUNT ? &table[id] : NULL;
}

/* console_units.c: the units the console shows (metric, US, turf): each quantity converted at the console's edge, the firmware's values unchanged. */
#if defined(__SDCC)
#pragma stackauto           /* locals on the stack, not each its own XRAM (docs/MEMORY.md) */
#endif
#include "params.h"
#include "umath.h"
#include "console_int.h"

/*
 * Shown = the firmware's value x m / d, rounded, in the unit's decimals; an entry goes back as
 * x d / m. Each m / d is the definitions' ratio (1 US gal = 3.785411784 L, 1 acre =
 * 4046.8564224 m^2, 1 mile = 1609.344 m, 1 psi = 6.89475729 kPa, 1000 ft^2 = 92.90304 m^2)
 * with the decimals folded in: exact for the rates and the speed, within 1e-8 for the rest.
 * The firmware's scales: rate L/ha x10, speed km/h x10, pressure kPa, volume L, flow
 * L/min x100, area m^2; the totals' volume ml.
 */
static const __code con_unit_t units[CU_COUNT - 1][2] = {   /* US, turf */
    {{"gal/ac", 1, 2376u, 22225u}, {"gal/M", 2, 240u, 9779u}},      /* rate: x10, x100 */
    {{"mph", 1, 15625u, 25146u}, {"mph", 1, 15625u, 25146u}},      /* speed x10 */
    {{"PSI", 1, 59187u, 40808u}, {"PSI", 1, 59187u, 40808u}},      /* pressure x10 */
    {{"gal", 0, 15821u, 59889u}, {"gal", 0, 15821u, 59889u}},      /* volume */
    {{"gpm", 2, 15821u, 59889u}, {"gpm", 2, 15821u, 59889u}},      /* flow x100 */
    {{"ac", 2, 1511u, 61148u}, {"M", 1, 6941u, 64484u}},           /* area: acres x100, 1000 ft^2 x10 */
    {{"gal", 1, 85u, 32176u}, {"gal", 1, 85u, 32176u}},           /* volume in ml: x10 */
};

/* The class of a parameter's unit, from its metric unit's text: "L/ha", "km/h", "kPa", "L",
 * "L/min"; CU_NONE for the others (lengths, calibrations and counts stay as they are). */
uint8_t con_unit_class(const __code char *u)
{
    if (u[0] == 'L')
        return u[1] == 0 ? CU_VOL : u[2] == 'h' ? CU_RATE : CU_FLOW;
    if (u[0] == 'k')
        return u[1] == 'm' ? CU_SPEED : CU_PRESS;
    return CU_NONE;
}

/* The unit shown for a quantity of class cls: 0 for metric (the firmware's own) or CU_NONE. */
const __code con_unit_t *con_unit(uint8_t cls)
{
    uint8_t sys = (uint8_t)param_v[P_UNITS];
    if (!sys || cls == CU_NONE)
        return 0;
    return &units[cls - 1][sys - 1];
}

const __code con_unit_t *con_unit_of(uint8_t id)
{
    return con_unit(con_unit_class(param_info(id)->unit));
}

/* A value typed in unit u back in the firmware's scale. */
uint32_t con_unit_in(const __code con_unit_t *u, uint32_t shown)
{
    return um_scaled_div(shown, u->d, u->m);
}

/* Append v, a value of parameter id, as shown (flags: CON_TRIM); returns its unit's text. */
const __code char *con_cat_pnum(uint8_t id, uint16_t v, uint8_t flags)
{
    const __code param_info_t *pi = param_info(id);
    const __code con_unit_t *u = con_unit(con_unit_class(pi->unit));
    if (u) {
        con_cat_num(um_scaled_div(v, u->m, u->d), 0, (uint8_t)(u->dec | flags));
        return u->unit;
    }
    con_cat_num(v, 0, (uint8_t)(pi->decimals | flags));
    return pi->unit;
}

/* Append v, a quantity of class cls in the firmware's scale, and its unit: as form and unit
 * say in metric, in the unit's decimals otherwise. */
void con_cat_q(uint8_t cls, uint32_t v, uint8_t width, uint8_t form, const __code char *unit)
{
    const __code con_unit_t *u = con_unit(cls);
    if (u) {
        v = um_scaled_div(v, u->m, u->d);
        form = u->dec;
    }
    con_cat_num(v, width, form);
    if (!unit)
        return;                     /* the number alone */
    if (u) {
        if (unit[0] == ' ')
            con_cat(" ");
        unit = u->unit;
    }
    con_cat(unit);
}

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
 * The firmware's scales (CU_*): rate L/ha x10, speed km/h x100, pressure kPa, volume L, flow
 * L/min x100, area m^2, the totals' volume ml.
 */
static const __code con_unit_t units[CU_COUNT - 1][2] = {   /* US, turf */
    {{"gal/ac", 1, 2376u, 22225u}, {"gal/M", 2, 240u, 9779u}},      /* rate: x10, x100 */
    {{"mph", 1, 3125u, 50292u}, {"mph", 1, 3125u, 50292u}},        /* speed: km/h x100 -> mph x10 */
    {{"PSI", 1, 59187u, 40808u}, {"PSI", 1, 59187u, 40808u}},      /* pressure x10 */
    {{"gal", 0, 15821u, 59889u}, {"gal", 0, 15821u, 59889u}},      /* volume */
    {{"gpm", 2, 15821u, 59889u}, {"gpm", 2, 15821u, 59889u}},      /* flow x100 */
    {{"ac", 2, 1511u, 61148u}, {"M", 1, 6941u, 64484u}},           /* area: acres x100, 1000 ft^2 x10 */
    {{"gal", 1, 85u, 32176u}, {"gal", 1, 85u, 32176u}},            /* volume in ml: x10 */
};

/* The unit shown for a quantity of class cls: 0 in metric (the firmware's own) or for CU_NONE. */
const __code con_unit_t *con_unit(uint8_t cls)
{
    uint8_t sys = (uint8_t)param_v[P_UNITS];
    if (!sys || cls == CU_NONE)
        return 0;
    return &units[cls - 1][sys - 1];
}

/* The class of parameter id, from its metric unit's text: "L/ha", "km/h", "kPa", "L", "L/min";
 * CU_NONE for the others (lengths, calibrations and counts stay as they are). */
uint8_t con_id_class(uint8_t id)
{
    const __code char *u = param_info(id)->unit;
    if (u[0] == 'L')
        return u[1] == 0 ? CU_VOL : u[2] == 'h' ? CU_RATE : CU_FLOW;
    if (u[0] == 'k')
        return u[1] == 'm' ? CU_SPEED : CU_PRESS;
    return CU_NONE;
}

/* The screens' metric unit of each class (the run screen's pressure in bar, its flow L/mn) */
static const __code char *const __code metric_units[CU_COUNT] = {
    "", "L/ha", "km/h", "bar", "L", "L/mn", "ha", "L",
};

/* Append the unit of class cls in the units chosen: the screens' metric one when metric. */
void con_cat_unit(uint8_t cls)
{
    con_cat(con_unit_text(cls, metric_units[cls]));
}

/* The text of the unit of class cls: metric's when metric. */
const __code char *con_unit_text(uint8_t cls, const __code char *metric)
{
    const __code con_unit_t *u = con_unit(cls);
    return u ? u->unit : metric;
}

/* v, of class CON_Q(cls) in form, in the units chosen: x m / d rounded */
uint32_t con_q(uint32_t v, uint8_t form)
{
    const __code con_unit_t *u = con_unit((uint8_t)(form >> 5));
    return u ? um_scaled_div(v, u->m, u->d) : v;
}

/* The form con_q's value is shown with: the unit's decimals (CON_TRIM kept), or form itself. */
uint8_t con_q_form(uint8_t form)
{
    const __code con_unit_t *u = con_unit((uint8_t)(form >> 5));
    return u ? (uint8_t)(u->dec | (form & CON_TRIM)) : form;
}

/* A value typed in the unit chosen back in parameter id's scale (a speed setting is km/h x10,
 * the class's scale x100). */
uint32_t con_unit_in(uint8_t id, uint32_t shown)
{
    uint8_t cls = con_id_class(id);
    const __code con_unit_t *u = con_unit(cls);
    return um_scaled_div(shown, u->d, cls == CU_SPEED ? u->m * 10u : u->m);
}

/* units.c: the units the console and the link show (metric, US, turf): one table of ratios, each quantity converted at the edge, the firmware's values unchanged. */
#if defined(__SDCC)
#pragma stackauto           /* locals on the stack, not each its own XRAM (docs/MEMORY.md) */
#endif
#include "params.h"
#include "umath.h"
#include "units.h"

/*
 * Shown = the firmware's value x m / d, rounded, in the unit's decimals; an entry goes back as
 * x d / m. Each m / d is the definitions' ratio (1 US gal = 3.785411784 L, 1 acre =
 * 4046.8564224 m^2, 1 mile = 1609.344 m, 1 psi = 6.89475729 kPa, 1000 ft^2 = 92.90304 m^2,
 * 1 in = 2.54 cm, 1 ft = 0.3048 m) with the decimals folded in: exact for the rates, the speed
 * and the lengths, within 1e-8 for the rest. The firmware's scales (CU_*): rate L/ha x10,
 * speed km/h x100, pressure kPa, volume L, flow L/min x100, area m^2, the totals' volume ml.
 */
static const __code unit_t units[CU_COUNT - 1][2] = {   /* US, turf */
    {{"gal/ac", 1, 2376u, 22225u}, {"gal/M", 2, 240u, 9779u}},      /* rate: x10, x100 */
    {{"mph", 1, 3125u, 50292u}, {"mph", 1, 3125u, 50292u}},        /* speed: km/h x100 -> mph x10 */
    {{"PSI", 1, 59187u, 40808u}, {"PSI", 1, 59187u, 40808u}},      /* pressure x10 */
    {{"gal", 0, 15821u, 59889u}, {"gal", 0, 15821u, 59889u}},      /* volume */
    {{"gpm", 2, 15821u, 59889u}, {"gpm", 2, 15821u, 59889u}},      /* flow x100 */
    {{"ac", 2, 1511u, 61148u}, {"M", 1, 6941u, 64484u}},           /* area: acres x100, 1000 ft^2 x10 */
    {{"gal", 1, 85u, 32176u}, {"gal", 1, 85u, 32176u}},            /* volume in ml: x10 */
};
/* the same in US and turf units: a section's cm in inches, the wheel's mm x10 a pulse in
 * inches x100, metres in feet, the meter's pulses a litre x10 a gallon x10 (the volume's
 * ratio inverted); no unit text: the console shows none of them */
static const __code unit_t same[4] = {
    {0, 0, 50u, 127u}, {0, 2, 50u, 127u}, {0, 0, 1250u, 381u}, {0, 1, 59889u, 15821u},
};

const __code unit_t *unit_of(uint8_t cls)
{
    uint8_t sys = (uint8_t)param_v[P_UNITS];
    if (!sys || cls == CU_NONE)
        return 0;
    return cls >= CU_COUNT ? &same[cls - CU_COUNT] : &units[cls - 1][sys - 1];
}

/* "L/ha", "km/h", "kPa", "L", "L/min" */
uint8_t unit_class(uint8_t id)
{
    const __code char *u = param_info(id)->unit;
    if (u[0] == 'L')
        return u[1] == 0 ? CU_VOL : u[2] == 'h' ? CU_RATE : CU_FLOW;
    if (u[0] == 'k')
        return u[1] == 'm' ? CU_SPEED : CU_PRESS;
    return CU_NONE;
}

uint32_t unit_q(uint32_t v, uint8_t cls)
{
    const __code unit_t *u = unit_of(cls);
    return u ? um_scaled_div(v, u->m, u->d) : v;
}

/* (a speed setting is km/h x10, the class's scale x100) */
uint16_t unit_in(uint8_t id, uint16_t shown)
{
    uint8_t cls = unit_class(id);
    const __code unit_t *u = unit_of(cls);
    uint32_t v;
    if (!u)
        return shown;
    v = um_scaled_div(shown, u->d, cls == CU_SPEED ? u->m * 10u : u->m);
    return v >> 16 ? 0xFFFFu : (uint16_t)v;
}

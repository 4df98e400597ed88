/* console_units.c: the units the console shows (metric, US, turf; the ratios: ops/units.c): each quantity converted at the console's edge, its texts. */
#if defined(__SDCC)
#pragma stackauto           /* locals on the stack, not each its own XRAM (docs/MEMORY.md) */
#endif
#include "console_int.h"

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
    const __code unit_t *u = unit_of(cls);
    return u ? u->unit : metric;
}

/* The form unit_q's value of class CON_Q(cls) in form is shown with: the unit's decimals
 * (CON_TRIM kept), or form itself. */
uint8_t con_q_form(uint8_t form)
{
    const __code unit_t *u = unit_of((uint8_t)(form >> 5));
    return u ? (uint8_t)(u->dec | (form & CON_TRIM)) : form;
}

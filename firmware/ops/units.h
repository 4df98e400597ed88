/* units.h: the units the console's Units setting chooses (metric, US, turf) for what the console and the link show; the firmware's values stay its own. */
#ifndef UNITS_H
#define UNITS_H

#include "compiler.h"

/* The quantities that have a US and a turf unit (the console's CON_Q holds up to 7), then the
 * lengths that are the same in both (the link's calibration numbers and distance). */
enum { CU_NONE, CU_RATE, CU_SPEED, CU_PRESS, CU_VOL, CU_FLOW, CU_AREA, CU_ML, CU_COUNT,
       CU_INCH = CU_COUNT, CU_INCH100, CU_FEET, CU_PER_GAL };
typedef struct {
    const __code char *unit;
    uint8_t dec;                    /* decimals shown */
    uint16_t m, d;                  /* shown = the firmware's value x m / d */
} unit_t;

/* The unit of class cls in the units chosen: 0 in metric (the firmware's own) or for CU_NONE. */
const __code unit_t *unit_of(uint8_t cls) __reentrant;
/* v, of class cls in the firmware's scale, in the units chosen: x m / d rounded (v in metric). */
uint32_t unit_q(uint32_t v, uint8_t cls) __reentrant;
/* The class of parameter id, from its metric unit's text; CU_NONE for lengths, calibrations
 * and counts. */
uint8_t unit_class(uint8_t id) __reentrant;
/* A value of parameter id typed or received in the units chosen, in the
 * parameter's own scale, rounded; 0xFFFF (above every parameter's maximum) past 16 bits. */
uint16_t unit_in(uint8_t id, uint16_t shown) __reentrant;

#endif

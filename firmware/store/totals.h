/* totals.h: area and volume per job and over the machine's life, and the applied dose. */
#ifndef TOTALS_H
#define TOTALS_H

#include "compiler.h"

/*
 * Per period (no divide): area += v * 0.1 s * width of the open sections, volume += q * 0.1 s
 * while the boom sprays. Both carry their fractions (area in 1/65536 cm^2, volume in 2^-20 ml),
 * so nothing is lost to rounding over a long job. The applied dose (L/ha x10 = ml * 10000 /
 * dm^2) divides once a second, outside the control step.
 * The lifetime and job totals are kept in the EEPROM record with the parameters (store.c):
 * loaded at start, saved when the boom shuts after it has sprayed and every minute of spraying
 * (app.c), so a power cut loses at most the last minute.
 */
typedef struct {
    uint32_t job_dm2;               /* job area, 0.01 m^2 */
    uint32_t job_ml;
    uint32_t life_m2;
    uint32_t life_ml;
} totals_t;

void totals_init(void);
/* One control period: speed km/h x100, open width cm, flow L/min x100 (0 when not spraying). */
void totals_step(uint16_t speed_x100, uint16_t width_cm, int16_t flow_x100) __reentrant;
/* Zero the job totals. */
void totals_job_reset(void);
/* The totals (only totals.c writes them): at a fixed XRAM address, read without a call */
extern totals_t totals;
#define totals_get() ((const __xdata totals_t *)&totals)
/* The lifetime and the job totals read back from the EEPROM (store_load). */
void totals_set_life(uint32_t m2, uint32_t ml) __reentrant;
void totals_set_job(uint32_t dm2, uint32_t ml) __reentrant;
uint32_t totals_job_m2(void);
/* Applied dose of the job, L/ha x10 (0 before 1 m^2), saturates at 65535. */
uint16_t totals_applied_l_ha_x10(void) __reentrant;

#endif

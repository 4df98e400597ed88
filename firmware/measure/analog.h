/* analog.h: pressure and tank level from 4-20 mA loops (250 ohm, 10-bit ADC at 5 V), with open/short detection. */
#ifndef ANALOG_H
#define ANALOG_H

#include "compiler.h"

/*
 * I = counts * 5 V / 1023 / 250 ohm: 4 mA = 204.6 counts, 20 mA = 1023 (full scale).
 * Pressure, the corrected eq. (5): p = P_PSENS_MAX * (I - 4 mA) / 16 mA (4 mA reads 0).
 * Level, eq. (4): H = P_TANK_H * (I - 4 mA) / 16 mA, litres = H * P_TANK_L / P_TANK_H.
 * Four conversions a channel a period are averaged (the sum is the value in 1/4 count).
 * Faults, each needing ANALOG_FAULT_PERIODS periods in a row to set and ANALOG_OK_PERIODS
 * good ones to clear:
 *   open loop: below 3.6 mA (the sum below 736, i.e. < 184 counts; 3.5 mA = 179 counts);
 *   short:     the ADC saturated (1023 in any conversion): 20 mA and above cannot be told
 *              apart with a 250 ohm shunt at a 5 V reference, and 20 mA is 1.6 MPa on the
 *              default sensor, three times the relief setting: not a pressure of this machine.
 *              On the level channel full scale is a full tank, so only open is detected there.
 * Between 3.6 and 4 mA the reading is 0 (sensor tolerance). A faulty channel holds its last
 * good value and says so (analog_pressure_ok() / analog_level_ok()).
 */
#define ANALOG_OPEN_SUM 736u        /* 4 x 184 counts = 3.6 mA */
#define ANALOG_SAT_COUNTS 1023u
#define ANALOG_FAULT_PERIODS 3u
#define ANALOG_OK_PERIODS 10u
#define ANALOG_FAULT_OPEN 1
#define ANALOG_FAULT_SHORT 2

void analog_init(void);
/* One control period: read both channels. */
void analog_step(void) __reentrant;
uint16_t analog_pressure_kpa(void);
uint16_t analog_tank_l(void);
uint8_t analog_pressure_ok(void);
uint8_t analog_level_ok(void);
/* ANALOG_FAULT_* of the last raw reading (0 when good). */
uint8_t analog_pressure_fault(void);
uint8_t analog_level_fault(void);
/* The scaling alone, for a sum of four conversions (tests; no fault logic). */
uint16_t analog_kpa_of_sum(uint16_t sum4) __reentrant;

#endif

/* fmt.h: the one number formatter of the firmware (the LCD and the serial link): decimal, fixed point. */
#ifndef FMT_H
#define FMT_H

#include "compiler.h"

/* Room for any result: 10 digits, a point and the terminating 0. */
#define FMT_MAX 12

/* v as decimal into out (FMT_MAX bytes), with `decimals` digits after a point (v counts in
 * units of 10^-decimals; at least one digit before the point: 5 with 2 decimals is "0.05");
 * trim (with decimals): trailing zeros and then a trailing point dropped ("12.50" -> "12.5",
 * "3.0" -> "3"). No divide: the powers of ten are subtracted. Returns the length. out is in
 * the internal RAM (its callers' stack on the 8051): no generic pointer. */
uint8_t fmt_u32(__idata char *out, uint32_t v, uint8_t decimals, uint8_t trim) __reentrant;

#endif

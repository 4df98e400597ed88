/* linecheck.h: the serial link's line check: the CRC-8 of a line, and a command line's check and layout. */
#ifndef LINECHECK_H
#define LINECHECK_H

#include "compiler.h"

/* CRC-8 of the n bytes at p: polynomial 0x65 (x^8+x^6+x^5+x^2+1), initial 0, most significant
 * bit first. Sent in hex after '*', it catches every error of one or two bits in a line of up
 * to SERIAL_CRC_BYTES (serial.h) bytes, its hex digits' own included, and every error within
 * one byte (docs/PC.md: why this polynomial). */
uint8_t line_crc8(const __xdata char *p, uint8_t n) __reentrant;

/* A received line of n bytes at p (a NUL may follow at p[n]): its check "*HH" (either case),
 * when present, must be the CRC-8 of the bytes before '*', and its words single-spaced.
 * LINE_E_CSUM or LINE_E_ARG when not; else the line's length before the check, LINE_CHECKED
 * added when it had one, and the line ended there (a NUL). */
#define LINE_CHECKED 0x80u
#define LINE_E_ARG 0xFEu
#define LINE_E_CSUM 0xFFu
uint8_t line_check(__xdata char *p, uint8_t n) __reentrant;

/* The plain decimal 0..65535 at p, up to the byte sep or the line's end, into *v (v on the
 * caller's stack): the position after it, or 0 when there is no digit, a sixth one, a value
 * beyond 65535 or another byte (v unchanged). Both the commands and Raven's strings read
 * their numbers so. */
const __xdata char *line_number(const __xdata char *p, __idata uint16_t *v, char sep) __reentrant;

#endif

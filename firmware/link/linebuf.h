/* linebuf.h: the serial link's one line buffer, for the modules that compose lines into it (serial.c owns it). */
#ifndef LINEBUF_H
#define LINEBUF_H

#include "compiler.h"

/* Append to the line being composed: a character, a string, v in decimal as a value with `dec`
 * decimals, `keep` of them sent (truncated: 12345 with dec 3, keep 1 is "12.3"; keep 0, no point).
 * What does not fit (SERIAL_TX_MAX, less the line's end) is dropped. */
void serial_put_c(char c) __reentrant;
void serial_put_s(const __code char *s) __reentrant;
void serial_put_num(uint32_t v, uint8_t dec, uint8_t keep) __reentrant;

#endif

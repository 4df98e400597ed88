/* linebuf.h: the serial link's one line buffer, for the modules that compose lines into it (serial.c owns it). */
#ifndef LINEBUF_H
#define LINEBUF_H

#include "compiler.h"

/* Append to the line being composed: a character, a string, v in decimal with `dec` decimals
 * (1234 with dec 1 is "123.4"). What does not fit (SERIAL_TX_MAX, less the line's end) is
 * dropped. */
void serial_put_c(char c) __reentrant;
void serial_put_s(const __code char *s) __reentrant;
void serial_put_num(uint32_t v, uint8_t dec) __reentrant;

#endif

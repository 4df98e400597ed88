/* screen.h: the screen model: 4 lines of 16 characters the console writes, independent of the LCD's wiring. */
#ifndef SCREEN_H
#define SCREEN_H

#include "compiler.h"

#define SCREEN_ROWS 4
#define SCREEN_COLS 16

/* All spaces (only the characters that change are marked for the LCD). */
void screen_clear(void);
void screen_putc(uint8_t row, uint8_t col, char c) __reentrant;
/* A string from col on, cut at the end of the line; returns the column after it. */
uint8_t screen_puts(uint8_t row, uint8_t col, const char *s) __reentrant;
/* A whole line: the string, then spaces to the end. */
void screen_line(const char *s, uint8_t row) __reentrant;
/* Spaces from col to the end of the line. */
void screen_pad(uint8_t row, uint8_t col) __reentrant;
char screen_char(uint8_t row, uint8_t col) __reentrant;

/* For the LCD driver: the character pairs (ST7920 DDRAM words) changed since they were taken.
 * Bit p of screen_dirty(row) = columns 2p and 2p+1; screen_take(row, p) clears it. */
/* Nonzero while any pair of any row is changed (one test for an unchanged screen). */
uint8_t screen_any_dirty(void);
uint8_t screen_dirty(uint8_t row);
void screen_take(uint8_t row, uint8_t pair) __reentrant;
/* Mark everything changed (after an LCD reset). */
void screen_touch_all(void);

#endif

/* keypad.h: the 4x4 matrix keypad: scanned from the main loop, debounced, with auto-repeat. */
#ifndef KEYPAD_H
#define KEYPAD_H

#include "compiler.h"

/*
 * Layout (rows top to bottom, columns left to right; hal_keypad_row(row) bit col):
 *
 *     1  2  3  A        A  menu / up: open the menu, previous item, next choice
 *     4  5  6  B        B  down: next item, previous choice; on the run screen: totals page
 *     7  8  9  C        C  clear / back: clear the entry, then leave; cancel a procedure
 *     *  0  #  D        D  enter: edit, accept, start/stop a calibration
 *                       *  acknowledge alarms (any screen)
 *                       #  decimal point while entering a number; on the run screen:
 *                          manual <-> auto
 *                       2 / 8 on the run screen in manual mode: jog the valve (more / less flow)
 *                       0-9  digits
 * keypad_poll() returns the key's character ('0'..'9', 'A'..'D', '*', '#') once when it is
 * pressed, and again every KEYPAD_REPEAT_MS after KEYPAD_DELAY_MS held (A, B and digits
 * only; C, D, * and # never repeat, so a held Enter does not confirm twice).
 */
#define KEYPAD_SCAN_MS 10           /* a scan every 10 ms */
#define KEYPAD_STABLE_SCANS 3       /* the same reading 3 scans in a row (20-30 ms) */
#define KEYPAD_DELAY_MS 500
#define KEYPAD_REPEAT_MS 150
#define KEY_NONE 0

void keypad_init(void);
/* The next key event, or KEY_NONE. Call as often as the main loop runs. */
char keypad_poll(void);
/* Character of the key at row, col (for the host's panel and tests). */
char keypad_char(uint8_t row, uint8_t col) __reentrant;

#endif

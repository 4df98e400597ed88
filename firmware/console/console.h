/* console.h: the operator console: run screen, parameter menus, calibrations, totals, alarms, on the LCD12864 and keypad. */
#ifndef CONSOLE_H
#define CONSOLE_H

#include "compiler.h"
#include "params.h"

/*
 * Keys (keypad.h has the matrix):
 *   run screen   A menu, B totals page, # manual <-> auto, 2 / 8 jog the valve in manual
 *                mode (more / less flow; held: repeats); in auto 2 / 8 nudge the rate in use
 *                up / down by Rate step % (within +-50 %), 5 back to the preset, 0 Rate 1 <->
 *                Rate 2
 *   any screen   * acknowledges the alarm or the EEPROM notice the bottom line shows, only that;
 *                when it shows neither, * shows the first waiting (a second * acknowledges it)
 *   menu         A previous item, B next item, D open the item, C back to the run screen
 *   number entry 0-9 digits, # decimal point, D accept (refused with "Range lo..hi" when out
 *                of range: the old value stays), C clear the entry, C again back to the menu
 *   choice       A / B step through the choices, D accept, C back
 *   calibration  D start / stop / save, C cancel
 *   totals       D "Reset job? D=yes", D again resets the job totals, C back
 *   I/O test     1 spray relay on/off, 3 buzzer on/off, 2 / 8 jog the valve, C back (the
 *                boom's control is off while it shows; inputs as raw counts and pulses)
 * Every accepted change goes through param_set() and is written to the EEPROM (store.h).
 */
#define CONSOLE_REDRAW_MS 250       /* the run screen's refresh */
#define CONSOLE_MSG_MS 2500         /* how long a message stays on the bottom line */
#define CONSOLE_REMIND_MS 32768u    /* while the rate is nudged: a reminder this often (a power of 2) */

/* Menu entries after the parameters (their index in the menu is P_COUNT + n). */
#define MENU_CAL_SPEED (P_COUNT + 0)
#define MENU_CAL_TANK (P_COUNT + 1)
#define MENU_TOTALS (P_COUNT + 2)
#if FW_IOTEST
#define MENU_IOTEST (P_COUNT + 3)   /* the bench's images only (FW_IOTEST, hal/compiler.h) */
#endif
#define MENU_NOZZLES (P_COUNT + 3 + FW_IOTEST)  /* D: the nozzle model is learnt again (diag.h) */
#define MENU_COUNT (P_COUNT + 4 + FW_IOTEST)

void console_init(void);
/* From the main loop: keypad scan, key handling, screen refresh, LCD update. */
void console_poll(void);

#endif

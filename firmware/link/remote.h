/* remote.h: the subset of Raven's remote-computer serial strings a field computer uses to set the rate and read back. */
#ifndef REMOTE_H
#define REMOTE_H

#include "compiler.h"

/*
 * With Remote = Raven (P_REMOTE 1) the serial link also speaks the strings Raven's SCS consoles
 * exchange with a remote computer (a GPS display applying a prescription map), each ended by
 * CR LF, no checksum:
 *   from the computer            the console's answer (RAVEN_ID "$R100A")
 *   $R,RC,<rate_1>               the rate, L/ha with the decimal point not sent (1300 = 130.0),
 *                                taken within the operator's window around Dose (P_REMOTE_WIN):
 *                                $R100A,AR,<actual_rate>; refused: ERR WINDOW (our own line)
 *   $R,CR                        $R100A,C1,<switch_byte_1>,<switch_byte_2>,<boom_1_cal>,..,<boom_6_cal>,<speed_cal>
 *                                $R100A,C2,<meter_cal>,<spreader_constant>
 *                                $R100A,C3,<valve_cal>,<rate_1_cal>,<rate_2_cal>
 *   $R,DR                        $R100A,D1,<total_area>,<field_area>
 *                                $R100A,D2,<total_volume>,<field_volume>
 *                                $R100A,D3,<tank_volume>,<distance>
 * and $R100A,AR,<actual_rate> once a second, after the LOG line. README has the units.
 * Anything else starting with '$' gets our own ERR line (ERR REMOTE with Remote off, ERR CMD,
 * ERR ARG, ERR NUM) and changes nothing.
 */
#define RAVEN_ID "$R100A,"

/* A line that starts with '$': 0 when it was taken (its answers are queued), else the reason
 * for our ERR line ("REMOTE", "CMD", "ARG", "NUM", "WINDOW"). */
const __code char *remote_command(const __xdata char *line) __reentrant;
/* The error words both parsers answer with (one copy in the code memory; serial.c's too). */
extern const __code char link_e_cmd[], link_e_arg[], link_e_num[];
/* The next queued Raven line, composed with serial_put_* (linebuf.h; CR LF not included): 1, or 0 when
 * none is due. */
uint8_t remote_next(void) __reentrant;
/* Once a second: queue the actual rate (with Remote on). */
void remote_tick(void);

#endif

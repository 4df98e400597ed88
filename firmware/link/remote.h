/* remote.h: the serial link as a Raven console's (Remote = Raven): the strings a field computer uses to set the rate and read back, and the console's data logger. */
#ifndef REMOTE_H
#define REMOTE_H

#include "compiler.h"

/*
 * With Remote = Raven (P_REMOTE 1: 9600 baud, 2: 1200 baud, 8 data bits, no parity, 2 stop
 * bits, as Raven's SCS consoles) the link speaks only the strings those consoles exchange with
 * a remote computer (a GPS display applying a prescription map), each ended by CR LF, no check;
 * it sends nothing else (no LOG, ALM, BOOT or ERR line) and stays silent on a line it cannot
 * use. As the Hiniker 8605 emulating a Raven 450 (docs/REMOTE.md: the sources, and what we chose
 * where they are silent):
 *   from the computer              the console
 *   $R,RC,<rate_1>[,<rate_2>..]    rate 1, L/ha with the decimal point not sent (1300 = 130.0;
 *                                  in US units gal/acre, 150 = 15.0; turf gal/1000 ft^2, 34 =
 *                                  0.34), taken within the operator's window around the preset
 *                                  in use (P_REMOTE_WIN);
 *                                  an empty field changes nothing, the other products' are
 *                                  checked and not used; no reply (a refusal shows on the LCD)
 *   $R,CR                          C1, C2, C3
 *   $R,DR                          D1, D2, D3, TD
 * every RAVEN_ID then:
 *   AR,<actual_rate>
 *   C1,<switch_byte_1>,<switch_byte_2>,<boom_1_cal>,..,<boom_6_cal>,<speed_cal>
 *   C2,<meter_cal>,<spreader_constant>     C3,<valve_cal>,<rate_1_cal>,<rate_2_cal>
 *   D1,<total_area>,<field_area>   D2,<total_volume>,<field_volume>   D3,<tank_volume>,<distance>
 *   TD,<hr:min>,<month/day/year>,<field_reference>
 * The data logger (on while Log every is not 0): every Log every metres or seconds (Log unit)
 * AR, D1, D2, D3, TD; after a value of the C lines changes C1, C2, C3; after a switch byte
 * changes D1, D2, D3, TD, C1, C2, C3. The fields are in the console's units (P_UNITS: metric,
 * or as a Raven console set to US units sends them; docs/REMOTE.md has each).
 */
#define RAVEN_ID "$R124F,"
/* switch byte 2's rate bits (bit 7 always set): rate 1 or rate 2 in use; neither: manual */
#define REMOTE_SW2_RATE1 0x08u
#define REMOTE_SW2_RATE2 0x10u

/* A line that starts with '$' (Remote on): 1 when it was taken (its answers are queued, a rate
 * set), 0 when it cannot be used (malformed, or a rate outside the window): nothing changes. */
uint8_t remote_command(const __xdata char *line) __reentrant;
/* The error words both parsers answer with (one copy in the code memory; serial.c's too). */
extern const __code char link_e_cmd[], link_e_arg[], link_e_num[];
/* The next line due (the data logger looked at first), composed with serial_put_* (linebuf.h;
 * CR LF not included): 1, or 0 when none is due. Remote on only. */
uint8_t remote_next(void) __reentrant;
/* Once a second: the data logger's time trigger (with Remote off: its state dropped). */
void remote_tick(void) __reentrant;

#endif

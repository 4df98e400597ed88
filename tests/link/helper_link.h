/* helper_link.h: the main loop on the host HAL, as the serial-link tests drive it: a bench start
 * (pressure 4 mA, tank full, every section on), 1 ms passes, bytes into the UART, lines out of it. */
#ifndef HELPER_LINK_H
#define HELPER_LINK_H

#include <stddef.h>
#include <stdint.h>

/* 4-20 mA input in ADC counts */
#define LINK_MA(x) ((uint16_t)((x) * 51.15 + 0.5))

extern uint64_t link_t_ms;     /* the host HAL's clock, in ms */

/* reset the host HAL, set the bench inputs (the pressure at pressure_ma), app_init(); the
 * clock at 0 */
void link_start_at(double pressure_ma);
/* the same with no pressure (4 mA) */
void link_start(void);
/* a power cut and a power-up: the chip restarts (hal_init, app_init) at time 0 with the EEPROM
 * as it was and the bench inputs again, nothing else kept */
void link_power_cycle(void);
/* ms passes of the main loop, one a millisecond */
void link_run_ms(uint32_t ms);
/* the bytes of s into the UART's receive side */
void link_send(const char *s);
/* the next line the firmware sent, up to and without its '\n', into buf (cut to n - 1 bytes);
 * its length, 0 when nothing waits */
size_t link_read_line(char *buf, size_t n);

#endif

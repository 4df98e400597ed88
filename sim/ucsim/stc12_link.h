/* stc12_link.h: the lock-step frames between the STC12C5A60S2 model in uCsim (sim/ucsim/stc12.cc) and the host's plant (sim/chip_host.c). */
#ifndef STC12_LINK_H
#define STC12_LINK_H

/*
 * Two FIFOs, named by the environment of the model (STC12_LINK_IN, the host's frames;
 * STC12_LINK_OUT, the model's). Numbers little-endian. Time is counted in SYSCLK clocks from the
 * model's power-on, 11.0592 MHz: a clock is 1e9 * 78125 / 864 / 1e9 ns (STC12_CLK_OF_NS).
 *
 * Start:  host 'C' eeprom(1024) app_poll(2) n_watch(1) (addr(2) len(1))*n_watch
 *         the EEPROM's content at power-on, the code address whose every fetch outside an
 *         interrupt begins a main-loop pass, the XRAM ranges each report carries.
 * Slot:   host 'S' end(8) n(2) (clock(8) kind(1) value(4))*n: the inputs up to the clock `end`,
 *         each at its exact clock (events in time order, all before `end`); the model runs to
 *         `end` and answers 'R' (below). Host 'Q': the model answers 'X' (below) and quits.
 * Report: 'R' pins(4) pwm1(2) resets(1) cause(1) passes(2) pass_max(4) pass_sum(4)
 *         max_adc(1) max_iap(1) step_max(4) early(2)
 *         n_tx(1) (clock(8) byte(1) bit_clocks(2) frame_bits(1))*n_tx  watch bytes
 *         pins: the level each output pin drives, strong high 1 (push-pull latch 1, or
 *         the PCA's PWM output where module 1 drives P1.4): P1 in byte 0, P3 in byte 1;
 *         weak high (quasi-bidirectional latch 1) in bytes 2 (P1) and 3 (P3);
 *         pwm1: module 1's high time in 1/256 of its period (0..256), 0 outside PWM mode;
 *         resets: chip resets in the slot (watchdog), cause: WDT_CONTR after the last one;
 *         passes: main-loop passes begun in the slot, their longest and total clocks (a
 *         pass ends where the next begins; interrupt time inside it included); the
 *         conversions and IAP operations the longest one started; the longest pass that
 *         started 8 conversions or more (a control step: pressure and level 4 times each);
 *         early: the output pins (P1 low byte, P3 high byte) that drove high at any instruction
 *         from a reset to the first main-loop pass after it, since the last report;
 *         tx: the frames the UART started sending in the slot (start bit's clock, the data
 *         byte, its bit time in clocks, data + stop bits: 9 for 8N1, 10 for 8N2).
 * End:    'X' sp_max(1) n_vec(1) (vector(2) count(4) max(4) own_max(4) own_sum(8))*n_vec: the
 *         highest SP from the first main-loop pass on (internal RAM ends at 0xFF); each interrupt
 *         handler's clocks from its acceptance (the hardware's call included) to the end of its
 *         RETI: the longest with the handlers that preempted it, and its own time without them.
 */
#define STC12_SYSCLK_HZ 11059200u
#define STC12_CLK_OF_NS(ns) ((uint64_t)(ns) * 864u / 78125u)
#define STC12_NS_OF_CLK(c) ((uint64_t)(c) * 78125u / 864u)
#define STC12_EEPROM_SIZE 1024
#define STC12_WATCH_MAX 8

#define STC12_EV_WHEEL 1        /* a falling edge on P3.2 (INT0); the pin back high 20 us later */
#define STC12_EV_METER 2        /* a falling edge on P1.3 (CCP0); back high 20 us later */
#define STC12_EV_RX 3           /* a frame on RXD from its start bit: byte | bit_clocks << 8 | stop bits << 24 */
#define STC12_EV_ADC 4          /* the voltage at ADC channel (value >> 12) as 10-bit counts (value & 0x3FF) */
#define STC12_EV_KEYS 5         /* keypad: bit 4 * row + column set while that key is held */
#define STC12_EV_P0 6           /* what the section switches drive on P0 (0: pulled to ground) */
#define STC12_EV_RESET 7        /* the reset pin pulsed: the chip starts again (RAM and EEPROM kept) */
#define STC12_EV_HANG 8         /* the main loop hangs from here (the CPU no longer advances outside
                                 * interrupts, as in a loop waiting for what never comes) until a reset */
#define STC12_EV_WHEEL_SWEEP 9  /* from here every wheel edge falls `value` + 3k clocks before the k-th
                                 * next PCA overflow (k = 0, 1, ... wrapping at 600): the capture race's
                                 * window swept; the host's own wheel edges are not sent meanwhile */
#define STC12_PULSE_CLOCKS 221  /* 20 us */

#endif

/* hal_host.h: the host backend's boundary to the plant model: actuator outputs in, sensor signals out. */
#ifndef HAL_HOST_H
#define HAL_HOST_H

#include "hal.h"

#define HAL_HOST_EDGES 4096         /* pulse edges queued between two takes, at most */
#define HAL_HOST_UART_Q 4096

/* One plain struct, as ArduPilot's SITL does: the simulator writes the sensor side and reads
 * the actuator side; the firmware sees it only through hal.h. Simulated time is the only clock. */
typedef struct {
    /* simulated time */
    uint64_t time_ns;               /* set by hal_host_set_time_ns only (it keeps hal_ms's copy) */
    /* actuators, written by the firmware */
    int8_t valve_dir;               /* HAL_VALVE_OPEN / _CLOSE / _OFF */
    uint8_t valve_duty;             /* 0..255 */
    uint8_t spray_on;
    uint8_t buzzer;
    /* sensors, written by the simulator */
    uint16_t adc[8];                /* 10-bit counts */
    uint8_t sections;               /* switch bits */
    uint16_t keys;                  /* bit 4*row + col set while that key is held */
    uint8_t wdt_kicks;              /* counts kicks (wraps) so tests can see the loop feeds it */
    uint32_t wdt_last_kick_ms;
    uint8_t reset_cause;            /* HAL_RESET_*, what hal_reset_cause() reports */
    uint8_t supply_low;             /* the low-voltage detector's answer */
    uint32_t eeprom_erases;         /* sector erases since the reset, for wear figures */
} hal_host_io_t;

extern hal_host_io_t hal_host_io;

/* Reset the whole backend (time 0, queues and EEPROM erased, actuators off). */
void hal_host_reset(void);
/* The supply comes back after a cut: the pulse and UART queues empty, the outputs off, no key
 * held, the reset cause HAL_RESET_POWER; the EEPROM, the clock, the switches and the ADC's
 * source stay (the firmware's RAM is its own: the caller starts it again). */
void hal_host_power_on(void);
/* Advance simulated time (never backwards). */
void hal_host_set_time_ns(uint64_t t_ns);
/* PCA time of a simulated instant, as the capture unit would latch it. */
uint32_t hal_host_pca_of_ns(uint64_t t_ns);
/* Queue a pulse edge at its exact simulated time (must not lie in the future of time_ns). */
void hal_host_flow_edge(uint64_t t_ns);
void hal_host_wheel_edge(uint64_t t_ns);

/* Serial link (hal_uart.c): bytes the firmware sent, and bytes for it to receive. The line is
 * modelled bit by bit: a pushed byte travels the wire as its frame (start bit, 8 data bits, the
 * stop bits) at the PC's framing, from the end of the one before or the time it is pushed; the
 * chip's receiver, at the framing the firmware set (hal_uart_framing), finds each start bit's
 * falling edge, samples every bit in its middle and takes the byte at the end of its own
 * frame, as the 8051's UART does: no framing error, so a PC at another baud rate or a chip in
 * mode 3 fed back-to-back 8N1 frames reads garbled bytes. Into a 16-byte receive queue (15
 * bytes waiting at most), a quarter of the chip's HAL_UART_RXQ: the host's tests and fuzzing
 * see losses a firmware that does not read for 4 ms makes (the chip's queue holds 16 ms), and
 * the bytes completed while an IAP erase holds the CPU (HAL_HOST_IAP_ERASE_NS) are lost; the
 * firmware reads HAL_UART_LOST where the gap is. By default the PC follows the chip's framing. */
#define HAL_HOST_UART_RXQ 16
#define HAL_HOST_IAP_ERASE_NS 21000000u
int hal_host_uart_tx_pop(void);     /* -1 when empty */
void hal_host_uart_rx_push(uint8_t b);
uint32_t hal_host_uart_rx_waiting(void);    /* hal_uart_get calls that would not return -1 now */
/* The PC's own framing (HAL_UART_*), or -1: the chip's, whatever it is (the default). With a
 * framing set, the PC receives what the chip sends bit by bit at that framing instead of
 * through hal_host_uart_tx_pop: hal_host_uart_pc_get gives the next byte whose frame has ended
 * by now, -1 when none (a frame nobody reads is forgotten after HAL_HOST_UART_Q more). */
void hal_host_uart_pc_framing(int f);
#define HAL_HOST_UART_9600_8N1 3    /* a framing for the PC only: one stop bit */
int hal_host_uart_pc_get(void);
/* The chip's framing now (HAL_UART_*) and the wire time of one of its frames, ns. */
uint8_t hal_host_uart_framing(void);
uint64_t hal_host_uart_frame_ns(uint8_t f);
/* (hal_host.c's) the UART's state at a reset or power-up; the framing hal_init sets; an IAP
 * operation holding the CPU from from_ns to until_ns */
void hal_host_uart_reset(void);
void hal_host_uart_init(void);
void hal_host_uart_hold(uint64_t from_ns, uint64_t until_ns);

/* EEPROM: direct access for tests, and a power cut after n more programmed bytes or erases
 * (-1: never). A cut operation leaves the cell as it was; later ones are lost as well. */
uint8_t *hal_host_eeprom(void);
void hal_host_eeprom_cut_after(int32_t n);
uint8_t hal_host_eeprom_cut(void);   /* 1 once the cut has happened */

/* LCD: the bytes written go to this function (the ST7920 emulator), when set. */
/* Where a conversion comes from: with a source set, each hal_adc_read(ch) asks it (the plant
 * draws the noise of that one conversion) and keeps the result in hal_host_io.adc[ch];
 * without one (NULL, after hal_host_reset), hal_adc_read returns hal_host_io.adc[ch]. */
void hal_host_adc_source(uint16_t (*source)(uint8_t ch));
void hal_host_lcd_sink(void (*sink)(uint8_t rs, uint8_t b));

#endif

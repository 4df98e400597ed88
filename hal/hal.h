/* hal.h: the only interface between the firmware and a machine; one backend per folder, chosen at link time. */
#ifndef HAL_H
#define HAL_H

#include "compiler.h"

/* The functions here with more than one parameter are __reentrant: modules compiled with
 * #pragma stackauto (docs/MEMORY.md) see every prototype as reentrant and pass the second
 * parameter on the stack, so the HAL's definitions must take it from there too. */

#if !defined(HAL_STC12) && !defined(HAL_HOST) && !defined(HAL_UCSIM) && !defined(HAL_PIL)
#error "unknown HAL backend: build with -DHAL_STC12, -DHAL_HOST, -DHAL_UCSIM or -DHAL_PIL (the Makefile passes the one each build needs)"
#endif

/* ---- clocks ------------------------------------------------------------------------------
 * hal_ms: milliseconds since start, counted off the PCA counter (wraps after 49 days); true
 * time also across a late interrupt or a CPU held by an IAP erase.
 * The capture clock is the PCA counter at SYSCLK/12 = 921600 Hz (1.085 us), extended to
 * 32 bits by counting its overflows (wraps after 77.7 min: use unsigned differences).  */
#define HAL_SYSCLK_HZ 11059200UL
#define HAL_PCA_HZ 921600UL
void hal_init(void);
uint32_t hal_ms(void);
uint32_t hal_pca_now(void);

/* ---- pulse inputs (flow meter on PCA capture, wheel on INT0 time-stamped with the PCA) --
 * take() hands over what arrived since the last take: the number of edges and the 32-bit
 * PCA time of the newest one (unchanged when count is 0), then starts a new window.     */
typedef struct {
    uint16_t count;     /* edges since the previous take */
    uint32_t last;      /* PCA time of the newest edge */
    uint8_t rejected;   /* edges dropped as too early since the previous take (saturates) */
} hal_capture_t;
/* c in the internal RAM (the caller's stack or __data): an 8-bit pointer, no generic stores */
void hal_flow_capture_take(__idata hal_capture_t *c);
void hal_wheel_capture_take(__idata hal_capture_t *c);
/* The wheel input drops an edge that comes sooner than min_ticks after the last one it kept
 * (bounce, interference: a real pulse cannot come that early) and counts it in `rejected`;
 * 0 keeps every edge. The speed module sets it each period from the speed it measures. */
void hal_wheel_min_interval(uint32_t min_ticks);

/* ---- analog inputs: 10-bit ADC (0..1023 over 0..5 V), 4-20 mA through 250 ohm ------------ */
#define HAL_ADC_PRESSURE 0
#define HAL_ADC_LEVEL 1
uint16_t hal_adc_read(uint8_t ch);

/* ---- digital inputs ----------------------------------------------------------------------- */
#define HAL_SECTIONS_MAX 8
/* Section switches, bit n set = section n+1 switched on (the operator's boom switches). */
uint8_t hal_sections(void);
/* Keypad matrix: drive row (0..3) low, return the 4 column bits, 1 = key pressed. */
uint8_t hal_keypad_row(uint8_t row);

/* ---- actuators ---------------------------------------------------------------------------- */
/* Valve H-bridge: dir +1 opens the bypass (less boom flow), -1 closes it, 0 leaves both half
 * bridges off (coast); duty 0..255 is the PWM on the enable line. Dead time on reversal is
 * the firmware's job (firmware/control/valve.c), not the HAL's. */
#define HAL_VALVE_OPEN 1
#define HAL_VALVE_CLOSE -1
#define HAL_VALVE_OFF 0
void hal_valve_out(int8_t dir, uint8_t duty) __reentrant;
/* Master boom valve: 1 sprays, 0 shuts the boom. */
void hal_spray_enable(uint8_t on);
void hal_buzzer(uint8_t on);

/* ---- hardware in the loop (firmware/link/hil.h) --------------------------------------------
 * Built in unless FW_HIL is 0: the chip's image leaves it out until its memory plan makes
 * room (make firmware HIL=1 builds it in; docs/HIL.md). */
#ifndef FW_HIL
#define FW_HIL 1
#endif
#if FW_HIL
/* hal_hil(s) with s set: the inputs above read *s, which the PC's plant model fills each
 * period over the serial link (PCA time, both captures, the two ADC channels, the section
 * switches), hal_wheel_min_interval writes s->wheel_min for the PC's edge filter, and the
 * valve bridge, boom relay and buzzer pins are held off: the outputs go to the PC in a frame,
 * never to a sprayer that may still be connected. hal_hil(0) gives the pins back. */
typedef struct {
    uint32_t pca_now;
    hal_capture_t wheel, meter;
    uint16_t adc[2];                /* HAL_ADC_PRESSURE, HAL_ADC_LEVEL */
    uint8_t sections;
    uint32_t wheel_min;             /* hal_wheel_min_interval's ticks, for the PC */
} hal_hil_t;
void hal_hil(hal_hil_t *s);
/* 1 while hal_hil holds a frame's inputs (the console shows "HIL"). */
uint8_t hal_hil_active(void);
#else
#define hal_hil_active() 0
#endif

/* ---- serial link (RS232 to the PC) -------------------------------------------------------- */
#define HAL_UART_BAUD 38400UL       /* our own protocol's rate (HAL_UART_38400_8N1) */
/* The link's framing: our own protocol's, or a Raven console's (9600 or 1200 baud, 8 data bits,
 * no parity, 2 stop bits). At reset HAL_UART_38400_8N1. */
#define HAL_UART_38400_8N1 0
#define HAL_UART_9600_8N2 1
#define HAL_UART_1200_8N2 2
/* Switch to framing f: 1 when done, 0 (nothing changed) while bytes still wait to go out at
 * the old one (call again later: it never waits). */
uint8_t hal_uart_framing(uint8_t f);
/* The receive queue's size (a power of two; the ring holds one byte less): hal/stc12's
 * uart.c sizes it for the main loop's passes, the host backend models the same. */
#define HAL_UART_RXQ 64
/* Queue one byte; returns 0 when the transmit buffer is full (the byte is not taken). */
uint8_t hal_uart_put(uint8_t b);
/* Next received byte, -1 when none, or HAL_UART_LOST where bytes were lost (the
 * receive queue full, or bytes arriving while an IAP operation held the CPU); the bytes
 * before the gap come first, the ones after it next. */
#define HAL_UART_LOST (-2)
int16_t hal_uart_get(void);

/* ---- parameter EEPROM (IAP flash: 2 sectors of 512 bytes, erased bytes read 0xFF) -------- */
#define HAL_EEPROM_SIZE 1024u
#define HAL_EEPROM_SECTOR 512u
uint8_t hal_eeprom_read(uint16_t addr);
/* Erase the sector that holds addr. */
void hal_eeprom_erase(uint16_t addr);
/* Program one byte (can only clear bits); returns 1 when the byte reads back as written. */
uint8_t hal_eeprom_write(uint16_t addr, uint8_t b) __reentrant;

/* ---- LCD12864 (ST7920, serial mode): one instruction (rs = 0) or data (rs = 1) byte -------- */
void hal_lcd_write(uint8_t rs, uint8_t b) __reentrant;
/* 1 while the ST7920 still executes the last byte (a write now would wait for it): the driver
 * leaves the rest of a screen to the next pass instead. */
uint8_t hal_lcd_busy(void);

/* ---- watchdog (about 1.1 s) ---------------------------------------------------------------- */
void hal_wdt_kick(void);

/* ---- reset cause and supply --------------------------------------------------------------- */
#define HAL_RESET_POWER 0           /* the supply came up */
#define HAL_RESET_WATCHDOG 1        /* the watchdog was not fed (a hung loop, an internal fault) */
#define HAL_RESET_BROWNOUT 2        /* the supply dipped below the low-voltage threshold */
#define HAL_RESET_OTHER 3           /* the reset pin */
/* Why the chip last reset (read once in hal_init). */
uint8_t hal_reset_cause(void);
/* 1 while the supply is below the low-voltage detector's threshold: no EEPROM writes then. */
uint8_t hal_supply_low(void);

#ifdef HAL_STC12
/* SDCC puts an interrupt vector only where the handler's prototype is seen by main()'s file. */
#include "stc12/isr.h"
#endif

#endif

/* pgn.h: AgOpenGPS machine frames and RateControl module frames among the serial link's text lines. */
#ifndef PGN_H
#define PGN_H

#include "compiler.h"

/* pgn_byte's verdicts */
#define PGN_NO 0                    /* not a frame's byte: the text parser's */
#define PGN_IN 1                    /* taken into a frame */
#define PGN_END 2                   /* a frame ended (taken or dropped) */
#define PGN_NOISE 3                 /* the byte before began no frame (dropped, counted): this
                                     * one is the text parser's, the line it fell in is spoilt */

#if FW_PGN

/*
 * With Remote = AgOpenGPS (P_REMOTE REMOTE_PGN) the link also takes binary PGN frames between (or
 * inside) its text lines; a byte that starts no frame goes to the text parser as before.
 *   AgOpenGPS (AgIO's machine port): 80 81 src pgn len data.. crc, crc the low byte of the sum of
 *   bytes 2 to n-2. Taken: 254 (len 8: speed km/h x10 u16 LE, status, steer, xte, sections 1-8,
 *   9-16), 239 (len 8: uturn, speed x10 u8, lift, tram, geoStop, -, sections 1-8, 9-16), 229
 *   (len 10: sections 1-64, tool speeds); another pgn with a good crc is skipped.
 *   RateControl (SK21, a module's frames): pgn u16 LE first, crc the low byte of the sum of bytes 0
 *   to n-2. 32500 (F4 7E, 14 bytes: module<<4|sensor, target UPM x1000 u24, meter cal x1000 u24,
 *   command, manual PWM i16, -, crc), 32501 (F5 7E, 11 bytes: module, relays lo, hi, power relays
 *   lo, hi, inverted lo, hi, master valve, crc), 32502 (F6 7E, 24 bytes: module<<4|sensor, max PWM %,
 *   min PWM %, Kp, Ki, dead band % x10, ...).
 * A frame whose second byte, length or crc is wrong, or that loses a byte or stalls (serial.c:
 * as a line does) is dropped and counted (pgn_rx.bad). Replies (pgn_next): 237 to each 239 taken
 * (AOG reply), 32400 and 32401 to each 32500 of this module (RC module).
 */
#define PGN_BUF 12                  /* frame bytes kept (those after are summed, not kept) */
#define PGN_OUT_MAX 15              /* the longest reply */
#define PGN_OFF_PERIODS 20u         /* "both": the speeds apart this many periods more than together */
#define PGN_CHECK_X100 200u         /* ... judged from this GPS speed, km/h x100 */


/* What the frames carried last (each field from its own frame). */
typedef struct {
    uint16_t gps_kmh_x10;           /* 254 */
    uint8_t sections;               /* boom sections (bit 0 = section 1) from 239, 229 or 32501 */
    uint32_t rc_upm_x1000;          /* 32500: the target, units (litres) a minute x1000 */
    uint8_t rc_cmd;                 /* 32500: command byte (bit 4 MasterOn, bit 6 AutoOn) */
    uint16_t taken;                 /* frames taken */
    uint16_t bad;                   /* frames dropped */
} pgn_rx_t;
extern __xdata pgn_rx_t pgn_rx;

void pgn_init(void);
/* One received byte (serial_poll): PGN_NO, PGN_IN or PGN_END. */
uint8_t pgn_byte(uint8_t b) __reentrant;
/* Bytes were lost (HAL_UART_LOST): a frame in progress is dropped. */
void pgn_drop(void);
/* Once a period: the speed the target follows (km/h x100) from the wheel's and the GPS's by
 * Speed src; judges the two ("both") and a stalled frame. */
uint16_t pgn_speed(uint16_t wheel_x100) __reentrant;
/* The boom sections to use: the switches', and with AOG sections on the frames' too (none
 * once the frames stop for Frames lost). */
uint8_t pgn_sections(uint8_t switches) __reentrant;
/* 1 while frames in use have stopped for Frames lost (SPEED_LOST). */
uint8_t pgn_lost(void) __reentrant;
/* The frames' state for the alarms: diag.h DIAG_FRAMES_* (lost, speeds apart, GPS in use). */
uint8_t pgn_frames(void) __reentrant;
/* A reply frame due, into buf (PGN_OUT_MAX bytes): its length, 0 when none. */
uint8_t pgn_next(__xdata uint8_t *buf) __reentrant;
/* 1 while a frame is coming in (the lines to send wait, as for a line coming in). */
uint8_t pgn_busy(void);
#else
/* without FW_PGN: the wheel's speed and the switches' sections as they are */
#define pgn_speed(wheel_x100) (wheel_x100)
#define pgn_sections(switches) (switches)
#define pgn_busy() 0
#define pgn_drop()
#endif
/* serial_poll's byte chain (serial.c), nothing without FW_PGN: the verdict v on each byte b;
 * PGN_CHAIN the branches for a frame's bytes (a frame ended: the pass's work done), PGN_NOISY
 * the text parser's condition that the byte before began no frame (this line refused) */
#if FW_PGN
#define PGN_VERDICT(v) uint8_t v;
#define PGN_CHAIN(v, b) } else if (((v) = pgn_byte(b)) == PGN_END) { return 1; } else if ((v) == PGN_IN) {
#define PGN_NOISY(v) || (v) == PGN_NOISE
#else
#define PGN_VERDICT(v)
#define PGN_CHAIN(v, b)
#define PGN_NOISY(v)
#endif

#endif

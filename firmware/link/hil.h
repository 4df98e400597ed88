/* hil.h: hardware-in-the-loop frames: the PC's plant sends sensor inputs, the controller answers with its outputs. */
#ifndef HIL_H
#define HIL_H

#include "compiler.h"

/*
 * Binary frames on the RS232 link (38400 8N1), every integer little endian, a CRC-16/CCITT
 * (poly 0x1021, init 0xFFFF, the EEPROM record's) over every byte before it, high byte first.
 * The PC sends one sensor frame a control period and waits for the answer (docs/HIL.md):
 *
 * sensor frame, PC -> controller, HIL_IN_BYTES:
 *   0      HIL_IN_START (0xA5: no log line or command holds it)
 *   1      sequence number, one more (mod 256) each frame
 *   2..5   PCA time of the frame's instant (921.6 kHz, hal_pca_now)
 *   6..7   wheel edges since the last frame      8..11  PCA time of the newest wheel edge
 *   12..13 meter edges since the last frame      14..17 PCA time of the newest meter edge
 *   18..19 pressure ADC counts (0..1023)         20..21 level ADC counts (0..1023)
 *   22     section switch bits
 *   23..24 CRC
 * output frame, controller -> PC, HIL_OUT_BYTES:
 *   0      HIL_OUT_START (0x5A)
 *   1      the sequence number of the sensor frame it answers
 *   2      valve direction (int8: +1 opens the bypass, -1 closes, 0 off)   3  PWM duty 0..255
 *   4      bit 0 master boom relay, bit 1 buzzer
 *   5..6   alarm bits
 *   7..8   frames lost or damaged since HIL mode began (the controller's count)
 *   9..10  working speed km/h x100    11..12 target L/min x100 (int16)
 *   13..14 measured flow L/min x100 (int16)    15..16 pressure kPa
 *   17..18 CRC
 */
#define HIL_IN_START 0xA5
#define HIL_OUT_START 0x5A
#define HIL_IN_BYTES 25
#define HIL_OUT_BYTES 19

typedef struct {
    uint8_t seq;
    uint32_t pca_now;
    uint16_t wheel_count;
    uint32_t wheel_last;
    uint16_t meter_count;
    uint32_t meter_last;
    uint16_t adc_pressure, adc_level;
    uint8_t sections;
} hil_in_t;

typedef struct {
    uint8_t seq;
    int8_t valve_dir;
    uint8_t valve_duty;
    uint8_t relays;                 /* bit 0 boom relay, bit 1 buzzer */
    uint16_t alarms;
    uint16_t lost;
    uint16_t speed_kmh_x100;
    int16_t target_lpm_x100;
    int16_t flow_lpm_x100;
    uint16_t pressure_kpa;
} hil_out_t;

/* The receiver of one direction's frames: bytes in, whole checked frames out. */
typedef struct {
    uint8_t buf[HIL_IN_BYTES];      /* the frame being collected (the longer of the two) */
    uint8_t n;                      /* bytes in buf */
    uint8_t start, size;            /* which frames it looks for */
    uint8_t synced;                 /* a good frame has been seen (bytes before the first one are noise) */
    uint16_t damaged;               /* frames that failed their CRC or were cut short */
} hil_rx_t;

uint16_t hil_crc(const uint8_t *p, uint8_t n) __reentrant;
/* Start a receiver for sensor frames (HIL_IN_START) or output frames (HIL_OUT_START). */
void hil_rx_init(hil_rx_t *rx, uint8_t start) __reentrant;
/* One received byte; 1 when it completes a frame whose CRC holds (then rx->buf holds it).
 * A frame that fails is counted in rx->damaged and the bytes after its start are searched
 * again for a start, so one lost byte costs one frame. */
uint8_t hil_rx_byte(hil_rx_t *rx, uint8_t b) __reentrant;
/* Write the CRC over the size - 2 bytes before it into the frame's last two bytes. */
void hil_put_crc(uint8_t *f, uint8_t size) __reentrant;
/* The controller's half: decode a checked sensor frame, encode an output frame (start byte and
 * CRC included) into f. */
void hil_in_decode(const uint8_t *f, hil_in_t *in) __reentrant;
void hil_out_encode(const hil_out_t *out, uint8_t *f) __reentrant;
/* The PC's half (sim/hil_pc.c, host only: the chip needs neither). */
void hil_in_encode(const hil_in_t *in, uint8_t *f);
void hil_out_decode(const uint8_t *f, hil_out_t *out);

#endif

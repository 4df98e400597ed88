/* hil.h: hardware-in-the-loop frames: the PC's plant sends sensor inputs, the controller answers with its outputs. */
#ifndef HIL_H
#define HIL_H

#include "compiler.h"
#include "hal.h"

#if FW_HIL

/*
 * Hardware in the loop (docs/HIL.md): the PC runs the plant model and stands in for the pins.
 * `HIL ON*HH` (the checksum is required) switches the controller over: from then on each
 * control period is one binary sensor frame from the PC, one control step on it (the
 * application restarts at the first, as at power-on), one output frame back; the pins are held
 * off (hal_hil), log lines stop. A reset leaves the mode; so does the watchdog when the frames
 * stop for 1.1 s. The LCD shows "HIL" on the run screen.
 *
 * Frames: every integer little endian, a CRC-16/CCITT (poly 0x1021, init 0xFFFF, the EEPROM
 * record's) over every byte before it, high byte first.
 * sensor frame, PC -> controller, HIL_IN_BYTES:
 *   0      HIL_IN_START (0xA5: no log line or command holds it)
 *   1      sequence number, one more (mod 256) each frame
 *   2..5   PCA time of the frame's instant (921.6 kHz, hal_pca_now)
 *   6..7   wheel edges since HIL ON (mod 2^16)   8..11  PCA time of the newest wheel edge
 *   12     wheel edges the PC's filter dropped since HIL ON (mod 2^8; the output frame's wheel_min)
 *   13..14 meter edges since HIL ON (mod 2^16)   15..18 PCA time of the newest meter edge
 *          (running totals: a frame that is lost loses no edge, the next one carries it)
 *   19..20 pressure ADC counts, the sum of the period's 4 conversions (0..4092: analog.c averages
 *          four; the HAL returns its quarters, which add up to it)   21..22 level, the same
 *   23     section switch bits
 *   24     a setting the operator changed (params.h id; HIL_NO_SETTING: none)   25..26 its value;
 *          set before the frame's step, as the keypad or SET would (one a frame)
 *   27..28 CRC
 * output frame, controller -> PC, HIL_OUT_BYTES:
 *   0      HIL_OUT_START (0x5A)
 *   1      the sequence number of the sensor frame it answers
 *   2      valve direction the bridge is to drive (int8: +1 opens the bypass, -1 closes, 0 off)
 *   3      its PWM duty 0..255      4  ms from the frame's instant until the bridge drives it
 *          (the dead time of a reversal; off until then)
 *   5      bit 0 master boom relay, bit 1 buzzer
 *   6..7   alarm bits
 *   8..9   sensor frames lost or damaged (a skipped sequence number, a failed CRC) since HIL ON
 *   10..13 the wheel input's shortest pulse interval, PCA ticks (0: every edge counts)
 *   14..15 working speed km/h x100    16..17 target L/min x100 (int16)
 *   18..19 measured flow L/min x100 (int16)    20..21 pressure kPa
 *   22     the sensor frame's setting: HIL_NO_SETTING when it carried none, else param_try's
 *          verdict (PARAM_OK: set; a refused one leaves the value as it was)
 *   23..24 CRC
 */
#define HIL_IN_START 0xA5
#define HIL_OUT_START 0x5A
#define HIL_IN_BYTES 29
#define HIL_OUT_BYTES 25
#define HIL_NO_SETTING 0xFF

typedef struct {
    uint8_t seq;
    uint32_t pca_now;
    uint16_t wheel_count;
    uint32_t wheel_last;
    uint8_t wheel_rejected;
    uint16_t meter_count;
    uint32_t meter_last;
    uint16_t adc_pressure, adc_level;
    uint8_t sections;
    uint8_t set_id;                 /* HIL_NO_SETTING, or the parameter set_value is for */
    uint16_t set_value;
} hil_in_t;

typedef struct {
    uint8_t seq;
    int8_t valve_dir;
    uint8_t valve_duty;
    uint8_t valve_delay_ms;
    uint8_t relays;                 /* bit 0 boom relay, bit 1 buzzer */
    uint16_t alarms;
    uint16_t lost;
    uint32_t wheel_min;
    uint16_t speed_kmh_x100;
    int16_t target_lpm_x100;
    int16_t flow_lpm_x100;
    uint16_t pressure_kpa;
    uint8_t set_verdict;            /* HIL_NO_SETTING, or PARAM_OK / why the setting was refused */
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
/* The controller's half: decode a checked sensor frame into what the HAL reads (returns its
 * sequence number; the counts are the frame's running totals), encode an output frame (start
 * byte and CRC included) into f. */
uint8_t hil_in_decode(const uint8_t *f, hal_hil_t *in) __reentrant;
void hil_out_encode(const hil_out_t *out, uint8_t *f) __reentrant;
/* The PC's half (sim/hil_pc.c, host only: the chip needs neither). */
void hil_in_encode(const hil_in_t *in, uint8_t *f);
void hil_out_decode(const uint8_t *f, hil_out_t *out);

/* ---- the controller's HIL mode (firmware/link/hil.c; serial.c feeds it, app.c steps on it) ---- */
/* Out of the mode, as at power-on (serial_init). */
void hil_init(void);
/* Enter the mode (the serial command HIL ON, once its reply is sent). */
void hil_begin(void);
uint8_t hil_active(void);
/* A received byte in the mode; 1 when it completed a sensor frame: its inputs are what the
 * HAL reads now (hal_hil), its setting is set, and one control step is due. */
uint8_t hil_byte(uint8_t b);
/* Read the serial link's bytes as frames until one is in (serial.c, in the mode); hil_due()
 * is 1 from then until its answer (one control step a frame). */
void hil_poll(void);
uint8_t hil_due(void);
/* 1 at the first frame of the mode: the application starts afresh on it. */
uint8_t hil_first(void);
/* After the step: o (valve, relays, alarms, the status values, filled by the application)
 * with the mode's own fields (sequence, lost frames, the wheel filter, the setting's verdict)
 * as a frame into f. */
void hil_answer(hil_out_t *o, uint8_t *f) __reentrant;

#endif
#endif

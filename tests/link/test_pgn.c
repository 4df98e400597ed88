/* test_pgn.c: AgOpenGPS and RateControl PGN frames through the host build: each frame of the sources' layouts decoded, damaged frames refused and counted, replies, text lines among frames at full rate, GPS speed, sections and frames stopping. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>
#include "hal_host.h"
#include "helper_link.h"
#include "link_crc.h"
#include "params.h"
#include "app.h"
#include "target.h"
#include "diag.h"
#include "store.h"
#include "pgn.h"
#include "diag_wheel.h"

/* ---- frames as the sources build them --------------------------------------------------- */
/* AgOpenGPS (AgIO): 80 81 src pgn len data.. crc, crc = low byte of the sum of bytes 2 .. n-2 */
static size_t aog(uint8_t *f, uint8_t pgn, const uint8_t *data, uint8_t len)
{
    unsigned sum = 0;
    f[0] = 0x80;
    f[1] = 0x81;
    f[2] = 0x7F;                    /* AgIO's source byte */
    f[3] = pgn;
    f[4] = len;
    memcpy(f + 5, data, len);
    for (size_t i = 2; i < 5u + len; i++)
        sum += f[i];
    f[5 + len] = (uint8_t)sum;
    return 6u + len;
}

/* RateControl: pgn u16 LE, the fields, crc = low byte of the sum of bytes 0 .. n-2 */
static size_t rc(uint8_t *f, uint16_t pgn, const uint8_t *fields, size_t n_fields)
{
    unsigned sum = 0;
    f[0] = (uint8_t)pgn;
    f[1] = (uint8_t)(pgn >> 8);
    memcpy(f + 2, fields, n_fields);
    for (size_t i = 0; i < 2u + n_fields; i++)
        sum += f[i];
    f[2 + n_fields] = (uint8_t)sum;
    return 3u + n_fields;
}

/* 32500 as RateControl's PGN32500.Send lays it out */
static size_t rc32500(uint8_t *f, uint8_t module, uint32_t upm_x1000, uint32_t cal_x1000, uint8_t cmd, int16_t pwm)
{
    uint8_t d[11] = {(uint8_t)(module << 4), (uint8_t)upm_x1000, (uint8_t)(upm_x1000 >> 8), (uint8_t)(upm_x1000 >> 16),
                     (uint8_t)cal_x1000, (uint8_t)(cal_x1000 >> 8), (uint8_t)(cal_x1000 >> 16), cmd,
                     (uint8_t)pwm, (uint8_t)((uint16_t)pwm >> 8), 0};
    return rc(f, 32500, d, sizeof d);
}

static void send_bytes(const uint8_t *f, size_t n)
{
    for (size_t i = 0; i < n; i++)
        hal_host_uart_rx_push(f[i]);
}

/* everything the firmware sent since the last call */
static size_t tx_all(uint8_t *buf, size_t n)
{
    size_t len = 0;
    int b;
    while ((b = hal_host_uart_tx_pop()) >= 0)
        if (len < n)
            buf[len++] = (uint8_t)b;
    return len;
}

/* the first reply frame of `pgn` (AgOpenGPS: its pgn byte; RateControl: its u16) in the bytes
 * sent, its crc checked by the source's rule; its offset or -1 */
static int find_reply(const uint8_t *b, size_t n, unsigned pgn)
{
    for (size_t i = 0; i + (pgn < 256 ? 14 : 15) <= n; i++) {
        unsigned sum = 0;
        if (pgn < 256 && b[i] == 0x80 && b[i + 1] == 0x81 && b[i + 3] == pgn && b[i + 4] == 8) {
            for (size_t k = i + 2; k < i + 13; k++)
                sum += b[k];
            assert_int_equal(b[i + 13], (uint8_t)sum);
            return (int)i;
        }
        if (pgn >= 256 && b[i] == (uint8_t)pgn && b[i + 1] == (uint8_t)(pgn >> 8)) {
            for (size_t k = i; k < i + 14; k++)
                sum += b[k];
            assert_int_equal(b[i + 14], (uint8_t)sum);
            return (int)i;
        }
    }
    return -1;
}

static int setup(void **state)
{
    (void)state;
    link_start();
    store_status_clear();
    link_run_ms(3000);
    tx_all(NULL, 0);
    assert_true(param_set(P_REMOTE, REMOTE_PGN));
    link_run_ms(200);
    return 0;
}

/* ---- the table -------------------------------------------------------------------------------- */
static void test_pgn_each_frame_of_the_layouts_decoded(void **state)
{
    (void)state;
    uint8_t f[32], out[4096];
    uint16_t taken = pgn_rx.taken;
    /* 254 Steer Data: 12.3 km/h as u16 LE, status, steer angle, xte, sections 1-8, 9-16 */
    const uint8_t d254[8] = {123, 0, 1, 0x10, 0x27, 0x7D, 0xFF, 0xFF};
    send_bytes(f, aog(f, 254, d254, 8));
    link_run_ms(20);
    assert_int_equal(pgn_rx.gps_kmh_x10, 123);
    /* 254 at 30.0 km/h: the u16's high byte */
    const uint8_t d254b[8] = {0x2C, 0x01, 1, 0, 0, 0x7D, 0, 0};
    send_bytes(f, aog(f, 254, d254b, 8));
    link_run_ms(20);
    assert_int_equal(pgn_rx.gps_kmh_x10, 300);
    /* 239 Machine Data: uturn, speed x10 (one byte), lift, tram, geoStop, -, sections 1-8, 9-16 */
    const uint8_t d239[8] = {0, 80, 0, 0, 0, 0, 0x15, 0x00};
    tx_all(out, sizeof out);
    send_bytes(f, aog(f, 239, d239, 8));
    link_run_ms(20);
    assert_int_equal(pgn_rx.sections, 0x15);
    /* ... answered with 237 as a machine module (AOG reply on) */
    size_t n = tx_all(out, sizeof out);
    assert_true(find_reply(out, n, 237) >= 0);
    /* 229 64 sections: sections 1-64, tool left and right speed */
    const uint8_t d229[10] = {0x2A, 0xFF, 0, 0, 0, 0, 0, 0, 20, 22};
    send_bytes(f, aog(f, 229, d229, 10));
    link_run_ms(20);
    assert_int_equal(pgn_rx.sections, 0x2A);
    /* 32500: module 0 sensor 0, 12.345 UPM, meter cal 380.5, MasterOn and AutoOn, manual PWM -100 */
    send_bytes(f, rc32500(f, 0, 12345, 380500, 0x50, -100));
    link_run_ms(20);
    assert_int_equal(pgn_rx.rc_upm_x1000, 12345);
    assert_int_equal(pgn_rx.rc_cmd, 0x50);
    link_run_ms(20);
    n = tx_all(out, sizeof out);
    /* ... answered with 32400 (module 0 sensor 0, status bit 0: the app heard) and 32401 */
    int i = find_reply(out, n, 32400);
    assert_true(i >= 0);
    assert_int_equal(out[i + 2], 0x00);
    uint32_t applied = out[i + 3] | (uint32_t)out[i + 4] << 8 | (uint32_t)out[i + 5] << 16;
    assert_int_equal(applied, (uint32_t)(app_status.in.flow_lpm_x100 > 0 ? app_status.in.flow_lpm_x100 : 0) * 10u);
    assert_int_equal(out[i + 11] & 1, 1);
    i = find_reply(out, n, 32401);
    assert_true(i >= 0);
    assert_int_equal(out[i + 3] | out[i + 4] << 8, app_status.in.pressure_kpa);
    /* 32501: module, relays lo, hi, power relays lo, hi, inverted lo, hi, master valve index */
    const uint8_t d32501[8] = {0, 0x0F, 0x00, 0, 0, 0, 0, 255};
    send_bytes(f, rc(f, 32501, d32501, 8));
    link_run_ms(20);
    assert_int_equal(pgn_rx.sections, 0x0F);
    /* 32502: module<<4|sensor, max PWM %, min PWM %, Kp, Ki, dead band % x10, then the rest */
    uint8_t d32502[21] = {0, 100, 20, 50, 5, 15, 35, 60};
    send_bytes(f, rc(f, 32502, d32502, 21));
    link_run_ms(20);
    assert_int_equal(pgn_rx.taken, taken + 7u);     /* checked and counted (nothing of it applies) */
    /* another module's 32500 and 32501 are not taken; AgIO's other pgns (238 settings) skipped */
    send_bytes(f, rc32500(f, 1, 999, 1000, 0x50, 0));
    link_run_ms(20);
    const uint8_t d32501m[8] = {3, 0xFF, 0xFF, 0, 0, 0, 0, 255};
    send_bytes(f, rc(f, 32501, d32501m, 8));
    link_run_ms(20);
    const uint8_t d238[8] = {2, 4, 0, 1, 0, 0, 0, 0};
    send_bytes(f, aog(f, 238, d238, 8));
    link_run_ms(20);
    assert_int_equal(pgn_rx.rc_upm_x1000, 12345);
    assert_int_equal(pgn_rx.sections, 0x0F);
    assert_int_equal(pgn_rx.taken, taken + 7u);
    assert_int_equal(pgn_rx.bad, 0);
}

/* The replies' fields from the meter's pulses: one every 2 ms is 500 Hz, 500 / 380 x 60 = 78.95
 * L/min (by hand) against a target of 36 L/min (150 L/ha, 8 km/h given, 18 m): 32400 carries the
 * applied UPM x1000 (within the meter's 1 %), the job's litres x10 (the pulses counted while
 * spraying over 380, within 0.1 L), a closing PWM (the flow twice the target: full closing, the module's -255 and
 * not the Q15 drive's -256), status bit
 * 0, 5000 for 500.0 Hz (within 1 %); 32401 the pressure, six zero bytes, InoID 0, the boom
 * spraying. */
static void test_pgn_replies_carry_their_fields(void **state)
{
    (void)state;
    uint8_t f[32], out[4096];
    assert_true(param_set(P_GIVEN_SPEED, 80));
    unsigned pulses = 0;
    for (int t = 1; t <= 10000; t++) {
        if (t % 2 == 0) {
            hal_host_flow_edge(hal_host_io.time_ns);
            pulses += app_status.spraying;
        }
        link_run_ms(1);
    }
    assert_true(app_status.spraying);
    tx_all(out, sizeof out);
    send_bytes(f, rc32500(f, 0, 36000, 380000, 0x50, 0));
    link_run_ms(40);
    size_t n = tx_all(out, sizeof out);
    int i = find_reply(out, n, 32400);
    assert_true(i >= 0);
    uint32_t upm = out[i + 3] | (uint32_t)out[i + 4] << 8 | (uint32_t)out[i + 5] << 16;
    uint32_t qty = out[i + 6] | (uint32_t)out[i + 7] << 8 | (uint32_t)out[i + 8] << 16;
    int16_t pwm = (int16_t)(out[i + 9] | out[i + 10] << 8);
    unsigned hz = out[i + 12] | out[i + 13] << 8;
    printf("# 32400: %u UPM x1000, %u L x10 (%u pulses: %.1f), PWM %d, %u Hz x10\n", upm, qty, pulses,
           pulses / 38.0, pwm, hz);                 /* (L x10 = pulses x 10 / 380) */
    assert_true(upm * 100 >= 78947u * 99 && upm * 100 <= 78947u * 101);
    assert_true(qty * 38 + 38 >= pulses && qty * 38 <= pulses + 38);
    assert_int_equal(pwm, -255);
    assert_int_equal(out[i + 11] & 1, 1);
    assert_true(hz * 100 >= 5000u * 99 && hz * 100 <= 5000u * 101);
    i = find_reply(out, n, 32401);
    assert_true(i >= 0);
    assert_int_equal(out[i + 2], 0);
    assert_int_equal(out[i + 3] | out[i + 4] << 8, app_status.in.pressure_kpa);
    for (int k = 5; k < 13; k++)
        assert_int_equal(out[i + k], 0);
    assert_int_equal(out[i + 13], 1);
}

/* One byte changed, one bit flipped, a short length, a lost second sync byte: each frame is
 * refused and counted, nothing it carried is taken; the next good frame is. */
static void test_pgn_damaged_frames_refused_and_counted(void **state)
{
    (void)state;
    uint8_t f[32];
    const uint8_t d254[8] = {80, 0, 1, 0, 0, 0x7D, 0, 0};
    send_bytes(f, aog(f, 254, d254, 8));
    link_run_ms(20);
    assert_int_equal(pgn_rx.gps_kmh_x10, 80);
    const uint8_t d254x[8] = {99, 0, 1, 0, 0, 0x7D, 0, 0};
    for (size_t at = 2; at < 14; at++) {
        for (int kind = 0; kind < 2; kind++) {
            uint16_t bad = pgn_rx.bad;
            size_t n = aog(f, 254, d254x, 8);
            f[at] ^= kind ? 0x04 : 0x5A;        /* one bit, or a byte changed */
            send_bytes(f, n);
            link_run_ms(400);                   /* (a frame made longer stalls: dropped) */
            assert_int_equal(pgn_rx.gps_kmh_x10, 80);
            assert_int_equal(pgn_rx.bad, bad + 1u);
        }
    }
    /* a short length for a known pgn */
    uint16_t bad = pgn_rx.bad;
    size_t n = aog(f, 254, d254x, 8);
    f[4] = 7;
    send_bytes(f, n - 1);
    link_run_ms(400);
    assert_int_equal(pgn_rx.bad, bad + 1u);
    /* RateControl's: a bit of the rate */
    n = rc32500(f, 0, 5000, 1000, 0x50, 0);
    f[4] ^= 0x01;
    send_bytes(f, n);
    link_run_ms(20);
    assert_int_equal(pgn_rx.bad, bad + 2u);
    assert_int_not_equal(pgn_rx.rc_upm_x1000, 5000 ^ 0x100);
    /* the next good one is taken */
    send_bytes(f, aog(f, 254, d254x, 8));
    link_run_ms(20);
    assert_int_equal(pgn_rx.gps_kmh_x10, 99);
}

/* AgIO's 10 Hz and a text command line between every two frames, the wire full: every command
 * answered, every frame taken, nothing refused. */
static void test_pgn_text_commands_among_frames_at_full_rate(void **state)
{
    (void)state;
    uint8_t f[32], out[65536];
    char line[64];
    uint16_t taken = pgn_rx.taken;
    tx_all(out, sizeof out);
    for (int k = 0; k < 100; k++) {
        const uint8_t d254[8] = {(uint8_t)(50 + k), 0, 1, 0, 0, 0x7D, 0, 0};
        send_bytes(f, aog(f, 254, d254, 8));
        snprintf(line, sizeof line, "GET %d\r\n", k % P_COUNT);
        link_send(line);
        const uint8_t d239[8] = {0, 0, 0, 0, 0, 0, 0x3F, 0};
        send_bytes(f, aog(f, 239, d239, 8));
    }
    link_run_ms(3000);
    size_t n = tx_all(out, sizeof out);
    int oks = 0;
    for (size_t i = 0; i + 3 < n; i++)
        oks += memcmp(out + i, "OK ", 3) == 0;
    assert_int_equal(oks, 100);
    assert_int_equal(pgn_rx.taken, taken + 200u);
    assert_int_equal(pgn_rx.bad, 0);
    assert_int_equal(pgn_rx.gps_kmh_x10, 149);
}

/* Speed src GPS: the target's speed is 254's; AOG sect on: the boom's sections the switches'
 * and the frames'; the frames stopping shut the boom within Frames lost, SPEED_LOST told. */
static void test_pgn_gps_speed_sections_and_frames_stopping(void **state)
{
    (void)state;
    uint8_t f[32];
    assert_true(param_set(P_SPEED_SRC, SPEED_SRC_GPS));
    assert_true(param_set(P_AOG_SECT, 1));
    assert_true(param_set(P_FRAMES_LOST, 10));     /* 1.0 s */
    uint64_t last = 0;
    for (int k = 0; k < 30; k++) {                  /* 3 s at 10 Hz: 8.0 km/h, sections 1-3 */
        const uint8_t d254[8] = {80, 0, 1, 0, 0, 0x7D, 0, 0};
        const uint8_t d239[8] = {0, 80, 0, 0, 0, 0, 0x07, 0};
        send_bytes(f, aog(f, 254, d254, 8));
        send_bytes(f, aog(f, 239, d239, 8));
        link_run_ms(100);
        last = link_t_ms;
    }
    assert_int_equal(app_status.in.speed_kmh_x100, 800);
    assert_int_equal(app_status.open_nozzles, 18);  /* 3 of 6 sections of 6 nozzles */
    assert_true(app_status.spraying);
    assert_false(app_status.alarms & (1u << AL_SPEED_LOST));
    /* a frame closes section 3: the boom follows within 0.2 s */
    const uint8_t d239c[8] = {0, 80, 0, 0, 0, 0, 0x03, 0};
    send_bytes(f, aog(f, 239, d239c, 8));
    link_run_ms(200);
    assert_int_equal(app_status.open_nozzles, 12);
    last = link_t_ms - 200;
    /* the frames stop: shut within 1.0 s (and a period), SPEED_LOST */
    while (app_status.spraying && link_t_ms < last + 3000)
        link_run_ms(1);
    assert_false(app_status.spraying);
    assert_true(link_t_ms - last <= 1000 + 100);
    assert_true(link_t_ms - last >= 1000);
    link_run_ms(200);
    assert_true(app_status.alarms & (1u << AL_SPEED_LOST));
    /* held while they stay away, every period of it (the wheel, never turned, says nothing
     * against it) */
    for (int ms = 0; ms < 3000; ms++) {
        link_run_ms(1);
        assert_true(app_status.alarms & (1u << AL_SPEED_LOST));
        assert_false(app_status.spraying);
    }
    /* they come back: the alarm clears */
    for (int k = 0; k < 20; k++) {
        const uint8_t d254[8] = {80, 0, 1, 0, 0, 0x7D, 0, 0};
        const uint8_t d239[8] = {0, 80, 0, 0, 0, 0, 0x07, 0};
        send_bytes(f, aog(f, 254, d254, 8));
        send_bytes(f, aog(f, 239, d239, 8));
        link_run_ms(100);
    }
    assert_false(app_status.alarms & (1u << AL_SPEED_LOST));
    assert_true(app_status.spraying);
}

/* Speed src both: the wheel at a standstill against 8 km/h of GPS raises WHEEL_NOISE after
 * PGN_OFF_PERIODS; wheel alone (the setting back) clears it. */
static void test_pgn_both_raises_wheel_noise_when_the_speeds_part(void **state)
{
    (void)state;
    uint8_t f[32];
    assert_true(param_set(P_SPEED_SRC, SPEED_SRC_BOTH));
    int raised_at = -1;
    for (int k = 0; k < 40; k++) {
        const uint8_t d254[8] = {80, 0, 1, 0, 0, 0x7D, 0, 0};
        send_bytes(f, aog(f, 254, d254, 8));
        link_run_ms(100);
        if (raised_at < 0 && (app_status.alarms & (1u << AL_WHEEL_NOISE)))
            raised_at = k;
    }
    assert_int_equal(app_status.in.speed_kmh_x100, 800);   /* the GPS's */
    assert_true(raised_at >= (int)PGN_OFF_PERIODS - 1 && raised_at <= (int)PGN_OFF_PERIODS + 2);
    /* held every period while they stay apart */
    for (int ms = 0; ms < 2000; ms++) {
        if (ms % 100 == 0) {
            const uint8_t d254[8] = {80, 0, 1, 0, 0, 0x7D, 0, 0};
            send_bytes(f, aog(f, 254, d254, 8));
        }
        link_run_ms(1);
        assert_true(app_status.alarms & (1u << AL_WHEEL_NOISE));
    }
    assert_true(param_set(P_SPEED_SRC, SPEED_SRC_WHEEL));
    link_run_ms(1500);
    assert_false(app_status.alarms & (1u << AL_WHEEL_NOISE));
}

/* Speed src both, the speeds apart (WHEEL_NOISE up), then the setting to GPS: the wheel is no
 * longer judged, so the alarm goes as it does with the wheel alone (no stale alarm stays on). */
static void test_pgn_both_to_gps_clears_wheel_noise(void **state)
{
    (void)state;
    uint8_t f[32];
    const uint8_t d254[8] = {80, 0, 1, 0, 0, 0x7D, 0, 0};
    assert_true(param_set(P_SPEED_SRC, SPEED_SRC_BOTH));
    for (int k = 0; k < 40; k++) {
        send_bytes(f, aog(f, 254, d254, 8));
        link_run_ms(100);
    }
    assert_true(app_status.alarms & (1u << AL_WHEEL_NOISE));
    assert_true(param_set(P_SPEED_SRC, SPEED_SRC_GPS));
    for (int k = 0; k < 15; k++) {
        send_bytes(f, aog(f, 254, d254, 8));
        link_run_ms(100);
    }
    assert_int_equal(app_status.in.speed_kmh_x100, 800);
    assert_false(app_status.alarms & (1u << AL_WHEEL_NOISE));
}

/* RateControl: a target UPM built from a rate by hand (130 L/ha x 8 km/h x 18 m / 600 = 31.2
 * L/min) gives back that rate; one outside the remote window is refused and the rate holds. */
static void test_pgn_ratecontrol_target_upm_is_a_rate_in_the_window(void **state)
{
    (void)state;
    uint8_t f[32];
    assert_true(param_set(P_GIVEN_SPEED, 80));
    link_run_ms(300);
    send_bytes(f, rc32500(f, 0, 31200, 380000, 0x50, 0));
    link_run_ms(300);
    assert_true(target_rate_remote());
    assert_int_equal(target_rate_x10(), 1300);
    /* 60 L/ha: under the 50 % window of 150 */
    send_bytes(f, rc32500(f, 0, 14400, 380000, 0x50, 0));
    link_run_ms(300);
    assert_int_equal(target_rate_x10(), 1300);
    /* AutoOn clear: no rate taken */
    send_bytes(f, rc32500(f, 0, 36000, 380000, 0x10, 0));
    link_run_ms(300);
    assert_int_equal(target_rate_x10(), 1300);
    /* a module id of its own */
    assert_true(param_set(P_RC_ID, 3));
    send_bytes(f, rc32500(f, 3, 36000, 380000, 0x50, 0));
    link_run_ms(300);
    assert_int_equal(target_rate_x10(), 1500);
}

/* A frame inside a text line: the line goes on after it. A start byte no frame follows inside
 * a line: counted, and the line refused (ERR CHAR) as any byte that is not text. */
static void test_pgn_a_frame_inside_a_line_and_noise(void **state)
{
    (void)state;
    uint8_t f[32], out[2048];
    const uint8_t d254[8] = {77, 0, 1, 0, 0, 0x7D, 0, 0};
    tx_all(out, sizeof out);
    link_send("GET ");
    send_bytes(f, aog(f, 254, d254, 8));
    link_send("0\r\n");
    link_run_ms(50);
    size_t n = tx_all(out, sizeof out);
    out[n < sizeof out ? n : sizeof out - 1] = 0;
    assert_non_null(strstr((char *)out, "OK 0 1500*"));
    assert_int_equal(pgn_rx.gps_kmh_x10, 77);
    uint16_t bad = pgn_rx.bad;
    const uint8_t noise[] = {'G', 'E', 'T', ' ', 0x80, '0', '\r', '\n'};
    send_bytes(noise, sizeof noise);
    link_run_ms(50);
    n = tx_all(out, sizeof out);
    out[n < sizeof out ? n : sizeof out - 1] = 0;
    assert_non_null(strstr((char *)out, "ERR CHAR*"));
    assert_null(strstr((char *)out, "OK 0"));
    assert_int_equal(pgn_rx.bad, bad + 1u);
}

/* A frame whose bytes stop half way is dropped and counted once they have stopped for 3 s (as a
 * text line is): the next frame is read from its own first byte and taken. */
static void test_pgn_a_stalled_frame_is_dropped_after_3_s(void **state)
{
    (void)state;
    uint8_t f[32];
    const uint8_t d254[8] = {66, 0, 1, 0, 0, 0x7D, 0, 0};
    uint16_t bad = pgn_rx.bad, taken = pgn_rx.taken;
    size_t n = aog(f, 254, d254, 8);
    send_bytes(f, 7);
    link_run_ms(2000);
    assert_int_equal(pgn_rx.bad, bad);              /* (under 3 s: still coming) */
    link_run_ms(2000);
    assert_int_equal(pgn_rx.bad, bad + 1u);
    send_bytes(f, n);
    link_run_ms(20);
    assert_int_equal(pgn_rx.taken, taken + 1u);
    assert_int_equal(pgn_rx.gps_kmh_x10, 66);
}

/* Remote off or Raven: a frame's bytes are not frames (ERR CHAR for its line, as ever) */
static void test_pgn_frames_only_with_remote_agopengps(void **state)
{
    (void)state;
    uint8_t f[32];
    assert_true(param_set(P_REMOTE, 0));
    uint16_t taken = pgn_rx.taken, bad = pgn_rx.bad;
    const uint8_t d254[8] = {80, 0, 1, 0, 0, 0x7D, 0, 0};
    send_bytes(f, aog(f, 254, d254, 8));
    link_send("\r\n");
    link_run_ms(50);
    assert_int_equal(pgn_rx.taken, taken);
    assert_int_equal(pgn_rx.bad, bad);
}

/* ---- pgn.c's rules called directly, a call of pgn_speed a period (as app.c makes it) ---------- */
/* a frame's bytes through pgn_byte: the last byte's verdict */
static uint8_t feed(const uint8_t *f, size_t n)
{
    uint8_t v = PGN_NO;
    for (size_t i = 0; i < n; i++)
        v = pgn_byte(f[i]);
    return v;
}

static void feed_254(uint16_t kmh_x10)
{
    uint8_t f[32];
    const uint8_t d[8] = {(uint8_t)kmh_x10, (uint8_t)(kmh_x10 >> 8), 1, 0, 0, 0x7D, 0, 0};
    assert_int_equal(feed(f, aog(f, 254, d, 8)), PGN_END);
}

static void feed_239(uint8_t sections)
{
    uint8_t f[32];
    const uint8_t d[8] = {0, 80, 0, 0, 0, 0, sections, 0};
    assert_int_equal(feed(f, aog(f, 239, d, 8)), PGN_END);
}

/* Frames lost (1.0 s: 10 periods) after the last frame in use: on the 11th period lost, not on
 * the 10th; the sections' frames with AOG sect, the speed's with Speed src GPS or both. Nothing
 * of the frames is in use with the wheel and AOG sect off, or with Remote not AgOpenGPS. */
static void test_pgn_rules_frames_lost_on_the_period_after_frames_lost(void **state)
{
    (void)state;
    assert_true(param_set(P_FRAMES_LOST, 10));
    for (int k = 0; k < 30; k++)
        assert_int_equal(pgn_speed(1234), 1234);
    assert_int_equal(pgn_lost(), 0);
    assert_int_equal(pgn_frames(), 0);
    assert_int_equal(pgn_sections(0x2A), 0x2A);
    /* AOG sect: the sections' frames stopped long ago: lost, no section */
    assert_true(param_set(P_AOG_SECT, 1));
    assert_int_equal(pgn_lost(), 1);
    assert_int_equal(pgn_frames(), DIAG_FRAMES_LOST);
    assert_int_equal(pgn_sections(0x3F), 0);
    /* and 300 periods on (the frames' ages stop at 255, they do not wrap) */
    for (int k = 0; k < 300; k++)
        pgn_speed(0);
    assert_int_equal(pgn_lost(), 1);
    feed_239(0x15);
    for (int k = 1; k <= 10; k++) {
        pgn_speed(0);
        assert_int_equal(pgn_lost(), 0);
        assert_int_equal(pgn_sections(0x3F), 0x15);
        assert_int_equal(pgn_sections(0x0C), 0x04);
    }
    pgn_speed(0);
    assert_int_equal(pgn_lost(), 1);
    assert_int_equal(pgn_sections(0x3F), 0);
    /* RateControl's master off (32500's command bit 4): no section, frames or not */
    uint8_t f[32];
    feed_239(0x15);
    assert_int_equal(feed(f, rc32500(f, 0, 0, 380000, 0x40, 0)), PGN_END);
    assert_int_equal(pgn_sections(0x3F), 0);
    assert_int_equal(feed(f, rc32500(f, 0, 0, 380000, 0x50, 0)), PGN_END);
    assert_int_equal(pgn_sections(0x3F), 0x15);
    /* Speed src GPS, AOG sect off: the GPS bit; the speed's frames stopped: lost, speed 0 */
    assert_true(param_set(P_AOG_SECT, 0));
    assert_true(param_set(P_SPEED_SRC, SPEED_SRC_GPS));
    for (int k = 0; k < 300; k++)
        assert_int_equal(pgn_speed(1234), 0);
    assert_int_equal(pgn_frames(), DIAG_FRAMES_LOST | DIAG_FRAMES_GPS);
    feed_254(80);
    for (int k = 1; k <= 10; k++) {
        assert_int_equal(pgn_speed(1234), 800);
        assert_int_equal(pgn_lost(), 0);
        assert_int_equal(pgn_frames(), DIAG_FRAMES_GPS);
    }
    assert_int_equal(pgn_speed(1234), 0);
    assert_int_equal(pgn_lost(), 1);
    /* both: the wheel's speed while the GPS's is lost */
    assert_true(param_set(P_SPEED_SRC, SPEED_SRC_BOTH));
    assert_int_equal(pgn_speed(1234), 1234);
    assert_int_equal(pgn_lost(), 1);
    assert_int_equal(pgn_frames(), DIAG_FRAMES_LOST | DIAG_FRAMES_GPS);
    feed_254(80);
    assert_int_equal(pgn_speed(1234), 800);
    assert_int_equal(pgn_lost(), 0);
    /* the wheel again: the speed frames are not in use */
    for (int k = 0; k < 20; k++)
        pgn_speed(0);
    assert_true(param_set(P_SPEED_SRC, SPEED_SRC_WHEEL));
    assert_int_equal(pgn_speed(1234), 1234);
    assert_int_equal(pgn_lost(), 0);
    assert_int_equal(pgn_frames(), 0);
    /* Remote not AgOpenGPS, every frame setting on and every frame stopped: nothing in use */
    assert_true(param_set(P_SPEED_SRC, SPEED_SRC_GPS));
    assert_true(param_set(P_AOG_SECT, 1));
    assert_true(param_set(P_REMOTE, 0));
    for (int k = 0; k < 20; k++)
        assert_int_equal(pgn_speed(1234), 1234);
    assert_int_equal(pgn_lost(), 0);
    assert_int_equal(pgn_frames(), 0);
    assert_int_equal(pgn_sections(0x2A), 0x2A);
}

/* A frame starts at 0x80 (AgOpenGPS) or 0xF4..0xF6 (RateControl's 32500..32502) only, and only
 * with Remote AgOpenGPS; every other byte is the text parser's. A start byte whose second is
 * not its own sync byte (0x81 after 0x80, 0x7E after 0xF4..0xF6) was noise: counted. */
static void test_pgn_rules_frame_start_and_sync_bytes(void **state)
{
    (void)state;
    for (int r = 0; r < 2; r++) {
        for (unsigned b = 0; b < 256; b++) {
            uint16_t bad = pgn_rx.bad;
            int start = r == 0 && (b == 0x80 || (b >= 0xF4 && b <= 0xF6));
            assert_int_equal(pgn_byte((uint8_t)b), start ? PGN_IN : PGN_NO);
            assert_int_equal(pgn_busy(), start);
            if (start) {
                assert_int_equal(pgn_byte(b == 0x80 ? 0x7E : 0x81), PGN_NOISE);
                assert_int_equal(pgn_busy(), 0);
                assert_int_equal(pgn_rx.bad, bad + 1u);
                assert_int_equal(pgn_byte((uint8_t)b), PGN_IN);
                assert_int_equal(pgn_byte(b == 0x80 ? 0x81 : 0x7E), PGN_IN);
                pgn_drop();
            }
            assert_int_equal(pgn_rx.bad, bad + 2u * (unsigned)start);
        }
        assert_true(param_set(P_REMOTE, 0));
    }
}

/* The lengths: 254 and 239 carry 8 bytes, 229 10: another length is refused at the length byte
 * and counted. Another pgn with a good check is skipped, uncounted, whatever its length up to
 * 249 (its 255 bytes: a byte's count); 250 and over are refused and counted. */
static void test_pgn_rules_frame_lengths(void **state)
{
    (void)state;
    uint8_t f[300], d[256];
    memset(d, 0x11, sizeof d);
    static const struct { uint8_t pgn, len; int ok; } c[] = {
        {254, 8, 1}, {254, 7, 0}, {254, 9, 0}, {239, 8, 1}, {239, 7, 0}, {239, 9, 0}, {239, 10, 0},
        {229, 10, 1}, {229, 8, 0}, {229, 9, 0}, {229, 11, 0},
        {238, 3, 1}, {240, 3, 1}, {228, 3, 1}, {230, 3, 1}, {228, 10, 1}, {230, 8, 1},
        {200, 249, 1}, {200, 250, 0}, {200, 251, 0}, {200, 255, 0},
    };
    for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
        uint16_t bad = pgn_rx.bad, taken = pgn_rx.taken;
        size_t n = aog(f, c[i].pgn, d, c[i].len);
        uint8_t v = PGN_IN;
        size_t at = 0;
        while (at < n && v == PGN_IN)
            v = pgn_byte(f[at++]);
        assert_int_equal(v, PGN_END);
        assert_int_equal(at, c[i].ok ? n : 5u);         /* refused at its length byte */
        assert_int_equal(pgn_busy(), 0);
        assert_int_equal(pgn_rx.bad, bad + (c[i].ok ? 0u : 1u));
        int known = c[i].pgn == 254 || c[i].pgn == 239 || c[i].pgn == 229;
        assert_int_equal(pgn_rx.taken, taken + (c[i].ok && known ? 1u : 0u));
    }
    /* the longest with a wrong check: counted */
    uint16_t bad = pgn_rx.bad;
    size_t n = aog(f, 200, d, 249);
    f[n - 1] ^= 1;
    assert_int_equal(n, 255u);
    assert_int_equal(feed(f, n), PGN_END);
    assert_int_equal(pgn_rx.bad, bad + 1u);
}

/* The frames taken and answered: a 239 answered with a 237 while AOG reply is on, nothing else
 * of AgOpenGPS's; RateControl's 32500 and 32502 of this module's sensor 0 only (module << 4 |
 * sensor), 32501 of this module (its byte the module alone). */
static void test_pgn_rules_modules_sensors_and_replies(void **state)
{
    (void)state;
    uint8_t f[32], out[PGN_OUT_MAX + 1];
    uint8_t d[11] = {0}, d2[21] = {0};
    while (pgn_next(out))
        ;
    feed_239(0x15);
    assert_int_equal(pgn_next(out), 14);
    assert_int_equal(out[3], 237);
    assert_int_equal(pgn_next(out), 0);
    const uint8_t d229[10] = {0x2A, 0, 0, 0, 0, 0, 0, 0, 20, 22};
    assert_int_equal(feed(f, aog(f, 229, d229, 10)), PGN_END);
    assert_int_equal(pgn_rx.sections, 0x2A);
    feed_254(80);
    assert_int_equal(pgn_next(out), 0);
    assert_true(param_set(P_AOG_REPLY, 0));
    feed_239(0x15);
    assert_int_equal(pgn_rx.sections, 0x15);
    assert_int_equal(pgn_next(out), 0);
    /* RateControl, module 3 */
    assert_true(param_set(P_RC_ID, 3));
    uint16_t taken = pgn_rx.taken;
    feed(f, rc32500(f, 3, 4242, 380000, 0x50, 0));
    assert_int_equal(pgn_rx.taken, taken + 1u);
    assert_int_equal(pgn_rx.rc_upm_x1000, 4242);
    assert_int_equal(pgn_next(out), 15);            /* 32400, then 32401 */
    assert_int_equal(out[0] | out[1] << 8, 32400);
    assert_int_equal(out[2], 0x30);
    assert_int_equal(pgn_next(out), 15);
    assert_int_equal(out[0] | out[1] << 8, 32401);
    assert_int_equal(pgn_next(out), 0);
    for (int m = 0; m < 3; m++) {                   /* sensor 1 of module 3; module 0; module 4 */
        feed(f, rc32500(f, 3, 5000, 380000, 0x50, 0));
        uint8_t b = m == 0 ? 0x31 : m == 1 ? 0x00 : 0x40;
        memcpy(d, f + 2, sizeof d);
        d[0] = b;
        taken = pgn_rx.taken;
        d2[0] = b;
        assert_int_equal(feed(f, rc(f, 32500, d, sizeof d)), PGN_END);
        assert_int_equal(feed(f, rc(f, 32502, d2, sizeof d2)), PGN_END);
        assert_int_equal(pgn_rx.taken, taken);
        assert_int_equal(pgn_rx.rc_upm_x1000, 5000);
    }
    const uint8_t s3[8] = {3, 0x0C, 0, 0, 0, 0, 0, 255}, s0[8] = {0, 0x33, 0, 0, 0, 0, 0, 255};
    feed(f, rc(f, 32501, s3, 8));
    assert_int_equal(pgn_rx.sections, 0x0C);
    feed(f, rc(f, 32501, s0, 8));
    assert_int_equal(pgn_rx.sections, 0x0C);
    d2[0] = 0x30;
    taken = pgn_rx.taken;
    assert_int_equal(feed(f, rc(f, 32502, d2, sizeof d2)), PGN_END);
    assert_int_equal(pgn_rx.taken, taken + 1u);
}

/* Speed src both at 30.0 km/h of GPS, Speed diff 10 %: the wheel 3.00 km/h off (10 % of it) is
 * together, 3.01 apart (x 100 against 10 x 3000: 30000 and 30100). 20 periods apart more than
 * together raise the flag (WHEEL_NOISE), on the 20th, not the 19th; the count stops at 20, and
 * 20 periods together clear it on the 20th. Not judged under 2.00 km/h of GPS, nor with Speed
 * src GPS. */
static void test_pgn_rules_speeds_apart_counted_to_20(void **state)
{
    (void)state;
    assert_true(param_set(P_SPEED_SRC, SPEED_SRC_BOTH));
    assert_true(param_set(P_SPEED_DIFF, 10));
    for (int k = 0; k < 60; k++) {
        feed_254(300);
        assert_int_equal(pgn_speed(k & 1 ? 3300 : 2700), 3000);
        assert_int_equal(pgn_frames() & DIAG_FRAMES_SPEED_OFF, 0);
    }
    for (int k = 1; k <= 20; k++) {
        feed_254(300);
        pgn_speed(3301);
        assert_int_equal(pgn_frames() & DIAG_FRAMES_SPEED_OFF, k == 20 ? DIAG_FRAMES_SPEED_OFF : 0);
    }
    for (int k = 0; k < 10; k++) {
        feed_254(300);
        pgn_speed(2699);
    }
    for (int k = 1; k <= 20; k++) {
        feed_254(300);
        pgn_speed(2700);
        assert_int_equal(pgn_frames() & DIAG_FRAMES_SPEED_OFF, k == 20 ? 0 : DIAG_FRAMES_SPEED_OFF);
    }
    for (int k = 0; k < 10; k++) {             /* together: the count stays at 0 */
        feed_254(300);
        pgn_speed(3000);
    }
    feed_254(300);
    pgn_speed(3301);
    assert_int_equal(pgn_frames() & DIAG_FRAMES_SPEED_OFF, 0);
    feed_254(300);
    pgn_speed(3000);                            /* (the count back to 0) */
    /* 1.9 km/h of GPS and the wheel standing: not judged; 2.0: judged */
    for (int k = 0; k < 40; k++) {
        feed_254(19);
        assert_int_equal(pgn_speed(0), 190);
        assert_int_equal(pgn_frames() & DIAG_FRAMES_SPEED_OFF, 0);
    }
    for (int k = 1; k <= 19; k++) {
        feed_254(20);
        pgn_speed(0);
    }
    assert_int_equal(pgn_frames() & DIAG_FRAMES_SPEED_OFF, 0);
    feed_254(20);
    pgn_speed(0);
    assert_int_equal(pgn_frames() & DIAG_FRAMES_SPEED_OFF, DIAG_FRAMES_SPEED_OFF);
    /* the flag up, then Speed src GPS: gone on the next period, frames coming or stopped */
    for (int stop = 0; stop < 2; stop++) {
        assert_true(param_set(P_SPEED_SRC, SPEED_SRC_BOTH));
        for (int k = 0; k < 20; k++) {
            feed_254(300);
            pgn_speed(0);
        }
        assert_int_equal(pgn_frames() & DIAG_FRAMES_SPEED_OFF, DIAG_FRAMES_SPEED_OFF);
        assert_true(param_set(P_SPEED_SRC, SPEED_SRC_GPS));
        for (int k = 0; stop && k <= param_v[P_FRAMES_LOST]; k++)
            pgn_speed(0);
        if (!stop)
            feed_254(300);
        assert_int_equal(pgn_speed(0), stop ? 0 : 3000);
        assert_int_equal(pgn_frames() & DIAG_FRAMES_SPEED_OFF, 0);
    }
    /* the wheel in use: no flag; then Speed src GPS: the wheel is not judged */
    assert_true(param_set(P_SPEED_SRC, SPEED_SRC_WHEEL));
    assert_int_equal(pgn_speed(0), 0);
    assert_int_equal(pgn_frames() & DIAG_FRAMES_SPEED_OFF, 0);
    assert_true(param_set(P_SPEED_SRC, SPEED_SRC_GPS));
    for (int k = 0; k < 40; k++) {
        feed_254(300);
        assert_int_equal(pgn_speed(0), 3000);
    }
    assert_int_equal(pgn_frames() & DIAG_FRAMES_SPEED_OFF, 0);
}

/* RateControl's target flow as a rate: at 1.00 km/h over the 18 m boom, r = UPM x 60000 /
 * (100 x 1800) = UPM / 3 (L/ha x10). Not under 1.00 km/h; a change of 1/128 or less of the
 * rate last handed on is not handed on, up or down (1300 -> 1310: 10 x 128 = 1280, not over
 * 1300; 1311: 1408). The first one is handed on whatever it is (0: refused by the window, counted); none
 * with the boom shut (no width). */
static void test_pgn_rules_ratecontrol_rate_handed_on(void **state)
{
    (void)state;
    uint8_t f[32];
    assert_int_equal(target_width_cm(), 1800);
    app_status.in.speed_kmh_x100 = 100;
    uint8_t refused = target_remote_refusals();
    feed(f, rc32500(f, 0, 1, 380000, 0x50, 0));          /* r = 0 */
    assert_int_equal(target_remote_refusals(), (uint8_t)(refused + 1));
    assert_int_equal(target_rate_x10(), 1500);
    app_status.in.speed_kmh_x100 = 99;
    feed(f, rc32500(f, 0, 3900, 380000, 0x50, 0));
    assert_int_equal(target_rate_x10(), 1500);
    app_status.in.speed_kmh_x100 = 100;
    feed(f, rc32500(f, 0, 3900, 380000, 0x50, 0));
    assert_int_equal(target_rate_x10(), 1300);
    feed(f, rc32500(f, 0, 3930, 380000, 0x50, 0));
    assert_int_equal(target_rate_x10(), 1300);
    feed(f, rc32500(f, 0, 3885, 380000, 0x50, 0));      /* 5 down: 640 */
    assert_int_equal(target_rate_x10(), 1300);
    feed(f, rc32500(f, 0, 3933, 380000, 0x50, 0));
    assert_int_equal(target_rate_x10(), 1311);
    feed(f, rc32500(f, 0, 3900, 380000, 0x50, 0));      /* 11 down: 1408 over 1311 */
    assert_int_equal(target_rate_x10(), 1300);
    feed(f, rc32500(f, 0, 3840, 380000, 0x50, 0));
    assert_int_equal(target_rate_x10(), 1280);
    feed(f, rc32500(f, 0, 3870, 380000, 0x50, 0));      /* 10 x 128 = 1280: not over 1280 */
    assert_int_equal(target_rate_x10(), 1280);
    /* no target (0 UPM): nothing handed on, nothing refused */
    refused = target_remote_refusals();
    feed(f, rc32500(f, 0, 0, 380000, 0x50, 0));
    assert_int_equal(target_rate_x10(), 1280);
    assert_int_equal(target_remote_refusals(), refused);
    /* the boom shut: no width, nothing handed on, nothing refused */
    hal_host_io.sections = 0;
    link_run_ms(300);
    assert_int_equal(target_width_cm(), 0);
    app_status.in.speed_kmh_x100 = 100;
    refused = target_remote_refusals();
    feed(f, rc32500(f, 0, 4500, 380000, 0x50, 0));
    assert_int_equal(target_rate_x10(), 1280);
    assert_int_equal(target_remote_refusals(), refused);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_pgn_each_frame_of_the_layouts_decoded, setup),
        cmocka_unit_test_setup(test_pgn_replies_carry_their_fields, setup),
        cmocka_unit_test_setup(test_pgn_damaged_frames_refused_and_counted, setup),
        cmocka_unit_test_setup(test_pgn_text_commands_among_frames_at_full_rate, setup),
        cmocka_unit_test_setup(test_pgn_gps_speed_sections_and_frames_stopping, setup),
        cmocka_unit_test_setup(test_pgn_both_raises_wheel_noise_when_the_speeds_part, setup),
        cmocka_unit_test_setup(test_pgn_both_to_gps_clears_wheel_noise, setup),
        cmocka_unit_test_setup(test_pgn_ratecontrol_target_upm_is_a_rate_in_the_window, setup),
        cmocka_unit_test_setup(test_pgn_a_frame_inside_a_line_and_noise, setup),
        cmocka_unit_test_setup(test_pgn_a_stalled_frame_is_dropped_after_3_s, setup),
        cmocka_unit_test_setup(test_pgn_frames_only_with_remote_agopengps, setup),
        cmocka_unit_test_setup(test_pgn_rules_frames_lost_on_the_period_after_frames_lost, setup),
        cmocka_unit_test_setup(test_pgn_rules_frame_start_and_sync_bytes, setup),
        cmocka_unit_test_setup(test_pgn_rules_frame_lengths, setup),
        cmocka_unit_test_setup(test_pgn_rules_modules_sensors_and_replies, setup),
        cmocka_unit_test_setup(test_pgn_rules_speeds_apart_counted_to_20, setup),
        cmocka_unit_test_setup(test_pgn_rules_ratecontrol_rate_handed_on, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* test_hil.c: the controller's hardware-in-the-loop mode through the main loop: entered only on purpose, one step per sensor frame on its inputs, pins held off, lost frames counted. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>
#include "speed.h"
#include "flow.h"
#include "hal_host.h"
#include "helper_link.h"
#include "link_crc.h"
#include "params.h"
#include "app.h"
#include "hil.h"
#include "screen.h"

static hil_rx_t out_rx;

#define MA(x) LINK_MA(x)

static int setup(void **state)
{
    (void)state;
    link_start();
    hil_rx_init(&out_rx, HIL_OUT_START);
    return 0;
}

/* everything the controller sent as text ('\0' for a binary byte) */
static size_t take_text(char *buf, size_t n)
{
    size_t k = 0;
    int b;
    while ((b = hal_host_uart_tx_pop()) >= 0)
        if (k + 1 < n)
            buf[k++] = (char)b;
    buf[k] = 0;
    return k;
}

/* the output frames the controller sent since the last call; the last one in o */
static int take_frames(hil_out_t *o)
{
    int b, n = 0;
    while ((b = hal_host_uart_tx_pop()) >= 0)
        if (hil_rx_byte(&out_rx, (uint8_t)b)) {
            hil_out_decode(out_rx.buf, o);
            n++;
        }
    return n;
}

static void hil_on(void)
{
    char buf[256];
    const char *c = "HIL ON";
    snprintf(buf, sizeof buf, "%s*%02X\r\n", c, link_crc8(c, strlen(c)));
    take_text(buf + 64, sizeof buf - 64);
    link_send(buf);
    link_run_ms(20);                     /* the loop serves the link in its idle passes */
    take_text(buf, sizeof buf);
    assert_non_null(strstr(buf, "OK HIL*"));
}

/* a sensor frame with a setting (set_id HIL_NO_SETTING: none) onto the controller's wire */
static void frame_set(uint8_t seq, uint32_t at_ms, uint16_t wheel_total, uint16_t meter_total, uint16_t adc_p,
                      uint8_t set_id, uint16_t set_value)
{
    hil_in_t in;
    uint8_t f[HIL_IN_BYTES];
    memset(&in, 0, sizeof in);
    in.seq = seq;
    in.set_id = set_id;
    in.set_value = set_value;
    in.pca_now = hal_host_pca_of_ns(at_ms * 1000000ull);
    in.wheel_count = wheel_total;
    in.wheel_last = in.pca_now - 1000;
    in.meter_count = meter_total;
    in.meter_last = in.pca_now - 100;
    in.adc_pressure = (uint16_t)(4 * adc_p);   /* the sum of a period's 4 conversions */
    in.adc_level = (uint16_t)(4 * MA(20.0));
    in.sections = 0x3F;
    hil_in_encode(&in, f);
    for (size_t i = 0; i < sizeof f; i++)
        hal_host_uart_rx_push(f[i]);
}

static void frame(uint8_t seq, uint32_t at_ms, uint16_t wheel_total, uint16_t meter_total, uint16_t adc_p)
{
    frame_set(seq, at_ms, wheel_total, meter_total, adc_p, HIL_NO_SETTING, 0);
}

static void test_hil_is_entered_only_by_the_checksummed_command(void **state)
{
    char buf[256];
    (void)state;
    link_send("HIL ON\r\n");
    link_run_ms(5);
    take_text(buf, sizeof buf);
    assert_non_null(strstr(buf, "ERR NOCSUM"));
    assert_false(hal_hil_active());
    link_send("HIL ONX*00\r\n");
    link_run_ms(5);
    take_text(buf, sizeof buf);
    assert_non_null(strstr(buf, "ERR"));
    assert_false(hal_hil_active());
    /* with their checksums: the word ON exactly, nothing else */
    static const char *const bad[] = {"HIL OX", "HIL XN", "HIL NO", "HIL ONN", "HIL O", "HIL on"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char l[32];
        snprintf(l, sizeof l, "%s*%02X\r\n", bad[i], link_crc8(bad[i], strlen(bad[i])));
        link_send(l);
        link_run_ms(5);
        take_text(buf, sizeof buf);
        assert_non_null(strstr(buf, "ERR ARG"));
        assert_false(hal_hil_active());
    }
    hil_on();
    assert_true(hal_hil_active());
    /* the run screen says so */
    link_run_ms(300);
    char row2[17];
    for (int c = 0; c < 16; c++)
        row2[c] = screen_char(2, (uint8_t)c);
    row2[16] = 0;
    assert_non_null(strstr(row2, "HIL"));
}

static void test_hil_steps_once_per_frame_on_its_inputs_and_never_without_one(void **state)
{
    hil_out_t o;
    char buf[512];
    (void)state;
    hil_on();
    uint8_t kicks = hal_host_io.wdt_kicks;
    link_run_ms(2000);                       /* no frame: no step, no log line, no watchdog kick */
    assert_int_equal(take_text(buf, sizeof buf), 0);
    assert_int_equal(hal_host_io.wdt_kicks, kicks);
    /* 3 bar on the frame's pressure ADC (16 bar sensor: 4 mA + 3/16 of 16 mA) */
    frame(1, link_t_ms + 8, 0, 0, MA(4.0 + 16.0 * 3.0 / 16.0));
    link_run_ms(8);                          /* 29 bytes at 38400 baud: 7.6 ms on the wire */
    assert_int_equal(take_frames(&o), 1);
    assert_int_equal(o.seq, 1);
    assert_int_equal(o.lost, 0);
    assert_in_range(o.pressure_kpa, 290, 310);
    assert_int_equal((uint8_t)(hal_host_io.wdt_kicks - kicks), 1);
    link_run_ms(92);
    assert_int_equal(take_frames(&o), 0);   /* one answer a frame, nothing in between */
    frame(2, link_t_ms + 8, 0, 0, MA(4.0));
    link_run_ms(8);
    assert_int_equal(take_frames(&o), 1);
    assert_int_equal(o.seq, 2);
    assert_in_range(o.pressure_kpa, 0, 10);
}

static void test_hil_counts_lost_frames_and_loses_no_edge_with_them(void **state)
{
    hil_out_t o;
    (void)state;
    hil_on();
    uint32_t w0 = speed_pulses(), m0 = flow_pulses();
    frame(1, 100, 3, 40, MA(4.0));
    link_run_ms(100);
    assert_int_equal(take_frames(&o), 1);
    assert_int_equal(speed_pulses() - w0, 3);
    assert_int_equal(flow_pulses() - m0, 40);
    /* frames 2 and 3 never come; 4 carries the running totals: the edges of the lost frames
     * are counted with it, none lost */
    frame(4, 400, 12, 160, MA(4.0));
    link_run_ms(300);
    assert_int_equal(take_frames(&o), 1);
    assert_int_equal(o.seq, 4);
    assert_int_equal(o.lost, 2);
    assert_int_equal(speed_pulses() - w0, 12);
    assert_int_equal(flow_pulses() - m0, 160);
    /* a damaged frame: dropped, counted at the next good one */
    hil_in_t in;
    uint8_t f[HIL_IN_BYTES];
    memset(&in, 0, sizeof in);
    in.seq = 5;
    hil_in_encode(&in, f);
    f[10] ^= 1;
    for (size_t i = 0; i < sizeof f; i++)
        hal_host_uart_rx_push(f[i]);
    link_run_ms(100);
    assert_int_equal(take_frames(&o), 0);
    frame(6, 600, 20, 240, MA(4.0));
    link_run_ms(100);
    assert_int_equal(take_frames(&o), 1);
    assert_int_equal(o.lost, 3);
    assert_int_equal(speed_pulses() - w0, 20);      /* the damaged frame's edges too */
    assert_int_equal(flow_pulses() - m0, 240);
    /* the count stops at 65535: frames whose sequence byte steps back by one (254 lost each) */
    uint8_t seq = 6;
    for (uint32_t i = 0; i < 260; i++) {
        seq = (uint8_t)(seq - 1u);
        frame(seq, 700 + 100 * i, 20, 240, MA(4.0));
        link_run_ms(100);
        assert_int_equal(take_frames(&o), 1);
        assert_int_equal(o.lost, i < 257 ? 3 + 254 * (i + 1) : 0xFFFF);
    }
}

static void test_hil_holds_the_pins_off_and_reports_the_outputs(void **state)
{
    hil_out_t o;
    (void)state;
    assert_true(param_set(P_GIVEN_SPEED, 60));      /* 6 km/h given: the boom sprays */
    hil_on();
    uint16_t meter = 0;
    int sprayed = 0, drove = 0;
    for (uint8_t seq = 1; seq <= 30; seq++) {
        meter = (uint16_t)(meter + 20);             /* 20 edges a period: 31.6 L/min at 380 /L */
        frame(seq, (uint32_t)seq * 100u, 0, meter, MA(4.0 + 16.0 * 1.0 / 16.0));
        link_run_ms(100);
        assert_int_equal(take_frames(&o), 1);
        sprayed |= o.relays & 1;
        drove |= o.valve_dir != 0;
        assert_int_equal(hal_host_io.spray_on, 0);
        assert_int_equal(hal_host_io.valve_dir, HAL_VALVE_OFF);
        assert_int_equal(hal_host_io.buzzer, 0);
    }
    assert_true(sprayed);
    assert_true(drove);
    assert_int_equal(o.target_lpm_x100, 2700);      /* 150 L/ha, 18 m, 6 km/h */
    assert_in_range(o.flow_lpm_x100, 3000, 3300);
}

/* A frame's setting is set before its step, as the keypad would set it, and the answer says so;
 * one out of range or against another setting is refused with its reason and changes nothing.
 * 150 L/ha on 36 nozzles at 0.5 m (18 m) at 6 km/h: 150 x 18 x 6 / 600 = 27 L/min; 100 L/ha: 18. */
static void test_hil_sets_a_frames_setting_before_its_step(void **state)
{
    hil_out_t o;
    uint8_t seq = 0;
    (void)state;
    assert_int_equal(param_v[P_GIVEN_SPEED], 0);
    assert_int_equal(param_v[P_RATE], 1500);
    hil_on();
    frame(++seq, 100, 0, 0, MA(4.0));
    link_run_ms(100);
    assert_int_equal(take_frames(&o), 1);
    assert_int_equal(o.set_verdict, HIL_NO_SETTING);
    assert_int_equal(o.target_lpm_x100, 0);         /* no wheel, no given speed: standing */
    frame_set(++seq, 200, 0, 0, MA(4.0), P_GIVEN_SPEED, 60);
    link_run_ms(100);
    assert_int_equal(take_frames(&o), 1);
    assert_int_equal(o.set_verdict, PARAM_OK);
    assert_int_equal(param_v[P_GIVEN_SPEED], 60);
    assert_int_equal(o.speed_kmh_x100, 600);         /* this very step drove at it */
    assert_int_equal(o.target_lpm_x100, 2700);
    frame_set(++seq, 300, 0, 0, MA(4.0), P_RATE, 1000);
    link_run_ms(100);
    assert_int_equal(take_frames(&o), 1);
    assert_int_equal(o.set_verdict, PARAM_OK);
    assert_int_equal(o.target_lpm_x100, 1800);
    /* out of the range 10.0..1000.0: refused, the rate stays */
    frame_set(++seq, 400, 0, 0, MA(4.0), P_RATE, 5);
    link_run_ms(100);
    assert_int_equal(take_frames(&o), 1);
    assert_int_equal(o.set_verdict, PARAM_E_RANGE);
    assert_int_equal(param_v[P_RATE], 1000);
    assert_int_equal(o.target_lpm_x100, 1800);
    /* Tank min at the tank's size: against the cross-check, refused */
    frame_set(++seq, 500, 0, 0, MA(4.0), P_TANK_MIN, param_v[P_TANK_L]);
    link_run_ms(100);
    assert_int_equal(take_frames(&o), 1);
    assert_int_equal(o.set_verdict, PARAM_X_TANK);
    assert_true(param_v[P_TANK_MIN] < param_v[P_TANK_L]);
    /* no such parameter */
    frame_set(++seq, 600, 0, 0, MA(4.0), P_COUNT, 1);
    link_run_ms(100);
    assert_int_equal(take_frames(&o), 1);
    assert_int_equal(o.set_verdict, PARAM_E_RANGE);
    frame(++seq, 700, 0, 0, MA(4.0));
    link_run_ms(100);
    assert_int_equal(take_frames(&o), 1);
    assert_int_equal(o.set_verdict, HIL_NO_SETTING);
    assert_int_equal(o.target_lpm_x100, 1800);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_hil_is_entered_only_by_the_checksummed_command, setup),
        cmocka_unit_test_setup(test_hil_steps_once_per_frame_on_its_inputs_and_never_without_one, setup),
        cmocka_unit_test_setup(test_hil_counts_lost_frames_and_loses_no_edge_with_them, setup),
        cmocka_unit_test_setup(test_hil_holds_the_pins_off_and_reports_the_outputs, setup),
        cmocka_unit_test_setup(test_hil_sets_a_frames_setting_before_its_step, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

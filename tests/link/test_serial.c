/* test_serial.c: the main loop through the host HAL: fixed period, watchdog only while healthy, the RS232 log, alarm messages and strict commands. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>
#include "hal_host.h"
#include "params.h"
#include "app.h"
#include "diag.h"

static uint64_t t_ms;
static char line[128];

/* 4-20 mA counts */
#define MA(x) ((uint16_t)((x) * 51.15 + 0.5))

static int setup(void **state)
{
    (void)state;
    hal_host_reset();
    hal_init();
    t_ms = 0;
    hal_host_io.adc[HAL_ADC_PRESSURE] = MA(4.0);
    hal_host_io.adc[HAL_ADC_LEVEL] = MA(20.0);
    hal_host_io.sections = 0x3F;
    app_init();
    return 0;
}

static void run_ms(uint32_t ms)
{
    for (uint32_t i = 0; i < ms; i++) {
        t_ms++;
        hal_host_set_time_ns(t_ms * 1000000ull);
        app_poll();
    }
}

static void send(const char *s)
{
    while (*s)
        hal_host_uart_rx_push((uint8_t)*s++);
}

/* the next line the firmware sent ("" when none), its checksum verified */
static const char *next_line(void)
{
    size_t n = 0;
    int b;
    while ((b = hal_host_uart_tx_pop()) >= 0 && b != '\n')
        if (n < sizeof line - 1)
            line[n++] = (char)b;
    line[n] = 0;
    if (n == 0)
        return line;
    assert_true(n >= 5 && line[n - 1] == '\r' && line[n - 4] == '*');
    unsigned x = 0, cs;
    for (size_t i = 0; i < n - 4; i++)
        x ^= (uint8_t)line[i];
    assert_int_equal(sscanf(line + n - 3, "%2X", &cs), 1);
    assert_int_equal(cs, x);
    line[n - 4] = 0;
    return line;
}

/* send a command, let the loop answer, return the reply line */
static const char *cmd(const char *c)
{
    while (next_line()[0])
        ;
    send(c);
    run_ms(5);
    return next_line();
}

static void test_serial_loop_runs_every_100_ms_and_feeds_the_watchdog(void **state)
{
    (void)state;
    uint8_t k0 = hal_host_io.wdt_kicks;
    run_ms(1000);
    assert_int_equal((uint8_t)(hal_host_io.wdt_kicks - k0), 10);
    /* a stall of the loop (time jumps 500 ms): that step is late and does not feed */
    k0 = hal_host_io.wdt_kicks;
    t_ms += 500;
    run_ms(1);
    assert_int_equal(hal_host_io.wdt_kicks, k0);
    assert_int_equal(app_overruns(), 1);
    run_ms(300);
    assert_true((uint8_t)(hal_host_io.wdt_kicks - k0) >= 2);
    /* a parameter corrupted in RAM latches the internal fault: no more feeding */
    param_v[P_NOZZLES] = 0;
    k0 = hal_host_io.wdt_kicks;
    run_ms(1000);
    assert_int_equal(hal_host_io.wdt_kicks, k0);
    assert_true(app_status.alarms & (1u << AL_INTERNAL));
    assert_false(hal_host_io.spray_on);
}

static void test_serial_logs_every_second_like_the_paper_s_pc_monitor(void **state)
{
    (void)state;
    run_ms(1001);                               /* the 10th step at 1000 ms, sent on the next turn */
    unsigned long t;
    unsigned v, p, al;
    int q1, q3;
    const char *l = next_line();
    assert_int_equal(sscanf(l, "LOG %lu %u %u %d %d %4X", &t, &v, &p, &q1, &q3, &al), 6);
    assert_int_equal(t, 1001);
    assert_int_equal(v, 0);
    assert_true(p <= 1);                        /* 4 mA = 204.6 counts; 205 reads 0.8 kPa */
    run_ms(1000);
    l = next_line();
    assert_int_equal(sscanf(l, "LOG %lu", &t), 1);
    assert_int_equal(t, 2001);
    assert_string_equal(next_line(), "");
}

static void test_serial_commands_read_and_set_parameters_strictly(void **state)
{
    (void)state;
    run_ms(200);
    assert_string_equal(cmd("GET 0\r\n"), "OK 0 150");
    assert_string_equal(cmd("SET 0 120\n"), "OK 0 120");
    assert_int_equal(param_v[P_RATE], 120);
    assert_string_equal(cmd("SET 0 5\n"), "ERR RANGE");          /* below 10 L/ha */
    assert_int_equal(param_v[P_RATE], 120);
    assert_string_equal(cmd("SET 0 70000\n"), "ERR NUM");
    assert_string_equal(cmd("SET 99 1\n"), "ERR ID");
    assert_string_equal(cmd("SET 0  100\n"), "ERR ARG");
    assert_string_equal(cmd("SET 0 -100\n"), "ERR NUM");
    assert_string_equal(cmd("SET 0 1e2\n"), "ERR NUM");
    assert_string_equal(cmd("FOO\n"), "ERR CMD");
    assert_string_equal(cmd("set 0 100\n"), "ERR CMD");
    assert_int_equal(param_v[P_RATE], 120);
    /* checksum: "SET 0 130" XOR = 0x..., a wrong one changes nothing */
    char ok[32];
    unsigned x = 0;
    for (const char *s = "SET 0 130"; *s; s++)
        x ^= (uint8_t)*s;
    snprintf(ok, sizeof ok, "SET 0 130*%02X\r\n", x);
    assert_string_equal(cmd(ok), "OK 0 130");
    snprintf(ok, sizeof ok, "SET 0 140*%02X\r\n", x);
    assert_string_equal(cmd(ok), "ERR CSUM");
    assert_string_equal(cmd("SET 0 140*4\r\n"), "ERR CSUM");
    assert_int_equal(param_v[P_RATE], 130);
    /* too long, not ASCII */
    assert_string_equal(cmd("SET 0 100 0000000000000000000000000000000\n"), "ERR LONG");
    assert_string_equal(cmd("SET 0 1\x01" "00\n"), "ERR CHAR");
    assert_int_equal(param_v[P_RATE], 130);
    /* controller, pulse totals, totals, ack, jog outside manual */
    assert_string_equal(cmd("CTL 0\n"), "OK CTL 0");
    run_ms(200);
    assert_int_equal(param_v[P_CONTROLLER], 0);
    assert_string_equal(cmd("CTL 9\n"), "ERR RANGE");
    assert_string_equal(cmd("PUL\n"), "OK PUL 0 0");
    assert_string_equal(cmd("ACK now\n"), "ERR ARG");
    assert_string_equal(cmd("ACK\n"), "OK ACK");
    assert_string_equal(cmd("JOG +\n"), "ERR MODE");
    assert_string_equal(cmd("TOT\n"), "OK TOT 0 0 0");
}

/* an alarm is told once when raised (code and LCD text) and once when it clears; the
 * buzzer sounds until it is acknowledged */
static void test_serial_alarm_messages_and_the_buzzer(void **state)
{
    (void)state;
    run_ms(500);
    while (next_line()[0])
        ;
    hal_host_io.adc[HAL_ADC_PRESSURE] = MA(3.5);                 /* open pressure sensor */
    run_ms(500);
    assert_string_equal(next_line(), "ALM PSENS_FAULT P sensor fault");
    assert_true(hal_host_io.buzzer);
    assert_true(app_status.alarms_unacked & (1u << AL_PSENS));
    ops_alarm_ack();
    run_ms(100);
    assert_false(hal_host_io.buzzer);
    assert_true(app_status.alarms & (1u << AL_PSENS));           /* still active */
    hal_host_io.adc[HAL_ADC_PRESSURE] = MA(4.0);
    run_ms(2500);                               /* 1 s of good readings, 1 s to clear */
    const char *l;
    int seen = 0;
    while ((l = next_line())[0])
        if (strcmp(l, "CLR PSENS_FAULT") == 0)
            seen = 1;
    assert_true(seen);
    for (uint8_t b = 0; b < AL_COUNT; b++) {
        assert_true(strlen(app_alarm_text(b)) <= 16);
        assert_true(strlen(app_alarm_code(b)) > 0);
    }
}

/* manual mode: the operator jogs the valve; auto again starts the controller bumplessly */
static void test_serial_manual_jog_drives_the_valve_for_a_jog(void **state)
{
    (void)state;
    assert_true(param_set(P_MODE, 1));
    run_ms(200);
    assert_true(app_status.manual);
    assert_true(app_status.spraying);                            /* sections on, tank full */
    assert_string_equal(cmd("JOG +\n"), "OK JOG");
    run_ms(100);
    assert_int_equal(hal_host_io.valve_dir, HAL_VALVE_CLOSE);
    run_ms(400);
    assert_int_equal(hal_host_io.valve_dir, HAL_VALVE_OFF);
    /* a jog the other way while one runs: the bridge is off for the dead time first */
    assert_string_equal(cmd("JOG +\n"), "OK JOG");
    run_ms(100);
    assert_int_equal(hal_host_io.valve_dir, HAL_VALVE_CLOSE);
    ops_jog(-1);
    int off_ms = 0;
    while (hal_host_io.valve_dir != HAL_VALVE_OPEN && off_ms < 300) {
        run_ms(1);
        if (hal_host_io.valve_dir == HAL_VALVE_OFF)
            off_ms++;
    }
    assert_int_equal(hal_host_io.valve_dir, HAL_VALVE_OPEN);
    assert_true(off_ms >= 20);
    /* back to auto: the controller takes over from rest */
    assert_true(param_set(P_MODE, 0));
    run_ms(500);
    assert_false(app_status.manual);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_serial_loop_runs_every_100_ms_and_feeds_the_watchdog, setup),
        cmocka_unit_test_setup(test_serial_logs_every_second_like_the_paper_s_pc_monitor, setup),
        cmocka_unit_test_setup(test_serial_commands_read_and_set_parameters_strictly, setup),
        cmocka_unit_test_setup(test_serial_alarm_messages_and_the_buzzer, setup),
        cmocka_unit_test_setup(test_serial_manual_jog_drives_the_valve_for_a_jog, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

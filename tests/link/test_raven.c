/* test_remote.c: a field computer's Raven strings through the host build: rate change within the window, calibration and data replies, refusals and malformed strings. */
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
#include "screen.h"
#include "serial.h"
#include "remote.h"
#include "store.h"
#include "console.h"

static char line[128];

#define MA(x) LINK_MA(x)

/* the next line sent, CR LF removed ("" when none); ours end in "*HH" (checked and cut), Raven's
 * have none */
static const char *next_line(void)
{
    size_t n = link_read_line(line, sizeof line);
    if (n == 0)
        return line;
    assert_true(n >= 2 && line[n - 1] == '\r');
    line[--n] = 0;
    if (line[0] == '$') {
        assert_null(strchr(line, '*'));
        return line;
    }
    assert_true(n >= 4 && line[n - 3] == '*');
    unsigned cs;
    assert_int_equal(sscanf(line + n - 2, "%2X", &cs), 1);
    assert_int_equal(cs, link_crc8(line, n - 3));
    line[n - 3] = 0;
    return line;
}

static void drain_lines(void)
{
    while (next_line()[0])
        ;
}

static int setup(void **state)
{
    (void)state;
    link_start();
    store_status_clear();                   /* a first boot's "EE: defaults" seen */
    link_run_ms(CONSOLE_MSG_MS + 100);           /* the reset cause's message gone */
    drain_lines();                          /* the BOOT line */
    return 0;
}

/* send a string, let the loop answer (after a settings change the loop first spends a pass a module on
 * their constants; well inside a second: no log line), return the first reply */
static const char *req(const char *c)
{
    drain_lines();
    link_send(c);
    link_run_ms(20);
    return next_line();
}

/* the screen model's bottom line */
static const char *bottom(void)
{
    static char out[17];
    link_run_ms(600);
    for (int c = 0; c < 16; c++)
        out[c] = screen_char(3, (uint8_t)c);
    out[16] = 0;
    return out;
}

static void test_raven_strings_are_refused_while_remote_is_off(void **state)
{
    (void)state;
    assert_int_equal(param_v[P_REMOTE], 0);
    assert_string_equal(req("$R,RC,1300\r\n"), "ERR REMOTE");
    assert_string_equal(req("$R,DR\r\n"), "ERR REMOTE");
    assert_int_equal(target_rate_x10(), 1500);
    assert_false(target_rate_remote());
    link_run_ms(1000);                           /* no AR line with Remote off, the LOG line as ever */
    assert_memory_equal(next_line(), "LOG ", 4);
    assert_string_equal(next_line(), "");
}

static void test_raven_rate_change_within_the_window_sets_the_rate(void **state)
{
    (void)state;
    assert_true(param_set(P_REMOTE, 1));
    link_run_ms(200);
    /* 130.0 L/ha (the decimal point not sent): taken, the actual rate answers */
    assert_string_equal(req("$R,RC,1300\r\n"), "$R100A,AR,0");
    assert_int_equal(target_rate_x10(), 1300);
    assert_true(target_rate_remote());
    assert_string_equal(bottom(), "T 1000L  RC130.0");
    /* the target flow follows the rate: 130 L/ha x 8 km/h (given) x 18 m / 600 = 31.2 L/min */
    assert_true(param_set(P_GIVEN_SPEED, 80));
    link_run_ms(200);
    assert_int_equal(app_status.target_lpm_x100, 3120);
    /* 130.5 is kept to the tenth */
    assert_string_equal(req("$R,RC,1305\r\n"), "$R100A,AR,0");
    assert_int_equal(target_rate_x10(), 1305);
    /* the window's edges: 50 % of 150 L/ha: 75.0 .. 225.0 taken, 74.9 and 225.1 refused */
    assert_string_equal(req("$R,RC,750\r\n"), "$R100A,AR,0");
    assert_string_equal(req("$R,RC,2250\r\n"), "$R100A,AR,0");
    assert_string_equal(req("$R,RC,749\r\n"), "ERR WINDOW");
    assert_string_equal(req("$R,RC,2251\r\n"), "ERR WINDOW");
    assert_int_equal(target_rate_x10(), 2250);
    /* Remote switched off: back to Dose */
    assert_true(param_set(P_REMOTE, 0));
    link_run_ms(200);
    assert_int_equal(target_rate_x10(), 1500);
    assert_false(target_rate_remote());
    assert_int_equal(app_status.target_lpm_x100, 3600);     /* 150 L/ha: 36.0 L/min */
}

/* The strings' letters and numbers exactly: any other letter at any place is ERR CMD, a rate
 * beyond 65535 or with a character that is no digit ERR NUM (one past '9' too), and one parsed
 * but outside the window ERR WINDOW; nothing changes the rate. */
static void test_raven_strings_letter_by_letter_and_rates_to_65535(void **state)
{
    (void)state;
    assert_true(param_set(P_REMOTE, 1));
    static const char *const bad_cmd[] = {"$RXRC,1500", "$R,XC,1500", "$R,RX,1500", "$R,RC.1500", "$R,CX",
                                          "$R,XR", "$R,DX", "$X,RC,1500"};
    static const char *const bad_num[] = {"$R,RC,15:0", "$R,RC,15/0", "$R,RC,65536", "$R,RC,65539",
                                          "$R,RC,65540", "$R,RC,65600", "$R,RC,100000", "$R,RC,"};
    static const char *const window[] = {"$R,RC,65535", "$R,RC,65529", "$R,RC,65499", "$R,RC,6553"};
    char l[32];
    for (size_t i = 0; i < sizeof bad_cmd / sizeof bad_cmd[0]; i++) {
        snprintf(l, sizeof l, "%s\r\n", bad_cmd[i]);
        assert_string_equal(req(l), "ERR CMD");
    }
    for (size_t i = 0; i < sizeof bad_num / sizeof bad_num[0]; i++) {
        snprintf(l, sizeof l, "%s\r\n", bad_num[i]);
        assert_string_equal(req(l), "ERR NUM");
    }
    for (size_t i = 0; i < sizeof window / sizeof window[0]; i++) {
        snprintf(l, sizeof l, "%s\r\n", window[i]);
        assert_string_equal(req(l), "ERR WINDOW");
    }
    assert_int_equal(target_rate_x10(), 1500);
    assert_false(target_rate_remote());
    const char *r = req("$R,CR\r\n");
    while (!strncmp(r, "LOG ", 4) || !strncmp(r, "$R100A,AR", 9))
        r = next_line();                            /* a second's lines meanwhile */
    assert_memory_equal(r, "$R100A,C1,", 10);
    r = req("$R,DR\r\n");
    while (!strncmp(r, "LOG ", 4) || !strncmp(r, "$R100A,AR", 9))
        r = next_line();
    assert_memory_equal(r, "$R100A,D1,", 10);
    assert_string_equal(req("$R,CR,1\r\n"), "ERR ARG");
}

static void test_raven_rate_outside_the_window_is_refused_and_shown(void **state)
{
    (void)state;
    assert_true(param_set(P_REMOTE, 1));
    assert_true(param_set(P_REMOTE_WIN, 20));           /* 120 .. 180 L/ha */
    assert_string_equal(req("$R,RC,1300\r\n"), "$R100A,AR,0");
    uint8_t n0 = target_remote_refusals();
    assert_string_equal(req("$R,RC,2300\r\n"), "ERR WINDOW");
    assert_int_equal(target_rate_x10(), 1300);          /* nothing changed */
    assert_int_equal(target_remote_refusals(), (uint8_t)(n0 + 1));
    assert_string_equal(bottom(), "RC rate refused ");
    assert_string_equal(req("$R,RC,0\r\n"), "ERR WINDOW");
    assert_int_equal(target_rate_x10(), 1300);
    /* a new Rate 1 whose window leaves the remote rate outside drops it */
    assert_true(param_set(P_RATE, 2000));               /* 160 .. 240 */
    link_run_ms(200);
    assert_false(target_rate_remote());
    assert_int_equal(target_rate_x10(), 2000);
}

static void test_raven_malformed_strings_get_an_error_and_change_nothing(void **state)
{
    (void)state;
    static const char *const bad[][2] = {
        {"$R,RC,\r\n", "ERR NUM"},          {"$R,RC,13a0\r\n", "ERR NUM"},
        {"$R,RC,-1300\r\n", "ERR NUM"},     {"$R,RC,130.0\r\n", "ERR NUM"},
        {"$R,RC,999999\r\n", "ERR NUM"},    {"$R,RC,1300,0,1027\r\n", "ERR ARG"},
        {"$R,RC,1300,\r\n", "ERR ARG"},     {"$R,CR,1\r\n", "ERR ARG"},
        {"$R,DRX\r\n", "ERR ARG"},          {"$R,XX\r\n", "ERR CMD"},
        {"$r,rc,1300\r\n", "ERR CMD"},      {"$X,RC,1300\r\n", "ERR CMD"},
        {"$R\r\n", "ERR CMD"},              {"$R,RC 1300\r\n", "ERR CMD"},
        {"$R,RC,65536\r\n", "ERR NUM"},
    };
    assert_true(param_set(P_REMOTE, 1));
    assert_string_equal(req("$R,RC,1400\r\n"), "$R100A,AR,0");
    uint8_t refusals = target_remote_refusals();
    for (unsigned i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        assert_string_equal(req(bad[i][0]), bad[i][1]);
        assert_string_equal(next_line(), "");           /* nothing else sent */
        assert_int_equal(target_rate_x10(), 1400);
    }
    assert_int_equal(target_remote_refusals(), refusals);      /* none was a rate refused */
    /* our own protocol goes on beside it */
    assert_string_equal(req("GET 0\r\n"), "OK 0 1500");
}

static void test_raven_calibration_and_data_requests_answer_in_raven_strings(void **state)
{
    (void)state;
    assert_true(param_set(P_REMOTE, 1));
    assert_string_equal(req("$R,RC,1300\r\n"), "$R100A,AR,0");
    /* six sections of 6 nozzles at 50 cm: booms 300 cm; sections 1-6 on; auto: rate 1 */
    assert_string_equal(req("$R,CR\r\n"), "$R100A,C1,191,136,300,300,300,300,300,300,3927");
    assert_string_equal(next_line(), "$R100A,C2,3800,0");
    link_run_ms(5);
    assert_string_equal(next_line(), "$R100A,C3,2123,1300,0");
    link_run_ms(5);
    assert_string_equal(next_line(), "");
    /* Rate 2 in use: bit 4 of switch byte 2 in place of bit 3 (0x90); the remote rate stays in
     * its window around Rate 2 (200 L/ha by default: 100..300), nudged 5 % in C3's rate */
    assert_true(param_set(P_PRESET, 1));
    target_nudge(1);
    link_run_ms(200);
    assert_string_equal(req("$R,CR\r\n"), "$R100A,C1,191,144,300,300,300,300,300,300,3927");
    assert_string_equal(next_line(), "$R100A,C2,3800,0");
    link_run_ms(5);
    assert_string_equal(next_line(), "$R100A,C3,2123,1365,0");
    link_run_ms(5);
    target_nudge(0);
    assert_true(param_set(P_PRESET, 0));
    drain_lines();
    /* manual mode: both rate bits 0; section 2 off */
    assert_true(param_set(P_MODE, 1));
    hal_host_io.sections = 0x3D;
    link_run_ms(200);
    assert_string_equal(req("$R,CR\r\n"), "$R100A,C1,189,128,300,300,300,300,300,300,3927");
    drain_lines();
    link_run_ms(20);
    drain_lines();
    char want[64];
    assert_string_equal(req("$R,DR\r\n"), "$R100A,D1,0,0");
    link_run_ms(5);
    assert_string_equal(next_line(), "$R100A,D2,0,0");
    link_run_ms(5);
    snprintf(want, sizeof want, "$R100A,D3,%u,0", app_status.tank_l);
    assert_string_equal(next_line(), want);
    assert_true(app_status.tank_l > 900);
}

static void test_raven_actual_rate_once_a_second_after_the_log_line(void **state)
{
    (void)state;
    assert_true(param_set(P_REMOTE, 1));
    drain_lines();
    link_run_ms(1100);
    assert_memory_equal(next_line(), "LOG ", 4);
    link_run_ms(5);
    assert_string_equal(next_line(), "$R100A,AR,0");
    /* spraying 36 L/min at 8 km/h over 18 m: 150.0 L/ha */
    drain_lines();
    app_status.spraying = 1;
    app_status.speed_kmh_x100 = 800;
    app_status.flow_lpm_x100 = 3600;
    remote_tick();
    serial_poll(1);
    assert_string_equal(next_line(), "$R100A,AR,1500");
    app_status.flow_lpm_x100 = 3000;                /* 125.0 */
    remote_tick();
    serial_poll(1);
    assert_string_equal(next_line(), "$R100A,AR,1250");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_raven_strings_are_refused_while_remote_is_off, setup),
        cmocka_unit_test_setup(test_raven_rate_change_within_the_window_sets_the_rate, setup),
        cmocka_unit_test_setup(test_raven_rate_outside_the_window_is_refused_and_shown, setup),
        cmocka_unit_test_setup(test_raven_strings_letter_by_letter_and_rates_to_65535, setup),
        cmocka_unit_test_setup(test_raven_malformed_strings_get_an_error_and_change_nothing, setup),
        cmocka_unit_test_setup(test_raven_calibration_and_data_requests_answer_in_raven_strings, setup),
        cmocka_unit_test_setup(test_raven_actual_rate_once_a_second_after_the_log_line, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* test_diag_wheel.c: the pump against the wheel (diag_pump) called period by period with synthetic inputs: what it learns at a standstill, what then says the wheels turn, each edge on both sides. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <string.h>
#include <cmocka.h>
#include "hal_host.h"
#include "params.h"
#include "ops.h"
#include "speed.h"
#include "valve.h"
#include "analog.h"
#include "diag_line.h"
#include "diag_wheel.h"

#define PERIOD_NS 100000000ull

static struct {
    uint64_t now_ns;
    uint64_t wheel_ns, wheel_next;  /* 0 ns: no pulses */
    app_status_t st;
} sy;

static uint16_t adc_counts[2];      /* 614: 12 mA; 179: 3.5 mA, the loop open */

static uint16_t adc(uint8_t ch)
{
    return ch < 2 ? adc_counts[ch] : 0;
}

static int setup(void **state)
{
    (void)state;
    hal_host_reset();
    params_defaults();
    speed_init();
    analog_init();
    valve_init();
    diag_wheel_init();
    adc_counts[0] = adc_counts[1] = 614;
    hal_host_adc_source(adc);
    memset(&sy, 0, sizeof sy);
    sy.st.open_nozzles = 36;
    return 0;
}

/* one period: the wheel's pulses up to its end, the loops, then the rule */
static uint8_t pump(void)
{
    sy.now_ns += PERIOD_NS;
    hal_host_set_time_ns(sy.now_ns);
    while (sy.wheel_ns && sy.wheel_next <= sy.now_ns) {
        hal_host_wheel_edge(sy.wheel_next);
        sy.wheel_next += sy.wheel_ns;
    }
    speed_step();
    analog_step();
    diag_period(&sy.st, 0);
    return diag_pump();
}

/* periods until diag_pump says the wheels turn, at most max (max + 1: never) */
static int pump_after(int max)
{
    for (int n = 1; n <= max; n++)
        if (pump())
            return n;
    return max + 1;
}

/* The wheel measured a speed once (a pulse every 50 ms for 2 s), then stood; the bypass opened
 * by 0.6 of a stroke (valve.c's full period at the defaults is 819 / 32768 of it: 24 periods). */
static void wheel_measured_bypass_open(void)
{
    sy.wheel_ns = 50000000u;
    sy.wheel_next = sy.now_ns + sy.wheel_ns;
    for (int i = 0; i < 20; i++)
        assert_int_equal(pump(), 0);
    sy.wheel_ns = 0;
    assert_true(speed_at_last_pulse_x100() > 0);
    for (int i = 0; i < 24; i++) {
        valve_set(-Q15_MAX);
        valve_set(0);
    }
    assert_true(valve_opened_by(DIAG_PUMP_OPEN_Q15));
}

/* At a standstill with the boom shut the line under 10 kPa for 30 periods: the pump stands with
 * the wheels. Then a period at 30 kPa (neither standing nor delivering: the count starts again). */
static void pump_learnt_on_the_wheels(void)
{
    sy.st.in.pressure_kpa = DIAG_PUMP_STOP_KPA - 1u;
    for (int i = 0; i < 40; i++)
        assert_int_equal(pump(), 0);
    sy.st.in.pressure_kpa = 30;
    assert_int_equal(pump(), 0);
}

/* Learnt, the wheel's speed measured once: the line at 50 kPa with the sections on and the bypass
 * open by half a stroke says the pump turns: the 30th period of it; 49 kPa never. */
static void test_pump_runs_at_50_kpa_on_the_30th_period(void **state)
{
    (void)state;
    for (int k = 0; k < 2; k++) {
        setup(NULL);
        wheel_measured_bypass_open();
        pump_learnt_on_the_wheels();
        sy.st.in.pressure_kpa = (uint16_t)(DIAG_PUMP_RUN_KPA - 1u + k);
        assert_int_equal(pump_after(60), k ? 30 : 61);
    }
}

/* The line straight from under 10 kPa (the pump learnt standing, 40 periods of it) to 50 kPa and
 * more: the pump's delivery is its own evidence, 30 periods of it from the first at 50 kPa, none
 * carried over from the standing. The same when the line falls back under 10 kPa for a period
 * inside the 30 (the count of the delivery starts again after it). */
static void test_pump_counts_its_30_periods_afresh_when_the_line_jumps(void **state)
{
    (void)state;
    setup(NULL);
    wheel_measured_bypass_open();
    sy.st.in.pressure_kpa = DIAG_PUMP_STOP_KPA - 1u;
    for (int i = 0; i < 40; i++)
        assert_int_equal(pump(), 0);
    sy.st.in.pressure_kpa = DIAG_PUMP_RUN_KPA;
    assert_int_equal(pump_after(60), 30);
    /* said once, it holds while the line does */
    assert_int_equal(pump(), 1);
    /* under 10 kPa for a period, then 50 kPa again: 30 periods more */
    sy.st.in.pressure_kpa = DIAG_PUMP_STOP_KPA - 1u;
    assert_int_equal(pump(), 0);
    sy.st.in.pressure_kpa = DIAG_PUMP_RUN_KPA;
    assert_int_equal(pump_after(60), 30);
    /* 20 periods at 50 kPa, one under 10, then 50 again: 30 from there */
    sy.st.in.pressure_kpa = DIAG_PUMP_STOP_KPA - 1u;
    for (int i = 0; i < 40; i++)
        assert_int_equal(pump(), 0);
    sy.st.in.pressure_kpa = DIAG_PUMP_RUN_KPA;
    assert_int_equal(pump_after(20), 21);
    sy.st.in.pressure_kpa = DIAG_PUMP_STOP_KPA - 1u;
    assert_int_equal(pump(), 0);
    sy.st.in.pressure_kpa = DIAG_PUMP_RUN_KPA;
    assert_int_equal(pump_after(60), 30);
}

/* Learnt under 10 kPa: 9 kPa is under it, 10 is not (nothing learnt, nothing said after). */
static void test_pump_learnt_under_10_kpa(void **state)
{
    (void)state;
    for (int k = 0; k < 2; k++) {
        setup(NULL);
        wheel_measured_bypass_open();
        sy.st.in.pressure_kpa = (uint16_t)(DIAG_PUMP_STOP_KPA - 1u + k);
        for (int i = 0; i < 40; i++)
            assert_int_equal(pump(), 0);
        sy.st.in.pressure_kpa = 30;
        assert_int_equal(pump(), 0);
        sy.st.in.pressure_kpa = 60;
        assert_int_equal(pump_after(60), k ? 61 : 30);
    }
}

/* Nothing is learnt while the wheels turn, the boom sprays, a speed is given or the pressure
 * sensor has failed (its last reading 0 says nothing); nothing is said with the sections off or
 * before the wheel ever measured a speed. */
static void test_pump_learns_and_says_only_at_a_reported_standstill(void **state)
{
    (void)state;
    for (int c = 0; c < 4; c++) {
        setup(NULL);
        wheel_measured_bypass_open();
        sy.st.in.pressure_kpa = 0;
        sy.st.in.speed_kmh_x100 = c == 0 ? 1 : 0;
        sy.st.spraying = c == 1;
        if (c == 2)
            assert_true(param_set(P_GIVEN_SPEED, 80));
        if (c == 3)
            adc_counts[0] = 179;
        for (int i = 0; i < 40; i++)
            assert_int_equal(pump(), 0);
        if (c == 3)
            assert_false(analog_pressure_ok());
        /* everything back as a standstill wants it: nothing was learnt */
        sy.st.in.speed_kmh_x100 = 0;
        sy.st.spraying = 0;
        assert_true(param_set(P_GIVEN_SPEED, 0));
        adc_counts[0] = 614;
        sy.st.in.pressure_kpa = 60;
        assert_int_equal(pump_after(60), 61);
    }
    /* the sections off */
    setup(NULL);
    wheel_measured_bypass_open();
    pump_learnt_on_the_wheels();
    sy.st.open_nozzles = 0;
    sy.st.in.pressure_kpa = 60;
    assert_int_equal(pump_after(60), 61);
    sy.st.open_nozzles = 36;
    assert_int_equal(pump_after(60), 30);
    /* the wheel never measured a speed since power-up */
    setup(NULL);
    for (int i = 0; i < 24; i++) {
        valve_set(-Q15_MAX);
        valve_set(0);
    }
    pump_learnt_on_the_wheels();
    assert_int_equal(speed_at_last_pulse_x100(), 0);
    sy.st.in.pressure_kpa = 60;
    assert_int_equal(pump_after(60), 61);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pump_runs_at_50_kpa_on_the_30th_period),
        cmocka_unit_test(test_pump_learnt_under_10_kpa),
        cmocka_unit_test(test_pump_counts_its_30_periods_afresh_when_the_line_jumps),
        cmocka_unit_test(test_pump_learns_and_says_only_at_a_reported_standstill),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* test_valve.c: the H-bridge drive: direction and duty, dead time on reversal, end stops from the estimated position. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include "hal_host.h"
#include "params.h"
#include "ctl.h"
#include "valve.h"

static uint64_t t_ms;

static int setup(void **state)
{
    (void)state;
    hal_host_reset();
    params_defaults();                          /* 4 s full stroke */
    t_ms = 0;
    valve_init();
    return 0;
}

static void to_ms(uint64_t ms)
{
    t_ms = ms;
    hal_host_set_time_ns(ms * 1000000ull);
    valve_poll((uint32_t)ms);
}

/* one control period with this drive, the loop polling every ms */
static void period(q15_t drive)
{
    valve_set(drive);
    for (int i = 1; i <= 100; i++)
        to_ms(t_ms + 1);
}

static void test_valve_positive_drive_closes_the_bypass_with_its_duty(void **state)
{
    (void)state;
    valve_set(Q15(0.5));
    assert_int_equal(hal_host_io.valve_dir, HAL_VALVE_CLOSE);
    assert_int_equal(hal_host_io.valve_duty, 128);
    valve_set(Q15(0.5));
    assert_int_equal(hal_host_io.valve_dir, HAL_VALVE_CLOSE);  /* driven on, not off and on */
    assert_int_equal(hal_host_io.valve_duty, 128);
    valve_set(0);
    assert_int_equal(hal_host_io.valve_dir, HAL_VALVE_OFF);
    /* the same way again: no dead time (no reversal) */
    valve_set(Q15(0.5));
    assert_int_equal(hal_host_io.valve_dir, HAL_VALVE_CLOSE);
    /* the least drive is duty 1 of 255, not off */
    valve_set(0);
    valve_set(1);
    assert_int_equal(hal_host_io.valve_dir, HAL_VALVE_CLOSE);
    assert_int_equal(hal_host_io.valve_duty, 1);
}

static void test_valve_reversal_waits_the_dead_time_with_the_bridge_off(void **state)
{
    (void)state;
    period(Q15(0.6));
    assert_int_equal(hal_host_io.valve_dir, HAL_VALVE_CLOSE);
    valve_set(-Q15(0.6));
    assert_int_equal(hal_host_io.valve_dir, HAL_VALVE_OFF);    /* never straight across */
    uint64_t t0 = t_ms;
    while (hal_host_io.valve_dir == HAL_VALVE_OFF && t_ms < t0 + 100)
        to_ms(t_ms + 1);
    assert_int_equal(hal_host_io.valve_dir, HAL_VALVE_OPEN);
    assert_int_equal(t_ms - t0, VALVE_DEAD_MS);
    /* the same direction again after a pause needs no dead time */
    period(0);
    valve_set(-Q15(0.6));
    assert_int_equal(hal_host_io.valve_dir, HAL_VALVE_OPEN);
}

/* driven closed for longer than a stroke: at the stop it is not driven that way any more */
static void test_valve_stops_driving_into_its_end_stop(void **state)
{
    (void)state;
    int driven = 0;
    for (int i = 0; i < 160; i++) {             /* 16 s at full duty; the stroke is 4 s */
        period(Q15_MAX);
        if (hal_host_io.valve_dir == HAL_VALVE_CLOSE)
            driven++;
    }
    assert_true(valve_limit() & CTL_AT_CLOSED);
    /* at most 3.6 strokes (144 periods), then refused (the 0.1-stroke retry comes after 2 s) */
    assert_true(driven >= 144 && driven <= 145);
    assert_int_equal(valve_position(), 0);
    /* the other way frees it at once */
    period(-Q15_MAX);
    assert_int_equal(hal_host_io.valve_dir, HAL_VALVE_OPEN);
    period(-Q15_MAX);
    assert_false(valve_limit() & CTL_AT_CLOSED);
    /* position known: from closed, a stroke and 0.15 more finds the open stop */
    int n = 2;
    while (!(valve_limit() & CTL_AT_OPEN) && n < 100) {
        period(-Q15_MAX);
        n++;
    }
    print_message("# open stop found after %d periods\n", n);
    assert_true(n >= 46 && n <= 48);         /* 40 for the stroke, 6 past it, 1 to integrate */
    period(-Q15_MAX);
    assert_int_equal(hal_host_io.valve_dir, HAL_VALVE_OFF);
    assert_true(valve_limit() & CTL_AT_OPEN);
    /* a demand that goes on gets a 0.1-stroke retry every 2 s: 5 periods (4 of travel, 1 to
     * integrate) of every 25 */
    driven = 0;
    for (int i = 0; i < 240; i++) {
        period(-Q15_MAX);
        if (hal_host_io.valve_dir == HAL_VALVE_OPEN)
            driven++;
    }
    print_message("# against the open stop: driven %d of 240 periods\n", driven);
    assert_true(driven >= 40 && driven <= 52);
}

/* small drives below the stiction duty do not count as travel */
static void test_valve_sub_stiction_drive_does_not_move_the_estimate(void **state)
{
    (void)state;
    for (int i = 0; i < 200; i++)
        period(Q15(0.1));
    assert_false(valve_limit() & CTL_AT_CLOSED);
    assert_int_equal(hal_host_io.valve_dir, HAL_VALVE_CLOSE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_valve_positive_drive_closes_the_bypass_with_its_duty, setup),
        cmocka_unit_test_setup(test_valve_reversal_waits_the_dead_time_with_the_bridge_off, setup),
        cmocka_unit_test_setup(test_valve_stops_driving_into_its_end_stop, setup),
        cmocka_unit_test_setup(test_valve_sub_stiction_drive_does_not_move_the_estimate, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

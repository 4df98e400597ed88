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

/* ---- the position estimate and the stops, step by step ------------------------------------------
 * Worked by hand for the defaults (Valve time 4.0 s, Min duty 20 %): the running duty is 10/16
 * of Min duty, 0.125 = 4096 in Q15; a period at full speed moves 0.1 s / 4.0 s of the stroke,
 * and the rate per unit of duty above the running one is 2^30 / 40 / (32768 - 4096) = 936
 * (floored). A period's step: ((|d| - 4096) 936 + 2^14) >> 15 Q15 strokes, 819 at full duty,
 * 23 at the stiction limit VALVE_MOVE_Q15 (4915). The drives below sit mid-way in the range of
 * |d| that gives the step named. */
#define D_STEP_28 5076
#define D_STEP_29 5111
#define D_STEP_762 30773
#define D_STEP_803 32208
#define D_STEP_804 32243

/* one period of this drive integrated (valve_set integrates the period before it) */
static void one(q15_t drive)
{
    valve_set(drive);
    valve_set(0);
}

/* the closed stop found from an unknown position: 145 full periods (144 x 819 < 117965) */
static void to_closed_stop(void)
{
    for (int i = 0; i < 145; i++)
        one(Q15_MAX);
    assert_int_equal(valve_limit(), CTL_AT_CLOSED);
    assert_int_equal(valve_position(), 0);
}

/* The stop from an unknown position: driven one way by 3.6 strokes (117965) exactly, not one
 * less: 144 x 819 = 117936, then 28 more is 117964, 29 more 117965. */
static void test_valve_stop_at_exactly_3_6_strokes_one_way(void **state)
{
    (void)state;
    for (int k = 0; k < 2; k++) {
        setup(NULL);
        for (int i = 0; i < 144; i++)
            one(Q15_MAX);
        one(k ? D_STEP_29 : D_STEP_28);
        valve_set(0);
        assert_int_equal(valve_limit(), k ? CTL_AT_CLOSED : 0);
        assert_int_equal(valve_position(), k ? 0 : VALVE_POS_UNKNOWN);
    }
    /* the other way, from an unknown position, 3.6 strokes open */
    setup(NULL);
    for (int i = 0; i < 144; i++)
        one(-Q15_MAX);
    one(-D_STEP_28);
    assert_int_equal(valve_limit(), 0);
    one(-23);                                   /* under stiction: no travel */
    assert_int_equal(valve_limit(), 0);
    one(-D_STEP_28);
    assert_int_equal(valve_limit(), CTL_AT_OPEN);
    assert_int_equal(valve_position(), 32767);
}

/* With the position known: the other stop 0.15 stroke (4915) past the estimated end, not one
 * less. From closed: 45 x 819 + 804 + 23 = 37682 = 32767 + 4915; 803 instead is 4914 over. */
static void test_valve_known_end_stop_at_exactly_0_15_stroke_over(void **state)
{
    (void)state;
    for (int k = 0; k < 2; k++) {
        setup(NULL);
        to_closed_stop();
        one(-Q15_MAX);
        assert_int_equal(valve_limit(), 0);             /* the other way frees it */
        assert_int_equal(valve_position(), 819);
        for (int i = 1; i < 45; i++)
            one(-Q15_MAX);
        assert_int_equal(valve_position(), 32767);      /* 4088 over the end */
        assert_int_equal(valve_limit(), 0);
        one(k ? -D_STEP_804 : -D_STEP_803);
        assert_int_equal(valve_position(), 32767);
        assert_int_equal(valve_limit(), 0);
        one(-VALVE_MOVE_Q15);                           /* 23 */
        assert_int_equal(valve_limit(), k ? CTL_AT_OPEN : 0);
        assert_int_equal(valve_position(), 32767);
    }
}

/* The estimate step by step: 762 x 43 = 32766 opens to one short of the open end (nothing over
 * it); closing from the open end at full duty, 32767 - 819 k, the 41st period ends at 0 with
 * 812 over it, the 47th past 4915 over (812 + 6 x 819 = 5726; 5 x 819 more is 4907). Under
 * stiction nothing moves either way; at it, 23 a period. */
static void test_valve_position_estimate_by_the_step(void **state)
{
    (void)state;
    to_closed_stop();
    for (int i = 1; i <= 43; i++) {
        one(-D_STEP_762);
        assert_int_equal(valve_position(), 762 * i);
        assert_int_equal(valve_limit(), 0);
    }
    one(-D_STEP_762);
    assert_int_equal(valve_position(), 32767);
    assert_int_equal(valve_limit(), 0);
    for (int i = 1; i <= 40; i++) {
        one(Q15_MAX);
        assert_int_equal(valve_position(), 32767 - 819 * i);
    }
    for (int i = 41; i <= 46; i++) {
        one(Q15_MAX);
        assert_int_equal(valve_position(), 0);
        assert_int_equal(valve_limit(), 0);
    }
    one(Q15_MAX);
    assert_int_equal(valve_limit(), CTL_AT_CLOSED);
    /* stiction, both ways: 4914 moves nothing, 4915 moves 23 */
    one(-(VALVE_MOVE_Q15 - 1));
    assert_int_equal(valve_position(), 0);
    assert_int_equal(valve_limit(), CTL_AT_CLOSED);
    one(-VALVE_MOVE_Q15);
    assert_int_equal(valve_position(), 23);
    assert_int_equal(valve_limit(), 0);
    one(VALVE_MOVE_Q15 - 1);
    assert_int_equal(valve_position(), 23);
    one(VALVE_MOVE_Q15);
    assert_int_equal(valve_position(), 0);
    /* the open stop found, then a step closed frees it (and sets no closed stop) */
    for (int i = 0; i < 47; i++)
        one(-Q15_MAX);
    assert_int_equal(valve_limit(), CTL_AT_OPEN);
    one(Q15_MAX);
    assert_int_equal(valve_limit(), 0);
    assert_int_equal(valve_position(), 32767 - 819);
    /* the most negative drive is a full one: 819 */
    one(Q15_MIN);
    assert_int_equal(valve_position(), 32767);
}

/* A stop is believed for VALVE_RETRY_PERIODS (20) periods, the one that found it the first: a
 * demand that goes on into it is refused 19 periods after, then the bridge drives again. A
 * drive of 1 (duty 1) into a stop is refused like any other. */
static void test_valve_stop_believed_for_20_periods(void **state)
{
    (void)state;
    for (int i = 0; i < 145; i++)
        valve_set(Q15_MAX);
    assert_int_equal(valve_limit(), 0);
    valve_set(Q15_MAX);                             /* integrates the 145th: the stop */
    assert_int_equal(valve_limit(), CTL_AT_CLOSED);
    assert_int_equal(hal_host_io.valve_dir, HAL_VALVE_OFF);
    for (int n = 1; n <= 18; n++) {
        valve_set(n == 9 ? 1 : Q15_MAX);
        assert_int_equal(hal_host_io.valve_dir, HAL_VALVE_OFF);
        assert_int_equal(valve_limit(), CTL_AT_CLOSED);
    }
    valve_set(Q15_MAX);                             /* the 20th: forgotten, driven */
    assert_int_equal(valve_limit(), 0);
    assert_int_equal(hal_host_io.valve_dir, HAL_VALVE_CLOSE);
    /* 0.1 stroke (3277) of travel to try: 4 full periods (3276) then the 5th finds it again */
    for (int n = 1; n <= 4; n++) {
        valve_set(Q15_MAX);
        assert_int_equal(valve_limit(), 0);
    }
    valve_set(Q15_MAX);
    assert_int_equal(valve_limit(), CTL_AT_CLOSED);
}

/* A new Valve time applies at the next period: 8.0 s halves the rate (2^30 / 80 / 28672 = 468,
 * a full period (28671 x 468 + 2^14) >> 15 = 409). */
static void test_valve_new_valve_time_at_the_next_period(void **state)
{
    (void)state;
    to_closed_stop();
    one(-Q15_MAX);
    assert_int_equal(valve_position(), 819);
    assert_true(param_set(P_VALVE_TRAVEL, 80));
    one(-Q15_MAX);
    assert_int_equal(valve_position(), 819 + 409);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_valve_positive_drive_closes_the_bypass_with_its_duty, setup),
        cmocka_unit_test_setup(test_valve_reversal_waits_the_dead_time_with_the_bridge_off, setup),
        cmocka_unit_test_setup(test_valve_stops_driving_into_its_end_stop, setup),
        cmocka_unit_test_setup(test_valve_sub_stiction_drive_does_not_move_the_estimate, setup),
        cmocka_unit_test_setup(test_valve_stop_at_exactly_3_6_strokes_one_way, setup),
        cmocka_unit_test_setup(test_valve_known_end_stop_at_exactly_0_15_stroke_over, setup),
        cmocka_unit_test_setup(test_valve_position_estimate_by_the_step, setup),
        cmocka_unit_test_setup(test_valve_stop_believed_for_20_periods, setup),
        cmocka_unit_test_setup(test_valve_new_valve_time_at_the_next_period, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

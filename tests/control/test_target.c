/* test_target.c: eq. (1) with the paper's numbers (Table 3), the minimum-flow rule (Table 1), sections and the gain factor they give, standstill, given speed. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <stdio.h>
#include <cmocka.h>
#include "hal_host.h"
#include "params.h"
#include "target.h"

static int setup(void **state)
{
    (void)state;
    hal_host_reset();
    params_defaults();
    target_init();
    target_update(0x3F);                        /* 6 sections of 6: all 36 nozzles */
    return 0;
}

/* Table 3: given speed 6/7/8 km/h at 100/125/150 L/ha, 36 nozzles at 50 cm: 18.0 ... 36.0 L/min */
static void test_target_table3_flows_18_to_36_lpm(void **state)
{
    static const struct { uint16_t rate, kmh; int16_t lpm_x100; } t3[] = {
        {100, 6, 1800}, {100, 7, 2100}, {100, 8, 2400},
        {125, 6, 2250}, {125, 7, 2625}, {125, 8, 3000},
        {150, 6, 2700}, {150, 7, 3150}, {150, 8, 3600},
    };
    (void)state;
    assert_int_equal(target_open_nozzles(), 36);
    for (size_t i = 0; i < sizeof t3 / sizeof t3[0]; i++) {
        assert_true(param_set(P_RATE, t3[i].rate * 10));        /* 0.1 L/ha */
        assert_true(param_set(P_GIVEN_SPEED, t3[i].kmh * 10));
        target_update(0x3F);
        uint16_t v = target_speed_x100(0);      /* the wheel says standing: masked */
        assert_int_equal(v, t3[i].kmh * 100);
        assert_int_equal(target_flow_x100(v), t3[i].lpm_x100);
    }
}

/* Table 1: below 4 km/h and above 0 the line keeps the 4 km/h flow: 12 / 15 / 18 L/min */
static void test_target_table1_minimum_flow_below_4_kmh(void **state)
{
    static const struct { uint16_t rate; int16_t lpm_x100; } t1[] = {{100, 1200}, {125, 1500}, {150, 1800}};
    (void)state;
    for (size_t i = 0; i < 3; i++) {
        assert_true(param_set(P_RATE, t1[i].rate * 10));
        target_update(0x3F);
        for (uint16_t v = 1; v < 400; v += 37)
            assert_int_equal(target_flow_x100(v), t1[i].lpm_x100);
        assert_int_equal(target_flow_x100(400), t1[i].lpm_x100);
        assert_true(target_flow_x100(500) > t1[i].lpm_x100);   /* above it eq. (1) again */
        assert_int_equal(target_flow_x100(0), 0);              /* standstill: nothing */
    }
    /* the threshold is a parameter */
    assert_true(param_set(P_MINF_SPEED, 60));
    target_update(0x3F);
    assert_int_equal(target_flow_x100(300), 2700);             /* 150 L/ha at 6 km/h */
    assert_true(param_set(P_MINF_SPEED, 0));
    target_update(0x3F);
    assert_int_equal(target_flow_x100(300), 1350);             /* rule off: eq. (1) */
}

static void test_target_counts_the_nozzles_of_the_switched_on_sections(void **state)
{
    (void)state;
    target_update(0x0F);                        /* 4 of 6 sections: 24 nozzles */
    assert_int_equal(target_open_nozzles(), 24);
    assert_int_equal(target_width_cm(), 1200);
    assert_int_equal(target_flow_x100(1100), 3300);            /* 150 L/ha, 11 km/h, 24 nozzles */
    target_update(0xC0);                        /* switches beyond P_SECTIONS count nothing */
    assert_int_equal(target_open_nozzles(), 0);
    assert_int_equal(target_flow_x100(1100), 0);
    assert_true(param_set(P_SECTIONS, 5));      /* 36 over 5: 8 7 7 7 7 */
    target_update(0x01);
    assert_int_equal(target_open_nozzles(), 8);
    target_update(0x1F);
    assert_int_equal(target_open_nozzles(), 36);
    target_update(0x02);
    assert_int_equal(target_open_nozzles(), 7);
}

/* The gain factor of a loop set on the whole boom, (n / o + 1) / 2 in quarters for o of n
 * nozzles open (ffmap.c): 1 with all open, 3.5 with 6 of 36, at most 4, on every count */
static void test_target_gain_factor_for_the_nozzles_open(void **state)
{
    static const struct { uint8_t mask; uint8_t q; } t[] = {
        {0x3F, 4}, {0x1F, 4}, {0x0F, 5}, {0x07, 6}, {0x03, 8}, {0x01, 14},
    };
    (void)state;
    for (size_t i = 0; i < sizeof t / sizeof t[0]; i++) {
        target_update(t[i].mask);               /* 36, 30, 24, 18, 12, 6 nozzles */
        assert_int_equal(target_noz_q, t[i].q);
    }
    for (uint16_t n = 1; n <= 96; n++) {
        assert_true(param_set(P_NOZZLES, n));
        for (uint8_t ns = 1; ns <= 8 && ns <= n; ns++) {
            assert_true(param_set(P_SECTIONS, ns));
            for (uint16_t m = 1; m < (1u << ns); m++) {
                target_update((uint8_t)m);
                uint8_t o = target_open_nozzles();
                double f = 2.0 + 2.0 * n / o;           /* in quarters */
                assert_true(target_noz_q >= 4 && target_noz_q <= TARGET_NOZ_MAX);
                assert_int_equal(target_noz_q, f >= TARGET_NOZ_MAX ? TARGET_NOZ_MAX : (uint8_t)f);
            }
        }
    }
}

/* eq. (1) over the whole range against the double formula: within 1 LSB (0.01 L/min) */
static void test_target_eq1_matches_the_formula_over_the_range(void **state)
{
    (void)state;
    for (uint16_t rate = 10; rate <= 1000; rate += 33)
        for (uint16_t sp = 10; sp <= 200; sp += 47) {
            assert_true(param_set(P_RATE, rate * 10));
            assert_true(param_set(P_SPACING, sp));
            target_update(0x3F);
            for (uint16_t v = 400; v <= 3000; v += 123) {
                double q = rate * (v / 100.0) * sp * 36 / 60000.0 * 100.0;
                int16_t t = target_flow_x100(v);
                if (q >= 32767)
                    assert_int_equal(t, 32767);
                else
                    assert_true(t - q <= 1.0 && q - t <= 1.0);
            }
        }
}

/* A field computer's rate: within Remote win % of the preset in use and never under 10 L/ha,
 * the presets' least. Rate 1 10 L/ha, window 50 %: 5.0 .. 15.0 L/ha by the window, 10.0 .. 15.0 taken; Remote off:
 * nothing taken; every refusal counted. */
static void test_target_remote_rate_window_and_its_10_l_ha_floor(void **state)
{
    (void)state;
    assert_true(param_set(P_REMOTE, 1));
    assert_true(param_set(P_RATE, 100));
    assert_true(param_set(P_REMOTE_WIN, 50));
    uint8_t r0 = target_remote_refusals();
    assert_int_equal(target_remote_rate(99), 0);       /* 9.9 L/ha: inside the window, under the floor */
    assert_int_equal(target_remote_rate(100), 1);
    assert_int_equal(target_rate_x10(), 100);
    assert_int_equal(target_remote_rate(150), 1);      /* the window's top: 10 + 50 % */
    assert_int_equal(target_remote_rate(151), 0);
    assert_int_equal(target_rate_x10(), 150);
    assert_int_equal(target_remote_refusals(), (uint8_t)(r0 + 2));
    /* Rate 1 150, window 10 %: 135.0 .. 165.0 */
    assert_true(param_set(P_RATE, 1500));
    assert_true(param_set(P_REMOTE_WIN, 10));
    assert_int_equal(target_remote_rate(1349), 0);
    assert_int_equal(target_remote_rate(1350), 1);
    assert_int_equal(target_remote_rate(1650), 1);
    assert_int_equal(target_remote_rate(1651), 0);
    assert_true(param_set(P_REMOTE, 0));
    assert_int_equal(target_remote_rate(1500), 0);     /* Remote off */
    assert_int_equal(target_remote_refusals(), (uint8_t)(r0 + 5));
}

/* Working speed is MinQ speed and up (4.0 km/h by default), the minimum-flow rule under it. */
static void test_target_working_speed_from_minq_speed_up(void **state)
{
    (void)state;
    assert_int_equal(target_working_speed(399), 0);
    assert_int_equal(target_working_speed(400), 1);
    assert_true(param_set(P_MINF_SPEED, 55));
    assert_int_equal(target_working_speed(549), 0);
    assert_int_equal(target_working_speed(550), 1);
}

/* The flow saturates at 327.67 L/min, never wraps: one section of 6 nozzles at 50 cm and 150
 * L/ha is 0.75 L/min x100 per km/h x100 (1500 x 50 x 6 x 65536 / 600000 = 49152 in Q16), so the
 * speed's units from 436.88 km/h ask 32766, 32767, 32768 (held at 32767), ... rising by 0.75. */
static void test_target_flow_saturates_at_32767(void **state)
{
    (void)state;
    target_update(0x01);
    int16_t q0 = target_flow_x100(43680);
    assert_int_equal(q0, 32760);                /* 0.75 x 43680 */
    for (uint32_t v = 43681; v <= 44000; v++) {
        int16_t q = target_flow_x100((uint16_t)v);
        assert_true(q >= q0);                   /* (so never negative: no wrap) */
        q0 = q;
    }
    assert_int_equal(q0, 32767);
    assert_int_equal(target_flow_x100(65535), 32767);
}

/* The nudge: Rate step % of the preset a press, up to +-50 %, back with 0; the target follows
 * in the same update. 150 L/ha at 8 km/h on 36 nozzles at 50 cm: 36.00 L/min (by hand:
 * 150 x 8 x 18 / 600); +20 %: 43.20; at the +50 % bound 54.00; -50 %: 18.00. */
static void test_target_nudge_steps_the_rate_in_use_within_50_pct(void **state)
{
    (void)state;
    assert_true(param_set(P_RATE_STEP, 10));
    target_update(0x3F);
    assert_int_equal(target_flow_x100(800), 3600);
    assert_int_equal(target_nudge(1), 10);
    assert_int_equal(target_nudge(1), 20);
    assert_int_equal(target_rate_x10(), 1800);
    target_update(0x3F);
    assert_int_equal(target_flow_x100(800), 4320);
    for (int i = 0; i < 5; i++)
        target_nudge(1);
    assert_int_equal(target_nudge_pct(), 50);          /* bounded */
    target_update(0x3F);
    assert_int_equal(target_flow_x100(800), 5400);
    assert_int_equal(target_nudge(0), 0);               /* back to the preset */
    assert_int_equal(target_rate_x10(), 1500);
    for (int i = 0; i < 7; i++)
        target_nudge(-1);
    assert_int_equal(target_nudge_pct(), -50);
    target_update(0x3F);
    assert_int_equal(target_flow_x100(800), 1800);
    /* a step that does not divide 50: the last press stops at the bound */
    target_nudge(0);
    assert_true(param_set(P_RATE_STEP, 15));
    for (int i = 0; i < 4; i++)
        target_nudge(1);
    assert_int_equal(target_nudge_pct(), 50);
    assert_int_equal(target_rate_x10(), 2250);
    target_nudge(0);
}

/* Two presets: Preset picks Rate 1 or Rate 2; the nudge, an offset of the rate in use, stays
 * over a change of preset; a remote rate stands in for the preset in use, its window around
 * that preset (a change of preset that leaves it outside drops it), the nudge on top of it.
 * 8 km/h on 18 m: L/ha x 8 x 18 / 600 L/min. */
static void test_target_presets_and_the_remote_rate_in_their_place(void **state)
{
    (void)state;
    assert_true(param_set(P_RATE2, 2000));
    assert_true(param_set(P_RATE_STEP, 5));
    target_update(0x3F);
    assert_int_equal(target_rate_x10(), 1500);
    target_nudge(1);
    assert_int_equal(target_rate_x10(), 1575);
    assert_true(param_set(P_PRESET, 1));
    target_update(0x3F);
    assert_int_equal(target_nudge_pct(), 5);
    assert_int_equal(target_rate_x10(), 2100);
    assert_int_equal(target_flow_x100(800), 5040);      /* 210 x 8 x 18 / 600 */
    target_nudge(0);
    target_update(0x3F);
    assert_int_equal(target_flow_x100(800), 4800);
    /* a remote rate within 50 % of Rate 2 (100.0 .. 300.0) */
    assert_true(param_set(P_REMOTE, 1));
    assert_int_equal(target_remote_rate(2900), 1);
    assert_int_equal(target_rate_x10(), 2900);
    target_nudge(-1);
    assert_int_equal(target_rate_x10(), 2755);          /* 290.0 x 0.95 */
    assert_true(param_set(P_PRESET, 0));                /* Rate 1's window, 75.0 .. 225.0, leaves it out */
    target_update(0x3F);
    assert_int_equal(target_rate_remote(), 0);
    assert_int_equal(target_rate_x10(), 1425);          /* 150.0 x 0.95 */
    assert_int_equal(target_remote_rate(2900), 0);
    assert_int_equal(target_remote_rate(2200), 1);      /* inside it */
    assert_true(param_set(P_REMOTE, 0));
    target_nudge(0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_target_table3_flows_18_to_36_lpm, setup),
        cmocka_unit_test_setup(test_target_table1_minimum_flow_below_4_kmh, setup),
        cmocka_unit_test_setup(test_target_counts_the_nozzles_of_the_switched_on_sections, setup),
        cmocka_unit_test_setup(test_target_eq1_matches_the_formula_over_the_range, setup),
        cmocka_unit_test_setup(test_target_gain_factor_for_the_nozzles_open, setup),
        cmocka_unit_test_setup(test_target_remote_rate_window_and_its_10_l_ha_floor, setup),
        cmocka_unit_test_setup(test_target_working_speed_from_minq_speed_up, setup),
        cmocka_unit_test_setup(test_target_flow_saturates_at_32767, setup),
        cmocka_unit_test_setup(test_target_nudge_steps_the_rate_in_use_within_50_pct, setup),
        cmocka_unit_test_setup(test_target_presets_and_the_remote_rate_in_their_place, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

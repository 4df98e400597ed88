/* test_metrics.c: the metrics on hand-made traces whose answers are worked out by hand in the comments. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <math.h>
#include <cmocka.h>
#include "metrics.h"

#define N 200
#define DT 0.1
static double T[N], Y[N];
static metrics_step_t st[8];

#define assert_within(x, want, tol) do { double x_ = (x), w_ = (want), t_ = (tol); \
    if (!(fabs(x_ - w_) <= t_)) fail_msg("%s = %.6f, want %.6f +- %.6f", #x, x_, w_, t_); } while (0)

/* Target 10 -> 20 L/min at sample 50 (t = 5.0 s); flow ramps 1 L/min a sample from 10 at k = 50
 * to 20 at k = 60, then stays. By hand: from 10, to 20; 10 % (11) at k = 51, 90 % (19) at k = 59:
 * rise 0.8 s; no overshoot; the 5 % band (+-1) is entered at 19 (k = 59): settle 0.9 s;
 * the 2 % band (+-0.4) at 19.6, between k = 59 (19) and 60 (20): 59.6 -> 0.96 s; sse 0. */
static void test_metrics_pure_step(void **state)
{
    int k, n;
    (void)state;
    for (k = 0; k < N; k++) {
        T[k] = k < 50 ? 10 : 20;
        Y[k] = k < 50 ? 10 : k < 60 ? 10 + (k - 50) : 20;
    }
    n = metrics_find_steps(T, Y, N, DT, st, 8);
    assert_int_equal(n, 1);
    assert_within(st[0].t_s, 5.0, 1e-9);
    assert_within(st[0].from_lpm, 10, 1e-9);
    assert_within(st[0].to_lpm, 20, 1e-9);
    assert_within(st[0].rise_s, 0.8, 1e-6);
    assert_within(st[0].overshoot_pct, 0.0, 1e-9);
    assert_within(st[0].settle_5pct_s, 0.9, 1e-6);
    assert_within(st[0].settle_2pct_s, 0.96, 1e-6);
    assert_true(st[0].settled_5 && st[0].settled_2);
    assert_within(st[0].sse_pct, 0.0, 1e-9);
}

/* Known overshoot: 10 -> 20 at k = 50; flow jumps to 23 for k = 50..54, then 20.
 * Overshoot 3/10 = 30 %. Rise, interpolated between k = 49 (progress 0) and 50 (1.3):
 * 10 % at 49 + 0.1/1.3, 90 % at 49 + 0.9/1.3: (0.8/1.3) * 0.1 s = 0.061538 s.
 * Settle: last sample outside is k = 54 (error 3), next is 0: 5 % band (1) crossed at
 * 54 + (3 - 1)/3 = 54.6667 -> 0.46667 s after k = 50; 2 % band (0.4): 54 + 2.6/3 -> 0.48667 s. */
static void test_metrics_known_overshoot(void **state)
{
    int k;
    (void)state;
    for (k = 0; k < N; k++) {
        T[k] = k < 50 ? 10 : 20;
        Y[k] = k < 50 ? 10 : k < 55 ? 23 : 20;
    }
    assert_int_equal(metrics_find_steps(T, Y, N, DT, st, 8), 1);
    assert_within(st[0].overshoot_pct, 30.0, 1e-9);
    assert_within(st[0].rise_s, 0.061538, 1e-6);
    assert_within(st[0].settle_5pct_s, 0.46667, 1e-5);
    assert_within(st[0].settle_2pct_s, 0.48667, 1e-5);
}

/* Downward: 40 -> 20 at k = 30, flow dips to 15 at k = 30, 31, then 20: overshoot (beyond 20, in
 * the direction of the change) 5/20 = 25 %. Then 20 -> 30 at k = 120 followed exactly: 0 %.
 * Two changes; the means 12.5 %, the max 25 %. */
static void test_metrics_downward_undershoot_and_two_changes(void **state)
{
    int k, n;
    metrics_t m;
    metrics_result_t r;
    (void)state;
    metrics_init(&m, DT);
    for (k = 0; k < N; k++) {
        T[k] = k < 30 ? 40 : k < 120 ? 20 : 30;
        Y[k] = k < 30 ? 40 : k < 32 ? 15 : k < 120 ? 20 : 30;
        metrics_sample(&m, T[k], Y[k]);
    }
    n = metrics_find_steps(T, Y, N, DT, st, 8);
    assert_int_equal(n, 2);
    assert_within(st[0].t_s, 3.0, 1e-9);
    assert_within(st[0].overshoot_pct, 25.0, 1e-9);
    assert_within(st[1].t_s, 12.0, 1e-9);
    assert_within(st[1].overshoot_pct, 0.0, 1e-9);
    assert_within(st[1].settle_5pct_s, 0.0, 1e-9);
    metrics_finish(&m, &r);
    assert_int_equal(r.n_steps, 2);
    assert_within(r.overshoot_mean_pct, 12.5, 1e-9);
    assert_within(r.overshoot_max_pct, 25.0, 1e-9);
    metrics_free(&m);
}

/* A ramp of the target (speed change): 10 -> 20 over k = 50..70; times count from the moment the
 * target reaches its plateau, t = 7.0 s. A flow that follows exactly: no overshoot, settled at
 * once; its rise (11 at k = 52, 19 at k = 68) is 1.6 s. */
static void test_metrics_ramp_counts_from_the_plateau(void **state)
{
    int k;
    (void)state;
    for (k = 0; k < N; k++) {
        T[k] = k < 50 ? 10 : k < 70 ? 10 + (k - 50) * 0.5 : 20;
        Y[k] = T[k];
    }
    assert_int_equal(metrics_find_steps(T, Y, N, DT, st, 8), 1);
    assert_within(st[0].t_s, 7.0, 1e-9);
    assert_within(st[0].rise_s, 1.6, 1e-6);
    assert_within(st[0].overshoot_pct, 0.0, 1e-9);
    assert_within(st[0].settle_5pct_s, 0.0, 1e-9);
}

/* Changes of 5 % or less are not steps; 6 % is. A steady offset: flow settles at 20.5 for a
 * target of 20: sse = 0.5/20 = 2.5 %, overshoot 0.5/10 = 5 %. */
static void test_metrics_small_changes_and_steady_error(void **state)
{
    int k;
    (void)state;
    for (k = 0; k < N; k++) {
        T[k] = k < 50 ? 20 : 20.8;              /* 4 % */
        Y[k] = T[k];
    }
    assert_int_equal(metrics_find_steps(T, Y, N, DT, st, 8), 0);
    for (k = 0; k < N; k++) {
        T[k] = k < 50 ? 20 : 21.2;              /* 6 % (of 21.2: 5.7 %) */
        Y[k] = T[k];
    }
    assert_int_equal(metrics_find_steps(T, Y, N, DT, st, 8), 1);
    for (k = 0; k < N; k++) {
        T[k] = k < 50 ? 10 : 20;
        Y[k] = k < 50 ? 10 : 20.5;
    }
    assert_int_equal(metrics_find_steps(T, Y, N, DT, st, 8), 1);
    assert_within(st[0].sse_pct, 2.5, 1e-9);
    assert_within(st[0].overshoot_pct, 5.0, 1e-9);
}

/* A target that never stays within 1 % for 2 s has no plateau and no steps. */
static void test_metrics_no_plateau_no_steps(void **state)
{
    int k;
    (void)state;
    for (k = 0; k < N; k++) {
        T[k] = 20 + 5 * sin(k * 0.3);
        Y[k] = T[k];
    }
    assert_int_equal(metrics_find_steps(T, Y, N, DT, st, 8), 0);
}

/*
 * Zones. 18 m boom (36 x 50 cm), 150 L/ha: a 5 m zone expects 150 * 18 * 5 / 10000 = 1.35 L.
 * At 2 m/s (7.2 km/h) a zone takes 2.5 s; 1.35 L in 2.5 s is 32.4 L/min. Ten zones alternately at
 * 32.4 * 1.1 and 32.4 * 0.9 L/min: volumes 1.485 and 1.215 L, errors +10 % and -10 %; the ratios
 * 1.1/0.9 have mean 1 and sample sd 0.1 * sqrt(10/9) = 0.105409: CV 10.5409 %. Then 4 zones at
 * 1 m/s (3.6 km/h, 5 s a zone) at 1.25 x 16.2 L/min (1.6875 L, +25 %): left out of cv_pct but in
 * cv_all_pct. All 14 ratios (5 x 1.1, 5 x 0.9, 4 x 1.25): sum 15.0, sum of squares
 * 5*1.21 + 5*0.81 + 4*1.5625 = 16.35; mean 15/14 = 1.0714286; var (16.35 - 225/14)/13 = 0.0214286;
 * sd 0.146385; CV 0.146385/1.0714286 = 13.6626 %. Dose over v >= 4 km/h: exactly as set, 0 %.
 */
static void test_metrics_zone_volumes_and_cv(void **state)
{
    metrics_t m;
    metrics_result_t r;
    int z, i;
    (void)state;
    metrics_init(&m, DT);
    for (z = 0; z < 10; z++)
        for (i = 0; i < 25; i++)
            metrics_add(&m, 0.1, 2.0, 32.4 * (z % 2 ? 0.9 : 1.1), 18.0, 150, 2.0, 1);
    for (z = 0; z < 4; z++)
        for (i = 0; i < 50; i++)
            metrics_add(&m, 0.1, 1.0, 16.2 * 1.25, 18.0, 150, 0.5, 1);
    metrics_finish(&m, &r);
    assert_int_equal(r.zones_all, 14);
    assert_int_equal(r.zones_used, 10);
    assert_within(m.zones[0].vol_l, 1.485, 1e-6);
    assert_within(m.zones[1].vol_l, 1.215, 1e-6);
    assert_within(m.zones[0].expect_l, 1.35, 1e-6);
    assert_within(m.zones[12].vol_l, 1.6875, 1e-6);
    assert_within(r.zone_error_max_pct, 10.0, 1e-4);
    assert_within(r.zone_error_min_pct, -10.0, 1e-4);
    assert_within(r.zone_error_all_max_pct, 25.0, 1e-4);
    assert_within(r.cv_pct, 10.5409, 1e-3);
    assert_within(r.cv_all_pct, 13.6626, 1e-3);
    assert_within(r.dose_error_pct, 0.0, 1e-6);
    /* area 18 m x (50 + 20) m = 1260 m2 = 0.126 ha; volume 13.5 + 4 x 1.6875 = 20.25 L -> 160.71 L/ha */
    assert_within(r.area_ha, 0.126, 1e-9);
    assert_within(r.volume_l, 20.25, 1e-6);
    assert_within(r.applied_l_ha, 160.714, 1e-3);
    /* pressure over the part at v >= 4 km/h only (the slow zones ran at 0.5 bar) */
    assert_within(r.pressure_min_bar, 2.0, 0);
    metrics_free(&m);
    /* a run that never reaches 4 km/h (a bench test) gives the range while spraying */
    metrics_init(&m, DT);
    metrics_add(&m, 1.0, 0.0, 18.0, 18.0, 150, 0.9, 1);
    metrics_add(&m, 1.0, 0.0, 18.0, 18.0, 150, 7.0, 0);
    metrics_add(&m, 1.0, 0.0, 30.0, 18.0, 150, 2.4, 1);
    metrics_finish(&m, &r);
    assert_within(r.pressure_min_bar, 0.9, 0);
    assert_within(r.pressure_max_bar, 2.4, 0);
    assert_true(isnan(r.applied_l_ha));         /* no ground covered: no dose */
    metrics_free(&m);
}

/* A slice that crosses a zone end is split there: 7.5 m in one 2.5 s slice at 60 L/min (2.5 L):
 * the first zone gets 5/7.5 of it (1.6667 L); a second 2.5 m slice of 2.5 L completes zone 2 with
 * 0.8333 + 2.5 = 3.3333 L. Dose: 5 L over 18 x 10 m = 0.018 ha expecting 2.7 L: +85.185 %. */
static void test_metrics_zone_split_inside_a_slice(void **state)
{
    metrics_t m;
    metrics_result_t r;
    (void)state;
    metrics_init(&m, DT);
    metrics_add(&m, 2.5, 3.0, 60.0, 18.0, 150, 2.0, 1);
    assert_int_equal(m.n_zones, 1);
    assert_within(m.zones[0].vol_l, 5.0 / 3.0, 1e-9);
    metrics_add(&m, 2.5, 1.0, 60.0, 18.0, 150, 2.0, 1);
    assert_int_equal(m.n_zones, 2);
    assert_within(m.zones[1].vol_l, 2.5 / 3.0 + 2.5, 1e-9);
    metrics_finish(&m, &r);
    assert_within(r.dose_error_all_pct, (5.0 / 2.7 - 1) * 100, 1e-6);
    metrics_free(&m);
}

/* The dose error's split: two 10 s slices at 2 m/s over 18 m (5.4 L expected each), the target
 * 33 L/min (5.5 L), the nozzles 36 then 40 L/min (6 then 6.667 L), the second with the valve at
 * an end stop; a slice under 4 km/h counts in neither. The shares add up to the dose error. */
static void test_metrics_dose_split(void **state)
{
    metrics_t m;
    metrics_result_t r;
    (void)state;
    metrics_init(&m, DT);
    metrics_add(&m, 10.0, 2.0, 36.0, 18.0, 150, 2.0, 1);
    metrics_target(&m, 10.0, 2.0, 36.0, 33.0, 0);
    metrics_add(&m, 10.0, 2.0, 40.0, 18.0, 150, 2.0, 1);
    metrics_target(&m, 10.0, 2.0, 40.0, 33.0, 1);
    metrics_add(&m, 10.0, 0.5, 40.0, 18.0, 150, 2.0, 1);
    metrics_target(&m, 10.0, 0.5, 40.0, 10.0, 1);
    metrics_finish(&m, &r);
    assert_within(r.dose_error_pct, (12.6667 / 10.8 - 1) * 100, 1e-3);
    assert_within(r.dose_target_pct, (11.0 / 10.8 - 1) * 100, 1e-6);
    assert_within(r.dose_ctl_pct, 1.6667 / 10.8 * 100, 1e-3);
    assert_within(r.dose_ctl_stop_pct, 1.16667 / 10.8 * 100, 1e-3);
    assert_within(r.dose_target_pct + r.dose_ctl_pct, r.dose_error_pct, 1e-9);
    metrics_free(&m);
}

/* The valve's wear: a reversal is a drive of the other sign than the last nonzero one (pauses
 * do not count), the travel is the sum of the position's moves either way. */
static void test_metrics_valve_wear(void **state)
{
    metrics_t m;
    metrics_result_t r;
    static const double drive[] = {0, 0.5, 0.5, 0, -0.2, 0, 0, -1.0, 0.3, 0.3, 0, 0.3};
    static const double theta[] = {0.5, 0.6, 0.7, 0.7, 0.65, 0.65, 0.65, 0.45, 0.5, 0.55, 0.55, 0.6};
    (void)state;
    metrics_init(&m, DT);
    for (unsigned i = 0; i < sizeof drive / sizeof drive[0]; i++)
        metrics_valve(&m, drive[i], theta[i]);
    metrics_finish(&m, &r);
    assert_within(r.valve_reversals, 2, 1e-12);            /* + to - (over a pause), - to + */
    assert_within(r.valve_travel_strokes, 0.2 + 0.05 + 0.2 + 0.15, 1e-9);
    metrics_free(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_metrics_pure_step),
        cmocka_unit_test(test_metrics_known_overshoot),
        cmocka_unit_test(test_metrics_downward_undershoot_and_two_changes),
        cmocka_unit_test(test_metrics_ramp_counts_from_the_plateau),
        cmocka_unit_test(test_metrics_small_changes_and_steady_error),
        cmocka_unit_test(test_metrics_no_plateau_no_steps),
        cmocka_unit_test(test_metrics_zone_volumes_and_cv),
        cmocka_unit_test(test_metrics_zone_split_inside_a_slice),
        cmocka_unit_test(test_metrics_dose_split),
        cmocka_unit_test(test_metrics_valve_wear),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

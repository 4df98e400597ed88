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
static double T[N], Y[N], R[N];
static unsigned char WORK[N], SPRAY[N];
static metrics_step_t st[8];

#define assert_within(x, want, tol) do { double x_ = (x), w_ = (want), t_ = (tol); \
    if (!(fabs(x_ - w_) <= t_)) fail_msg("%s = %.6f, want %.6f +- %.6f", #x, x_, w_, t_); } while (0)

/* The series of T (target and reference alike, unless ref is given) and Y, working speed and
 * boom on throughout. */
static metrics_series_t series(const double *ref)
{
    metrics_series_t s;
    int k;
    for (k = 0; k < N; k++) {
        WORK[k] = 1;
        SPRAY[k] = 1;
    }
    s.ref = ref ? ref : T;
    s.target = T;
    s.flow = Y;
    s.work = WORK;
    s.spray = SPRAY;
    s.n = N;
    s.dt_s = DT;
    return s;
}

static int find(void)
{
    metrics_series_t s = series(NULL);
    return metrics_find_steps(&s, st, 8);
}

/* Target 10 -> 20 L/min at sample 50 (t = 5.0 s); flow ramps 1 L/min a sample from 10 at k = 50
 * to 20 at k = 60, then stays. The old hold ends at k = 49, so t_c = t_a = 50. By hand: 10 % (11)
 * at k = 51, 90 % (19) at k = 59: rise 0.8 s; no overshoot; the 5 % band (+-1) is entered at 19
 * (error 2 at k = 58, 1 at 59: 58 + 1 = 59): settle 0.9 s; the 2 % band (+-0.4) between
 * k = 59 (error 1) and 60 (0): 59.6 -> 0.96 s; sse 0. */
static void test_metrics_pure_step(void **state)
{
    int k, n;
    (void)state;
    for (k = 0; k < N; k++) {
        T[k] = k < 50 ? 10 : 20;
        Y[k] = k < 50 ? 10 : k < 60 ? 10 + (k - 50) : 20;
    }
    n = find();
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
 * Overshoot 3/10 = 30 %. Rise, interpolated between k = 49 (10) and 50 (23):
 * 10 % at 49 + 1/13, 90 % at 49 + 9/13: (8/13) * 0.1 s = 0.061538 s.
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
    assert_int_equal(find(), 1);
    assert_within(st[0].overshoot_pct, 30.0, 1e-9);
    assert_within(st[0].rise_s, 0.061538, 1e-6);
    assert_within(st[0].settle_5pct_s, 0.46667, 1e-5);
    assert_within(st[0].settle_2pct_s, 0.48667, 1e-5);
}

/* A second-order response to a true step, zeta 0.3, peak at 1.0 s (omega_n = pi / sqrt(1 -
 * zeta^2)): the textbook overshoot exp(-pi zeta / sqrt(1 - zeta^2)) = 37.23 % at sample 60. */
static void test_metrics_second_order_textbook_overshoot(void **state)
{
    const double z = 0.3, wd = M_PI, wn = wd / sqrt(1 - z * z);
    int k;
    (void)state;
    for (k = 0; k < N; k++) {
        double t = (k - 50) * DT;
        T[k] = k < 50 ? 10 : 20;
        Y[k] = k < 50 ? 10 : 10 + 10 * (1 - exp(-z * wn * t) * (cos(wd * t) + z / sqrt(1 - z * z) * sin(wd * t)));
    }
    assert_int_equal(find(), 1);
    assert_within(st[0].overshoot_pct, 100 * exp(-M_PI * z / sqrt(1 - z * z)), 0.1);
    assert_true(st[0].settled_5 && st[0].settled_2);
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
        metrics_sample(&m, T[k], T[k], Y[k], 8.0, 1);
    }
    n = find();
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

/* A ramp of the target (a speed change): 10 -> 20 over k = 50..70. The old hold ends at k = 50
 * (t_c = 51), the target is within 1 % of 20 from k = 70 (t_a). A flow that follows exactly
 * scores 0 % and 0 s; its rise (11 at k = 52, 19 at k = 68) is 1.6 s. */
static void test_metrics_ramp_flow_equal_to_target_scores_zero(void **state)
{
    int k;
    (void)state;
    for (k = 0; k < N; k++) {
        T[k] = k < 50 ? 10 : k < 70 ? 10 + (k - 50) * 0.5 : 20;
        Y[k] = T[k];
    }
    assert_int_equal(find(), 1);
    assert_within(st[0].t_s, 5.1, 1e-9);
    assert_within(st[0].rise_s, 1.6, 1e-6);
    assert_within(st[0].overshoot_pct, 0.0, 1e-9);
    assert_within(st[0].settle_5pct_s, 0.0, 1e-9);
    assert_within(st[0].sse_pct, 0.0, 1e-9);
}

/* The same ramp followed by a flow that is the target d samples late: no overshoot, and the
 * settling grows with the delay. By hand for d = 10 (1 s): the error is -5 on the ramp, then
 * falls 0.5 a sample from k = 70; the last sample outside the 5 % band (1) is k = 77 (1.5),
 * k = 78 is at 1.0: 77 + 0.5/0.5 = 78, 27 samples after t_c = 51: 2.7 s. */
static void test_metrics_pure_delay_no_overshoot_settling_grows(void **state)
{
    static const int delays[] = {0, 5, 10, 20};
    double last = -1;
    unsigned i;
    int k;
    (void)state;
    for (i = 0; i < sizeof delays / sizeof delays[0]; i++) {
        int d = delays[i];
        for (k = 0; k < N; k++)
            T[k] = k < 50 ? 10 : k < 70 ? 10 + (k - 50) * 0.5 : 20;
        for (k = 0; k < N; k++)
            Y[k] = T[k - d < 0 ? 0 : k - d];
        assert_int_equal(find(), 1);
        assert_within(st[0].overshoot_pct, 0.0, 1e-9);
        assert_true(st[0].settle_5pct_s > last);
        if (d == 10)
            assert_within(st[0].settle_5pct_s, 2.7, 1e-6);
        last = st[0].settle_5pct_s;
    }
}

/* Holds merge within 5 % (20 -> 20.8: one hold), a change under 10 % is not scored (20 -> 21.2),
 * 10 % is (20 -> 22.5: 2.5 of 22.5 is 11 %). A steady offset: flow settles at 20.5 for a target
 * of 20: sse = 0.5/20 = 2.5 %, overshoot 0.5/10 = 5 %. */
static void test_metrics_small_changes_and_steady_error(void **state)
{
    static const double to[] = {20.8, 21.2, 22.5};
    static const int want[] = {0, 0, 1};
    int k;
    unsigned i;
    (void)state;
    for (i = 0; i < 3; i++) {
        for (k = 0; k < N; k++) {
            T[k] = k < 50 ? 20 : to[i];
            Y[k] = T[k];
        }
        assert_int_equal(find(), want[i]);
    }
    for (k = 0; k < N; k++) {
        T[k] = k < 50 ? 10 : 20;
        Y[k] = k < 50 ? 10 : 20.5;
    }
    assert_int_equal(find(), 1);
    assert_within(st[0].sse_pct, 2.5, 1e-9);
    assert_within(st[0].overshoot_pct, 5.0, 1e-9);
}

/* A target that never stays within 1 % for 2 s has no hold and no steps. */
static void test_metrics_no_hold_no_steps(void **state)
{
    int k;
    (void)state;
    for (k = 0; k < N; k++) {
        T[k] = 20 + 5 * sin(k * 0.3);
        Y[k] = T[k];
    }
    assert_int_equal(find(), 0);
}

/* The start from standstill is not a step: 0 -> 18 at k = 30 (boom opens there), the flow ramps
 * 1.8 a sample and is within 5 % (17.1) from k = 40 on: start_s 1.0 s. A later 18 -> 27 is. */
static void test_metrics_start_is_not_a_step(void **state)
{
    metrics_series_t s;
    double first, longest;
    int k;
    (void)state;
    s = series(NULL);
    for (k = 0; k < N; k++) {
        T[k] = k < 30 ? 0 : k < 120 ? 18 : 27;
        Y[k] = k < 30 ? 0 : k < 40 ? 1.8 * (k - 30) : T[k];
        SPRAY[k] = k >= 30;
    }
    assert_int_equal(metrics_find_steps(&s, st, 8), 1);
    assert_within(st[0].from_lpm, 18, 1e-9);
    metrics_start(&s, &first, &longest);
    assert_within(first, 1.0, 1e-9);
    assert_within(longest, 1.0, 1e-9);
}

/* Holds come from the reference, errors from the firmware's target: a clean reference step with
 * a target that wobbles +-3 % still gives one change, and a flow equal to the wobbling target
 * scores 0; a hold below the working speed is not scored. */
static void test_metrics_holds_on_reference_errors_on_target(void **state)
{
    metrics_series_t s;
    int k;
    (void)state;
    for (k = 0; k < N; k++) {
        R[k] = k < 50 ? 10 : 20;
        T[k] = R[k] * (1 + 0.03 * ((k % 3) - 1));
        Y[k] = T[k];
    }
    s = series(R);
    assert_int_equal(metrics_find_steps(&s, st, 8), 1);
    assert_within(st[0].overshoot_pct, 0.0, 1e-9);
    assert_within(st[0].settle_5pct_s, 0.0, 1e-9);
    s.ref = T;
    assert_int_equal(metrics_find_steps(&s, st, 8), 0);  /* the wobble hides every hold */
    s.ref = R;
    WORK[10] = 0;
    assert_int_equal(metrics_find_steps(&s, st, 8), 0);
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
 * 33 L/min (5.5 L), the nozzles 36 then 40 L/min (6 then 6.667 L) which a meter true to its
 * calibration reads as 35 and 39 (5.833 and 6.5 L: the meter's share is 1/6 + 1/6 L), the
 * first slice in the start, the second with the valve at an end stop; a slice under 4 km/h
 * counts in none. The three shares add up to the dose error. */
static void test_metrics_dose_split(void **state)
{
    metrics_t m;
    metrics_result_t r;
    (void)state;
    metrics_init(&m, DT);
    metrics_add(&m, 10.0, 2.0, 36.0, 18.0, 150, 2.0, 1);
    metrics_target(&m, 10.0, 2.0, 35.0, 33.0, METRICS_AT_START);
    metrics_add(&m, 10.0, 2.0, 40.0, 18.0, 150, 2.0, 1);
    metrics_target(&m, 10.0, 2.0, 39.0, 33.0, METRICS_AT_STOP);
    metrics_add(&m, 10.0, 0.5, 40.0, 18.0, 150, 2.0, 1);
    metrics_target(&m, 10.0, 0.5, 40.0, 10.0, METRICS_AT_STOP | METRICS_AT_START);
    metrics_finish(&m, &r);
    assert_within(r.dose_error_pct, (12.6667 / 10.8 - 1) * 100, 1e-3);
    assert_within(r.dose_target_pct, (11.0 / 10.8 - 1) * 100, 1e-6);
    assert_within(r.dose_meter_pct, 0.33333 / 10.8 * 100, 1e-3);
    assert_within(r.dose_ctl_pct, 1.33333 / 10.8 * 100, 1e-3);
    assert_within(r.dose_ctl_stop_pct, 1.0 / 10.8 * 100, 1e-3);
    assert_within(r.dose_ctl_start_pct, 0.33333 / 10.8 * 100, 1e-3);
    assert_within(r.dose_target_pct + r.dose_meter_pct + r.dose_ctl_pct, r.dose_error_pct, 1e-9);
    metrics_free(&m);
}

/* The valve's wear from the plant's running totals: 2 reversals over the run, 1 of them while
 * spraying for 30 s: 2 a minute of spraying; the travel is the plant's. */
static void test_metrics_valve_wear(void **state)
{
    metrics_t m;
    metrics_result_t r;
    (void)state;
    metrics_init(&m, DT);
    metrics_valve(&m, 10.0, 0, 0.1, 0);
    metrics_valve(&m, 10.0, 1, 0.2, 0);        /* a reversal with the boom shut */
    metrics_valve(&m, 30.0, 2, 0.6, 1);        /* one while spraying */
    metrics_finish(&m, &r);
    assert_within(r.valve_reversals, 2, 1e-12);
    assert_within(r.valve_reversals_per_min, 2.0, 1e-12);
    assert_within(r.valve_travel_strokes, 0.6, 1e-12);
    metrics_free(&m);
}

/* What counts as a wrong dose, by hand at 150 L/ha over 18 m (36 nozzles at 50 cm):
 * L/ha = L/min x 600 / (km/h x m): 36 L/min at 8 km/h is 150 (right); 28.5 is 118.75 (-20.8 %),
 * 33 is 137.5 (-8.3 %), 39.7 is 165.42 (+10.3 %), 39.5 is 164.58 (+9.7 %). */
static void test_metrics_what_is_a_wrong_dose(void **state)
{
    metrics_watch_t w = {36.0, 8.0, 18.0, 150.0, 1, 1, 0};
    (void)state;
    assert_int_equal(metrics_dose_wrong(&w), 0);
    w.boom_lpm = 28.5;
    assert_int_equal(metrics_dose_wrong(&w), 1);
    w.boom_lpm = 33.0;
    assert_int_equal(metrics_dose_wrong(&w), 0);
    w.boom_lpm = 39.7;
    assert_int_equal(metrics_dose_wrong(&w), 1);
    w.boom_lpm = 39.5;
    assert_int_equal(metrics_dose_wrong(&w), 0);
    w.width_m = 13.0;                           /* 10 of 36 clogged: 39.5 over 13 m is +37.9 % */
    assert_int_equal(metrics_dose_wrong(&w), 1);
    w.width_m = 0.0;                            /* every open nozzle clogged */
    assert_int_equal(metrics_dose_wrong(&w), 1);
    w.width_m = 18.0;
    w.v_kmh = 0.3;                              /* standing: any liquid out is wrong */
    w.boom_lpm = 0.5;
    assert_int_equal(metrics_dose_wrong(&w), 1);
    w.boom_lpm = 0.0;
    assert_int_equal(metrics_dose_wrong(&w), 0);
    w.spraying = 0;                             /* boom shut, sections on: wrong from 2 km/h */
    w.v_kmh = 2.5;
    assert_int_equal(metrics_dose_wrong(&w), 1);
    w.v_kmh = 1.5;
    assert_int_equal(metrics_dose_wrong(&w), 0);
    w.v_kmh = 8.0;
    w.sections_on = 0;                          /* the operator switched them off */
    assert_int_equal(metrics_dose_wrong(&w), 0);
}

/* A trace of 0.1 s slices: 3 s right, 7 s wrong untold, 1 s wrong but told (the 7 s end),
 * 4 s wrong untold (under 5 s: not counted), 0.5 s right, 6 s wrong untold to the end (closed
 * by metrics_finish). silent_wrong_s = 7, silent_wrong_total_s = 7 + 6 = 13. */
static void test_metrics_silent_wrong_stretches(void **state)
{
    static const struct { int n; double boom; int told; } parts[] = {
        {30, 36.0, 0}, {70, 28.5, 0}, {10, 28.5, 1}, {40, 28.5, 0}, {5, 36.0, 0}, {60, 0.0, 0},
    };
    metrics_t m;
    metrics_result_t r;
    size_t p;
    int i;
    (void)state;
    metrics_init(&m, DT);
    for (p = 0; p < sizeof parts / sizeof parts[0]; p++)
        for (i = 0; i < parts[p].n; i++) {
            metrics_watch_t w = {parts[p].boom, 8.0, 18.0, 150.0, 1, 1, parts[p].told};
            metrics_watch(&m, DT, &w);
        }
    metrics_finish(&m, &r);
    assert_within(r.silent_wrong_s, 7.0, 1e-9);
    assert_within(r.silent_wrong_total_s, 13.0, 1e-9);
    assert_true(isnan(r.ripple_p95_pct));       /* no samples: no holds */
    metrics_free(&m);
}

#define RN 300
static double RR[RN], RT[RN], RY[RN];
static unsigned char RW[RN], RS[RN];

/* A series of RN samples, reference = target = 10, flow 10 (1 + (k mod 20) / 1000). */
static metrics_series_t ripple_series(void)
{
    metrics_series_t s;
    int k;
    for (k = 0; k < RN; k++) {
        RR[k] = RT[k] = 10.0;
        RY[k] = 10.0 * (1.0 + (k % 20) * 0.001);
        RW[k] = RS[k] = 1;
    }
    s.ref = RR;
    s.target = RT;
    s.flow = RY;
    s.work = RW;
    s.spray = RS;
    s.n = RN;
    s.dt_s = DT;
    return s;
}

/* ripple_p95 by hand. Samples 80..299 are 8 s into the hold: 220 of them, errors 0..19 per mille
 * 11 times each; the nearest rank ceil(0.95 x 220) = 209 is the 209th smallest: 11 x 19 = 209
 * reach 18 per mille: 1.8 %. Samples 80..90 at 30 % (11, 5 % of 220): they take the top 11
 * ranks, the 209th is then 19 per mille (11 of them left): 1.9 %; with 80..91 (12) it is 30 %.
 * A step of the reference at sample 150 (10 -> 12, the target and flow with it, the flow 50 %
 * off for 150..229): 150..229 are within 8 s of it and not counted: 80..149 and 230..299, 140
 * samples, 7 of each error, rank 133: 7 x 19 = 133 reach 18 per mille: 1.8 % again. No spraying:
 * none. */
static void test_metrics_ripple_p95(void **state)
{
    metrics_series_t s = ripple_series();
    int k;
    (void)state;
    assert_within(metrics_ripple_p95(&s), 1.8, 1e-9);
    for (k = 80; k <= 90; k++)
        RY[k] = 13.0;
    assert_within(metrics_ripple_p95(&s), 1.9, 1e-9);
    RY[91] = 13.0;
    assert_within(metrics_ripple_p95(&s), 30.0, 1e-9);
    s = ripple_series();
    for (k = 150; k < RN; k++) {
        RR[k] = RT[k] = 12.0;
        RY[k] = 12.0 * (1.0 + (k % 20) * 0.001);
    }
    for (k = 150; k < 230; k++)
        RY[k] = 18.0;
    assert_within(metrics_ripple_p95(&s), 1.8, 1e-9);
    for (k = 0; k < RN; k++)
        RS[k] = 0;
    assert_true(isnan(metrics_ripple_p95(&s)));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_metrics_pure_step),
        cmocka_unit_test(test_metrics_known_overshoot),
        cmocka_unit_test(test_metrics_downward_undershoot_and_two_changes),
        cmocka_unit_test(test_metrics_second_order_textbook_overshoot),
        cmocka_unit_test(test_metrics_ramp_flow_equal_to_target_scores_zero),
        cmocka_unit_test(test_metrics_pure_delay_no_overshoot_settling_grows),
        cmocka_unit_test(test_metrics_small_changes_and_steady_error),
        cmocka_unit_test(test_metrics_no_hold_no_steps),
        cmocka_unit_test(test_metrics_start_is_not_a_step),
        cmocka_unit_test(test_metrics_holds_on_reference_errors_on_target),
        cmocka_unit_test(test_metrics_zone_volumes_and_cv),
        cmocka_unit_test(test_metrics_zone_split_inside_a_slice),
        cmocka_unit_test(test_metrics_dose_split),
        cmocka_unit_test(test_metrics_valve_wear),
        cmocka_unit_test(test_metrics_what_is_a_wrong_dose),
        cmocka_unit_test(test_metrics_silent_wrong_stretches),
        cmocka_unit_test(test_metrics_ripple_p95),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* test_plant.c: the plant model against numbers worked out by hand from docs/SCENARIOS.md's formulas and defaults. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <math.h>
#include <cmocka.h>
#include "plant.h"

#define TICK 1000000u                           /* 1 ms */

static plant_t pl;

/* A plant with docs/SCENARIOS.md's defaults, pulsation and sensor noise off unless a test wants them. */
static void setup(double theta0, int coupled, double pto_rpm)
{
    plant_params_t p;
    plant_params_default(&p);
    p.pump_pulsation_pct = 0;
    p.pressure_noise_lsb = 0;
    p.level_noise_lsb = 0;
    p.valve_start_pos = theta0;
    p.pto_coupled = coupled;
    p.pto_rpm = pto_rpm;
    plant_init(&pl, &p, 1);
}

static void run(double seconds, double drive, int spray)
{
    plant_in_t in = {drive, spray};
    long n = lround(seconds * 1000.0), i;
    for (i = 0; i < n; i++)
        plant_step(&pl, &in, TICK);
}

#define assert_within(x, want, tol) do { double x_ = (x), w_ = (want), t_ = (tol); \
    if (!(fabs(x_ - w_) <= t_)) fail_msg("%s = %.6f, want %.6f +- %.6f", #x, x_, w_, t_); } while (0)

/*
 * Sanity point 11 km/h (docs/SCENARIOS.md), fixed 540 rpm PTO, by hand:
 *   boom 150 L/ha * 11 km/h * 50 cm * 36 / 60000 = 49.5 L/min, 1.375 L/min a nozzle;
 *   K_n = 1.18/sqrt(3) = 0.68127; nozzle pressure = (1.375/0.68127)^2 + 0.3 = 4.0736 + 0.3 = 4.3736;
 *   line loss 0.025 bar at 50 L/min -> 0.025*(49.5/50)^2 = 0.0245: boom P = 4.398 bar ("about 4.4").
 *   pump 120 * (1 - 0.01*4.398) = 114.72 L/min; bypass takes 114.72 - 49.5 = 65.22 L/min
 *   -> Cv = 65.22/sqrt(4.398) = 31.10; equal % (R 30) shifted: (30^(th-1) - 1/30)/(1 - 1/30) = 31.10/120
 *   -> 30^(th-1) = 0.2592*0.96667 + 0.03333 = 0.28388 -> th = 1 + ln(0.28388)/ln(30) = 0.62978.
 * Held at that position the line must settle at 4.40 bar and 49.5 L/min (within 2 %).
 */
static void test_plant_sanity_11kmh_pressure_and_flow(void **state)
{
    (void)state;
    setup(0.62978, 0, 540);
    run(3.0, 0, 1);
    assert_within(pl.p_bar, 4.398, 0.02 * 4.398);
    assert_within(pl.q_boom, 49.5, 0.02 * 49.5);
    assert_within(pl.q_boom / 36, 1.375, 0.02 * 1.375);
}

/*
 * Sanity point 4 km/h, PTO coupled: boom 18 L/min, 0.5 L/min a nozzle;
 *   nozzle P = (0.5/0.68127)^2 + 0.3 = 0.5386 + 0.3 = 0.8386, + line loss 0.025*(18/50)^2 = 0.0032
 *   -> 0.8419 bar ("about 0.84"). PTO 540*4/11 = 196.36 rpm: pump 120*196.36/540 = 43.636 L/min,
 *   slip (1 - 0.008419) -> 43.269; bypass 25.269 L/min at sqrt(0.8419) = 0.91755 -> Cv 27.540
 *   -> 30^(th-1) = 0.22950*0.96667 + 0.03333 = 0.25518 -> th = 1 + ln(0.25518)/3.40120 = 0.59838.
 */
static void test_plant_sanity_4kmh_coupled(void **state)
{
    (void)state;
    setup(0.59838, 1, 540);
    pl.v_cmd_kmh = 4.0;
    pl.v_mps = 4.0 / 3.6;
    run(3.0, 0, 1);
    assert_within(pl.pto_now_rpm, 196.36, 0.01);
    assert_within(pl.p_bar, 0.8419, 0.02 * 0.8419);
    assert_within(pl.q_boom, 18.0, 0.02 * 18.0);
}

/*
 * With a fixed PTO the valve must travel about a third of its stroke between 11 and 4 km/h:
 * at 4 km/h, 540 rpm: pump 120*(1 - 0.008419) = 118.99; bypass 100.99 L/min at 0.91755
 * -> Cv 110.06 -> 30^(th-1) = 0.91719*0.96667 + 0.03333 = 0.91995 -> th = 0.97547
 * (0.3457 of the stroke above the 11 km/h position 0.62978: 1.38 s at full drive).
 * With the PTO coupled, 0.59838 against 0.62978: 0.031 of the stroke ("barely moves").
 */
static void test_plant_fixed_pto_4kmh_needs_a_third_of_the_stroke(void **state)
{
    (void)state;
    setup(0.97547, 0, 540);
    run(3.0, 0, 1);
    assert_within(pl.q_boom, 18.0, 0.02 * 18.0);
    assert_within(pl.p_bar, 0.8419, 0.02 * 0.8419);
}

/* PTO coupling: n = 540 * v_wheel / 11 (the wheel's speed, slip included); at 5.5 km/h 270 rpm,
 * pump at 0 bar 120*270/540 = 60 L/min, at 2 bar 60*(1 - 0.02) = 58.8; with 10 % slip the wheel
 * turns 6.05 km/h: 297 rpm. Uncoupled: 540 rpm whatever the speed: 120 L/min. */
static void test_plant_pto_coupling_scales_the_pump(void **state)
{
    (void)state;
    setup(1.0, 1, 540);
    pl.v_cmd_kmh = 5.5;
    pl.v_mps = 5.5 / 3.6;
    run(0.01, 0, 1);
    assert_within(pl.pto_now_rpm, 270.0, 1e-9);
    assert_within(plant_pump_flow(&pl, 0.0), 60.0, 1e-9);
    assert_within(plant_pump_flow(&pl, 2.0), 58.8, 1e-9);
    pl.p.wheel_slip_pct = 10;
    run(0.01, 0, 1);
    assert_within(pl.pto_now_rpm, 297.0, 1e-9);
    setup(1.0, 0, 540);
    pl.v_cmd_kmh = 5.5;
    pl.v_mps = 5.5 / 3.6;
    run(0.01, 0, 1);
    assert_within(plant_pump_flow(&pl, 0.0), 120.0, 1e-9);
}

/* A throttle step 4 -> 11 km/h with the PTO coupled: the pump follows the true wheel speed through
 * the tractor's lag, so pump speed / 540 and wheel speed / 11 stay within 1 % of each other at
 * every tick, while the driver's command runs well ahead of both (over 50 % at first). */
static void test_plant_coupled_pto_follows_the_true_speed(void **state)
{
    plant_in_t in = {0, 1};
    double lead = 0;
    int i;
    (void)state;
    setup(0.6, 1, 540);
    pl.v_mps = 4 / 3.6;
    pl.v_cmd_kmh = 11;
    for (i = 0; i < 20000; i++) {
        double wheel;
        plant_step(&pl, &in, TICK);
        wheel = plant_speed_kmh(&pl) / 11.0;
        assert_within(pl.pto_now_rpm / 540.0, wheel, 0.01 * wheel);
        lead = fmax(lead, pl.v_cmd_kmh / plant_speed_kmh(&pl) - 1);
    }
    assert_true(lead > 0.5);
}

/* Pulsation: 3 diaphragms at 540 rpm give 3*540/60 = 27 Hz, +-4 %: in 1 s the pump flow (slip
 * taken out) crosses its mean upwards 27 times (+-1 for the phase) and spans 120*0.96..120*1.04. */
static void test_plant_pump_pulsation_27hz_4pct(void **state)
{
    double lo = 1e9, hi = 0, prev = 0;
    int i, up = 0;
    plant_in_t in = {0, 1};
    (void)state;
    setup(0.62978, 0, 540);
    pl.p.pump_pulsation_pct = 4;
    run(1.0, 0, 1);
    for (i = 0; i < 1000; i++) {
        double q;
        plant_step(&pl, &in, TICK);
        q = pl.q_pump / (1.0 - 0.01 * pl.p_bar) - 120.0;
        lo = fmin(lo, q);
        hi = fmax(hi, q);
        if (i > 0 && prev < 0 && q >= 0)
            up++;
        prev = q;
    }
    assert_true(up >= 26 && up <= 28);
    assert_within(hi, 4.8, 0.05);
    assert_within(lo, -4.8, 0.05);
}

/* A fast mode's 10 ms tick turns the pulsation by a = 2 pi 27 Hz 0.01 s = 1.696 rad, past the
 * series: the tick's pump flow takes the pulsation's mean over the turn, whose swing is the 1 ms
 * one's times sin(a/2)/(a/2) = 0.8774: +-4.8 L/min -> +-4.212; its mean over 1 s (27 periods)
 * stays at 120 L/min (within the part of a period left over). */
static void test_plant_pulsation_over_a_long_tick_is_its_mean(void **state)
{
    double lo = 1e9, hi = -1e9, sum = 0;
    int i;
    plant_in_t in = {0, 1};
    (void)state;
    setup(0.62978, 0, 540);
    pl.p.pump_pulsation_pct = 4;
    for (i = 0; i < 100; i++)
        plant_step(&pl, &in, 10 * TICK);
    for (i = 0; i < 100; i++) {
        double q;
        plant_step(&pl, &in, 10 * TICK);
        q = pl.q_pump / (1.0 - 0.01 * pl.p_bar) - 120.0;
        lo = fmin(lo, q);
        hi = fmax(hi, q);
        sum += q;
    }
    assert_within(hi, 4.212, 0.05);
    assert_within(lo, -4.212, 0.05);
    assert_within(sum / 100, 0.0, 0.05);
}

/* Relief valve: bypass shut (th 0), boom shut, 540 rpm: 120*(1 - 0.01 P) = 200*(P - 5)
 * -> 1120 = 201.2 P -> P = 5.5666 bar, relief flow 200*0.5666 = 113.3 L/min. */
static void test_plant_relief_valve_caps_pressure(void **state)
{
    (void)state;
    setup(0.0, 0, 540);
    run(1.0, 0, 0);
    assert_within(pl.p_bar, 5.5666, 0.001);
    assert_within(pl.q_relief, 113.32, 0.1);
    assert_within(pl.q_boom, 0.0, 0.0);
}

/* Check valves: pressurise the line with the bypass shut, then stop the pump. The nozzles drain
 * it down to their cracking pressure 0.3 bar and hold it there (no other way out); no flow. */
static void test_plant_check_valves_hold_0_3_bar(void **state)
{
    (void)state;
    setup(0.0, 0, 540);
    run(1.0, 0, 1);
    assert_true(pl.p_bar > 5.0);
    pl.pto_rpm = 0;
    run(5.0, 0, 1);
    assert_within(pl.p_bar, 0.3, 0.002);
    assert_true(pl.q_boom < 0.2);
    run(5.0, 0, 1);
    assert_within(pl.q_boom, 0.0, 1e-3);
    /* the nozzle law directly: nothing at 0.29 bar; at 0.55 bar 36 * 0.68127 * sqrt(0.25) = 12.26
     * L/min less the line loss: 12.26/sqrt(1 + 24.526^2 * 1e-5) = 12.223 */
    assert_within(plant_boom_flow(&pl, 0.29), 0.0, 0.0);
    assert_within(plant_boom_flow(&pl, 0.55), 12.223, 0.01);
}

/* Pump stopped with the bypass open: the line empties to 0 bar through the valve (which has no
 * check valve), never below, and every flow stays a number. */
static void test_plant_line_drains_to_zero_through_the_open_bypass(void **state)
{
    (void)state;
    setup(1.0, 0, 540);
    run(1.0, 0, 1);
    assert_true(pl.p_bar > 0.5);
    pl.pto_rpm = 0;
    run(3.0, 0, 1);
    assert_true(pl.p_bar >= 0.0 && pl.p_bar < 1e-6);
    assert_true(isfinite(pl.q_bypass) && isfinite(pl.q_boom) && isfinite(pl.tank_v));
    assert_within(pl.q_pump, 0.0, 0.0);
}

/* Valve motor (docs/SCENARIOS.md): full drive runs at (1 - 0.12)/(1 - 0.12)/4 s = 0.25 stroke/s, reached
 * with tau_m = 0.05 s: from rest the motor has gone 0.25 (t - 0.05 (1 - e^(-t/0.05))), and the
 * valve 1 % (half the 2 % gap) less: 0.4775 at 2 s, 0.9775 at 4 s; the end stop holds it at 1. */
static void test_plant_valve_travel_time_and_end_stop(void **state)
{
    (void)state;
    setup(0.0, 0, 540);
    run(2.0, 1.0, 1);
    assert_within(pl.theta, 0.25 * (2 - 0.05) - 0.01, 1e-6);
    run(2.0, 1.0, 1);
    assert_within(pl.theta, 0.25 * (4 - 0.05) - 0.01, 1e-6);
    run(1.0, 1.0, 1);
    assert_within(pl.theta, 1.0, 0.0);
    /* half duty (128/255 = 0.50196) back: (0.50196 - 0.12)/0.88/4 = 0.108511 stroke/s; the motor
     * pushed the valve open, so it crosses the whole 2 % gap first: after 2 s
     * th = 1 - (0.108511 (2 - 0.05) - 0.02) = 0.808403 */
    run(2.0, -128.0 / 255.0, 1);
    assert_within(pl.theta, 1 - ((128.0 / 255.0 - 0.12) / 0.88 / 4 * 1.95 - 0.02), 1e-6);
}

/* A 0.25 duty pulse of 100 ms from rest (no backlash): w* = (0.25 - 0.12)/0.88/4 = 0.0369318
 * stroke/s; during the pulse the motor goes w* (0.1 - 0.05 (1 - e^-2)) = 0.0020965 and reaches
 * w* (1 - e^-2) = 0.0319337 stroke/s; braked with tau_m it goes 0.05 (0.0319337 - 0.0025) =
 * 0.0014717 more before it falls under 1 % of full speed (0.0025): 0.0035682 in all (the simple
 * rule (d - d_run)/(1 - d_run) L / T gives 0.0036932). */
static void test_plant_valve_pulse_from_rest(void **state)
{
    const double w = (0.25 - 0.12) / 0.88 / 4, e2 = exp(-2.0);
    double want = w * (0.1 - 0.05 * (1 - e2)) + 0.05 * (w * (1 - e2) - 0.0025);
    (void)state;
    setup(0.5, 0, 540);
    pl.p.valve_backlash = 0;
    pl.motor = 0.5;
    run(0.1, 0.25, 1);
    assert_true(pl.moving);
    run(0.5, 0.0, 1);
    assert_false(pl.moving);
    assert_within(pl.theta - 0.5, want, 5e-6);
}

/* Break-away and running friction: from rest 0.19 (and 0.15) start nothing. A moving valve (1 s
 * at full drive) kept at 0.15 >= d_run keeps moving, towards (0.15 - 0.12)/0.88/4 = 0.0085227
 * stroke/s: in 2 s 2 w* + (0.25 - w*) 0.05 = 0.0291193; then 0.10 < d_run brakes it to rest, and
 * from rest 0.15 does not start it again. */
static void test_plant_valve_break_away_and_running_friction(void **state)
{
    const double w = 0.03 / 0.88 / 4;
    double th;
    (void)state;
    setup(0.5, 0, 540);
    pl.p.valve_backlash = 0;
    pl.motor = 0.5;
    run(10.0, 0.19, 1);
    assert_within(pl.theta, 0.5, 0.0);
    run(10.0, -0.15, 1);
    assert_within(pl.theta, 0.5, 0.0);
    run(1.0, 1.0, 1);
    th = pl.theta;
    run(2.0, 0.15, 1);
    assert_true(pl.moving);
    assert_within(pl.theta - th, 2 * w + (0.25 * (1 - exp(-20.0)) - w) * 0.05, 1e-5);
    run(1.0, 0.10, 1);
    assert_false(pl.moving);
    th = pl.theta;
    run(2.0, 0.15, 1);
    assert_within(pl.theta, th, 0.0);
}

/* Backlash 2 %: from 0.5, +1 for 1 s -> 0.5 + 0.25 (1 - 0.05) - 0.01 = 0.7275; the drive off, the
 * motor coasts 0.05 (0.25 - 0.0025) = 0.012375 to rest: 0.739875; reversing, -1 for 1 s: the motor
 * crosses the whole gap (0.02) before the valve follows -> 0.739875 - (0.2375 - 0.02) = 0.522375;
 * the turn of direction is one reversal. */
static void test_plant_valve_backlash_on_reversal(void **state)
{
    (void)state;
    setup(0.5, 0, 540);
    run(1.0, 1.0, 1);
    assert_within(pl.theta, 0.7275, 1e-6);
    run(0.5, 0.0, 1);
    assert_within(pl.theta, 0.739875, 1e-5);
    assert_int_equal(pl.valve_reversals, 0);
    run(1.0, -1.0, 1);
    assert_within(pl.theta, 0.522375, 1e-5);
    assert_int_equal(pl.valve_reversals, 1);
}

static void test_plant_valve_stuck_does_not_move(void **state)
{
    (void)state;
    setup(0.3, 0, 540);
    pl.valve_stuck = 1;
    run(2.0, 1.0, 1);
    assert_within(pl.theta, 0.3, 0.0);
}

/* Meter K curve (docs/SCENARIOS.md): 380 p/L in range, -3 % at 7.5 L/min, -15 % at 3, none below 1.5.
 * Pulses in 10 s at steady flow (after the rotor has settled): 380*0.85*3/60*10 = 161.5 at
 * 3 L/min; 380*0.97*7.5/60*10 = 460.75 at 7.5; 380*30/60*10 = 1900 at 30; 0 at 1.4. */
static uint64_t meter_pulses(double q, double seconds)
{
    uint64_t t = 0, n0;
    long i;
    setup(0.5, 0, 540);
    for (i = 0; i < 1000; i++, t += TICK)
        plant_meter_step(&pl, q, t, TICK);
    n0 = pl.flow_pulses;
    for (i = 0; i < lround(seconds * 1000); i++, t += TICK)
        plant_meter_step(&pl, q, t, TICK);
    return pl.flow_pulses - n0;
}

static void test_plant_meter_falls_off_below_its_range(void **state)
{
    (void)state;
    assert_within(plant_meter_k(&pl, 30.0), 380.0, 1e-9);
    assert_within(plant_meter_k(&pl, 7.5), 368.6, 1e-9);
    assert_within(plant_meter_k(&pl, 3.0), 323.0, 1e-9);
    assert_within(plant_meter_k(&pl, 1.4), 0.0, 0.0);
    assert_within((double)meter_pulses(3.0, 10), 161.5, 1.0);
    assert_within((double)meter_pulses(7.5, 10), 460.75, 1.0);
    assert_within((double)meter_pulses(30.0, 10), 1900.0, 1.0);
    assert_within((double)meter_pulses(1.4, 10), 0.0, 0.0);
}

/* Rotor lag 30 ms: after a step 0 -> 30 L/min the rotor's flow is 30*(1 - e^-1) = 18.96 L/min at
 * 30 ms; pulses in the first 100 ms are about 380/60*30*(0.1 - 0.03*(1 - e^(-0.1/0.03))) = 13.5
 * (19 without lag; the fall-off below 15 L/min takes off a little more). */
static void test_plant_meter_rotor_lags(void **state)
{
    uint64_t t = 0;
    int i;
    (void)state;
    setup(0.5, 0, 540);
    for (i = 0; i < 30; i++, t += TICK)
        plant_meter_step(&pl, 30.0, t, TICK);
    assert_within(pl.q_rotor, 18.964, 0.01);
    for (; i < 100; i++, t += TICK)
        plant_meter_step(&pl, 30.0, t, TICK);
    assert_true(pl.flow_pulses >= 11 && pl.flow_pulses <= 14);
}

/* Wheel: 2*pi*0.75/12 = 0.39270 m a pulse; 11 km/h = 3.05556 m/s -> 7.7808 pulses/s, 778.1 in
 * 100 s; without spacing error evenly 0.39270/3.05556 = 128.52 ms apart; slip 10 % -> 855.9. */
static uint64_t edges[1800];
static int n_edges;
static void edge(uint64_t t_ns)
{
    if (n_edges < 1800)
        edges[n_edges] = t_ns;
    n_edges++;
}

static void wheel_run(double seconds)
{
    uint64_t t = 0;
    long i;
    n_edges = 0;
    pl.wheel_edge = edge;
    for (i = 0; i < lround(seconds * 1000); i++, t += TICK)
        plant_wheel_step(&pl, 11 / 3.6, t, TICK);
}

static void test_plant_wheel_pulses_and_slip(void **state)
{
    plant_params_t p;
    int i;
    (void)state;
    setup(0.5, 0, 540);
    p = pl.p;
    p.wheel_spacing_jitter_pct = 0;
    plant_init(&pl, &p, 1);
    wheel_run(100);
    assert_within((double)pl.wheel_pulses, 778.1, 1.0);
    for (i = 2; i < 700; i++)
        assert_within((double)(edges[i] - edges[i - 1]), 128.52e6, 1.0e3);
    setup(0.5, 0, 540);
    pl.p.wheel_slip_pct = 10;
    wheel_run(100);
    assert_within((double)pl.wheel_pulses, 855.9, 1.0);
}

/* Spacing error: the 12 elements' offsets (2 %) and the meter's 6 blades' (1.5 %) sum to zero and
 * the intervals repeat every revolution; a revolution's 12 intervals add up to the wheel's
 * circumference at 11 km/h, 2 pi 0.75 / (11 / 3.6) = 1.5422364 s;
 * the offsets spread about as drawn (sample sd of 12 within 0.5-2 x 2 %), so single intervals do
 * differ from the mean. */
static void test_plant_spacing_patterns_repeat_and_sum_to_zero(void **state)
{
    double sum = 0, ss = 0, sum_m = 0;
    int i;
    (void)state;
    setup(0.5, 0, 540);
    for (i = 0; i < pl.wheel_teeth.n; i++) {
        sum += pl.wheel_teeth.e[i];
        ss += pl.wheel_teeth.e[i] * pl.wheel_teeth.e[i];
    }
    for (i = 0; i < pl.meter_teeth.n; i++)
        sum_m += pl.meter_teeth.e[i];
    assert_int_equal(pl.wheel_teeth.n, 12);
    assert_int_equal(pl.meter_teeth.n, 6);
    assert_within(sum, 0.0, 1e-12);
    assert_within(sum_m, 0.0, 1e-12);
    assert_true(sqrt(ss / 11) > 0.01 && sqrt(ss / 11) < 0.04);
    wheel_run(100);
    for (i = 2; i + 12 < 700; i++)
        assert_within((double)(edges[i + 12] - edges[i + 11]), (double)(edges[i] - edges[i - 1]), 2.0e3);
    for (i = 2; i + 12 < 700; i += 12)
        assert_within((double)(edges[i + 12] - edges[i]), 2 * M_PI * 0.75 / (11 / 3.6) * 1e9, 2.0e3);
    assert_true(fabs((double)(edges[3] - edges[2]) - 128.52e6) > 0.001 * 128.52e6
                || fabs((double)(edges[4] - edges[3]) - 128.52e6) > 0.001 * 128.52e6);
}

/* Bounce adds one pulse 0.5 ms after a real one (at most; never past the end of the 1 ms tick):
 * at 100 % every real edge has its echo (twice the pulses), at 50 % about half of the 778
 * (1167 +- 4 sd, sd sqrt(778/4) = 14). */
static void test_plant_bounce_adds_one_pulse_after_a_real_one(void **state)
{
    int i;
    (void)state;
    setup(0.5, 0, 540);
    pl.bounce_pct = 100;
    wheel_run(100);
    assert_within((double)pl.wheel_pulses, 2 * 778.1, 2.0);
    for (i = 0; i + 1 < 1500; i += 2)
        assert_true(edges[i + 1] > edges[i] && edges[i + 1] - edges[i] <= 500000u);
    setup(0.5, 0, 540);
    pl.bounce_pct = 50;
    wheel_run(100);
    assert_within((double)pl.wheel_pulses, 1167.0, 56.0);
}

/* Tractor: 0 -> 11 km/h command: (3.0556 - v)/1 s exceeds 0.5 m/s2 until v = 2.5556, so for the
 * first 5.11 s the speed grows at 0.5 m/s2: 1.000 m/s at 2 s; then the lag: 3.0556 - 0.5 e^-(t-5.111). */
static void test_plant_tractor_lag_and_acceleration_limit(void **state)
{
    (void)state;
    setup(0.5, 1, 540);
    pl.v_cmd_kmh = 11;
    run(2.0, 0, 1);
    assert_within(pl.v_mps, 1.0, 1e-3);
    run(5.111, 0, 1);                           /* t = 7.111: two lag times after the limit ended */
    assert_within(pl.v_mps, 3.05556 - 0.5 * exp(-2.0), 0.003);     /* 2.98789 */
}

/* Sensors: P 4 bar -> 4 + 16*4/16 = 8 mA -> 8*250 ohm = 2 V -> 2/5*1023 = 409.2 -> 409; an open
 * loop reads 0; a full tank 20 mA -> 1023, half 12 mA -> 613.8 -> 614. */
static void test_plant_sensors_4_20_ma_into_the_adc(void **state)
{
    plant_in_t in = {0, 0};
    (void)state;
    setup(0.0, 0, 0);
    pl.p_bar = 4.0;
    pl.p.check_valve_bar = 5.0;                 /* nothing drains: the line keeps its 4 bar */
    plant_step(&pl, &in, TICK);
    assert_within(pl.p_bar, 4.0, 1e-9);
    assert_int_equal(plant_adc_ideal(&pl, 0), 409);
    assert_int_equal(plant_adc_ideal(&pl, 1), 1023);
    pl.tank_v = 500;
    pl.psens_open = 1;
    plant_step(&pl, &in, TICK);
    assert_int_equal(plant_adc_ideal(&pl, 0), 0);
    assert_int_equal(plant_adc_ideal(&pl, 1), 614);
}

/* Noise: 1 LSB Gaussian: over 20000 reads at 8 mA the mean is 409.2 (+-0.05) and the sd about
 * sqrt(1 + 1/12) = 1.04 (rounding adds 1/12 LSB^2). */
static void test_plant_pressure_noise_is_1_lsb(void **state)
{
    plant_in_t in = {0, 0};
    double s = 0, ss = 0;
    int i;
    (void)state;
    setup(0.0, 0, 0);
    pl.p.pressure_noise_lsb = 1;
    pl.p.check_valve_bar = 5.0;
    pl.p_bar = 4.0;
    for (i = 0; i < 20000; i++) {
        plant_step(&pl, &in, TICK);
        plant_adc_sample(&pl, 0);
        s += pl.adc_pressure;
        ss += (double)pl.adc_pressure * pl.adc_pressure;
    }
    assert_within(s / 20000, 409.2, 0.05);
    assert_within(sqrt(ss / 20000 - (s / 20000) * (s / 20000)), 1.04, 0.05);
}

/* The tank drains by what leaves the boom: 49.5 L/min for 60 s = 49.5 L. */
static void test_plant_tank_drains_by_the_boom_flow(void **state)
{
    (void)state;
    setup(0.62978, 0, 540);
    run(60.0, 0, 1);
    assert_within(pl.tank_v, 1000 - 49.5, 0.02 * 49.5);
}

/* Tank empty: the pump loses its suction over the last 2 L (linearly): with 1 L left it delivers
 * half, 120 * 0.5 = 60 L/min (before slip); with none, nothing, and the boom runs dry. */
static void test_plant_empty_tank_stops_the_pump(void **state)
{
    plant_in_t in = {0, 1};
    (void)state;
    setup(0.62978, 0, 540);
    run(1.0, 0, 1);
    pl.tank_v = 1.0;
    plant_step(&pl, &in, TICK);
    assert_within(pl.q_pump / (1.0 - 0.01 * pl.p_bar), 60.0, 0.05);
    pl.tank_v = 0.0;
    run(2.0, 0, 1);
    assert_within(pl.q_pump, 0.0, 0.0);
    assert_within(pl.q_boom, 0.0, 1e-6);
    assert_within(pl.tank_v, 0.0, 0.0);
}

/* Leak after the meter: an orifice passing X L/min at 3 bar, X sqrt(P/3); the meter sees nozzles
 * plus leak. Clogged nozzles pass nothing: 6 of 36 clogged at 4.398 bar leave 30 * 0.681273 =
 * 20.4382 L/min/sqrt(bar): 20.4382 * sqrt(4.098) / sqrt(1 + 20.4382^2 * 1e-5) = 41.288 L/min. */
static void test_plant_leak_and_clogged_nozzles(void **state)
{
    (void)state;
    setup(0.62978, 0, 540);
    pl.leak_lpm = 3.0;
    run(2.0, 0, 1);
    assert_within(pl.q_leak, 3.0 * sqrt(pl.p_bar / 3.0), 1e-9);
    assert_within(pl.q_meter, pl.q_boom + pl.q_leak, 1e-12);
    assert_true(pl.p_bar < 4.398 - 0.1);        /* the leak takes pressure away from the nozzles */
    pl.clogged = 6;
    assert_within(plant_boom_flow(&pl, 4.398), 41.288, 0.005);
}

/* The transmitters' faults, by hand (4-20 mA over 0-16 bar, 51.15 counts a mA):
 *   4 bar: 8 mA = 409.2 -> 409; 1 bar high: 9 mA = 460.35 -> 460;
 *   a drift of 0.6 bar a minute for 10 s on top: 1.1 bar, 9.1 mA = 465.47 -> 465;
 *   2 bar low at 1 bar: -1 bar, 3 mA, saturated at 3.8 mA = 194.37 -> 194;
 *   the level at 500 of 1000 L: 12 mA = 613.8 -> 614; 100 L high: 13.6 mA = 695.64 -> 696;
 *   1000 L low: -500 L, saturated at 3.8 mA -> 194. */
static void test_plant_transmitter_offsets_and_drift(void **state)
{
    plant_in_t in = {0, 0};
    (void)state;
    setup(0.0, 0, 0);
    pl.p_bar = 4.0;
    pl.p.check_valve_bar = 5.0;                 /* nothing drains: the line keeps its 4 bar */
    pl.tank_v = 500;
    plant_step(&pl, &in, TICK);
    assert_int_equal(plant_adc_ideal(&pl, 0), 409);
    assert_int_equal(plant_adc_ideal(&pl, 1), 614);
    pl.psens_offset_bar = 1.0;
    pl.level_offset_l = 100;
    plant_step(&pl, &in, TICK);
    assert_int_equal(plant_adc_ideal(&pl, 0), 460);
    assert_int_equal(plant_adc_ideal(&pl, 1), 696);
    pl.psens_drift_bar_per_min = 0.6;
    run(10.0, 0, 0);
    assert_within(pl.psens_offset_bar, 1.1, 1e-9);
    assert_int_equal(plant_adc_ideal(&pl, 0), 465);
    assert_within(pl.p_bar, 4.0, 1e-9);         /* the line itself is untouched */
    pl.psens_drift_bar_per_min = 0;
    pl.psens_offset_bar = -2.0;
    pl.p_bar = 1.0;
    pl.level_offset_l = -1000;
    plant_step(&pl, &in, TICK);
    assert_int_equal(plant_adc_ideal(&pl, 0), 194);
    assert_int_equal(plant_adc_ideal(&pl, 1), 194);
}

/* wheel_pulse_mult: 100 s at 11 km/h give 778.1 pulses (test above); 2 edges a real one give
 * 1556.2, 128.52 / 2 = 64.26 ms apart; 0.5 gives 389.05, 257.04 ms apart. */
static void test_plant_wheel_pulse_mult_doubles_and_halves(void **state)
{
    plant_params_t p;
    int i;
    (void)state;
    setup(0.5, 0, 540);
    p = pl.p;
    p.wheel_spacing_jitter_pct = 0;
    plant_init(&pl, &p, 1);
    pl.wheel_mult = 2.0;
    wheel_run(100);
    assert_within((double)pl.wheel_pulses, 1556.2, 1.0);
    for (i = 2; i < 1500; i++)
        assert_within((double)(edges[i] - edges[i - 1]), 64.26e6, 1.0e3);
    plant_init(&pl, &p, 1);
    pl.wheel_mult = 0.5;
    wheel_run(100);
    assert_within((double)pl.wheel_pulses, 389.05, 1.0);
    for (i = 2; i < 380; i++)
        assert_within((double)(edges[i] - edges[i - 1]), 257.04e6, 1.0e3);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_plant_sanity_11kmh_pressure_and_flow),
        cmocka_unit_test(test_plant_sanity_4kmh_coupled),
        cmocka_unit_test(test_plant_fixed_pto_4kmh_needs_a_third_of_the_stroke),
        cmocka_unit_test(test_plant_pto_coupling_scales_the_pump),
        cmocka_unit_test(test_plant_coupled_pto_follows_the_true_speed),
        cmocka_unit_test(test_plant_pump_pulsation_27hz_4pct),
        cmocka_unit_test(test_plant_pulsation_over_a_long_tick_is_its_mean),
        cmocka_unit_test(test_plant_relief_valve_caps_pressure),
        cmocka_unit_test(test_plant_check_valves_hold_0_3_bar),
        cmocka_unit_test(test_plant_line_drains_to_zero_through_the_open_bypass),
        cmocka_unit_test(test_plant_valve_travel_time_and_end_stop),
        cmocka_unit_test(test_plant_valve_pulse_from_rest),
        cmocka_unit_test(test_plant_valve_break_away_and_running_friction),
        cmocka_unit_test(test_plant_valve_backlash_on_reversal),
        cmocka_unit_test(test_plant_valve_stuck_does_not_move),
        cmocka_unit_test(test_plant_meter_falls_off_below_its_range),
        cmocka_unit_test(test_plant_meter_rotor_lags),
        cmocka_unit_test(test_plant_wheel_pulses_and_slip),
        cmocka_unit_test(test_plant_spacing_patterns_repeat_and_sum_to_zero),
        cmocka_unit_test(test_plant_bounce_adds_one_pulse_after_a_real_one),
        cmocka_unit_test(test_plant_tractor_lag_and_acceleration_limit),
        cmocka_unit_test(test_plant_sensors_4_20_ma_into_the_adc),
        cmocka_unit_test(test_plant_pressure_noise_is_1_lsb),
        cmocka_unit_test(test_plant_tank_drains_by_the_boom_flow),
        cmocka_unit_test(test_plant_empty_tank_stops_the_pump),
        cmocka_unit_test(test_plant_leak_and_clogged_nozzles),
        cmocka_unit_test(test_plant_transmitter_offsets_and_drift),
        cmocka_unit_test(test_plant_wheel_pulse_mult_doubles_and_halves),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* test_ffmap_ripple.c: the project's own controller (ffmap) does not hunt on a held target: a fast valve told 4 s or told its time, a smallest pulse a stall left too big stepped back, a reversal's answer awaited. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <stdio.h>
#include <cmocka.h>
#include "ctl.h"
#include "ctl_int.h"
#include "params.h"
#include "sim.h"
#include "helper_ffmap.h"

/* ripple_p95_pct (sim/metrics.h), the family's bound (issue 51): on this 40 s run 4.0-5.0 % over
 * noise draws 1-6 (6.8-11.5 % were every pulse sent after a reversal) */
#define RIPPLE_BOUND_PCT 5.0

/* A held-target run (`fmt`: its scenario, whose one %d is the noise draw) for draws 1-6: the
 * worst ripple_p95_pct and reversals a minute, and the alarms raised. */
static double ripple_of_draws(const char *what, const char *fmt, double *rev, int *alarms)
{
    double worst = 0;
    *rev = 0;
    *alarms = 0;
    for (int seed = 1; seed <= 6; seed++) {
        char text[1024];
        metrics_result_t r;
        snprintf(text, sizeof text, fmt, seed);
        ffmap_anew();
        *alarms += ffmap_run(text, &r);
        print_message("ffmap, %s, seed %d: ripple %.2f %%, %.1f reversals/min, gain %d\n", what, seed,
                      r.ripple_p95_pct, r.valve_reversals_per_min, ctl_st.fm.gain);
        worst = r.ripple_p95_pct > worst ? r.ripple_p95_pct : worst;
        *rev = r.valve_reversals_per_min > *rev ? r.valve_reversals_per_min : *rev;
    }
    return worst;
}

/* A 1.65 s valve with a 0.12 s motor the firmware believes 4 s, its break-away 0.12 (told 0.2),
 * a fixed PTO, held at 6.8 km/h from the start, noise draws 1-6.
 * The start cuts the gain to its floor; each reversal (0.6 of a period at full duty) then moves
 * the flow by itself, and two smallest pulses sent before the meter shows it would carry the flow
 * as far past the target: a cycle of +-12 %. After a reversal nothing more is sent that way until
 * the flow can show it (ffmap.c ffmap_out). */
static void test_ffmap_ripple_a_fast_valve_told_4_s_does_not_hunt(void **state)
{
    double rev;
    int alarms;
    (void)state;
    assert_true(ripple_of_draws("a fast valve told 4 s",
        "[run]\nduration_s = 40\nseed = %d\n[config]\ncontroller = ffmap\nrate_l_ha = 101\n[plant]\n"
        "valve_travel_s = 1.65\nvalve_stiction_duty = 0.122\nvalve_running_duty = 0.072\n"
        "valve_backlash = 0.0192\nvalve_motor_tau_s = 0.122\npump_lpm_at_540 = 126.4\n"
        "pump_pulsation_pct = 7.62\npto_coupled = 0\npto_rpm = 560\nmeter_k_ppl = 380.17\n"
        "meter_blade_jitter_pct = 1.44\nwheel_spacing_jitter_pct = 3.79\nwheel_slip_pct = 1.01\n"
        "speed_bounce_pct = 1.54\npressure_noise_lsb = 1.88\nnozzle_wear_pct = 4.0\n"
        "check_valve_bar = 0.604\nvalve_cv_open = 231.3\n[drive]\n0 0\n2 0\n2 6.8\n40 6.8\n",
        &rev, &alarms) <= RIPPLE_BOUND_PCT);
    assert_int_equal(alarms, 0);
}

/* A 1.69 s valve told 1.7 s, its break-away 0.256 and running friction 0.195 (told Min duty 20 %),
 * backlash 1.06 %, a 0.088 s motor, 9 % pump pulsation, held at 4.5 km/h for a minute, noise
 * draws 1-6. Its backlash is 0.18 of a period at full duty; a reversal worth 0.6 (3.5 % of the
 * stroke) swung the flow +-13 %, 30-35 reversals a minute, until cycles had learnt it down
 * (ripple 3.9-5.6 %). One worth 3/4 of the told backlash (ffmap_learnt.c): 0.5-1.6 %. */
static void test_ffmap_ripple_a_fast_valve_told_its_time_does_not_hunt(void **state)
{
    double rev;
    int alarms;
    (void)state;
    assert_true(ripple_of_draws("a fast valve told 1.7 s",
        "[run]\nduration_s = 60\nseed = %d\n[config]\ncontroller = ffmap\nrate_l_ha = 125\n"
        "valve_travel_s = 1.7\n[plant]\nvalve_travel_s = 1.69\nvalve_stiction_duty = 0.256\n"
        "valve_running_duty = 0.195\nvalve_backlash = 0.0106\nvalve_motor_tau_s = 0.088\n"
        "pump_lpm_at_540 = 111.1\npump_pulsation_pct = 9.03\npto_coupled = 0\npto_rpm = 493\n"
        "meter_blade_jitter_pct = 0.24\nwheel_spacing_jitter_pct = 3.82\nspeed_bounce_pct = 2.49\n"
        "pressure_noise_lsb = 1.42\n[drive]\n0 0\n2 0\n2 4.5\n60 4.5\n", &rev, &alarms) <= 2.5);
    assert_true(rev <= 20);
    assert_int_equal(alarms, 0);
}

/* A 12 s valve told 12 s with twice the backlash it was told (0.04 of the stroke: about five
 * periods at full duty), break-away 0.1, a fixed PTO, every noise at the family's top, the drive
 * of a field's first minute (9.2, 4.3, 7.2, 9 and 4.5 km/h), noise draws 1-6. A half cycle
 * through its slack and the meter's lag is longer than a fast valve's FFMAP_OSC_GAP; counted
 * within FFMAP_OSC_GAP_SLOW (a valve whose stroke takes FFMAP_SLOW_T periods at its gain) its
 * cycles cut the gain, and the flow holds within the family's bound; counted within
 * FFMAP_OSC_GAP, two of the six draws cycle past it. */
static void test_ffmap_ripple_a_slow_valve_with_twice_its_slack_does_not_hunt(void **state)
{
    double rev;
    int alarms;
    (void)state;
    assert_true(ripple_of_draws("a 12 s valve with twice its told slack",
        "[run]\nduration_s = 63\nseed = %d\n[config]\ncontroller = ffmap\nrate_l_ha = 100\n"
        "valve_travel_s = 12.0\n[plant]\nvalve_travel_s = 12.0\nvalve_stiction_duty = 0.1\n"
        "valve_running_duty = 0.08\nvalve_backlash = 0.04\nvalve_motor_tau_s = 0.15\n"
        "pump_lpm_at_540 = 103.4\npump_pulsation_pct = 10.0\npto_coupled = 0\npto_rpm = 511\n"
        "meter_k_ppl = 379.81\nmeter_blade_jitter_pct = 3.0\nwheel_spacing_jitter_pct = 4.0\n"
        "wheel_slip_pct = 3.0\nspeed_bounce_pct = 3.0\npressure_noise_lsb = 3.0\n"
        "nozzle_wear_pct = 0.91\ncheck_valve_bar = 0.569\nvalve_cv_open = 221.1\n[drive]\n"
        "0 0\n2 0\n2 9.2\n12.1 9.2\n12.1 4.3\n22.4 4.3\n22.4 7.2\n35.1 7.2\n35.1 9\n43.5 9\n"
        "43.5 4.5\n63 4.5\n", &rev, &alarms) <= RIPPLE_BOUND_PCT);
    assert_int_equal(alarms, 0);
}

/* ffmap's step alone (ctl_step), its input: target and flow x100 L/min, a steady 7 km/h, the gain
 * as learnt (no pressure cut), no end stop */
static ctl_in_t step_in(int target, int flow)
{
    ctl_in_t in;
    in.target_lpm_x100 = (int16_t)target;
    in.flow_lpm_x100 = (int16_t)flow;
    in.speed_kmh_x100 = 700;
    in.pressure_kpa = FFMAP_P_REF;
    in.valve_limit = 0;
    return in;
}

/* A smallest pulse a stall left FFMAP_BRK_MAX over Min duty, on a valve whose every pulse moves the
 * flow by 8 % of the 30 L/min target (a toy: the flow steps at once): the loop cycles +-4 % at a
 * steady target, and each reversal within a half cycle's bound of the last takes FFMAP_BRK_STEP
 * off while its pulse is near the smallest (the rule's own words, counted here from the drives:
 * reversals and the periods between them). With the target moving by 2 % a period (up for 10
 * periods, down for 10: not a steady target) nothing is taken off. */
static int brk_after_cycles(int ramp, int *stepped, int *reversals)
{
    ctl_in_t in = step_in(3000, 3000);
    int dir = 0, since = 1000, k;
    ffmap_anew();                           /* the default settings: Valve time 4 s */
    for (k = 0; k < FFMAP_WARM + 5; k++)    /* the start over, at rest on the target */
        ctl_step(&in);
    ctl_st.fm.brk_extra = 5 * FFMAP_BRK_STEP;  /* FFMAP_BRK_MAX's last step */
    in.flow_lpm_x100 = 2880;                /* 4 % under the target */
    *stepped = *reversals = 0;
    for (k = 0; k < 300; k++) {
        int16_t before = ctl_st.fm.brk_extra;
        if (ramp)
            in.target_lpm_x100 = (int16_t)(in.target_lpm_x100 + (k / 10 % 2 ? -60 : 60));
        q15_t d = ctl_step(&in);
        since++;
        if (d != 0) {
            int s = d > 0 ? 1 : -1;
            if (dir != 0 && s != dir) {
                (*reversals)++;
                /* (the valve told 4 s: a half cycle's bound FFMAP_OSC_GAP_SLOW while its stroke
                 * takes FFMAP_SLOW_T periods at its gain) */
                int gap = UMUL(ctl_travel, ctl_st.fm.gain) >= (uint32_t)FFMAP_SLOW_T << 8
                          ? FFMAP_OSC_GAP_SLOW : FFMAP_OSC_GAP;
                *stepped += since <= gap && before - ctl_st.fm.brk_extra == FFMAP_BRK_STEP;
                since = 0;
            }
            dir = s;
            in.flow_lpm_x100 = (int16_t)(in.flow_lpm_x100 + s * 240);   /* 8 % of the target a pulse */
        }
    }
    return ctl_st.fm.brk_extra;
}

static void test_ffmap_ripple_a_resolution_cycle_steps_the_smallest_pulse_back(void **state)
{
    int stepped, reversals, brk;
    (void)state;
    brk = brk_after_cycles(0, &stepped, &reversals);
    print_message("ffmap, a resolution cycle: %d reversals, %d stepped the smallest pulse back: %d of %d\n",
                  reversals, stepped, brk, 5 * FFMAP_BRK_STEP);
    assert_true(stepped >= 2);
    assert_int_equal(brk, 5 * FFMAP_BRK_STEP - stepped * FFMAP_BRK_STEP);
    brk = brk_after_cycles(1, &stepped, &reversals);
    print_message("ffmap, a moving target: %d reversals, the smallest pulse %d of %d\n", reversals, brk,
                  5 * FFMAP_BRK_STEP);
    assert_int_equal(stepped, 0);
    assert_true(brk >= 5 * FFMAP_BRK_STEP);
}

/* Half cycles of 24 periods (the flow 10 % over the target, then 10 % under: big swings) on a
 * valve told `travel` (0.1 s), from the gain a new one starts with; with `ramp` the speed and the
 * target rise by 1 % a period (a speed change, not a steady speed). What the second reversal (24
 * periods after the first, both half cycles big) took off the gain, in eighths of it; -1 if that
 * reversal came elsewhen. */
static int cut_at_second_reversal(uint16_t travel, int ramp)
{
    ctl_in_t in = step_in(3000, 3000);
    int k, dir = 0, reversals = 0;
    ffmap_anew();
    assert_int_equal(param_set(P_VALVE_TRAVEL, travel), 1);
    ctl_select(CTL_FFMAP);
    for (k = 0; k < FFMAP_WARM + 5; k++)
        ctl_step(&in);
    for (k = 0; k < 3 * 24; k++) {
        q15_t d;
        int16_t before = ctl_st.fm.gain;
        if (ramp) {
            in.speed_kmh_x100 = (uint16_t)(in.speed_kmh_x100 + in.speed_kmh_x100 / 100);
            in.target_lpm_x100 = (int16_t)(in.target_lpm_x100 + in.target_lpm_x100 / 100);
        }
        in.flow_lpm_x100 = (int16_t)(in.target_lpm_x100 + (k / 24 % 2 ? -1 : 1) * (in.target_lpm_x100 / 10));
        d = ctl_step(&in);
        if (d != 0 && dir != 0 && (d > 0) != (dir > 0) && ++reversals == 2)
            return k == 48 ? (before - ctl_st.fm.gain) * 8 / before : -1;
        dir = d != 0 ? (d > 0 ? 1 : -1) : dir;
    }
    return -1;
}

/* Reversals 24 periods apart are a cycle on a valve whose stroke takes FFMAP_SLOW_T periods or
 * more at its gain (told 4 s, at as a new one starts: 30 periods), at a steady speed: the second
 * big swing cuts the gain by a quarter. On a valve told 0.8 s (at most 16 periods, at any gain)
 * they are not one (FFMAP_OSC_GAP), nor while the speed changes: there the loop follows the speed. */
static void test_ffmap_ripple_a_slow_valves_cycle_is_longer(void **state)
{
    (void)state;
    int slow = cut_at_second_reversal(40, 0), ramp = cut_at_second_reversal(40, 1);
    int fast = cut_at_second_reversal(8, 0);
    print_message("ffmap, half cycles of 24 periods: the second reversal took %d/8 off the gain on a "
                  "valve told 4 s, %d/8 with the speed rising, %d/8 on one told 0.8 s\n", slow, ramp, fast);
    assert_int_equal(slow, 2);
    assert_int_equal(ramp, 0);
    assert_int_equal(fast, 0);
}

/* A reversal at a steady target, the flow not answering yet (20 % under the target): on a valve
 * learnt at a quarter of as told (under FFMAP_G_INIT / 2) the FFMAP_ANSWER - 1 periods after it
 * send nothing; learnt at as told, the integral's next pulses go out at once. */
static int quiet_after_reversal(int16_t gain)
{
    ctl_in_t in = step_in(3000, 3000);
    int k, quiet = 0;
    ffmap_anew();                           /* the default settings: Valve time 4 s */
    for (k = 0; k < FFMAP_WARM + 5; k++)
        ctl_step(&in);
    ctl_st.fm.gain = gain;
    in.flow_lpm_x100 = 3600;                /* 20 % over: the valve opens the bypass */
    for (k = 0; k < 50 && ctl_step(&in) >= 0; k++)
        ;
    in.flow_lpm_x100 = 2400;                /* 20 % under: a reversal, then the wait */
    for (k = 0; k < 50 && ctl_step(&in) <= 0; k++)
        ;
    while (quiet < 10 && ctl_step(&in) == 0)
        quiet++;
    return quiet;
}

static void test_ffmap_ripple_a_fast_valve_awaits_its_reversals_answer(void **state)
{
    (void)state;
    int fast = quiet_after_reversal(FFMAP_G_INIT / 4), told = quiet_after_reversal(256);
    print_message("ffmap, periods without a pulse after a reversal: %d on a fast valve, %d as told\n", fast,
                  told);
    assert_int_equal(fast, FFMAP_ANSWER - 1);
    assert_int_equal(told, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ffmap_ripple_a_fast_valve_told_4_s_does_not_hunt),
        cmocka_unit_test(test_ffmap_ripple_a_fast_valve_told_its_time_does_not_hunt),
        cmocka_unit_test(test_ffmap_ripple_a_slow_valve_with_twice_its_slack_does_not_hunt),
        cmocka_unit_test(test_ffmap_ripple_a_resolution_cycle_steps_the_smallest_pulse_back),
        cmocka_unit_test(test_ffmap_ripple_a_fast_valve_awaits_its_reversals_answer),
        cmocka_unit_test(test_ffmap_ripple_a_slow_valves_cycle_is_longer),
    };
    return cmocka_run_group_tests_name("ffmap_ripple", tests, NULL, NULL);
}

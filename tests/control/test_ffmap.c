/* test_ffmap.c: the project's own controller (ffmap) on the simulated sprayer: an over-pressure start settles on the target, the valve rests at a steady target, a valve faster or stiffer than it was told is followed (a fast one started without over-pressure, a fast stiff one told the truth keeps its gain), the speed's feed-forward is learnt where the PTO is fixed, never pushes the flow past the target and near P max never closes over it. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include "ctl.h"
#include "ctl_int.h"
#include "speed.h"
#include "sim.h"
#include "helper_ffmap.h"

static int setup(void **state)
{
    (void)state;
    ffmap_anew();
    return 0;
}

/* The highest pressure of eight runs of a new controller (seeds 1-8) of DURATION_S s at RATE
 * L/ha, the firmware told CONFIG ([config] lines, "" for its defaults), on the plant and drive
 * PLANT ([plant] lines, then [drive]); adds their alarms to *alarms. */
static double p_max_on_seeds(int duration_s, int rate, const char *config, const char *plant, int *alarms)
{
    double p_max = 0;
    for (int seed = 1; seed <= 8; seed++) {
        char text[1024];
        metrics_result_t r;
        snprintf(text, sizeof text,
                 "[run]\nduration_s = %d\nseed = %d\n[config]\ncontroller = ffmap\nrate_l_ha = %d\n%s[plant]\n%s",
                 duration_s, seed, rate, config, plant);
        ffmap_anew();
        *alarms += ffmap_run(text, &r);
        p_max = r.pressure_max_bar > p_max ? r.pressure_max_bar : p_max;
    }
    return p_max;
}

/* p_max_on_seeds over seeds 1-8 on a fast valve near P max (WHAT names it): the line stays under
 * BOUND bar and nothing is raised. */
static void assert_p_max_on_seeds(const char *what, int duration_s, int rate, const char *config,
                                  const char *plant, double bound)
{
    int alarms = 0;
    double p_max = p_max_on_seeds(duration_s, rate, config, plant, &alarms);
    print_message("ffmap, %s: pressure up to %.2f bar, %d alarms over 8 seeds\n", what, p_max, alarms);
    assert_true(p_max < bound);
    assert_int_equal(alarms, 0);
}

/* A whole run of a new controller: the longest stretch (s) with the meter more than 10 % off the
 * target at working speed; adds the alarms it raised to *alarms when given. */
static double longest_off_stretch(const char *text, int *alarms)
{
    sim_t sim;
    double run_s = 0, worst = 0;
    ffmap_anew();
    ffmap_sim_from(&sim, text);
    while (!sim_done(&sim)) {
        for (int i = 0; i < 100; i++)
            sim_step(&sim);
        sim_row_t r;
        sim_row(&sim, &r);
        if (r.spray_on && r.v_true_kmh >= 4 && r.target_lpm > 0
            && fabs(r.flow_meas_lpm - r.target_lpm) > 0.1 * r.target_lpm)
            run_s += 0.1;
        else
            run_s = 0;
        worst = run_s > worst ? run_s : worst;
    }
    if (alarms)
        *alarms += sim.metrics.n_alarms;
    sim_free(&sim);
    return worst;
}

/* longest_off_stretch over seeds 1-8 of a DURATION_S s run of a new controller, BODY its
 * [config], [plant] and [drive] sections: the worst; the alarms they raised are added to *alarms. */
static double worst_off_stretch_on_seeds(int duration_s, const char *body, int *alarms)
{
    double worst = 0;
    for (int seed = 1; seed <= 8; seed++) {
        char text[1024];
        snprintf(text, sizeof text, "[run]\nduration_s = %d\nseed = %d\n%s", duration_s, seed, body);
        double w = longest_off_stretch(text, alarms);
        worst = w > worst ? w : worst;
    }
    return worst;
}

/* Closed loop on the simulated sprayer with the valve starting shut and the boom spraying at
 * once (given speed): the start climbs to the relief valve, the application opens the bypass
 * under over-pressure, then the loop takes over. The pressure must come under P max and the
 * flow follow the target: the drive the relief overrode is not owed afterwards (before, the
 * estimate of the old servo stayed at "closed" while the valve opened, and the loop drove the
 * pressure back over P max). */
static void test_ffmap_over_pressure_start_settles_on_the_target(void **state)
{
    (void)state;
    static const char text[] =
        "[run]\nduration_s = 60\nseed = 5\n[config]\ncontroller = ffmap\nrate_l_ha = 150\ngiven_speed_kmh = 6\n"
        "[plant]\npto_coupled = 0\nvalve_start_pos = 0\n[drive]\n0 0\n[events]\n30 given_speed_kmh 8\n";
    sim_t sim;
    ffmap_sim_from(&sim, text);
    int saw_over = 0;
    double worst_late = 0, p_late = 0;
    while (sim_time_s(&sim) < 60) {
        for (int i = 0; i < 100; i++)
            sim_step(&sim);
        if (sim.plant.p_bar > 4.8)
            saw_over = 1;
        sim_row_t r;
        sim_row(&sim, &r);
        if ((sim_time_s(&sim) > 15 && sim_time_s(&sim) < 30) || sim_time_s(&sim) > 40) {
            double e = fabs(r.flow_true_lpm - r.target_lpm) / r.target_lpm;
            worst_late = e > worst_late ? e : worst_late;
            p_late = r.p_bar > p_late ? r.p_bar : p_late;
        }
    }
    sim_free(&sim);
    print_message("ffmap: after an over-pressure start, worst flow error %.1f %%, pressure up to %.2f bar\n",
                  worst_late * 100, p_late);
    assert_true(saw_over);
    assert_true(worst_late < 0.05);
    assert_true(p_late < 4.8);
}

/* The paper's kind of run on the default sprayer: the valve rests between speed changes (few
 * reversals a minute), the dose holds and the flow follows the target. */
static void test_ffmap_holds_still_at_a_steady_target(void **state)
{
    (void)state;
    static const char text[] =
        "[run]\nduration_s = 120\nseed = 3\n[config]\ncontroller = ffmap\nrate_l_ha = 150\n"
        "[plant]\nspeed_bounce_pct = 3\npump_pulsation_pct = 8\npressure_noise_lsb = 2\n"
        "[drive]\n0 0\n2 0\n2 6\n40 6\n40 9\n80 9\n80 5\n120 5\n";
    metrics_result_t r;
    ffmap_run(text, &r);
    print_message("ffmap: %.1f reversals a minute, CV %.2f %%, dose (loop) %.3f %%\n", r.valve_reversals_per_min,
                  r.cv_pct, r.dose_ctl_pct);
    assert_true(r.valve_reversals_per_min < 25);
    assert_true(r.cv_pct < 1.0);
    assert_true(fabs(r.dose_ctl_pct) < 0.5);
}

/* Sections switched between 18 and 30 of 36 nozzles every 12 s at a steady 6.4 km/h, a 10.6 s
 * valve told 4 s, the pump on the wheels (plant 23 of `make family SEED=18 KIND=field EVENTS=1`,
 * whose learnt gain fell 192 -> 25 and raised OFF_RATE). The boom's flow steps by itself a period
 * after the target does; the proportional and derivative terms read that as the valve's answer
 * and turned the valve with the error a fifth of the target, and the reversal rules cut the gain
 * by a quarter twice at each switch. With the step seeing no change of the error for FFMAP_P_WAIT
 * periods after a switch (ffmap.c), the gain the valve needs is kept: at least FFMAP_G_INIT at the
 * end (30 without the hold, and CV 3.78 % against 0.95 %), and no alarm. */
static void test_ffmap_a_section_switch_does_not_cut_the_gain(void **state)
{
    (void)state;
    static char text[1536];
    int n = snprintf(text, sizeof text,
                     "[run]\nduration_s = 200\nseed = 5\n[config]\ncontroller = ffmap\nrate_l_ha = 133\n"
                     "[plant]\nvalve_travel_s = 10.63\nvalve_stiction_duty = 0.171\nvalve_running_duty = 0.093\n"
                     "valve_backlash = 0.0185\nvalve_motor_tau_s = 0.028\npump_lpm_at_540 = 123.2\npto_coupled = 1\n"
                     "valve_cv_open = 262.1\n[drive]\n0 0\n2 0\n8 6.4\n200 6.4\n[events]\n");
    for (int t = 30; t < 200; t += 12)
        n += snprintf(text + n, sizeof text - (size_t)n, "%d sections_open %d\n", t, (t / 12) % 2 ? 18 : 30);
    metrics_result_t r;
    int alarms = ffmap_run(text, &r);
    print_message("ffmap, sections switched every 12 s on a 10.6 s valve told 4 s: gain %d (256: as told), "
                  "%d alarms, CV %.2f %%, %.1f reversals a minute\n", ctl_st.fm.gain, alarms, r.cv_pct,
                  r.valve_reversals_per_min);
    assert_true(ctl_st.fm.gain >= FFMAP_G_INIT);
    assert_int_equal(alarms, 0);
}

/* A valve that the firmware was not told about: 1.5 s of travel where it believes 4 s, or a
 * break-away of 0.33 where it believes 0.2. The loop learns the gain and the smallest pulse: it
 * does not hunt, and the flow follows. */
static void test_ffmap_does_not_hunt_on_an_untold_valve(void **state)
{
    (void)state;
    static const char *const plants[2] = {
        "valve_travel_s = 1.5\npto_coupled = 0\npto_rpm = 540\n",
        "valve_stiction_duty = 0.33\nvalve_running_duty = 0.22\n",
    };
    for (int i = 0; i < 2; i++) {
        char text[512];
        snprintf(text, sizeof text,
                 "[run]\nduration_s = 180\nseed = 7\n[config]\ncontroller = ffmap\nrate_l_ha = 125\n[plant]\n%s"
                 "[drive]\n0 0\n2 0\n2 7\n60 7\n60 10\n120 10\n120 5\n180 5\n", plants[i]);
        metrics_result_t r;
        ffmap_run(text, &r);
        print_message("ffmap, untold valve %d: %.1f reversals a minute, CV %.2f %%, dose (loop) %.3f %%\n", i,
                      r.valve_reversals_per_min, r.cv_pct, r.dose_ctl_pct);
        assert_true(r.valve_reversals_per_min < 50);
        assert_true(r.cv_pct < 2.0);
        assert_true(fabs(r.dose_ctl_pct) < 0.5);
    }
}

/* A 1.6 s valve breaking away at 0.33 (told 0.2: the family's stiffest) with a fixed PTO,
 * through a slow-down and a speed-up, seeds 1-6: pulses under the break-away do not move it, and
 * the stall rule raises the smallest pulse; a smallest pulse counts twice as much toward a stall
 * while the error is beyond target/16, so no stretch with the meter more than 10 % off the
 * target at working speed lasts longer than 1.5 s (with the count as for a small error, 3.1 s
 * on seed 1: OFF_RATE needs 5 s). 1.5 s from the start's 3/4 of the gain (FFMAP_G_INIT), 0.9 s
 * from the full gain. */
static void test_ffmap_a_stiff_valve_breaks_away_within_seconds(void **state)
{
    double worst = 0;
    (void)state;
    for (int seed = 1; seed <= 6; seed++) {
        char text[512];
        snprintf(text, sizeof text,
                 "[run]\nduration_s = 120\nseed = %d\n[config]\ncontroller = ffmap\nrate_l_ha = 120\n"
                 "valve_travel_s = 1.6\n[plant]\nvalve_travel_s = 1.6\nvalve_stiction_duty = 0.33\n"
                 "valve_running_duty = 0.17\nvalve_backlash = 0.01\npto_coupled = 0\npto_rpm = 540\n"
                 "[drive]\n0 0\n2 0\n6 8\n40 8\n44 4.3\n80 4.3\n84 7\n120 7\n", seed);
        double w = longest_off_stretch(text, NULL);
        worst = w > worst ? w : worst;
    }
    print_message("ffmap, a stiff valve: the longest stretch over 10 %% off the target %.1f s\n", worst);
    assert_true(worst <= 1.55);              /* 15 periods */
}

/* A valve of 1.6 s that the firmware believes 4 s, with a slow motor (0.145 s) and 3.3 % of
 * backlash, a fixed PTO (plant 118 of `make family SEED=17`, its first 40 s), seeds 1-8: after
 * the start-up closing, the flow arrives after the valve stops (the motor's coast, the backlash,
 * the line, the meter), and a loop that turns only when the flow has arrived swung at full duty
 * up to the relief valve (4.7-5.0 bar, OVERPRESSURE on 4 of the 8). The integral on the flow a
 * few periods ahead turns it in time: the line stays under 4.5 bar and nothing is raised. */
static void test_ffmap_a_fast_valve_with_a_slow_motor_starts_without_over_pressure(void **state)
{
    (void)state;
    assert_p_max_on_seeds("a fast valve with a slow motor", 40, 137, "",
                          "valve_travel_s = 1.59\nvalve_stiction_duty = 0.161\nvalve_running_duty = 0.083\n"
                          "valve_backlash = 0.0333\nvalve_motor_tau_s = 0.145\npump_lpm_at_540 = 139.1\n"
                          "pump_pulsation_pct = 2.31\npto_coupled = 0\npto_rpm = 523\nmeter_k_ppl = 381.23\n"
                          "meter_blade_jitter_pct = 0.45\nwheel_spacing_jitter_pct = 0.71\nwheel_slip_pct = 2.67\n"
                          "speed_bounce_pct = 1.54\npressure_noise_lsb = 0.7\nnozzle_wear_pct = 10.27\n"
                          "check_valve_bar = 0.719\nvalve_cv_open = 307.4\n"
                          "[drive]\n0 0\n2 0\n2 9.3\n20 9.3\n20 4.7\n34.7 4.7\n34.7 6.6\n", 4.5);
}

/* A valve of 1.77 s that the firmware believes 4 s, with a slow motor (0.12 s), at 145 L/ha on a
 * fixed PTO (plant 124 of `make family SEED=120`, untold, its first 25 s), seeds 1-8: in the
 * first seconds the flow swings from a fifth under the target to a sixth over it (the motor's
 * coast, the backlash), and a gain that learnt from such cycles only after FFMAP_WARM let the
 * line reach 4.76 bar (5.04 bar and OVERPRESSURE on seed 14). Over FFMAP_P_HI_F's 360 kPa, cycles
 * cut the gain in a start too: the line stays under 4.6 bar (4.33). */
static void test_ffmap_a_fast_valve_near_p_max_learns_its_gain_in_the_start(void **state)
{
    (void)state;
    assert_p_max_on_seeds("a fast valve near P max", 25, 145, "",
                          "valve_travel_s = 1.77\nvalve_stiction_duty = 0.12\nvalve_running_duty = 0.066\n"
                          "valve_backlash = 0.0221\nvalve_motor_tau_s = 0.12\npump_lpm_at_540 = 144.1\n"
                          "pump_pulsation_pct = 2.33\npto_coupled = 0\npto_rpm = 533\nmeter_k_ppl = 382.5\n"
                          "meter_blade_jitter_pct = 0.93\nwheel_spacing_jitter_pct = 3.66\nwheel_slip_pct = 0.77\n"
                          "speed_bounce_pct = 2.61\npressure_noise_lsb = 2.62\nnozzle_wear_pct = 2.87\n"
                          "check_valve_bar = 0.645\nvalve_cv_open = 335.4\n"
                          "[drive]\n0 0\n2 0\n2 10.5\n20.8 10.5\n20.8 6.8\n25 6.8\n", 4.6);
}

/* A valve of 2.04 s that the firmware believes 4 s, with a 0.10 s motor and 3.4 % of backlash, on
 * a pump on the wheels at 146 L/ha and 11 km/h, the target at 4.4 bar against P max 4.8 (plant
 * 107 of `make family SEED=72`, untold, its first 25 s), seeds 1-8: after a swing under the
 * target, where the line is at 3 bar, the loop closed at full duty and the motor's coast carried
 * the flow a sixth past the target, the line to 4.91 and 4.99 bar with OVERPRESSURE on seeds 1
 * and 7. Closing toward a target that needs over 400 kPa on a valve learnt faster than a new one
 * starts is held to the smallest pulse + FFMAP_P_T_DUTY: at most 4.59 bar (4.71 when that was 1/4),
 * nothing raised. */
static void test_ffmap_a_fast_valve_closes_slowly_toward_a_target_near_p_max(void **state)
{
    (void)state;
    assert_p_max_on_seeds("a fast valve closing toward a target near P max", 25, 146, "",
                          "valve_travel_s = 2.04\nvalve_stiction_duty = 0.163\nvalve_running_duty = 0.096\n"
                          "valve_backlash = 0.0339\nvalve_motor_tau_s = 0.103\npump_lpm_at_540 = 132.5\n"
                          "pump_pulsation_pct = 3.52\npto_coupled = 1\npto_rpm = 540\nmeter_k_ppl = 378.96\n"
                          "meter_blade_jitter_pct = 1.48\nwheel_spacing_jitter_pct = 0.3\nwheel_slip_pct = 0.29\n"
                          "speed_bounce_pct = 2.52\npressure_noise_lsb = 2.56\nnozzle_wear_pct = 6.53\n"
                          "check_valve_bar = 0.792\nvalve_cv_open = 317.8\n"
                          "[drive]\n0 0\n2 0\n2 11\n15.8 11\n15.8 7.6\n25 7.6\n", 4.8);
}

/* A valve of 1.91 s that the firmware believes 4 s, its motor 0.15 s and 3.3 % of backlash, on a
 * fixed PTO at 146 L/ha (plant 35 of `make family SEED=28`, untold, its first 25 s), seeds 1-8:
 * 3 % under a target that needs 4.3 bar, the loop closed at 0.40 of full duty for five periods,
 * the motor took up the backlash in the first three and coasted on after the last; the flow went
 * 7 % over the target and the line to 4.96 bar, OVERPRESSURE on seed 6. With the closing there
 * held to the smallest pulse + FFMAP_P_T_DUTY of 0.15 (from 1/4, which let 0.40 through) the line
 * stayed under 4.8 bar (4.74), nothing raised. With the speed tracked from the start (speed.c) the
 * start no longer cuts the loop gain, and at 0.15 the first cycles at the steady target took the
 * line to 4.81 bar (seed 2); at 0.10, 4.68 bar. */
static void test_ffmap_a_slow_motor_closes_gently_toward_a_target_near_p_max(void **state)
{
    (void)state;
    assert_p_max_on_seeds("a slow motor closing toward a target near P max", 25, 146, "",
                          "valve_travel_s = 1.91\nvalve_stiction_duty = 0.215\nvalve_running_duty = 0.133\n"
                          "valve_backlash = 0.0333\nvalve_motor_tau_s = 0.15\npump_lpm_at_540 = 113.6\n"
                          "pump_pulsation_pct = 8.86\npto_coupled = 0\npto_rpm = 538\nmeter_k_ppl = 378.56\n"
                          "meter_blade_jitter_pct = 2.05\nwheel_spacing_jitter_pct = 1.04\nwheel_slip_pct = 1.75\n"
                          "speed_bounce_pct = 2.23\npressure_noise_lsb = 1.52\nnozzle_wear_pct = 0.07\n"
                          "check_valve_bar = 0.596\nvalve_cv_open = 280.5\n"
                          "[drive]\n0 0\n2 0\n2 10.7\n21.5 10.7\n21.5 7.3\n25 7.3\n", 4.8);
}

/* A valve of 2.34 s that the firmware is told (2.3 s), its motor 0.15 s, on a pump on the wheels
 * at 149 L/ha (plant 128 of `make family SEED=605`, told, its first 60 s), seeds 1-8: the
 * speed-up at 33 s teaches kff a closing with the speed and the start's swings take the loop
 * gain to a fifth; on the speed-up from 7.1 to 11 km/h the flow ran 2-4 % over the target for 1.5 s while
 * the feed-forward's closing outweighed the loop's opening (a reversal, owed until it is worth
 * FFMAP_REV_MIN), and the line reached 4.88 bar, OVERPRESSURE on seed 8. Over 360 kPa the
 * feed-forward does not close while the flow, filtered over 4 periods, is over the target by
 * more than 1/128 of it: at most 4.76 bar, nothing raised. */
static void test_ffmap_the_feed_forward_does_not_close_over_the_target_near_p_max(void **state)
{
    (void)state;
    assert_p_max_on_seeds("the feed-forward near P max", 60, 149, "valve_travel_s = 2.3\n",
                          "valve_travel_s = 2.34\nvalve_stiction_duty = 0.146\nvalve_running_duty = 0.082\n"
                          "valve_backlash = 0.0168\nvalve_motor_tau_s = 0.148\npump_lpm_at_540 = 149.3\n"
                          "pump_pulsation_pct = 2.66\npto_coupled = 1\npto_rpm = 540\nmeter_k_ppl = 376.83\n"
                          "meter_blade_jitter_pct = 2.9\nwheel_spacing_jitter_pct = 2.81\nwheel_slip_pct = 2.19\n"
                          "speed_bounce_pct = 1.71\npressure_noise_lsb = 1.62\nnozzle_wear_pct = 1.5\n"
                          "check_valve_bar = 0.53\nvalve_cv_open = 259.1\n"
                          "[drive]\n0 0\n2 0\n2 7.9\n20.5 7.9\n20.5 4.2\n33.2 4.2\n33.2 8.1\n43.5 8.1\n"
                          "43.5 7.1\n52.1 7.1\n52.1 11\n60 11\n", 4.8);
}

/* A valve of 2.01 s that the firmware is told (2.0 s), breaking away at 0.348 (told 0.2), on a
 * fixed PTO at 105 L/ha (plant 68 of `make family SEED=9`, told, its first 30 s), seeds 1-8. A
 * reversal waits for FFMAP_REV_MIN, 0.6 of a period at full speed: on a 2 s valve 3 % of its
 * travel, which swings the flow by a tenth of the target however low the loop gain. Read as a
 * loop too fast for the valve, each swing cut the gain by a quarter, 192 -> 33 in 12 s; at the
 * slow-down from 6.7 to 4.5 km/h the flow stayed over the target for 4.3 s (seed 9 of the
 * family: 5 s, OFF_RATE). After a reversal near the smallest the gain is cut only to half of
 * where a new valve starts: at most 1.9 s. With the speed tracked from the start (speed.c) the
 * start's rough target no longer stalls the valve, so at the slow-down its break-away (0.35
 * against Min duty's 0.2) is not learnt yet and the first pulses there leave the flow over the
 * target until the stall rule grows them: at most 3.4 s (seeds 3, 4, 6, 7: 3.0-3.4 s; 0.4-1.9 s
 * before). Counting every pulse up to twice the smallest as a stall while the error is big took
 * it to 1.6 s but let a noisy wheel teach kff past FFMAP_FF_LEAD on a pump on the wheels
 * (test_ffmap_ff.c: 44): not kept. The gain
 * is kept: no OFF_RATE. */
static void test_ffmap_a_stiff_fast_valve_keeps_its_gain(void **state)
{
    int alarms = 0;
    (void)state;
    double worst = worst_off_stretch_on_seeds(
        30,
        "[config]\ncontroller = ffmap\nrate_l_ha = 105\nvalve_travel_s = 2.0\n[plant]\n"
        "valve_travel_s = 2.01\nvalve_stiction_duty = 0.348\nvalve_running_duty = 0.214\n"
        "valve_backlash = 0.0081\nvalve_motor_tau_s = 0.041\npump_lpm_at_540 = 112.6\n"
        "pump_pulsation_pct = 2.56\npto_coupled = 0\npto_rpm = 561\nmeter_k_ppl = 380.98\n"
        "meter_blade_jitter_pct = 2.48\nwheel_spacing_jitter_pct = 2.95\nwheel_slip_pct = 0.92\n"
        "speed_bounce_pct = 2.1\npressure_noise_lsb = 1.17\nnozzle_wear_pct = 13.47\n"
        "check_valve_bar = 0.652\nvalve_cv_open = 233.8\n[drive]\n0 0\n2 0\n2 6.7\n22 6.7\n22 4.5\n30 4.5\n",
        &alarms);
    print_message("ffmap, a stiff fast valve: the longest stretch over 10 %% off the target %.1f s, "
                  "%d alarms over 8 seeds\n", worst, alarms);
    assert_true(worst <= 3.5);
    assert_int_equal(alarms, 0);
}

/* The speed's feed-forward: with the PTO at a fixed speed the bypass must move at every change
 * of speed, and kff is learnt from the lag the loop shows; with the pump on the wheels the flow
 * follows the speed by itself, and kff stays near nothing. The same drive both ways. kff also
 * tells the speed whether to lead a change (speed.h speed_plain): on the fixed PTO it does, on
 * the wheels it does not; another controller selected, it does again. */
static void test_ffmap_learns_the_speed_feed_forward_of_a_fixed_pto(void **state)
{
    (void)state;
    static const char *const pto[2] = { "pto_coupled = 0\npto_rpm = 540\n", "pto_coupled = 1\n" };
    int16_t kff[2];
    int plain[2];
    double cv[2];
    for (int i = 0; i < 2; i++) {
        char text[512];
        snprintf(text, sizeof text,
                 "[run]\nduration_s = 240\nseed = 11\n[config]\ncontroller = ffmap\nrate_l_ha = 125\n[plant]\n%s"
                 "[drive]\n0 0\n2 0\n2 6\n30 6\n30 10\n50 10\n50 5\n70 5\n70 9\n90 9\n90 6\n110 6\n"
                 "110 10\n130 10\n130 5\n150 5\n150 9\n170 9\n170 6\n190 6\n190 10\n210 10\n210 5\n240 5\n",
                 pto[i]);
        metrics_result_t r;
        ffmap_run(text, &r);
        kff[i] = ctl_st.fm.ff_gain;
        plain[i] = speed_plain;
        cv[i] = r.cv_pct;
        print_message("ffmap, PTO %s: kff %d, CV %.2f %%, %.1f reversals a minute, dose (loop) %.3f %%\n",
                      i ? "coupled" : "fixed", kff[i], r.cv_pct, r.valve_reversals_per_min, r.dose_ctl_pct);
        assert_true(fabs(r.dose_ctl_pct) < 0.5);
        assert_true(r.valve_reversals_per_min < 20);
    }
    assert_true(kff[0] >= 40);
    assert_true(kff[1] <= 10);
    assert_true(!plain[0] && plain[1]);
    ctl_select(CTL_BP_PID);
    assert_false(speed_plain);
    assert_true(cv[0] < 1.4);
    assert_true(cv[1] < 1.0);
}

/* The feed-forward at a steady speed: the wheel's spacing (3.9 % here) moves the target up and
 * back by a percent from one period to the next. A 4.2 s valve breaking away at 0.31 (told 0.2),
 * a fixed PTO (plant 54 of `make family SEED=54`), seeds 1-6: with the feed-forward on each
 * period's change of the target, every such step was two pulses against each other (18-40
 * reversals a minute, 27 on average); on the change filtered over four periods, a ramp's
 * feed-forward is the same and the steps cancel. Since the feed-forward stops while the flow is
 * past the target its way by a big error, the loop alone turns those overshoots: 18.3
 * reversals a minute on average (15.7 before), CV 2.37 % on average (2.77 % before). */
static void test_ffmap_the_feed_forward_does_not_follow_the_wheels_jitter(void **state)
{
    double sum = 0, worst = 0;
    (void)state;
    for (int seed = 1; seed <= 6; seed++) {
        char text[1024];
        metrics_result_t r;
        snprintf(text, sizeof text,
                 "[run]\nduration_s = 240\nseed = %d\n[config]\ncontroller = ffmap\nrate_l_ha = 147\n[plant]\n"
                 "valve_travel_s = 4.19\nvalve_stiction_duty = 0.311\nvalve_running_duty = 0.232\n"
                 "valve_backlash = 0.0117\nvalve_motor_tau_s = 0.028\npump_lpm_at_540 = 107.4\n"
                 "pump_pulsation_pct = 6.31\npto_coupled = 0\npto_rpm = 548\nmeter_k_ppl = 381.03\n"
                 "meter_blade_jitter_pct = 1.76\nwheel_spacing_jitter_pct = 3.87\nwheel_slip_pct = 0.14\n"
                 "speed_bounce_pct = 0.43\npressure_noise_lsb = 1.89\nnozzle_wear_pct = 12.66\n"
                 "check_valve_bar = 0.413\nvalve_cv_open = 181.7\n[drive]\n0 0\n2 0\n2 10.9\n15.2 10.9\n"
                 "15.2 6.2\n25.7 6.2\n25.7 8\n36.1 8\n36.1 4.1\n55.3 4.1\n55.3 8.4\n66.5 8.4\n66.5 6.1\n"
                 "83.8 6.1\n83.8 10\n96.2 10\n96.2 6.3\n112.7 6.3\n112.7 9.6\n126.8 9.6\n126.8 7.9\n"
                 "136.2 7.9\n136.2 4.9\n146.8 4.9\n146.8 7.1\n162.3 7.1\n162.3 5.3\n181 5.3\n181 8.5\n"
                 "200.7 8.5\n200.7 6.4\n211 6.4\n211 7.8\n224.8 7.8\n224.8 4.1\n240 4.1\n", seed);
        ffmap_anew();
        ffmap_run(text, &r);
        sum += r.valve_reversals_per_min;
        worst = r.valve_reversals_per_min > worst ? r.valve_reversals_per_min : worst;
        assert_true(r.cv_pct < 4.0);
    }
    print_message("ffmap, the wheel's jitter with a fixed PTO: %.1f reversals a minute on average, at most %.1f\n",
                  sum / 6, worst);
    assert_true(sum / 6 < 20);
    assert_true(worst < 28);
}

/* The feed-forward never pushes the flow further past the target. A 6.25 s valve the firmware
 * believes 4 s, 3.3 % of backlash, the pump on the wheels (plant 171 of `make family SEED=69`,
 * its first 60 s), seeds 1-8: the slow-downs teach kff a closing with the speed, the start's
 * swings cut the loop gain to a third, and on the speed-up from 5.3 to 10.6 km/h the flow ran
 * 15-20 % over the target for 2-3 s while the feed-forward's closing outweighed the loop's
 * opening (OVERPRESSURE on the plant's own seed). Dropped while the error is big the other way,
 * no stretch with the meter more than 10 % off the target at working speed lasts over 1.2 s
 * (2.2 s when it was not: seed 6). */
static void test_ffmap_the_feed_forward_does_not_push_the_flow_past_the_target(void **state)
{
    int alarms = 0;
    (void)state;
    double worst = worst_off_stretch_on_seeds(
        60,
        "[config]\ncontroller = ffmap\nrate_l_ha = 144\n[plant]\n"
        "valve_travel_s = 6.25\nvalve_stiction_duty = 0.188\nvalve_running_duty = 0.119\n"
        "valve_backlash = 0.0325\nvalve_motor_tau_s = 0.027\npump_lpm_at_540 = 143.0\n"
        "pump_pulsation_pct = 7.3\npto_coupled = 1\npto_rpm = 540\nmeter_k_ppl = 381.97\n"
        "meter_blade_jitter_pct = 2.82\nwheel_spacing_jitter_pct = 3.84\nwheel_slip_pct = 1.0\n"
        "speed_bounce_pct = 1.63\npressure_noise_lsb = 2.46\nnozzle_wear_pct = 3.81\n"
        "check_valve_bar = 0.78\nvalve_cv_open = 307.0\n[drive]\n0 0\n2 0\n2 7.8\n16.4 7.8\n"
        "16.4 6.8\n26.2 6.8\n26.2 5.3\n42.4 5.3\n42.4 10.6\n51.3 10.6\n51.3 5.3\n60 5.3\n",
        &alarms);
    print_message("ffmap, a feed-forward learnt on a coupled PTO: the longest stretch over 10 %% off the "
                  "target %.1f s, %d alarms over 8 seeds\n", worst, alarms);
    assert_true(worst <= 1.25);             /* 12 periods */
    assert_int_equal(alarms, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_ffmap_over_pressure_start_settles_on_the_target, setup),
        cmocka_unit_test_setup(test_ffmap_holds_still_at_a_steady_target, setup),
        cmocka_unit_test_setup(test_ffmap_does_not_hunt_on_an_untold_valve, setup),
        cmocka_unit_test_setup(test_ffmap_a_section_switch_does_not_cut_the_gain, setup),
        cmocka_unit_test_setup(test_ffmap_a_stiff_valve_breaks_away_within_seconds, setup),
        cmocka_unit_test_setup(test_ffmap_a_fast_valve_with_a_slow_motor_starts_without_over_pressure, setup),
        cmocka_unit_test_setup(test_ffmap_a_fast_valve_near_p_max_learns_its_gain_in_the_start, setup),
        cmocka_unit_test_setup(test_ffmap_a_fast_valve_closes_slowly_toward_a_target_near_p_max, setup),
        cmocka_unit_test_setup(test_ffmap_a_slow_motor_closes_gently_toward_a_target_near_p_max, setup),
        cmocka_unit_test_setup(test_ffmap_the_feed_forward_does_not_close_over_the_target_near_p_max, setup),
        cmocka_unit_test_setup(test_ffmap_a_stiff_fast_valve_keeps_its_gain, setup),
        cmocka_unit_test_setup(test_ffmap_learns_the_speed_feed_forward_of_a_fixed_pto, setup),
        cmocka_unit_test_setup(test_ffmap_the_feed_forward_does_not_follow_the_wheels_jitter, setup),
        cmocka_unit_test_setup(test_ffmap_the_feed_forward_does_not_push_the_flow_past_the_target, setup),
    };
    return cmocka_run_group_tests_name("ffmap", tests, NULL, NULL);
}

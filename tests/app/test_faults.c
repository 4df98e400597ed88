/* test_faults.c: the firmware against the simulated sprayer: each fault detected in a stated time, the valve and pressure kept safe, recovery; measurement error against the plant's truth. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>
#include "sim.h"
#include "helper_sim.h"
#include "store.h"
#include "totals.h"
#include "hal_host.h"
#include "app.h"
#include "diag.h"
#include "flow.h"
#include "params.h"

static sim_t sim;

/* What a run saw from `from_s` on (the fault's time). */
typedef struct {
    double from_s;
    double first[AL_COUNT];         /* first time each alarm was active after from_s, -1 never */
    double p_max_bar;               /* truth, after from_s */
    double stop_drive_s;            /* valve driven while it sits at an end stop (truth) */
    double boom_l, target_l;        /* integrals over [win0, win1) */
    double win0, win1;
    double spray_on_s;              /* time the boom valve was open after from_s */
    double boom_after_l;            /* volume out of the nozzles after from_s */
} run_t;

static int sim_live;
/* The controller the faults are run with: the paper's conventional pid, then the default `ffmap`
 * (the whole suite runs once with each; the `ffmap` run's names start with "ffmap: "). */
static const char *fault_ctl = "pid";

static void start_drive(const char *events, const char *extra_config, const char *plant, const char *drive)
{
    static char text[4096];
    snprintf(text, sizeof text,
             "[run]\nduration_s = 400\nseed = 3\n[config]\ncontroller = %s\n%s\n[plant]\n%s\n"
             "[drive]\n%s\n[events]\n%s\n", fault_ctl, extra_config, plant, drive, events);
    helper_sim_load(&sim, &sim_live, text, "test_faults");
}

/* accelerate to kmh in 5 s and hold it */
static void start(const char *events, const char *extra_config, const char *plant, double kmh)
{
    char drive[64];
    snprintf(drive, sizeof drive, "0 0\n5 %g\n400 %g", kmh, kmh);
    start_drive(events, extra_config, plant, drive);
}

static int teardown(void **state)
{
    (void)state;
    helper_sim_end(&sim, &sim_live);
    return 0;
}

static void run_init(run_t *r, double from_s)
{
    memset(r, 0, sizeof *r);
    r->from_s = from_s;
    for (int i = 0; i < AL_COUNT; i++)
        r->first[i] = -1;
    r->win0 = r->win1 = -1;
}

/* step to t_s, sampling the trace every 10 ms */
static void run_to(run_t *r, double t_s)
{
    sim_row_t row;
    while (sim_time_s(&sim) < t_s - 1e-9) {
        for (int i = 0; i < 10; i++)
            sim_step(&sim);
        sim_row(&sim, &row);
        if (row.t_s < r->from_s)
            continue;
        for (int b = 0; b < AL_COUNT; b++)
            if ((row.alarms >> b) & 1u && r->first[b] < 0)
                r->first[b] = row.t_s;
        if (row.p_bar > r->p_max_bar)
            r->p_max_bar = row.p_bar;
        if ((row.valve_pos <= 1e-6 && row.valve_drive < 0) || (row.valve_pos >= 1 - 1e-6 && row.valve_drive > 0))
            r->stop_drive_s += 0.01;
        if (row.t_s >= r->win0 && row.t_s < r->win1) {
            r->boom_l += row.boom_lpm * 0.01 / 60;
            r->target_l += row.target_lpm * 0.01 / 60;
        }
        if (row.spray_on)
            r->spray_on_s += 0.01;
        r->boom_after_l += row.boom_lpm * 0.01 / 60;
    }
}

static double detect_s(const run_t *r, int bit)
{
    return r->first[bit] < 0 ? 1e9 : r->first[bit] - r->from_s;
}

static int active(int bit)
{
    return (app_status.alarms >> bit) & 1u;
}

/* mean |flow - target| / target over the next seconds, %, from the firmware's own view */
static double follow_error_pct(double seconds)
{
    sim_row_t row;
    double e = 0;
    int n = 0;
    double t_end = sim_time_s(&sim) + seconds;
    while (sim_time_s(&sim) < t_end - 1e-9) {
        for (int i = 0; i < 100; i++)
            sim_step(&sim);
        sim_row(&sim, &row);
        if (row.target_lpm > 0) {
            e += fabs(row.boom_lpm - row.target_lpm) / row.target_lpm;
            n++;
        }
    }
    return n ? 100 * e / n : 1e9;
}

#define RELIEF_BAR 5.0

/* meter lost: detected within 1.5 s (the rule: 1 s of suspicion, which starts 0.3 s after the
 * last pulse), the pressure fallback holds the dose within 0.75 % (+0.34 % pid, -0.12 % ffmap
 * measured), back on the meter within 3 s of its return, following within 1 % (0.42 %, 0.13 %) */
static void test_faults_meter_lost_falls_back_to_pressure_and_holds_the_dose(void **state)
{
    run_t r;
    (void)state;
    start("40 meter_fail\n140 meter_restore", "", "pto_coupled = 0", 7);
    run_init(&r, 0);
    run_to(&r, 40);
    run_init(&r, 40);
    r.win0 = 50;
    r.win1 = 140;
    run_to(&r, 140);
    double dose_err = 100 * (r.boom_l / r.target_l - 1);
    printf("# meter lost: detected after %.2f s, dose with the pressure fallback %+.2f %% "
           "(40-140 s window 50-140 s), p max %.2f bar, %.2f s driven into a stop\n",
           detect_s(&r, AL_METER_LOST), dose_err, r.p_max_bar, r.stop_drive_s);
    assert_true(detect_s(&r, AL_METER_LOST) <= 1.5);
    assert_true(fabs(dose_err) <= 0.75);
    assert_true(r.p_max_bar < RELIEF_BAR);
    assert_true(r.stop_drive_s <= 0.5);
    assert_true(active(AL_METER_LOST));
    run_init(&r, 140);
    run_to(&r, 143);
    assert_false(active(AL_METER_LOST));
    double e = follow_error_pct(20);
    printf("# meter back: mean flow error %.2f %% over 20 s\n", e);
    assert_true(e <= 1.0);
}

/* speed sensor lost at 7 km/h: alarm within 2.5 s, the boom shuts as the speed estimate
 * falls to zero (no speed, no dose: nothing is sprayed on a guess); the given speed or the
 * sensor's return resumes spraying */
static void test_faults_speed_sensor_lost_alarms_and_spraying_resumes(void **state)
{
    run_t r;
    (void)state;
    start("40 speed_sensor_fail\n70 speed_sensor_restore", "", "pto_coupled = 0", 7);
    run_init(&r, 0);
    run_to(&r, 40);
    run_init(&r, 40);
    run_to(&r, 70);
    printf("# speed sensor lost: alarm after %.2f s, boom open %.2f s of the 30 s, p max %.2f bar, "
           "%.2f s driven at a stop\n", detect_s(&r, AL_SPEED_LOST), r.spray_on_s, r.p_max_bar, r.stop_drive_s);
    assert_true(detect_s(&r, AL_SPEED_LOST) <= 2.5);
    assert_true(r.spray_on_s <= 3.5);
    assert_false(app_status.spraying);
    assert_true(r.p_max_bar < RELIEF_BAR);
    /* the shut boom parks the bypass open; its position not yet known, the valve is driven until
     * the end-stop rule of valve.h (3.6 strokes one way = 14.4 s at full duty: a valve up to 3
     * times slower than told must get there too) says it is there */
    assert_true(r.stop_drive_s <= 3.6 * 4.0 + 0.2);
    run_init(&r, 70);
    run_to(&r, 75);
    assert_true(app_status.spraying);
    assert_false(active(AL_SPEED_LOST));
    double e = follow_error_pct(20);
    printf("# speed back: mean flow error %.2f %% over 20 s\n", e);
    assert_true(e <= 1.3);                      /* 0.64 % pid, 0.27 % ffmap */
}

/* pressure sensor open: fault within 0.5 s, the flow loop goes on on the meter */
static void test_faults_pressure_sensor_open_is_a_fault_and_control_goes_on(void **state)
{
    run_t r;
    (void)state;
    start("40 pressure_sensor_open\n80 pressure_sensor_restore", "", "pto_coupled = 0", 7);
    run_init(&r, 0);
    run_to(&r, 40);
    run_init(&r, 40);
    run_to(&r, 41);
    double e = follow_error_pct(30);
    printf("# pressure sensor open: fault after %.2f s, flow error meanwhile %.2f %%\n",
           detect_s(&r, AL_PSENS), e);
    assert_true(detect_s(&r, AL_PSENS) <= 0.5);  /* 3 periods of debounce */
    assert_true(e <= 1.0);                      /* 0.31 % pid, 0.43 % ffmap */
    run_to(&r, 80);
    run_init(&r, 80);
    run_to(&r, 82.5);
    assert_false(active(AL_PSENS));
    assert_true(r.p_max_bar < RELIEF_BAR);
}

/* a leak after the meter of 12 L/min at 3 bar at 11 km/h (49.5 L/min): LEAK within 4 s */
static void test_faults_leak_after_the_meter_is_seen_in_the_pressure(void **state)
{
    run_t r;
    (void)state;
    start("40 leak_lpm 12\n80 leak_lpm 0", "", "pto_coupled = 0", 11);
    run_init(&r, 0);
    run_to(&r, 40);
    assert_false(active(AL_LEAK));              /* no false alarm while all is well */
    assert_false(active(AL_CLOG));
    run_init(&r, 40);
    run_to(&r, 80);
    printf("# leak 12 L/min: alarm after %.2f s, p max %.2f bar\n", detect_s(&r, AL_LEAK), r.p_max_bar);
    assert_true(detect_s(&r, AL_LEAK) <= 4.0);
    assert_true(detect_s(&r, AL_CLOG) > 100);
    assert_true(r.p_max_bar < RELIEF_BAR);
    run_init(&r, 80);
    run_to(&r, 88);
    assert_false(active(AL_LEAK));
}

/* 12 of 36 nozzles clogged at 7 km/h: CLOG within 4 s */
static void test_faults_clogged_nozzles_raise_the_pressure_alarm(void **state)
{
    run_t r;
    (void)state;
    start("40 clog_nozzles 12\n80 clog_nozzles 0", "", "pto_coupled = 0", 7);
    run_init(&r, 0);
    run_to(&r, 40);
    run_init(&r, 40);
    run_to(&r, 80);
    printf("# 12 nozzles clogged: alarm after %.2f s, p max %.2f bar\n", detect_s(&r, AL_CLOG), r.p_max_bar);
    assert_true(detect_s(&r, AL_CLOG) <= 4.0);
    assert_true(detect_s(&r, AL_LEAK) > 100);
    assert_true(r.p_max_bar < RELIEF_BAR);
    run_init(&r, 80);
    run_to(&r, 88);
    assert_false(active(AL_CLOG));
}

/* 30 of 36 nozzles clogged: the meter still pulses (at what the 6 open nozzles pass), it reads
 * far under the nozzle model at that pressure. That is a CLOG (within 4 s), never a lost meter:
 * the loop, the LCD and the log go on with the meter's flow. */
static void test_faults_most_nozzles_clogged_is_a_clog_not_a_lost_meter(void **state)
{
    run_t r;
    (void)state;
    start("40 clog_nozzles 30", "", "pto_coupled = 0", 7);
    run_init(&r, 0);
    run_to(&r, 40);
    run_init(&r, 40);
    run_to(&r, 60);
    printf("# 30 nozzles clogged: CLOG after %.2f s, meter %.2f L/min, shown %.2f L/min\n", detect_s(&r, AL_CLOG),
           flow_lpm_x100() / 100.0, app_status.in.flow_lpm_x100 / 100.0);
    assert_true(detect_s(&r, AL_CLOG) <= 4.0);
    assert_true(detect_s(&r, AL_METER_LOST) > 100);
    assert_int_equal(app_status.in.flow_lpm_x100, flow_lpm_x100());
}

/* A leak of a tenth of the flow, and 3 of 36 nozzles clogged, on the nozzle model learnt from
 * the sprayer: each seen within 5 s (2.3 s and 2.0 s measured: the rule's 2 s). (7 km/h, 150 L/ha: 31.5 L/min at about 1.95 bar, where a
 * leak of 3.9 L/min at 3 bar passes 3.1 L/min.) */
static void test_faults_small_leak_and_few_clogs_are_seen(void **state)
{
    run_t r;
    (void)state;
    start("40 leak_lpm 3.9\n80 leak_lpm 0", "", "pto_coupled = 0", 7);
    run_init(&r, 0);
    run_to(&r, 40);
    assert_false(active(AL_LEAK));
    run_init(&r, 40);
    run_to(&r, 80);
    printf("# leak 10 %% of the flow: LEAK after %.2f s\n", detect_s(&r, AL_LEAK));
    assert_true(detect_s(&r, AL_LEAK) <= 5.0);   /* 2.31 s measured, the rule's 2 s and a period */
    assert_true(detect_s(&r, AL_CLOG) > 100);
    start("40 clog_nozzles 3\n80 clog_nozzles 0", "", "pto_coupled = 0", 7);
    run_init(&r, 0);
    run_to(&r, 40);
    assert_false(active(AL_CLOG));
    run_init(&r, 40);
    run_to(&r, 80);
    printf("# 3 of 36 nozzles clogged: CLOG after %.2f s\n", detect_s(&r, AL_CLOG));
    assert_true(detect_s(&r, AL_CLOG) <= 5.0);   /* 2.01 s */
    assert_true(detect_s(&r, AL_LEAK) > 100);
}

/* Six nozzles of 36 left open at 5.1 L/min (128 L/ha, 8 km/h, check valves at 0.6 bar), the
 * nozzle model learnt over the first minute's speeds. Below its range the turbine reads about 8 %
 * low (docs/SCENARIOS.md), which is 17 % of the pressure above the check valves: CLOG was raised
 * at 83-91 s on seeds 1-8, with the pump on the wheels or at a fixed PTO. Below 7.5 L/min the
 * model is judged on P_PDEV, not half of it: nothing is raised, and one of the six clogged
 * (70 % over the model's pressure) is still seen, once the loop has the flow back (ffmap: 2.6-2.9
 * s, asked within 5; pid, whose gains were set for the whole boom, 15.0-15.3 s since
 * the speed is tracked from the start (12 s before: a nozzle model learnt over other speeds in
 * the first minute), asked within 20). */
static void test_faults_few_nozzles_below_the_meters_range_are_no_clog(void **state)
{
    const char *drive = "0 0\n2 0\n8 9\n30 9\n35 5\n55 5\n60 8\n400 8";
    const char *plants[2] = {"pto_coupled = 0\ncheck_valve_bar = 0.6", "pto_coupled = 1\ncheck_valve_bar = 0.6"};
    run_t r;
    (void)state;
    for (int i = 0; i < 2; i++) {
        start_drive("80 sections_open 6\n130 clog_nozzles 1", "rate_l_ha = 128", plants[i], drive);
        run_init(&r, 0);
        run_to(&r, 130);
        for (int b = 0; b < AL_COUNT; b++)
            assert_true(detect_s(&r, b) > 1000);
        run_init(&r, 130);
        run_to(&r, 150);
        printf("# 6 of 36 nozzles open at 5.1 L/min, %s: nothing raised; one of them clogged: CLOG after "
               "%.2f s\n", i ? "coupled" : "fixed PTO", detect_s(&r, AL_CLOG));
        assert_true(detect_s(&r, AL_CLOG) <= (strcmp(fault_ctl, "ffmap") ? 20.0 : 5.0));
    }
}

/* Nozzles worn 15 % and check valves opening at 1.0 bar: learnt, not alarmed, over a drive
 * through the working speeds (the wear is a caused NOZZLE_WEAR notice where it is seen: learnt at
 * one speed, the told check valves hide part of it). */
static void test_faults_worn_nozzles_and_stiff_check_valves_raise_nothing(void **state)
{
    run_t r;
    (void)state;
    start_drive("", "", "pto_coupled = 0\nnozzle_wear_pct = 15\ncheck_valve_bar = 1.0",
                "0 0\n5 6\n60 6\n62 9\n120 9\n122 4.5\n180 4.5\n182 8\n240 8");
    run_init(&r, 0);
    run_to(&r, 240);
    printf("# worn nozzles, stiff check valves: model learnt %d, NOZZLE_WEAR %s\n", diag_nozzle_learnt(),
           detect_s(&r, AL_NOZZLE_WEAR) > 1000 ? "not raised" : "raised");
    assert_true(diag_nozzle_learnt() > 0);
    for (int b = 0; b < AL_COUNT; b++)
        assert_true(b == AL_NOZZLE_WEAR || detect_s(&r, b) > 1000);
}

/* A family plant's scenario `text` run to `t_end` s: the nozzle model it learnt, and no alarm;
 * its nozzles worn by `wear_pct` over 10 % are a caused NOZZLE_WEAR notice, raised where the
 * model was learnt over the range (its check valves learnt: the wear then seen within a few %).
 * A MIN_FLOW warning may come: its field drive slows under the minimum-flow speed. */
static void run_plant_raising_nothing(const char *text, double t_end, const char *what, double wear_pct)
{
    run_t r;
    helper_sim_load(&sim, &sim_live, text, "test_faults");
    run_init(&r, 0);
    run_to(&r, t_end);
    printf("# %s: model learnt %d, LEAK %s, NOZZLE_WEAR %s (worn %.1f %%)\n", what, diag_nozzle_learnt(),
           detect_s(&r, AL_LEAK) > 1000 ? "not raised" : "raised",
           detect_s(&r, AL_NOZZLE_WEAR) > 1000 ? "not raised" : "raised", wear_pct);
    for (int b = 0; b < AL_COUNT; b++)
        if ((b != AL_NOZZLE_WEAR || wear_pct <= 10) && b != AL_MIN_FLOW)
            assert_true(detect_s(&r, b) > 1000);
    if (wear_pct >= 13 && diag_nozzle_learnt() == 2)
        assert_true(detect_s(&r, AL_NOZZLE_WEAR) < 1000);
}

/* Family plant 26 of SEED=23 (check valves at 0.64 bar, its meter 0.7 % fast, the pump on the
 * wheels), its field drive cut short: through the slow-down from 6.4 to 2.6 km/h the meter's
 * rotor lags the flow that the pressure follows at once, and the metered flow reads high for
 * the pressure. No leak is judged while the target moves by more than 1/128 a period: nothing
 * is raised (with this seed ffmap raised LEAK at 174 s before). */
static void test_faults_a_slow_down_is_no_leak(void **state)
{
    static char text[2048];
    (void)state;
    snprintf(text, sizeof text,
             "[run]\nduration_s = 190\nseed = 387231\n[config]\ncontroller = %s\nrate_l_ha = 146\n"
             "valve_travel_s = 2.2\n[plant]\nvalve_travel_s = 2.21\nvalve_stiction_duty = 0.235\n"
             "valve_running_duty = 0.183\nvalve_backlash = 0.0098\nvalve_motor_tau_s = 0.046\n"
             "pump_lpm_at_540 = 105.2\npump_pulsation_pct = 6.53\npto_coupled = 1\nmeter_k_ppl = 382.83\n"
             "meter_blade_jitter_pct = 1.19\nwheel_spacing_jitter_pct = 1.25\nwheel_slip_pct = 2.49\n"
             "speed_bounce_pct = 2.83\npressure_noise_lsb = 1.88\nnozzle_wear_pct = 3.65\n"
             "check_valve_bar = 0.638\nvalve_cv_open = 186.5\n[drive]\n0 0\n2 0\n8 9.6\n68 9.6\n"
             "73 2.1\n80 2.1\n86 8.9\n120 8.9\n125 2.6\n132 2.6\n138 6.4\n170 6.4\n175 2.6\n190 2.6\n",
             fault_ctl);
    run_plant_raising_nothing(text, 190, "a slow-down at 0.64 bar check valves", 3.65);
}

/* Check valves at 1.0 bar (told 0.3), the pump on the wheels, 114 L/ha: 7.5, then 5.1, then 4.1
 * km/h. The samples of the first spraying flows spread too little for a fitted line, and the
 * rated curve through their mean with the told check valves is wrong by (1.0 - 0.3 bar) x
 * (1 - x / xm) at another squared flow x: at 4.1 km/h, about 4/5 of their mean xm, by 0.15
 * bar at 1 bar, and CLOG was raised at 54-72 s (seeds 1-4). Judged finely only within 7/8 ..
 * 8/7 of the mean: nothing is raised. (Found on held-out plant 0 of SEED=439, check valves at
 * 0.77 bar, nozzles 13 % worn.) */
static void test_faults_stiff_check_valves_at_a_nearby_flow_raise_nothing(void **state)
{
    static char text[1024];
    (void)state;
    snprintf(text, sizeof text,
             "[run]\nduration_s = 90\nseed = 2\n[config]\ncontroller = %s\nrate_l_ha = 114\n[plant]\n"
             "pto_coupled = 1\ncheck_valve_bar = 1.0\n[drive]\n0 0\n2 0\n2 7.5\n12.3 7.5\n12.3 5.1\n"
             "32.1 5.1\n32.1 4.1\n90 4.1\n", fault_ctl);
    run_plant_raising_nothing(text, 90, "check valves at 1.0 bar, 5.1 then 4.1 km/h", 0);
}

/* Family plant 20 of SEED=173 (clean nozzles, check valves at 0.607 bar, a 1.67 s valve told
 * 4 s on a pump on the wheels): its first minute at 9.7 km/h gave flows that spread by a tenth
 * around one target, enough for DIAG_LEARN_SPREAD, and the least-squares line through them put
 * the check valves at 91 kPa (the meter's noise flattens a line fitted over so little spread);
 * at 20-27 L/min that model asked for more pressure than the line had, and ffmap raised LEAK at
 * 274.7 s. A line is fitted only once the flows' squares spread by a quarter of their mean:
 * nothing is raised. */
static void test_faults_a_model_fitted_over_one_speed_makes_no_leak(void **state)
{
    static char text[2048];
    (void)state;
    snprintf(text, sizeof text,
             "[run]\nduration_s = 442\nseed = 927665\n[config]\ncontroller = %s\nrate_l_ha = 147\n"
             "[plant]\nvalve_travel_s = 1.67\nvalve_stiction_duty = 0.274\nvalve_running_duty = 0.143\n"
             "valve_backlash = 0.0268\nvalve_motor_tau_s = 0.024\npump_lpm_at_540 = 137.5\n"
             "pump_pulsation_pct = 3.52\npto_coupled = 1\nmeter_k_ppl = 379.6\nmeter_blade_jitter_pct = 2.24\n"
             "wheel_spacing_jitter_pct = 3.0\nwheel_slip_pct = 2.47\nspeed_bounce_pct = 0.75\n"
             "pressure_noise_lsb = 1.94\nnozzle_wear_pct = 1.61\ncheck_valve_bar = 0.607\nvalve_cv_open = 315.8\n"
             "[drive]\n0 0\n2 0\n8 9.7\n70.02 9.7\n75.02 0\n80.19 0\n86.19 8.8\n179.21 8.8\n184.21 0\n"
             "187.48 0\n193.48 6\n330.25 6\n335.25 2.2\n342.52 2.2\n348.52 9\n432.87 9\n437.87 0\n442 0\n",
             fault_ctl);
    run_plant_raising_nothing(text, 442, "a model fitted over one speed", 1.61);
}

/* Family plant 32 of SEED=47, told the truth: a 2.0 s valve breaking away at 0.341 (Min duty
 * says 0.2) on a fixed PTO. The start's stick-slip swings cut the loop gain to a tenth; the
 * drives it then asks for sit near the break-away, the valve creeps and the flow stays a
 * sixth under the target through a speed-up: OFF_RATE at 26.7 s before, the gain's raise held
 * for the start's first 10 s. A gain the start cut now comes back at once: nothing is raised.
 * That is ffmap's rule: pid learns no gain, and on this valve its flow sits 10-12 % over the
 * target for seconds after the slow-down at 29.7 s (OFF_RATE at 35.8 s since the speed is
 * tracked from the start, a true one; 10.5 % and none before): with pid only OFF_RATE may be
 * raised. */
static void test_faults_a_stiff_fast_valve_told_the_truth_keeps_the_rate(void **state)
{
    static char text[2048];
    (void)state;

    snprintf(text, sizeof text,
             "[run]\nduration_s = 45\nseed = 92869\n[config]\ncontroller = %s\nrate_l_ha = 107\n"
             "valve_travel_s = 2.0\n[plant]\nvalve_travel_s = 2.0\nvalve_stiction_duty = 0.341\n"
             "valve_running_duty = 0.258\nvalve_backlash = 0.0076\nvalve_motor_tau_s = 0.077\n"
             "pump_lpm_at_540 = 130.0\npump_pulsation_pct = 3.28\npto_coupled = 0\npto_rpm = 485\n"
             "meter_k_ppl = 377.21\nmeter_blade_jitter_pct = 2.76\nwheel_spacing_jitter_pct = 3.65\n"
             "wheel_slip_pct = 2.97\nspeed_bounce_pct = 2.1\npressure_noise_lsb = 2.31\nnozzle_wear_pct = 14.34\n"
             "check_valve_bar = 0.524\nvalve_cv_open = 225.0\n[drive]\n0 0\n2 0\n2 5.6\n21.5 5.6\n21.5 9.7\n"
             "29.7 9.7\n29.7 6.3\n41.2 6.3\n41.2 10\n45 10\n",
             fault_ctl);
    if (!strcmp(fault_ctl, "ffmap")) {
        run_plant_raising_nothing(text, 45, "a stiff fast valve told the truth", 14.34);
        return;
    }
    run_t r;
    helper_sim_load(&sim, &sim_live, text, "test_faults");
    run_init(&r, 0);
    run_to(&r, 45);
    printf("# a stiff fast valve told the truth, pid: OFF_RATE %s\n",
           detect_s(&r, AL_OFFRATE) > 1000 ? "not raised" : "raised");
    for (int b = 0; b < AL_COUNT; b++)
        assert_true(b == AL_OFFRATE || detect_s(&r, b) > 1000);
}

/* A wheel sensor that bounces now and then (3 % of its pulses, within the plant family) is
 * dropped at the input and raises nothing over 200 s; one that bounces on 30 % of its pulses
 * raises WHEEL_NOISE within 15 s while spraying and the measured speed go on (within 1 % of
 * the truth); the alarm clears within 70 s of the bounce stopping. */
static void test_faults_wheel_bounce_is_dropped_and_persistent_noise_alarms(void **state)
{
    run_t r;
    sim_row_t row;
    double err = 0;
    int n = 0;
    (void)state;
    start("200 speed_bounce_pct 30\n260 speed_bounce_pct 0", "", "pto_coupled = 0\nspeed_bounce_pct = 3", 8);
    run_init(&r, 0);
    run_to(&r, 200);
    assert_true(detect_s(&r, AL_WHEEL_NOISE) > 1000);
    run_init(&r, 200);
    while (sim_time_s(&sim) < 255 - 1e-9) {
        run_to(&r, sim_time_s(&sim) + 0.1);
        sim_row(&sim, &row);
        if (row.t_s >= 205) {
            err += (row.v_meas_kmh - row.v_true_kmh) / row.v_true_kmh;
            n++;
        }
    }
    printf("# wheel bounce 30 %%: WHEEL_NOISE after %.1f s, speed %+.2f %% of the truth\n",
           detect_s(&r, AL_WHEEL_NOISE), 100 * err / n);
    assert_true(detect_s(&r, AL_WHEEL_NOISE) <= 15);
    assert_true(fabs(err / n) <= 0.01);
    assert_true(app_status.spraying);
    run_to(&r, 330);                            /* the score (at most 255) runs down a pulse at a time */
    assert_false(active(AL_WHEEL_NOISE));
}

/* tank below its minimum (a sudden drop from 980 L to 25 L: the level filter's 0.4 s time
 * constant takes 2.1 s to come down, then 1 s of persistence) stops spraying within 3.5 s;
 * an empty tank sprays nothing and the dry pump has its alarm within 2.5 s; a refill
 * resumes spraying */
static void test_faults_empty_tank_sprays_nothing_and_the_dry_pump_alarms(void **state)
{
    run_t r;
    (void)state;
    start("40 tank_l 25\n60 tank_l 0\n80 tank_l 600", "tank_min_l = 30", "pto_coupled = 0", 7);
    run_init(&r, 0);
    run_to(&r, 40);
    assert_true(app_status.spraying);
    run_init(&r, 40);
    run_to(&r, 60);
    printf("# tank 25 L (< 30 L): alarm after %.2f s, boom open %.2f s more\n",
           detect_s(&r, AL_TANK_LOW), r.spray_on_s);
    assert_true(detect_s(&r, AL_TANK_LOW) <= 3.5);
    assert_true(r.spray_on_s <= 3.5);
    assert_false(hal_host_io.spray_on);
    run_init(&r, 60);
    run_to(&r, 80);
    printf("# tank empty: pump-dry alarm after %.2f s, %.3f L out of the nozzles, p max %.2f bar\n",
           detect_s(&r, AL_PUMP_DRY), r.boom_after_l, r.p_max_bar);
    assert_true(detect_s(&r, AL_PUMP_DRY) <= 2.5);
    assert_true(r.boom_after_l < 0.01);
    assert_true(r.spray_on_s == 0);
    assert_true(r.p_max_bar < RELIEF_BAR);
    assert_true(active(AL_PUMP_DRY) && active(AL_TANK_LOW));
    run_init(&r, 80);
    run_to(&r, 85);
    assert_true(app_status.spraying);
    assert_false(active(AL_TANK_LOW) || active(AL_PUMP_DRY));
    double e = follow_error_pct(20);
    printf("# refilled: mean flow error %.2f %% over 20 s\n", e);
    assert_true(e <= 0.6);                      /* 0.09 % pid, 0.26 % ffmap */
}

/* the valve stuck at 11 km/h, then a third of the boom shut: the line pressure rises past
 * P_P_MAX (4.8 bar) to the relief valve: OVERPRESSURE within 0.5 s of the crossing; freed,
 * the valve is opened and the alarm clears */
static void test_faults_over_pressure_with_a_stuck_valve(void **state)
{
    run_t r;
    sim_row_t row;
    (void)state;
    start("40 valve_stuck\n41 sections_open 24\n60 valve_free", "", "pto_coupled = 0", 11);
    run_init(&r, 0);
    run_to(&r, 41);
    double t_cross = -1;
    run_init(&r, 41);
    while (sim_time_s(&sim) < 60 - 1e-9) {
        run_to(&r, sim_time_s(&sim) + 0.01);
        sim_row(&sim, &row);
        if (t_cross < 0 && row.p_meas_kpa > 480)
            t_cross = row.t_s;
    }
    printf("# stuck valve, 24 nozzles: pressure above 4.8 bar at %.2f s, OVERPRESSURE at %.2f s, "
           "p max %.2f bar (the relief valve's)\n", t_cross, r.first[AL_OVERPRESSURE], r.p_max_bar);
    assert_true(t_cross > 0);
    assert_true(r.first[AL_OVERPRESSURE] >= 0 && r.first[AL_OVERPRESSURE] - t_cross <= 0.5);
    run_init(&r, 60);
    run_to(&r, 75);
    printf("# valve freed: p max %.2f bar after 60 s\n", r.p_max_bar);
    assert_false(active(AL_OVERPRESSURE));
    run_init(&r, 75);
    run_to(&r, 80);
    assert_true(r.p_max_bar < 4.8);
    double e = follow_error_pct(20);
    printf("# valve freed: mean flow error %.2f %% over 20 s\n", e);
    assert_true(e <= 1.0);                      /* 0.06 % pid, 0.42 % ffmap */
}

/* the valve stuck, then the tractor slows from 11 to 6 km/h: the flow stays, the target
 * falls; OFF_RATE P_OFFRATE_S (5 s) after the error passes P_OFFRATE (10 %), -0.2 .. +0.1 s */
static void test_faults_off_rate_when_the_flow_cannot_follow(void **state)
{
    run_t r;
    sim_row_t row;
    (void)state;
    start_drive("40 valve_stuck\n70 valve_free", "", "pto_coupled = 0", "0 0\n5 11\n45 11\n50 6\n400 6");
    run_init(&r, 0);
    run_to(&r, 40);
    assert_false(active(AL_OFFRATE));
    double t_cross = -1;
    run_init(&r, 40);
    while (sim_time_s(&sim) < 70 - 1e-9) {
        run_to(&r, sim_time_s(&sim) + 0.1);
        sim_row(&sim, &row);
        if (t_cross < 0 && fabs(row.flow_meas_lpm - row.target_lpm) > 0.1 * row.target_lpm)
            t_cross = row.t_s;
    }
    printf("# stuck valve, 11 -> 6 km/h: error above 10 %% at %.2f s, OFF_RATE at %.2f s\n", t_cross,
           r.first[AL_OFFRATE]);
    assert_true(t_cross > 0);
    /* Off-rate t 5 s: 50 periods from the firmware's first period off, which the trace's 10 ms
     * crossing leads by up to a period (4.91 s measured with both controllers) */
    assert_true(r.first[AL_OFFRATE] - t_cross >= 4.8 && r.first[AL_OFFRATE] - t_cross <= 5.1);
    run_init(&r, 70);
    run_to(&r, 100);
    printf("# valve freed at 70 s: OFF_RATE %s at 100 s\n", active(AL_OFFRATE) ? "still on" : "cleared");
    assert_false(active(AL_OFFRATE));
}

/* speed and flow against the plant's truth: 4, 7, 11 km/h; 12, 30, 50 L/min */
static void test_faults_measurement_error_against_the_truth(void **state)
{
    static const double kmh[] = {4, 7, 11};
    static const double lpm[] = {12, 30, 50};
    sim_row_t row;
    (void)state;
    for (int k = 0; k < 3; k++) {
        start("", "", "pto_coupled = 0", kmh[k]);
        double se = 0, emax = 0;
        int n = 0;
        while (sim_time_s(&sim) < 60) {
            for (int i = 0; i < 100; i++)
                sim_step(&sim);
            sim_row(&sim, &row);
            if (row.t_s < 40)               /* the wheel's spacing error learnt: 9 turns at 4 km/h */
                continue;
            double e = row.v_meas_kmh - row.v_true_kmh;
            se += e;
            if (fabs(e) > emax)
                emax = fabs(e);
            n++;
        }
        printf("# speed %2.0f km/h: mean error %+.3f %%, worst %.3f %% (40-60 s, every 0.1 s)\n", kmh[k],
               100 * se / n / kmh[k], 100 * emax / kmh[k]);
        assert_true(emax / kmh[k] <= 0.005);
    }
    /* 100 L/ha with 36 nozzles: q = 3 v, given speeds 4, 10, 16.67 km/h */
    for (int k = 0; k < 3; k++) {
        char cfg[128];
        snprintf(cfg, sizeof cfg, "rate_l_ha = 100\ngiven_speed_kmh = %.1f", lpm[k] / 3.0);
        start("", cfg, "pto_coupled = 0", 0);
        double se = 0, emax = 0;
        int n = 0;
        while (sim_time_s(&sim) < 40) {
            for (int i = 0; i < 100; i++)
                sim_step(&sim);
            sim_row(&sim, &row);
            if (row.t_s < 20)
                continue;
            double e = (row.flow_meas_lpm - row.flow_true_lpm) / row.flow_true_lpm;
            se += e;
            if (fabs(e) > emax)
                emax = fabs(e);
            n++;
        }
        printf("# flow %2.0f L/min: mean error %+.3f %%, worst %.3f %% (20 s, every 0.1 s)\n",
               lpm[k], 100 * se / n, 100 * emax);
        assert_true(fabs(se / n) <= 0.01);
        assert_true(emax <= 0.03);
    }
}

/* the lifetime totals survive a power cut: the boom shutting at the stop saves them with the
 * parameters; a restart (totals zeroed, the EEPROM read) finds what was sprayed */
static void test_faults_lifetime_totals_are_saved_when_the_boom_shuts(void **state)
{
    run_t r;
    uint32_t ml, m2;
    (void)state;
    start_drive("", "", "pto_coupled = 0", "0 0\n5 7\n40 7\n41 0\n400 0");
    run_init(&r, 0);
    run_to(&r, 50);
    assert_false(app_status.spraying);
    ml = totals_get()->life_ml;
    m2 = totals_get()->life_m2;
    printf("# boom shut at the stop: %u ml over %u m^2 sprayed and saved\n", (unsigned)ml, (unsigned)m2);
    /* by hand from the drive: 0 -> 7 km/h over 5 s, 35 s at 7, to 0 in 1 s: 2.5 + 35 + 0.5 s at
     * 7 km/h, 73.9 m of an 18 m boom (36 nozzles at 50 cm): 1,330 m^2 (measured 1,352, the
     * wheel's count; within 3.5 %); at 150 L/ha 15 ml/m^2, and the minimum-flow rule's excess
     * in the ramps under 4 km/h (+6 % pid, +4.9 % ffmap measured): within 0 .. 12 % above */
    assert_true(fabs((double)m2 - 1330.0) <= 0.035 * 1330.0);
    assert_true(ml >= 15u * m2 && ml <= 15u * m2 * 112u / 100u);
    totals_init();
    assert_int_equal(totals_get()->life_ml, 0);
    assert_int_equal(store_load(), STORE_OK);
    assert_int_equal(totals_get()->life_ml, ml);
    assert_int_equal(totals_get()->life_m2, m2);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_faults_meter_lost_falls_back_to_pressure_and_holds_the_dose),
        cmocka_unit_test(test_faults_speed_sensor_lost_alarms_and_spraying_resumes),
        cmocka_unit_test(test_faults_pressure_sensor_open_is_a_fault_and_control_goes_on),
        cmocka_unit_test(test_faults_leak_after_the_meter_is_seen_in_the_pressure),
        cmocka_unit_test(test_faults_clogged_nozzles_raise_the_pressure_alarm),
        cmocka_unit_test(test_faults_most_nozzles_clogged_is_a_clog_not_a_lost_meter),
        cmocka_unit_test(test_faults_small_leak_and_few_clogs_are_seen),
        cmocka_unit_test(test_faults_few_nozzles_below_the_meters_range_are_no_clog),
        cmocka_unit_test(test_faults_worn_nozzles_and_stiff_check_valves_raise_nothing),
        cmocka_unit_test(test_faults_stiff_check_valves_at_a_nearby_flow_raise_nothing),
        cmocka_unit_test(test_faults_a_slow_down_is_no_leak),
        cmocka_unit_test(test_faults_a_model_fitted_over_one_speed_makes_no_leak),
        cmocka_unit_test(test_faults_a_stiff_fast_valve_told_the_truth_keeps_the_rate),
        cmocka_unit_test(test_faults_wheel_bounce_is_dropped_and_persistent_noise_alarms),
        cmocka_unit_test(test_faults_empty_tank_sprays_nothing_and_the_dry_pump_alarms),
        cmocka_unit_test(test_faults_over_pressure_with_a_stuck_valve),
        cmocka_unit_test(test_faults_off_rate_when_the_flow_cannot_follow),
        cmocka_unit_test(test_faults_measurement_error_against_the_truth),
        cmocka_unit_test(test_faults_lifetime_totals_are_saved_when_the_boom_shuts),
    };
    int failed = cmocka_run_group_tests_name("faults with pid", tests, NULL, teardown);
    /* the same faults with the controller the firmware ships with */
    static struct CMUnitTest best_tests[sizeof tests / sizeof tests[0]];
    static char names[sizeof tests / sizeof tests[0]][96];
    for (size_t i = 0; i < sizeof tests / sizeof tests[0]; i++) {
        best_tests[i] = tests[i];
        snprintf(names[i], sizeof names[i], "ffmap: %s", tests[i].name);
        best_tests[i].name = names[i];
    }
    fault_ctl = "ffmap";
    return failed + cmocka_run_group_tests_name("faults with ffmap", best_tests, NULL, teardown);
}

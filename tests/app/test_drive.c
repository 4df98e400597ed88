/* test_drive.c: drive.c and the boom's opening against the simulated sprayer: a shut boom holds the bypass at the spraying pressure, parks it open without a pressure to hold on, the restart from a hold, the power-up wait for the line under P max, the start-up closing's end, a halt with the pump on the wheels, a restart with most sections shut. */
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
#include "app.h"
#include "drive.h"
#include "diag.h"
#include "params.h"

static sim_t sim;
static int sim_live;

/* A fixed PTO and a 12 s valve the firmware believes 4 s (the slowest of the family, where a
 * restart from the open stop costs most) at 8 km/h; the operator shuts the boom from 60 to 70 s
 * (a headland, the tractor going on); events as given. */
static void start(const char *events)
{
    static char text[2048];
    snprintf(text, sizeof text,
             "[run]\nduration_s = 120\nseed = 5\n[config]\ncontroller = ffmap\n"
             "[plant]\npto_coupled = 0\nvalve_travel_s = 12\n"
             "[drive]\n0 0\n5 8\n120 8\n[events]\n%s60 sections_open 0\n70 sections_open 36\n", events);
    helper_sim_load(&sim, &sim_live, text, "test_drive");
}

static int teardown(void **state)
{
    (void)state;
    helper_sim_end(&sim, &sim_live);
    return 0;
}

typedef struct {
    double p_spray_bar;             /* mean pressure over the 5 s before the stop */
    double p_max_shut_bar;          /* highest pressure once the boom has been shut 3 s */
    double pos_max_shut;            /* the valve's furthest open while shut */
    double drive_shut_s;            /* the valve driven in the last 5 s of the stop */
    double back_s;                  /* boom open again until the flow stays within 5 % for 2 s */
} seen_t;

static seen_t run(void)
{
    seen_t s = {0, 0, 0, 0, -1};
    sim_row_t row;
    double n = 0, in_since = -1, open_at = -1;
    while (sim_time_s(&sim) < 115.0) {
        for (int i = 0; i < 10; i++)
            sim_step(&sim);
        sim_row(&sim, &row);
        if (row.t_s >= 55 && row.t_s < 60) {
            s.p_spray_bar += row.p_bar;
            n++;
        }
        if (row.t_s >= 63 && row.t_s < 70 && !row.spray_on) {
            s.p_max_shut_bar = fmax(s.p_max_shut_bar, row.p_bar);
            s.pos_max_shut = fmax(s.pos_max_shut, row.valve_pos);
        }
        if (row.t_s >= 65 && row.t_s < 70 && row.valve_drive != 0)
            s.drive_shut_s += 0.01;
        if (row.t_s >= 70 && row.spray_on && open_at < 0)
            open_at = row.t_s;
        if (open_at >= 0 && s.back_s < 0) {
            int inside = fabs(row.boom_lpm - row.target_lpm) <= 0.05 * row.target_lpm && row.target_lpm > 0;
            if (!inside)
                in_since = -1;
            else if (in_since < 0)
                in_since = row.t_s;
            if (in_since >= 0 && row.t_s - in_since >= 2.0)
                s.back_s = in_since - open_at;
        }
    }
    s.p_spray_bar /= n;
    return s;
}

/* The boom shut: the bypass opens only until the pressure is back at the spraying pressure
 * (within 1/16 + 5 kPa, and the sensor's noise) and rests there, short of its open stop;
 * spraying again, the boom starts near its target, from below, and is within 5 % of it in
 * about a second (from the open stop the 12 s valve needs several). */
static void test_drive_a_shut_boom_holds_the_spraying_pressure(void **state)
{
    (void)state;
    start("");
    seen_t s = run();
    printf("# held: spraying %.2f bar, shut at most %.2f bar, the valve at most %.2f open, driven %.2f s "
           "of the stop's last 5 s; back within 5 %% %.1f s after the boom opened\n",
           s.p_spray_bar, s.p_max_shut_bar, s.pos_max_shut, s.drive_shut_s, s.back_s);
    assert_true(s.p_max_shut_bar <= s.p_spray_bar * 1.15 + 0.15);
    assert_true(s.pos_max_shut < 0.9);
    assert_true(s.drive_shut_s == 0);
    assert_true(s.back_s >= 0 && s.back_s <= 2.0);
}

/* Without a pressure to hold on (the sensor open before the boom shuts) the shut boom parks the
 * bypass at its open stop, as at power-up: the pump circulates at the lowest pressure; the
 * restart then takes longer. */
static void test_drive_without_the_pressure_sensor_the_bypass_parks_open(void **state)
{
    (void)state;
    start("50 pressure_sensor_open\n");
    seen_t s = run();
    printf("# pressure sensor open: the shut boom's valve at most %.2f open, %.2f bar; back within 5 %% "
           "%.1f s after the boom opened\n", s.pos_max_shut, s.p_max_shut_bar, s.back_s);
    assert_true(s.pos_max_shut >= 0.9);
}

/* Power-up with the bypass closed and a fixed PTO: the line is at the relief valve until the slow
 * valve has opened enough. At 4 km/h (18 L/min) the nozzles would spray about three times the
 * target there: the boom stays shut meanwhile, although the tractor moves, and opens once the
 * pressure is under P max (then the rule is done: a later over-pressure does not hold the boom,
 * it opens the bypass and raises the alarm). At 8 km/h they would spray under twice the target,
 * no further from it than a shut boom is, once the tractor passes about 6 km/h: the boom opens
 * then, 2.4 s after it moves off, over P max, and the flow stays under twice the target while
 * the bypass opens (it waited 6.9 s before, until 4.74 bar). */
static void test_drive_the_boom_waits_for_the_line_under_p_max_at_power_up(void **state)
{
    (void)state;
    static char text[512];
    for (int kmh = 4; kmh <= 8; kmh += 4) {
        snprintf(text, sizeof text,
                 "[run]\nduration_s = 40\nseed = 5\n[config]\ncontroller = ffmap\n"
                 "[plant]\npto_coupled = 0\nvalve_travel_s = 12\nvalve_start_pos = 0\n"
                 "[drive]\n0 0\n1 0\n3 %d\n40 %d\n[events]\n", kmh, kmh);
        helper_sim_load(&sim, &sim_live, text, "test_drive");
        sim_row_t row;
        double p_open = -1, t_open = -1, t_moving = -1, over = 0;
        while (sim_time_s(&sim) < 30.0) {
            for (int i = 0; i < 10; i++)
                sim_step(&sim);
            sim_row(&sim, &row);
            if (row.v_meas_kmh > 0 && t_moving < 0)
                t_moving = row.t_s;
            if (row.spray_on && t_open < 0) {
                t_open = row.t_s;
                p_open = row.p_bar;
            }
            if (row.spray_on && row.target_lpm > 0)
                over = fmax(over, row.boom_lpm / row.target_lpm);
        }
        printf("# power-up, bypass closed, %d km/h: moving at %.1f s, the boom opened at %.1f s at "
               "%.2f bar (P max %.2f), the flow at most %.2f times the target\n", kmh, t_moving, t_open,
               p_open, param_v[P_P_MAX] / 100.0, over);
        if (kmh == 4) {
            assert_true(t_moving > 0 && t_open > t_moving + 1.0);
            assert_true(p_open <= param_v[P_P_MAX] / 100.0 + 0.1);
        } else {
            assert_true(t_moving > 0 && t_open < t_moving + 3.0);
            assert_true(p_open > param_v[P_P_MAX] / 100.0);
            assert_true(over < 2.05);
        }
        assert_true(app_status.spraying);
    }
}

/* The next 0.1 s row in which the boom sprays toward a target, before `until`; the first such
 * row's time into *open_at (while it is still negative). 0: none left. */
static int spraying_row(sim_row_t *row, double *open_at, double until)
{
    while (sim_time_s(&sim) < until) {
        for (int i = 0; i < 100; i++)
            sim_step(&sim);
        sim_row(&sim, row);
        if (!row->spray_on || row->target_lpm <= 0)
            continue;
        if (*open_at < 0)
            *open_at = row->t_s;
        return 1;
    }
    return 0;
}

/* The paper's start (coupled PTO, the default plant, the bypass parked open, the tractor from
 * 0 to 6 km/h): the start-up closing stops once the meter reads 7/8 of the target a period
 * ahead (the flow plus its last rise), so the flow the valve's coast and the line's filling
 * still bring does not carry it far past the target. Over seeds 1-8: the flow's largest excess
 * over the firmware's target and the time from the boom's opening until the flow stays within
 * 5 % of it for 2 s (start_s). Stopping at 7/8 of the target as measured gave 24.7 % and
 * 3.69 s. A new valve's loop starts at 3/4 of the gain (FFMAP_G_INIT): 3.45 s on these seeds, 3.11
 * at the full gain (the paper run's seeds 1-32: 3.28 s either way). */
static void test_drive_the_start_up_closing_stops_a_period_ahead(void **state)
{
    (void)state;
    static char text[512];
    double over_sum = 0, start_sum = 0, start_max = 0;
    for (int seed = 1; seed <= 8; seed++) {
        snprintf(text, sizeof text,
                 "[run]\nduration_s = 20\nseed = %d\n[config]\ncontroller = ffmap\nrate_l_ha = 150\n"
                 "min_flow_speed_kmh = 4\n[plant]\npto_coupled = 1\n[drive]\n0 0\n3 0\n8 6\n20 6\n", seed);
        helper_sim_load(&sim, &sim_live, text, "test_drive");
        sim_row_t row;
        double open_at = -1, in_since = -1, start_s = -1, over = 0;
        while (spraying_row(&row, &open_at, 19.9)) {
            if (row.t_s < open_at + 4.0)
                over = fmax(over, (row.boom_lpm - row.target_lpm) / row.target_lpm * 100.0);
            if (fabs(row.boom_lpm - row.target_lpm) > 0.05 * row.target_lpm)
                in_since = -1;
            else if (in_since < 0)
                in_since = row.t_s;
            if (start_s < 0 && in_since >= 0 && row.t_s - in_since >= 2.0)
                start_s = in_since - open_at;
        }
        assert_true(open_at > 0 && start_s >= 0);
        over_sum += over;
        start_sum += start_s;
        start_max = fmax(start_max, start_s);
    }
    printf("# the paper's start, seeds 1-8: the flow at most %.1f %% over the target on average, "
           "within 5 %% after %.2f s on average, %.1f s at most\n", over_sum / 8, start_sum / 8, start_max);
    assert_true(over_sum / 8 <= 20.0);
    assert_true(start_sum / 8 <= 3.5);
}

/* The clean start of issue 14: the operator switches the boom on while driving at a steady
 * 8 km/h, at power-up, so the bypass stands parked open (no spraying pressure to hold yet); the
 * paper's sprayer at 150 L/ha, the pump on the wheels and on a fixed PTO, seeds 1-8 of each. The
 * flow (sampled every 0.1 s) comes within 5 % of the target 1.2-1.9 s after the boom opens and
 * is at most 7.5 % over it in the first 10 s (the issue asks 5 % and no more than 10 % over). */
static void test_drive_a_start_at_a_steady_speed_is_clean(void **state)
{
    (void)state;
    static char text[512];
    double reach_max = 0, over_max = 0;
    for (int pto = 0; pto <= 1; pto++) {
        for (int seed = 1; seed <= 8; seed++) {
            snprintf(text, sizeof text,
                     "[run]\nduration_s = 20\nseed = %d\n[config]\ncontroller = ffmap\nrate_l_ha = 150\n"
                     "[plant]\npto_coupled = %d\n[drive]\n0 8\n20 8\n[events]\n0 sections_open 0\n"
                     "10 sections_open 36\n", seed, pto);
            helper_sim_load(&sim, &sim_live, text, "test_drive");
            sim_row_t row;
            double open_at = -1, reach = -1, over = 0;
            while (spraying_row(&row, &open_at, 19.9)) {
                if (reach < 0 && fabs(row.boom_lpm - row.target_lpm) <= 0.05 * row.target_lpm)
                    reach = row.t_s - open_at;
                over = fmax(over, (row.boom_lpm - row.target_lpm) / row.target_lpm * 100.0);
            }
            assert_true(open_at >= 10.0 && open_at < 10.2);   /* the boom opened when told */
            assert_true(reach > 0);
            reach_max = fmax(reach_max, reach);
            over_max = fmax(over_max, over);
        }
    }
    printf("# the boom on at 8 km/h from a parked-open bypass, seeds 1-8 of each pump: within 5 %% of "
           "the target after %.1f s at most, at most %.1f %% over it\n", reach_max, over_max);
    assert_true(reach_max <= 2.5);
    assert_true(over_max <= 10.0);
}

/* A pump on the wheels (coupled PTO) and an 11.3 s valve (plant 59 of `make family SEED=61`):
 * the tractor halts for 3 s with the boom spraying under the minimum-flow rule, then goes on
 * to 9.2 km/h. While it stands, the pump gives nothing and the meter reads nothing: closing
 * the bypass makes no flow, so the loop does not (drive_starved); at the restart the pump finds
 * the bypass where it sprayed. The loop that closed it (here from 0.75 to 0.19) put the line at
 * the relief valve as the tractor went on (5.07 bar; on the family's plant OVERPRESSURE, then
 * OFF_RATE while the slow valve reopened). */
static void test_drive_a_halt_with_the_pump_on_the_wheels_keeps_the_bypass(void **state)
{
    (void)state;
    static char text[512];
    snprintf(text, sizeof text,
             "[run]\nduration_s = 60\nseed = 3\n[config]\ncontroller = ffmap\nrate_l_ha = 105\n"
             "valve_travel_s = 11.3\n[plant]\npto_coupled = 1\nvalve_travel_s = 11.31\n"
             "valve_backlash = 0.0383\nvalve_motor_tau_s = 0.127\n"
             "[drive]\n0 0\n2 0\n8 6\n30 6\n35 0\n38 0\n44 9.2\n60 9.2\n");
    helper_sim_load(&sim, &sim_live, text, "test_drive");
    sim_row_t row;
    double p_max = 0, pos_sprayed = -1, pos_min_stop = 1;
    unsigned alarms = 0;
    while (sim_time_s(&sim) < 59.9) {
        for (int i = 0; i < 100; i++)
            sim_step(&sim);
        sim_row(&sim, &row);
        alarms |= row.alarms;
        if (row.t_s >= 29.0 && row.t_s < 29.1)
            pos_sprayed = row.valve_pos;
        if (row.t_s >= 30.0 && row.t_s < 40.0)
            pos_min_stop = fmin(pos_min_stop, row.valve_pos);
        if (row.t_s >= 38.0)
            p_max = fmax(p_max, row.p_bar);
    }
    printf("# a halt, pump on the wheels: the bypass at %.2f spraying, at least %.2f through the halt; "
           "after it at most %.2f bar (P max %.2f), alarms 0x%04x\n",
           pos_sprayed, pos_min_stop, p_max, param_v[P_P_MAX] / 100.0, alarms);
    assert_true(pos_min_stop >= pos_sprayed - 0.25);
    assert_true(p_max < param_v[P_P_MAX] / 100.0);
    /* no alarm; the minimum-flow warning, as the boom sprays under the rule's speed for over 3 s */
    assert_true((alarms & ~(unsigned)DIAG_QUIET_BITS) == 0);
    assert_true(alarms & (1u << AL_MIN_FLOW));
}

/* Plant 17 of `make family SEED=5 KIND=field EVENTS=1` (a 3.2 s stiff valve told 4 s, the pump on
 * the wheels): o of the 36 nozzles open from 20 s, the tractor halts at 64 s and goes on to
 * 8.8 km/h. The mean of abs(metered - target) / target over the restart (66-80 s). */
static double restart_error(int open)
{
    static char text[1024];
    snprintf(text, sizeof text,
             "[run]\nduration_s = 80\nseed = 1\n[config]\ncontroller = ffmap\nrate_l_ha = 123\n"
             "[plant]\nvalve_travel_s = 3.21\nvalve_stiction_duty = 0.193\nvalve_running_duty = 0.141\n"
             "valve_backlash = 0.0124\npto_coupled = 1\n"
             "[drive]\n0 0\n5 8\n60 8\n64 0\n66 0\n72 8.8\n80 8.8\n[events]\n20 sections_open %d\n", open);
    helper_sim_load(&sim, &sim_live, text, "test_drive");
    sim_row_t row;
    double sum = 0, n = 0;
    while (sim_time_s(&sim) < 79.95) {
        for (int i = 0; i < 100; i++)
            sim_step(&sim);
        sim_row(&sim, &row);
        if (row.t_s >= 66.0 && row.spray_on && row.target_lpm > 0) {
            sum += fabs(row.flow_meas_lpm - row.target_lpm) / row.target_lpm;
            n++;
        }
    }
    return n > 0 ? 100.0 * sum / n : 1e9;
}

/* With o of n nozzles open the boom's flow answers the bypass about (n / o + 1) / 2 times less
 * than the whole boom's (ffmap.c ffmap_gain_at_p): the loop's gain follows, so a restart with six of
 * 36 nozzles open comes back to the target nearly as the whole boom does (before: 1.6 times the
 * whole boom's error; OFF_RATE on the family's plant). */
static void test_drive_few_nozzles_open_restart_as_the_whole_boom(void **state)
{
    (void)state;
    double whole = restart_error(36), six = restart_error(6), twelve = restart_error(12);
    printf("# a restart, mean abs error against the target: whole boom %.1f %%, 12 nozzles %.1f %%, "
           "6 nozzles %.1f %%\n", whole, twelve, six);
    assert_true(six <= 1.45 * whole);
    assert_true(twelve <= 1.25 * whole);
}

/* A fast valve near P max: the scenario `text` run for 30 s; the highest pressure after 5 s,
 * the largest closing drive (the plant's sign: closing < 0) after 8 s while the line is above
 * 3.8 bar, and the alarms raised. */
typedef struct {
    double p_max_bar, close_max;
    unsigned alarms;
} near_p_t;

static near_p_t run_near_p_max(const char *text)
{
    near_p_t n = {0, 0, 0};
    sim_row_t row;
    helper_sim_load(&sim, &sim_live, text, "test_drive");
    while (sim_time_s(&sim) < 29.9) {
        for (int i = 0; i < 100; i++)
            sim_step(&sim);
        sim_row(&sim, &row);
        n.alarms |= row.alarms;
        if (row.t_s >= 5.0)
            n.p_max_bar = fmax(n.p_max_bar, row.p_bar);
        if (row.t_s >= 8.0 && row.p_bar > 3.8)
            n.close_max = fmax(n.close_max, -row.valve_drive);
    }
    return n;
}

/* Family plant 72 of SEED=78: a 2.01 s valve told 4 s with a slow motor (0.14 s) and 3 % of
 * backlash, a fixed PTO, 141 L/ha at 10.9 km/h: the target needs 4.3 bar of the 4.8 allowed.
 * The loop turned once the meter showed the target, and the motor's coast, the backlash and the
 * meter's lag carried the pressure to 5.0 bar: OVERPRESSURE at 10.9 s. The pressure shows the
 * rise at once: no closing while 12 periods more of it would pass P max (drive_overp_soon), and
 * the pressure stays under P max with no alarm. */
static void test_drive_a_fast_valve_near_p_max_stops_closing_ahead_of_it(void **state)
{
    (void)state;
    static char text[1024];
    snprintf(text, sizeof text,
             "[run]\nduration_s = 30\nseed = 96914\n[config]\ncontroller = ffmap\nrate_l_ha = 141\n"
             "[plant]\nvalve_travel_s = 2.01\nvalve_stiction_duty = 0.112\nvalve_running_duty = 0.056\n"
             "valve_backlash = 0.0302\nvalve_motor_tau_s = 0.14\npump_lpm_at_540 = 115.1\n"
             "pump_pulsation_pct = 7.29\npto_coupled = 0\npto_rpm = 486\nmeter_k_ppl = 376.49\n"
             "meter_blade_jitter_pct = 0.15\nwheel_spacing_jitter_pct = 1.8\nwheel_slip_pct = 2.82\n"
             "speed_bounce_pct = 1.35\npressure_noise_lsb = 0.9\nnozzle_wear_pct = 4.04\n"
             "check_valve_bar = 0.458\nvalve_cv_open = 183.4\n"
             "[drive]\n0 0\n2 0\n2 10.9\n12.7 10.9\n12.7 6.2\n30 6.2\n");
    near_p_t n = run_near_p_max(text);
    printf("# a fast valve near P max: at most %.2f bar (P max %.2f), alarms 0x%04x\n", n.p_max_bar,
           param_v[P_P_MAX] / 100.0, n.alarms);
    assert_true(n.p_max_bar < param_v[P_P_MAX] / 100.0);
    assert_true(n.alarms == 0);
}

/* Family plant 35 of SEED=28: a 1.91 s valve told 4 s with a motor that coasts 0.15 s and 3.3 %
 * of backlash, a fixed PTO, 146 L/ha at 10.7 km/h: the target needs 4.5 bar of the 4.8 allowed.
 * Waking from a rest, the loop's reversal and the drives after it closed the valve by 4 % of
 * its stroke in 0.4 s, and the coast took the pressure from 4.1 to 4.9 bar: OVERPRESSURE at
 * 14.4 s, although the rule against a rise toward P max had stopped the closing. Above 3.6 bar a
 * closing drive is now at most twice Min duty: the pressure touches 4.82 bar for a moment, and no
 * alarm. */
static void test_drive_near_p_max_a_closing_drive_is_held_to_twice_min_duty(void **state)
{
    (void)state;
    static char text[1024];
    snprintf(text, sizeof text,
             "[run]\nduration_s = 30\nseed = 711347\n[config]\ncontroller = ffmap\nrate_l_ha = 146\n"
             "[plant]\nvalve_travel_s = 1.91\nvalve_stiction_duty = 0.215\nvalve_running_duty = 0.133\n"
             "valve_backlash = 0.0333\nvalve_motor_tau_s = 0.15\npump_lpm_at_540 = 113.6\n"
             "pump_pulsation_pct = 8.86\npto_coupled = 0\npto_rpm = 538\nmeter_k_ppl = 378.56\n"
             "meter_blade_jitter_pct = 2.05\nwheel_spacing_jitter_pct = 1.04\nwheel_slip_pct = 1.75\n"
             "speed_bounce_pct = 2.23\npressure_noise_lsb = 1.52\nnozzle_wear_pct = 0.07\n"
             "check_valve_bar = 0.596\nvalve_cv_open = 280.5\n"
             "[drive]\n0 0\n2 0\n2 10.7\n21.5 10.7\n21.5 7.3\n30 7.3\n");
    near_p_t n = run_near_p_max(text);
    printf("# near P max: at most %.2f bar (P max %.2f), closing drive above 3.8 bar at most %.2f, "
           "alarms 0x%04x\n", n.p_max_bar, param_v[P_P_MAX] / 100.0, n.close_max, n.alarms);
    assert_true(n.close_max <= 2 * param_v[P_VALVE_BRK] / 100.0 + 0.01);
    assert_true(n.alarms == 0);
}

/* The boom shut during the start-up closing (the paper's start with the pump on the wheels, the
 * sections off once the meter reads 5 L/min, the line under P start): nothing was sprayed at a
 * pressure worth holding, so the bypass parks open again, as at power-up. The flow the closing
 * keeps in p_hold's bytes is not a pressure: taken for one, it held the bypass 0.68 open at
 * 2.94 bar. */
static void test_drive_a_boom_shut_while_priming_parks_the_bypass_open(void **state)
{
    (void)state;
    static char text[512];
    snprintf(text, sizeof text,
             "[run]\nduration_s = 30\nseed = 5\n[config]\ncontroller = ffmap\nrate_l_ha = 150\n"
             "[plant]\npto_coupled = 1\n[drive]\n0 0\n3 0\n8 6\n30 6\n");
    helper_sim_load(&sim, &sim_live, text, "test_drive");
    sim_row_t row;
    double t_open = -1, t_shut = -1, pos_end = 0, p_end = 0;
    while (sim_time_s(&sim) < 15.0) {
        for (int i = 0; i < 10; i++)
            sim_step(&sim);
        sim_row(&sim, &row);
        if (row.spray_on && t_open < 0)
            t_open = row.t_s;
        if (t_open > 0 && t_shut < 0 && row.flow_meas_lpm > 5.0 && drive_priming()) {
            t_shut = row.t_s;
            assert_int_equal(sim_event_name(&sim, "sections_open", 0), 0);
        }
        if (row.t_s >= 14.9 && row.t_s < 15.0) {
            pos_end = row.valve_pos;
            p_end = row.p_bar;
        }
    }
    printf("# shut while priming: opened at %.2f s, shut at %.2f s; at 15 s the bypass %.2f open, "
           "%.2f bar\n", t_open, t_shut, pos_end, p_end);
    assert_true(t_shut > 0);
    assert_true(pos_end >= 0.9);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_teardown(test_drive_a_shut_boom_holds_the_spraying_pressure, teardown),
        cmocka_unit_test_teardown(test_drive_without_the_pressure_sensor_the_bypass_parks_open, teardown),
        cmocka_unit_test_teardown(test_drive_the_boom_waits_for_the_line_under_p_max_at_power_up, teardown),
        cmocka_unit_test_teardown(test_drive_the_start_up_closing_stops_a_period_ahead, teardown),
        cmocka_unit_test_teardown(test_drive_a_start_at_a_steady_speed_is_clean, teardown),
        cmocka_unit_test_teardown(test_drive_a_halt_with_the_pump_on_the_wheels_keeps_the_bypass, teardown),
        cmocka_unit_test_teardown(test_drive_a_fast_valve_near_p_max_stops_closing_ahead_of_it, teardown),
        cmocka_unit_test_teardown(test_drive_near_p_max_a_closing_drive_is_held_to_twice_min_duty, teardown),
        cmocka_unit_test_teardown(test_drive_a_boom_shut_while_priming_parks_the_bypass_open, teardown),
        cmocka_unit_test_teardown(test_drive_few_nozzles_open_restart_as_the_whole_boom, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

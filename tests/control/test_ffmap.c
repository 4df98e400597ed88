/* test_ffmap.c: the project's own controller (ffmap, `best`) beyond its twin: the valve estimate follows what the valve really got, end stops calibrate it and over-pressure does not, and the feed-forward's gates. */
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
#include "params.h"
#include "sim.h"

static ctl_in_t mk(int target, int flow, uint8_t limit)
{
    ctl_in_t in;
    memset(&in, 0, sizeof in);
    in.target_lpm_x100 = (int16_t)target;
    in.flow_lpm_x100 = (int16_t)flow;
    in.speed_kmh_x100 = 700;
    in.pressure_kpa = 250;
    in.valve_limit = limit;
    return in;
}

static int setup(void **state)
{
    (void)state;
    params_defaults();
    ctl_select(CTL_BEST);
    ctl_reset(0);
    return 0;
}

/* Over-pressure (CTL_NO_CLOSE) refuses closing like a closed stop, but the valve is not at the
 * stop: the estimate is not moved to "closed" (it was, when over-pressure was reported as
 * CTL_AT_CLOSED, and the valve opening under the relief drive then went unseen). */
static void test_ffmap_over_pressure_is_not_a_closed_stop(void **state)
{
    (void)state;
    ctl_in_t in = mk(3000, 3000, 0);
    for (int k = 0; k < 5; k++)
        ctl_applied(ctl_step(&in), 0);
    int16_t p0 = ctl_st.fm.p_hat, off0 = ctl_st.fm.off;
    in = mk(4000, 2000, CTL_NO_CLOSE);               /* wants more flow, closing refused */
    for (int k = 0; k < 20; k++) {
        q15_t d = ctl_step(&in);
        assert_true(d <= 0);                          /* never closes */
        assert_true(ctl_st.fm.p_ref <= ctl_st.fm.p_hat);
        ctl_applied(d, 0);
    }
    assert_int_equal(ctl_st.fm.p_hat, p0);            /* nothing moved it: no calibration */
    assert_int_equal(ctl_st.fm.off, off0);
    /* a real closed stop does calibrate: the estimate goes to "closed", the map's frame with it */
    in = mk(4000, 2000, CTL_AT_CLOSED);
    ctl_applied(ctl_step(&in), CTL_AT_CLOSED);
    assert_int_equal(ctl_st.fm.p_hat, FM_AT_CLOSED);
    assert_int_equal(ctl_st.fm.off, off0 + (FM_AT_CLOSED - p0));
}

/* The estimate integrates what the valve got (ctl_applied), not what the controller asked:
 * the application overrides the drive on over-pressure, priming, parking, jogging. Without
 * the call the controller assumes its own drive was applied. */
static void test_ffmap_estimate_follows_the_applied_drive(void **state)
{
    (void)state;
    ctl_in_t in = mk(3000, 3000, 0);
    ctl_applied(ctl_step(&in), 0);
    int16_t p0 = ctl_st.fm.p_hat;
    /* 10 periods of full opening drive the controller never asked for: 10/40 of a stroke
     * (less the 2 % backlash if the last motion was the other way) */
    for (int k = 0; k < 10; k++) {
        ctl_step(&in);
        ctl_applied(-32767, 0);
    }
    int moved = p0 - ctl_st.fm.p_hat;
    int travel = (int)param_v[P_VALVE_TRAVEL];
    print_message("ffmap: 10 periods of full opening moved the estimate %d LSB (expected %d less backlash)\n", moved,
                  10 * 32768 / travel);
    assert_true(moved <= 10 * 32768 / travel + 10);
    assert_true(moved >= 10 * 32768 / travel - (int)FM_BACKLASH - 10);
    /* below the break-away duty the valve does not move */
    p0 = ctl_st.fm.p_hat;
    ctl_step(&in);
    ctl_applied(CTL_STICTION - 1, 0);
    assert_int_equal(ctl_st.fm.p_hat, p0);
    /* no ctl_applied: the next step accounts the drive it sent */
    in = mk(5000, 3000, 0);
    q15_t d = ctl_step(&in);
    assert_true(d >= CTL_STICTION);
    p0 = ctl_st.fm.p_hat;
    in = mk(5000, 3000, 0);
    ctl_step(&in);
    assert_true(ctl_st.fm.p_hat > p0);
}

/* An early "closed" report (the valve's stop logic believed a stop the valve had not reached)
 * must not leave the loop stuck short of its target: the closed stop calibrates the estimate
 * below the int16 top (FM_AT_CLOSED), so the reference can still pass it and the drive goes on
 * closing once the report is gone, and driven past it the estimate takes the frame along. (At
 * 32767 the reference could not pass the estimate, the drive stayed 0 and the flow 2 % short
 * for good.) Toy valve without backlash: +0.5 L/min a 1 % of stroke. */
static void test_ffmap_early_closed_report_does_not_stall(void **state)
{
    (void)state;
    ctl_in_t in = mk(6000, 5000, 0);
    long pos = 16384L * 100;                            /* closure, Q15 x100 */
    double mean = 0;
    for (int k = 0; k < 300; k++) {
        in.valve_limit = k == 10 ? CTL_AT_CLOSED : 0;
        q15_t d = ctl_step(&in);
        ctl_applied(d, in.valve_limit);
        pos += (long)d * 100 / 40;
        in.flow_lpm_x100 = (int16_t)(5000 + (pos / 100 - 16384) * 5000L / 32768);
        if (in.flow_lpm_x100 > 6500)
            in.flow_lpm_x100 = 6500;
        if (k >= 200)
            mean += in.flow_lpm_x100 / 100.0 / 100;
    }
    print_message("ffmap: 20-30 s after an early closed report the flow is %.2f L/min for 60\n", mean);
    assert_true(fabs(mean - 60) <= 0.6);
    /* -32768 (Q15_MIN, which valve_set accepts) moves the estimate a full period's opening */
    int16_t p0 = ctl_st.fm.p_hat;
    ctl_applied(Q15_MIN, 0);
    ctl_applied(Q15_MIN, 0);
    assert_true(p0 - ctl_st.fm.p_hat >= 2 * 32768 / (int)param_v[P_VALVE_TRAVEL] - (int)FM_BACKLASH - 4);
    assert_true(ctl_st.fm.takeup >= 0 && ctl_st.fm.takeup <= FM_BACKLASH);
}

/* The feed-forward moves the valve only the way the target went, and not when the flow is
 * already past the target that way (a coupled PTO's pump leads the tractor). */
static void test_ffmap_feed_forward_gates(void **state)
{
    (void)state;
    ctl_in_t in = mk(3000, 3000, 0);
    for (int k = 0; k < 3; k++)
        ctl_applied(ctl_step(&in), 0);
    int16_t r0 = ctl_st.fm.p_ref;
    /* target up 20 %, flow at the old target: the map's move (toward closed) is made at once */
    in = mk(3600, 3000, 0);
    ctl_step(&in);
    int with_ff = ctl_st.fm.p_ref - r0;
    assert_true(with_ff > 1000);
    /* the same target change with the flow already 10 % above the new target: no feed-forward
     * (only the feedback, which opens) */
    setup(NULL);
    in = mk(3000, 3000, 0);
    for (int k = 0; k < 3; k++)
        ctl_applied(ctl_step(&in), 0);
    r0 = ctl_st.fm.p_ref;
    in = mk(3600, 3960, 0);
    ctl_step(&in);
    print_message("ffmap: target +6 L/min moves the reference %d LSB; with the flow already past it %d LSB\n",
                  with_ff, ctl_st.fm.p_ref - r0);
    assert_true(ctl_st.fm.p_ref - r0 <= 0);
}

/* After a feed-forward move bigger than one period at full duty the integral waits FM_HOLD
 * (ctl.c) periods (the meter shows the move 2-3 periods later). */
static void test_ffmap_integral_waits_after_a_big_move(void **state)
{
    (void)state;
    ctl_in_t in = mk(3000, 3000, 0);
    for (int k = 0; k < 3; k++)
        ctl_applied(ctl_step(&in), 0);
    in = mk(3600, 3000, 0);
    ctl_applied(ctl_step(&in), 0);
    int h = ctl_st.fm.hold;
    assert_true(h >= 2 && h <= 5);                    /* 0.2-0.5 s: the meter's delay */
    for (int k = 1; k <= h; k++) {
        ctl_applied(ctl_step(&in), 0);
        assert_int_equal(ctl_st.fm.hold, h - k);
    }
}

/* The gain schedule: the feedback is scaled by how little boom flow a stroke moves here. With
 * the valve nearly shut and little pressure (a coupled PTO at low speed: the bypass carries
 * little) the loop's gain is low and the schedule raises the feedback (up to 1.6); with the
 * valve wide open at high pressure (a fixed PTO: the bypass carries most of the pump) it
 * lowers it (down to 0.7). Before an end stop has set the estimate's frame it stays 1. */
/* the gain schedule's factor after one step with the estimate at `closure` (of the stroke, in
 * the frame the open stop set), target and flow (x100 L/min) and the boom's pressure */
static int gain_at(double closure, int target, int flow, uint16_t kpa)
{
    ctl_in_t in = mk(target, flow, 0);
    ctl_st.fm.p_hat = (int16_t)(FM_AT_OPEN + (int32_t)(closure * 32768));
    ctl_st.fm.p_ref = ctl_st.fm.p_hat;
    in.pressure_kpa = kpa;
    ctl_step(&in);
    return ctl_st.fm.gain;
}

static void test_ffmap_gain_schedule(void **state)
{
    (void)state;
    ctl_in_t in = mk(1800, 1800, 0);
    ctl_step(&in);
    assert_int_equal(ctl_st.fm.gain, 256);          /* frame unknown: 1 */
    ctl_applied(0, CTL_AT_OPEN);                     /* the open stop sets the frame */
    int low_gain_point = gain_at(0.54, 1800, 1700, 84);      /* coupled PTO, 3 km/h: 18 L/min */
    int high_gain_point = gain_at(0.37, 4950, 4850, 440);    /* fixed PTO, 11 km/h: 49.5 L/min */
    /* fixed PTO, 4 km/h: valve nearly open, 18 L/min: the bypass takes the whole pump, a stroke
     * moves the most */
    int open_point = gain_at(0.02, 1800, 1700, 84);
    print_message("ffmap: gain schedule %.2f (coupled, 3 km/h), %.2f (fixed PTO, 11 km/h), %.2f (fixed PTO, 4 km/h)\n",
                  low_gain_point / 256.0, high_gain_point / 256.0, open_point / 256.0);
    /* the plant's sensitivities there (tools/gen_fmgain.py): about 33, 100 and 76 L/min a stroke */
    assert_true(low_gain_point >= 400);              /* 80/33 = 2.4: clamped at 1.6 */
    assert_true(high_gain_point >= 179 && high_gain_point <= 230);     /* 80/100 = 0.8 */
    assert_true(open_point >= 230 && open_point <= 300);               /* 80/76 = 1.05 */
}

/* Closed loop on the simulated sprayer with the valve starting shut and the boom spraying at
 * once (given speed): the start climbs to the relief valve, the application opens the bypass
 * under over-pressure. The estimate (p_hat - off: the same in any frame; the frame moves when
 * the estimate passes a stop) must follow the real valve through it (before, over-pressure
 * pinned it at "closed" while the valve opened 0.6 of its stroke). */
/* A simulated sprayer from a scenario's text. */
static void sim_from(sim_t *sim, const char *text)
{
    scenario_t scn;
    char err[256];
    if (scenario_parse(&scn, text, "test_ffmap", err, sizeof err) != 0)
        fail_msg("scenario: %s", err);
    sim_init(sim, &scn);
}

/* How far the estimate in the map's frame (p_hat - off) has moved from p0, against how far the
 * true closure has moved from 1 - theta0, in strokes. */
static double frame_error(const sim_t *sim, int p0, double theta0)
{
    double truth = theta0 - sim->plant.theta;
    double est = (ctl_st.fm.p_hat - ctl_st.fm.off - p0) / 32768.0;
    return fabs(truth - est);
}

static void test_ffmap_estimate_tracks_the_valve_through_over_pressure(void **state)
{
    (void)state;
    static const char text[] =
        "[run]\nduration_s = 60\nseed = 5\n[config]\ncontroller = best\nrate_l_ha = 150\ngiven_speed_kmh = 6\n"
        "[plant]\npto_coupled = 0\nvalve_start_pos = 0\n[drive]\n0 0\n[events]\n30 given_speed_kmh 8\n";
    sim_t sim;
    sim_from(&sim, text);
    double worst = 0, theta0 = sim.plant.theta;
    int p0 = ctl_st.fm.p_hat - ctl_st.fm.off;      /* the estimate, whatever frame it is in */
    int saw_over = 0;
    while (sim_time_s(&sim) < 15) {             /* before the map can learn (off moves then) */
        for (int i = 0; i < 100; i++)
            sim_step(&sim);
        if (sim.plant.p_bar > 4.8)
            saw_over = 1;
        /* closure moved (truth) against estimate moved */
        if (frame_error(&sim, p0, theta0) > worst)
            worst = frame_error(&sim, p0, theta0);
    }
    sim_free(&sim);
    print_message("ffmap: worst estimate error over the 15 s after an over-pressure start %.3f stroke\n", worst);
    assert_true(saw_over);
    assert_true(worst < 0.05);
}

/* A long stay at the open stop (a fixed PTO at 4.3 km/h and 100 L/ha: the bypass cannot take
 * enough): the valve module believes the stop, then every 2 s lets the controller try 0.1 stroke
 * more. Those tries must not move the estimate's frame: before, each shifted the map 0.1 stroke
 * (a whole stroke in 20 s), and the feed-forward after the stay was wild. The estimate in the
 * map's frame (p_hat - off) follows the true closure from the first stop on. */
static void test_ffmap_frame_holds_at_a_long_stop(void **state)
{
    (void)state;
    static const char text[] =
        "[run]\nduration_s = 90\nseed = 16\n[config]\ncontroller = best\nrate_l_ha = 100\ngiven_speed_kmh = 8\n"
        "[plant]\npto_coupled = 0\n[drive]\n0 0\n[events]\n30 given_speed_kmh 4.3\n60 given_speed_kmh 9\n";
    sim_t sim;
    sim_from(&sim, text);
    double worst = 0, theta0 = 0, at_open = 0;
    int p0 = 0, have = 0;
    while (sim_time_s(&sim) < 90) {
        for (int i = 0; i < 100; i++)
            sim_step(&sim);
        if (sim_time_s(&sim) > 30 && sim_time_s(&sim) < 60 && sim.plant.theta >= 1.0)
            at_open += 0.1;
        if (!have && ctl_st.fm.cal && ctl_st.fm.warm >= 10) {
            have = 1;
            p0 = ctl_st.fm.p_hat - ctl_st.fm.off;
            theta0 = sim.plant.theta;
        }
        if (have && frame_error(&sim, p0, theta0) > worst)
            worst = frame_error(&sim, p0, theta0);
    }
    sim_free(&sim);
    print_message("ffmap: %.1f s at the open stop; worst estimate error in the map's frame %.3f stroke\n", at_open,
                  worst);
    assert_true(have);
    assert_true(at_open > 20);
    assert_true(worst < 0.06);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_ffmap_over_pressure_is_not_a_closed_stop, setup),
        cmocka_unit_test_setup(test_ffmap_estimate_follows_the_applied_drive, setup),
        cmocka_unit_test_setup(test_ffmap_early_closed_report_does_not_stall, setup),
        cmocka_unit_test_setup(test_ffmap_feed_forward_gates, setup),
        cmocka_unit_test_setup(test_ffmap_integral_waits_after_a_big_move, setup),
        cmocka_unit_test_setup(test_ffmap_gain_schedule, setup),
        cmocka_unit_test_setup(test_ffmap_estimate_tracks_the_valve_through_over_pressure, setup),
        cmocka_unit_test_setup(test_ffmap_frame_holds_at_a_long_stop, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

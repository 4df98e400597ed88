/* test_ctl.c: the controllers against double-precision twins, and the behaviours the loop needs (anti-windup, bumpless start, frozen learning, bounded weights). */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include "ctl_int.h"
#include "params.h"
#include "ctl_twin.h"

static uint32_t rng = 2468u;
static int rnd(int lo, int hi)
{
    rng = rng * 1103515245u + 12345u;
    return lo + (int)((rng >> 8) % (uint32_t)(hi - lo + 1));
}

static ctl_in_t mk(int target, int flow, uint8_t limit)
{
    ctl_in_t in;
    in.target_lpm_x100 = (int16_t)target;
    in.flow_lpm_x100 = (int16_t)flow;
    in.speed_kmh_x100 = 700;
    in.pressure_kpa = 300;
    in.valve_limit = limit;
    return in;
}

static int setup(void **state)
{
    (void)state;
    params_defaults();
    return 0;
}

static void test_ctl_names_and_selection(void **state)
{
    (void)state;
    assert_string_equal(ctl_name(CTL_PID), "pid");
    assert_string_equal(ctl_name(CTL_FUZZY_PID), "fuzzy_pid");
    assert_string_equal(ctl_name(CTL_BP_PID), "bp_pid");
    assert_string_equal(ctl_name(CTL_BEST), "ffmap");
    assert_int_equal(ctl_select(CTL_COUNT), 0);
    assert_int_equal(ctl_select(CTL_FUZZY_PID), 1);
    assert_int_equal(ctl_selected(), CTL_FUZZY_PID);
}

/* pid against the twin of eq. (7) (u = valve position, drive = du * T_travel periods): what
 * the output stage sends plus what it keeps back (the sub-stiction carry) equals the twin's
 * drive plus the carry it started with, within 10 LSB of Q15 + 0.06 % (du rounded to 1/16 x100
 * L/min, gains in Q12; the T * 0.2048 factor held in Q8: 2098/256 for 8.192), wherever it is not saturated. */
static void test_ctl_pid_matches_twin_within_10_lsb_and_0_06_pct(void **state)
{
    (void)state;
    double e1 = 0, e2 = 0, worst = 0;
    int first = 1;
    ctl_select(CTL_PID);
    for (int k = 0; k < 5000; k++) {
        int t = rnd(1000, 5000), f = t + rnd(-300, 300);
        ctl_in_t in = mk(t, f, 0);
        double e = (t - f) / 100.0;
        q15_t carry0 = ctl_carry_now();
        q15_t d = ctl_step(&in);
        if (first) {
            e1 = e2 = e;
            first = 0;
        }
        double twin = ctltw_drive(ctltw_pid_du_stroke(e, e1, e2, 1.2, 0.2, 0.8), 40) * 32768 + carry0;
        e2 = e1;
        e1 = e;
        assert_int_equal(ctl_gain(0), Q12(1.2));
        if (ctl_saturated() || fabs(twin) > 32000)
            continue;
        double err = fabs(d + ctl_carry_now() - twin);
        if (err > worst)
            worst = err;
        assert_true(err <= 10.0 + 0.0006 * fabs(twin));
        /* a drive is either 0 or at least the break-away duty */
        assert_true(d == 0 || d >= CTL_STICTION || d <= -CTL_STICTION);
    }
    print_message("pid: worst %.2f LSB of Q15 against the twin\n", worst);
}

/* fuzzy gains against the twin (bilinear blend of the rule tables): within 14 LSB of Q12
 * (0.0034: e and ec held in 1/256 of a level, rounding 1/512 each, times a table rise of up
 * to 4 levels between neighbours and 0.2 a level: 6.4 LSB a dimension). */
static void test_ctl_fuzzy_gains_match_twin_within_14_lsb(void **state)
{
    (void)state;
    double worst = 0;
    ctl_select(CTL_FUZZY_PID);
    int prev_e = 0;
    for (int k = 0; k < 5000; k++) {
        int t = rnd(1000, 5000), f = t + rnd(-400, 400);
        ctl_in_t in = mk(t, f, 0);
        int e = t - f;
        ctl_step(&in);
        if (k == 0)
            prev_e = e;
        double kt[3];
        ctltw_fuzzy_gains(e / 100.0, (e - prev_e) / 100.0, kt);
        prev_e = e;
        for (int i = 0; i < 3; i++) {
            double err = fabs(ctl_gain((uint8_t)i) - kt[i] * 4096);
            if (err > worst)
                worst = err;
            assert_true(err <= 14.0);
        }
    }
    print_message("fuzzy_pid: worst gain %.2f LSB of Q12 against the twin\n", worst);
}

static void bp_weights(double w[5][4], double v[3][5])
{
    for (int i = 0; i < 5; i++)
        for (int j = 0; j < 4; j++)
            w[i][j] = ctl_st.bp.w[i][j] / 4096.0;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 5; j++)
            v[i][j] = ctl_st.bp.v[i][j] / 4096.0;
}

/* bp forward pass against the twin from the same weights: hidden outputs (phase 0) within 12
 * LSB of Q15 (net input rounded to Q12: 4 LSB, tanh table 2 LSB, inputs' scaling 1e-4), gains
 * (phase 1, from the hidden outputs held) within 12 LSB of Q15; the output layer's change,
 * made on phases 2 and 3 from the deltas of phase 1, within 3.5 LSB of Q12 + 5 % of it (the
 * gradient and eta*delta rounded to Q12, the momentum's shifts floor: up to 2 LSB). */
static void test_ctl_bp_matches_twin(void **state)
{
    (void)state;
    double wo = 0, wk = 0, wdv = 0;
    int checked = 0, have = 0;
    double dv[3][5], ok[5], kf[3];
    int16_t v0[3][5];
    int8_t dv0[3][5];
    ctl_select(CTL_BP_PID);
    for (int k = 0; k < 6000; k++) {
        int t = rnd(1500, 5000), f = t + rnd(-600, 600);
        ctl_in_t in = mk(t, f, 0);
        double w[5][4], v[3][5], o[5], kk[3];
        uint8_t phase = ctl_st.bp.phase;
        int16_t n1 = ctl_st.bp.n1, n2 = ctl_st.bp.n2;
        bp_weights(w, v);
        ctl_step(&in);
        if (phase == 0) {
            ctltw_bp_forward(w, v, t / 100.0, f / 100.0, o, kk);
            for (int i = 0; i < 5; i++) {
                double err = fabs(ctl_st.bp.o[i] - o[i] * 32768);
                wo = err > wo ? err : wo;
                assert_true(err <= 12.0);
            }
        }
        if (phase == 1) {
            for (int l = 0; l < 3; l++) {
                double a = 0;
                for (int j = 0; j < 5; j++)
                    a += v[l][j] * ctl_st.bp.o[j] / 32768.0;
                double err = fabs(ctl_st.bp.k[l] - (1 + tanh(a)) / 2 * 32768);
                wk = err > wk ? err : wk;
                assert_true(err <= 12.0);
            }
        }
        if (phase == 1 && ctl_st.bp.phase == 2 && k > 1) {
            double n = ctl_st.bp.n1 / 4096.0;
            for (int j = 0; j < 5; j++)
                ok[j] = ctl_st.bp.o[j] / 32768.0;
            for (int l = 0; l < 3; l++)
                kf[l] = ctl_st.bp.k[l] / 32768.0;
            ctltw_bp_dv(kf, ok, n, n1 / 4096.0, n2 / 4096.0, dv);
            memcpy(v0, ctl_st.bp.v, sizeof v0);
            memcpy(dv0, ctl_st.bp.dv, sizeof dv0);
            have = 1;
        } else if (ctl_st.bp.phase != 3 && !(phase == 3 && ctl_st.bp.phase == 4)) {
            have = 0;
        }
        if (have && phase == 3 && ctl_st.bp.phase == 4) {
            for (int i = 0; i < 3; i++)
                for (int j = 0; j < 5; j++) {
                    double want = dv[i][j] * 4096 + 0.0508 * dv0[i][j];
                    double got = ctl_st.bp.v[i][j] - v0[i][j];
                    if (fabs(v0[i][j] + want) >= BP_WMAX)
                        continue;       /* at the bound */
                    double err = fabs(got - want);
                    wdv = err > wdv ? err : wdv;
                    assert_true(err <= 3.5 + 0.05 * fabs(want));
                }
            checked++;
            have = 0;
        }
    }
    assert_true(checked > 10);      /* saturation drops many updates; these were complete */
    print_message("bp_pid: worst hidden %.1f, gain %.1f LSB of Q15; weight change %.2f LSB of Q12 (%d updates)\n",
                  wo, wk, wdv, checked);
}

/* Anti-windup: against an end stop nothing is driven or stored; when the error turns, the
 * drive turns at once (nothing to unwind). */
static void test_ctl_anti_windup_at_end_stop(void **state)
{
    (void)state;
    for (uint8_t id = 0; id < CTL_COUNT; id++) {
        ctl_select(id);
        ctl_in_t in = mk(4000, 2000, CTL_AT_CLOSED);     /* wants more flow, valve fully closed */
        for (int k = 0; k < 200; k++) {
            assert_true(ctl_step(&in) <= 0);
            assert_int_equal(ctl_carry_now(), 0);
        }
        in = mk(2000, 3000, 0);                          /* now too much flow */
        q15_t d = 0;
        for (int k = 0; k < 3 && d == 0; k++)
            d = ctl_step(&in);
        assert_true(d < 0);
    }
}

/* Bumpless manual -> auto: after ctl_reset, a standing error gives no proportional or
 * derivative kick: the first drive is the integral term alone. */
static void test_ctl_bumpless_reset_has_no_kick(void **state)
{
    (void)state;
    ctl_select(CTL_PID);
    ctl_in_t in = mk(3000, 3000, 0);
    for (int k = 0; k < 10; k++)
        ctl_step(&in);
    ctl_reset(Q15(0.3));
    in = mk(3000, 2900, 0);                              /* 1 L/min short */
    q15_t d = ctl_step(&in);
    double integral_only = ctltw_drive(ctltw_pid_du_stroke(1.0, 1.0, 1.0, 1.2, 0.2, 0.8), 40) * 32768;
    assert_true(fabs(d + ctl_carry_now() - integral_only) <= 8.0);
    /* with a kick (history e1 = e2 = 0) it would have been 11 times larger */
    double kicked = ctltw_drive(ctltw_pid_du_stroke(1.0, 0.0, 0.0, 1.2, 0.2, 0.8), 40) * 32768;
    assert_true(fabs(d + ctl_carry_now() - kicked) > 0.5 * fabs(kicked));
}

/* Learning frozen while saturated: the network's weights and the map stay as they are while
 * the valve sits at an end stop, and learn again when it does not. */
static void test_ctl_learning_frozen_while_saturated(void **state)
{
    (void)state;
    bp_state_t before;
    ctl_select(CTL_BP_PID);
    ctl_in_t in = mk(4000, 3000, CTL_AT_CLOSED);
    ctl_step(&in);
    memcpy(&before, &ctl_st.bp, sizeof before);
    for (int k = 0; k < 300; k++) {
        in.flow_lpm_x100 = (int16_t)(3000 + rnd(-200, 200));
        ctl_step(&in);
    }
    assert_memory_equal(before.w, ctl_st.bp.w, sizeof before.w);
    assert_memory_equal(before.v, ctl_st.bp.v, sizeof before.v);
    in.valve_limit = 0;
    in.flow_lpm_x100 = 3950;
    for (int k = 0; k < 30; k++) {
        in.flow_lpm_x100 = (int16_t)(3950 + rnd(-150, 150));
        ctl_step(&in);
    }
    assert_true(memcmp(before.v, ctl_st.bp.v, sizeof before.v) != 0);

    fm_state_t fb;
    ctl_select(CTL_BEST);
    in = mk(3000, 3000, CTL_AT_OPEN);
    memcpy(&fb, &ctl_st.fm, sizeof fb);
    for (int k = 0; k < 100; k++)
        ctl_step(&in);
    assert_memory_equal(fb.node, ctl_st.fm.node, sizeof fb.node);
    in.valve_limit = 0;
    ctl_reset(0);
    for (int k = 0; k < FM_WARM; k++)       /* no learning in the first FM_WARM periods after a (re)start */
        ctl_step(&in);
    assert_memory_equal(fb.node, ctl_st.fm.node, sizeof fb.node);
    for (int k = 0; k < 100; k++)
        ctl_step(&in);
    assert_true(memcmp(fb.node, ctl_st.fm.node, sizeof fb.node) != 0);
}

/* One hour (36000 periods) of noisy, saturating, sign-changing inputs: every weight stays
 * within its bound, the gains within [0, 1), the drive within full duty. */
static void test_ctl_bp_weights_bounded_over_one_hour(void **state)
{
    (void)state;
    ctl_select(CTL_BP_PID);
    int wmax = 0;
    for (int k = 0; k < 36000; k++) {
        int t = (k / 300) % 2 ? rnd(500, 8000) : rnd(-2000, 16000);
        int f = rnd(-3000, 16000);
        uint8_t lim = rnd(0, 9) == 0 ? (uint8_t)rnd(1, 2) : 0;
        ctl_in_t in = mk(t, f, lim);
        q15_t d = ctl_step(&in);
        assert_true(d >= -32767);
        for (int i = 0; i < 5; i++)
            for (int j = 0; j < 4; j++) {
                int a = abs(ctl_st.bp.w[i][j]);
                wmax = a > wmax ? a : wmax;
                assert_true(a <= BP_WMAX);
            }
        for (int i = 0; i < 3; i++) {
            for (int j = 0; j < 5; j++)
                assert_true(abs(ctl_st.bp.v[i][j]) <= BP_WMAX);
            assert_true(ctl_st.bp.k[i] >= 0);
        }
    }
    print_message("bp_pid: largest |w| after one hour %.3f (bound %.1f)\n", wmax / 4096.0, BP_WMAX / 4096.0);
}

/* ffmap: a target change moves the valve in the same period, before the meter sees anything
 * (feed-forward), and a reversal adds the backlash take-up. */
static void test_ctl_ffmap_feed_forward_and_backlash(void **state)
{
    (void)state;
    ctl_select(CTL_BEST);
    ctl_in_t in = mk(3000, 3000, 0);
    for (int k = 0; k < 20; k++)
        assert_int_equal(ctl_step(&in), 0);
    in.target_lpm_x100 = 3500;                           /* +5 L/min; flow not yet moved */
    q15_t d = ctl_step(&in);
    /* default slope 1 stroke / 100 L/min: 0.05 stroke + 2 % backlash = 0.07 * 40 > 1: full */
    assert_true(d > Q15(0.9));
    /* the flow overshoots: the first drive back carries the 2 % backlash take-up (0.8 duty) */
    in.flow_lpm_x100 = 3800;
    q15_t r = 0;
    for (int k = 0; k < 5 && r >= 0; k++)
        r = ctl_step(&in);
    assert_true(r <= -(int32_t)FM_BACKLASH * 40 + 40);
}

/* ffmap: while the servo still travels toward the feed-forward's position, the integral is
 * held (the valve integrates already; counting the error on its way winds up and overshoots). */
static void test_ctl_ffmap_integral_held_while_servo_travels(void **state)
{
    (void)state;
    ctl_select(CTL_BEST);
    ctl_in_t in = mk(3000, 3000, 0);
    for (int k = 0; k < 20; k++)
        ctl_step(&in);
    in.target_lpm_x100 = 4000;                           /* +10 L/min: 0.1 stroke to travel */
    ctl_step(&in);
    int16_t ref = ctl_st.fm.p_ref;
    for (int k = 0; k < 2; k++) {                        /* flow not yet moved: e = 10 L/min */
        assert_true(ref - ctl_st.fm.p_hat > Q15(0.02));
        ctl_step(&in);
        assert_int_equal(ctl_st.fm.p_ref, ref);
    }
    /* once there, the error counts again */
    for (int k = 0; k < 10 && ctl_st.fm.p_ref == ref; k++)
        ctl_step(&in);
    assert_true(ctl_st.fm.p_ref > ref);
}

/* ffmap: a deadband with hysteresis. Within target/256 the servo stops where it is and only a
 * slow integral acts (no hunting between break-away pulses and backlash take-ups); beyond
 * target/128, or while the target moves, the full feedback is back. */
static void test_ctl_ffmap_deadband_hysteresis(void **state)
{
    (void)state;
    ctl_select(CTL_BEST);
    ctl_in_t in = mk(4500, 4500, 0);
    for (int k = 0; k < 20; k++)
        assert_int_equal(ctl_step(&in), 0);
    assert_int_equal(ctl_st.fm.rest, 1);
    /* 0.6 % low (between 4500/256 and 4500/128): it stays at rest; no P on the measurement,
     * only the slow integral creeps the reference (the dose is not left biased), so the servo
     * makes a break-away pulse now and then (the first with the backlash take-up) */
    in.flow_lpm_x100 = 4473;
    int moves = 0;
    for (int k = 0; k < 30; k++) {
        q15_t dd = ctl_step(&in);
        assert_int_equal(ctl_st.fm.rest, 1);
        assert_true(dd >= 0);
        if (k < 4)
            assert_int_equal(dd, 0);
        if (dd != 0) {
            moves++;
            if (moves > 1)
                assert_int_equal(dd, CTL_STICTION);
        }
    }
    assert_true(moves >= 2 && moves <= 5);
    /* 1 % low: beyond the outer band, the feedback re-engages and drives */
    in.flow_lpm_x100 = 4455;
    ctl_step(&in);
    assert_int_equal(ctl_st.fm.rest, 0);
    /* back within the inner band: rest again, the servo stops where it is */
    in.flow_lpm_x100 = 4495;
    ctl_step(&in);
    assert_int_equal(ctl_st.fm.rest, 1);
    assert_true(abs(ctl_st.fm.p_ref - ctl_st.fm.p_hat) < 8);
    /* a moving target (2 % a period) wakes the loop even with no error */
    in.target_lpm_x100 = 4590;
    in.flow_lpm_x100 = 4590;
    ctl_step(&in);
    assert_int_equal(ctl_st.fm.rest, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_ctl_names_and_selection, setup),
        cmocka_unit_test_setup(test_ctl_pid_matches_twin_within_10_lsb_and_0_06_pct, setup),
        cmocka_unit_test_setup(test_ctl_fuzzy_gains_match_twin_within_14_lsb, setup),
        cmocka_unit_test_setup(test_ctl_bp_matches_twin, setup),
        cmocka_unit_test_setup(test_ctl_anti_windup_at_end_stop, setup),
        cmocka_unit_test_setup(test_ctl_bumpless_reset_has_no_kick, setup),
        cmocka_unit_test_setup(test_ctl_learning_frozen_while_saturated, setup),
        cmocka_unit_test_setup(test_ctl_bp_weights_bounded_over_one_hour, setup),
        cmocka_unit_test_setup(test_ctl_ffmap_feed_forward_and_backlash, setup),
        cmocka_unit_test_setup(test_ctl_ffmap_integral_held_while_servo_travels, setup),
        cmocka_unit_test_setup(test_ctl_ffmap_deadband_hysteresis, setup),
    };
    return cmocka_run_group_tests_name("ctl", tests, NULL, NULL);
}

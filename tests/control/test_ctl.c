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
    assert_string_equal(ctl_name(CTL_AOG), "aog");
    assert_string_equal(ctl_name(CTL_RAVEN), "raven");
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

/* bp_pid's normalised error as a plain number: clamped to +-15 L/min, over 5 L/min */
static double ctltw_clamp_e5(int t, int f)
{
    double e = (t - f) / 100.0;
    return (e > 15 ? 15 : e < -15 ? -15 : e) / 5.0;
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

/* bp_pid every period against the twin: the forward pass from the same weights (hidden outputs
 * and gains within 12 LSB of Q15: net inputs rounded to Q12, 4 LSB; tanh table, 2 LSB; the
 * inputs' scaling 1e-4), and the learning step that follows in the same period: every weight's
 * change against the paper's rule (ctltw_bp_learn, fed the firmware's hidden outputs and gains,
 * the error and inputs as exact numbers) within 3 LSB of Q12 + 1 % of the change for the output
 * rows (the error's and the gradient's Q12 roundings, eta in Q12, the momentum's three floored
 * shifts for alpha: up to 1 LSB, the change rounded) and 4 LSB + 2 % for the hidden rows (the
 * output rows' errors through their deltas, 1 - O^2 and the backed-up sum rounded). A period
 * whose drive was cut changes no weight. */
static void test_ctl_bp_learns_every_period_as_the_twin(void **state)
{
    (void)state;
    double wo = 0, wk = 0, wv = 0, ww = 0, n1 = 0, n2 = 0;
    int learned = 0, frozen = 0, moved_v[3][5] = {{0}}, moved_w[5][4] = {{0}};
    ctl_select(CTL_BP_PID);
    for (int k = 0; k < 6000; k++) {
        int t = rnd(1500, 5000), f = t + rnd(-600, 600);
        ctl_in_t in = mk(t, f, 0);
        double w[5][4], v[3][5], dw0[5][4], dv0[3][5], o[5], kk[3], x[4], ko[3], oo[5];
        int16_t wq[5][4], vq[3][5];
        double n = ctltw_clamp_e5(t, f);
        bp_weights(w, v);
        memcpy(wq, ctl_st.bp.w, sizeof wq);
        memcpy(vq, ctl_st.bp.v, sizeof vq);
        for (int i = 0; i < 5; i++)
            for (int j = 0; j < 4; j++)
                dw0[i][j] = ctl_st.bp.dw[i][j] / 4096.0;
        for (int l = 0; l < 3; l++)
            for (int i = 0; i < 5; i++)
                dv0[l][i] = ctl_st.bp.dv[l][i] / 4096.0;
        if (k == 0)
            n1 = n2 = n;
        ctl_step(&in);
        /* forward pass of this period */
        ctltw_bp_forward(w, v, t / 100.0, f / 100.0, o, kk);
        for (int i = 0; i < 5; i++) {
            double err = fabs(ctl_st.bp.o[i] - o[i] * 32768);
            wo = err > wo ? err : wo;
            assert_true(err <= 12.0);
            oo[i] = ctl_st.bp.o[i] / 32768.0;
        }
        for (int l = 0; l < 3; l++) {
            double err = fabs(ctl_st.bp.k[l] - kk[l] * 32768);
            wk = err > wk ? err : wk;
            assert_true(err <= 12.0);
            ko[l] = ctl_st.bp.k[l] / 32768.0;
        }
        if (ctl_saturated()) {
            assert_memory_equal(wq, ctl_st.bp.w, sizeof wq);
            assert_memory_equal(vq, ctl_st.bp.v, sizeof vq);
            frozen++;
        } else {
            /* the learning step of this period */
            x[0] = 1.0;
            x[1] = t / 5000.0;
            x[2] = f / 5000.0;
            x[3] = n;
            ctltw_bp_learn(w, v, dw0, dv0, x, oo, ko, n, n1, n2, BP_WMAX / 4096.0);
            for (int l = 0; l < 3; l++)
                for (int i = 0; i < 5; i++) {
                    double want = v[l][i] * 4096 - vq[l][i], got = ctl_st.bp.v[l][i] - vq[l][i];
                    double err = fabs(got - want);
                    wv = err > wv ? err : wv;
                    assert_true(err <= 3.0 + 0.01 * fabs(want));
                    if (fabs(want) >= 5.0) {
                        assert_true(got * want > 0);
                        moved_v[l][i]++;
                    }
                }
            for (int i = 0; i < 5; i++)
                for (int j = 0; j < 4; j++) {
                    double want = w[i][j] * 4096 - wq[i][j], got = ctl_st.bp.w[i][j] - wq[i][j];
                    double err = fabs(got - want);
                    ww = err > ww ? err : ww;
                    assert_true(err <= 4.0 + 0.02 * fabs(want));
                    if (fabs(want) >= 5.0) {
                        assert_true(got * want > 0);
                        moved_w[i][j]++;
                    }
                }
            learned++;
        }
        n2 = n1;
        n1 = n;
    }
    /* every weight was asked to move by more than the tolerance (5 LSB) in 20 periods or more, and moved that way */
    int least = learned;
    for (int l = 0; l < 3; l++)
        for (int i = 0; i < 5; i++)
            least = moved_v[l][i] < least ? moved_v[l][i] : least;
    for (int i = 0; i < 5; i++)
        for (int j = 0; j < 4; j++)
            least = moved_w[i][j] < least ? moved_w[i][j] : least;
    print_message("bp_pid: worst hidden %.1f, gain %.1f LSB of Q15; weight change output %.2f, hidden %.2f LSB of "
                  "Q12 (%d periods learned, %d frozen; each weight moved >= 5 LSB in %d or more)\n",
                  wo, wk, wv, ww, learned, frozen, least);
    for (int l = 0; l < 3; l++)
        for (int i = 0; i < 5; i++)
            assert_true(moved_v[l][i] >= 20);
    for (int i = 0; i < 5; i++)
        for (int j = 0; j < 4; j++)
            assert_true(moved_w[i][j] >= 20);
    assert_true(learned > 1000);
}

/* The gains change every period while learning: on a steady error (constant target and flow)
 * the forward pass alone would give the same gains each period; the network learns in every
 * one, so the gains and the output weights move every period. */
static void test_ctl_bp_gains_change_every_period_while_learning(void **state)
{
    (void)state;
    ctl_select(CTL_BP_PID);
    ctl_in_t in = mk(3000, 2800, 0);            /* 2 L/min short, steady */
    int16_t k0[3], v0[3][5];
    ctl_step(&in);
    for (int p = 0; p < 200; p++) {
        memcpy(k0, ctl_st.bp.k, sizeof k0);
        memcpy(v0, ctl_st.bp.v, sizeof v0);
        ctl_step(&in);
        assert_false(ctl_saturated());
        assert_true(memcmp(v0, ctl_st.bp.v, sizeof v0) != 0);
        assert_true(memcmp(k0, ctl_st.bp.k, sizeof k0) != 0);
        assert_true(ctl_st.bp.k[1] > k0[1]);    /* ki grows: the steady error's gradient */
    }
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
    ctl_step(&in);                          /* the stop calibrates the estimate: the map's frame moves with it */
    memcpy(&fb, &ctl_st.fm, sizeof fb);
    for (int k = 0; k < 100; k++)
        ctl_step(&in);
    /* the map: its nodes, their frame and what it has seen */
    assert_memory_equal(fb.node, ctl_st.fm.node, sizeof fb.node);
    assert_int_equal(fb.off, ctl_st.fm.off);
    assert_memory_equal(fb.seen, ctl_st.fm.seen, sizeof fb.seen);
    in.valve_limit = 0;
    ctl_reset(0);
    for (int k = 0; k < FM_WARM; k++)       /* no learning in the first FM_WARM periods after a (re)start */
        ctl_step(&in);
    assert_memory_equal(fb.node, ctl_st.fm.node, sizeof fb.node);
    assert_int_equal(fb.off, ctl_st.fm.off);
    assert_memory_equal(fb.seen, ctl_st.fm.seen, sizeof fb.seen);
    for (int k = 0; k < 100; k++)
        ctl_step(&in);
    assert_true(memcmp(fb.seen, ctl_st.fm.seen, sizeof fb.seen) != 0);    /* it learned */
    assert_true(fb.off != ctl_st.fm.off || memcmp(fb.node, ctl_st.fm.node, sizeof fb.node) != 0);
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
 * slow integral acts (no hunting between break-away pulses and backlash take-ups), none at all
 * within target/1024; beyond target/128, or while the target moves, the full feedback is back. */
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
    int16_t hat0 = ctl_st.fm.p_hat;
    for (int k = 0; k < 30; k++) {
        q15_t dd = ctl_step(&in);
        int32_t a = dd < 0 ? -(int32_t)dd : dd;
        assert_int_equal(ctl_st.fm.rest, 1);
        if (k < 1)
            assert_int_equal(dd, 0);
        if (dd != 0) {
            moves++;
            /* a break-away pulse, or a reversal: the backlash and a fine move under FM_REV_MIN
             * (a break-away pulse that went further than the integral asked comes partly back) */
            if (a != CTL_STICTION) {
                assert_true(a >= (int32_t)FM_BACKLASH * 40);
                assert_true(a < ((int32_t)FM_BACKLASH + (int32_t)Q15(CTLTW_FM_REV_MIN)) * 40);
            }
        }
    }
    assert_true(moves >= 2 && moves <= 15);
    assert_true(ctl_st.fm.p_hat - hat0 > Q15(0.005));    /* closing, the way the error asks */
    /* within target/1024 (0.09 % high) nothing moves, however long: no reversal for a flow the
     * smallest move could not bring nearer */
    in.flow_lpm_x100 = 4504;
    int16_t ref = ctl_st.fm.p_ref;
    for (int k = 0; k < 600; k++) {
        assert_int_equal(ctl_step(&in), 0);
        assert_int_equal(ctl_st.fm.rest, 1);
    }
    assert_int_equal(ctl_st.fm.p_ref, ref);
    /* 0.2 % high: the slow integral opens, and inside the band the reversal may be as small as
     * FM_REV_MIN_REST (the backlash taken up, then a fine move), not FM_REV_MIN */
    in.flow_lpm_x100 = 4509;
    q15_t rv = 0;
    for (int k = 0; k < 200 && rv == 0; k++)
        rv = ctl_step(&in);
    assert_int_equal(ctl_st.fm.rest, 1);
    assert_true(rv <= -(int32_t)FM_BACKLASH * 40);
    assert_true(rv > -((int32_t)FM_BACKLASH + (int32_t)Q15(CTLTW_FM_REV_MIN)) * 40);
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

/* ffmap: what the stall and hunting checks learned (a larger smallest pulse, a smaller take-up)
 * stays through other settings' changes, and goes when the operator tells new Min duty or
 * Backlash values: they are taken as given. */
static void test_ctl_ffmap_valve_parameters_reset_what_was_learned(void **state)
{
    (void)state;
    ctl_select(CTL_BEST);
    ctl_in_t in = mk(3000, 3000, 0);
    ctl_step(&in);
    ctl_st.fm.brk = FM_BRK_STEP;
    ctl_st.fm.tk_cut = FM_TK_STEP;
    assert_int_equal(param_set(P_RATE, 140), 1);
    ctl_step(&in);
    assert_int_equal(ctl_st.fm.brk, FM_BRK_STEP);
    assert_int_equal(ctl_st.fm.tk_cut, FM_TK_STEP);
    assert_int_equal(param_set(P_VALVE_SLACK, 15), 1);
    ctl_step(&in);
    assert_int_equal(ctl_st.fm.brk, 0);
    assert_int_equal(ctl_st.fm.tk_cut, 0);
    assert_int_equal(FM_BACKLASH, Q15(0.015));
    ctl_st.fm.brk = FM_BRK_STEP;
    assert_int_equal(param_set(P_VALVE_BRK, 30), 1);
    ctl_step(&in);
    assert_int_equal(ctl_st.fm.brk, 0);
    assert_int_equal(CTL_STICTION, Q15(0.3));
    params_defaults();
    ctl_reset(0);                   /* the defaults derived again for the tests after this one */
    assert_int_equal(CTL_STICTION, CTL_STICTION_DEF);
    assert_int_equal(FM_BACKLASH, FM_BACKLASH_DEF);
}

/* ---- ffmap against its double-precision twin ----------------------------------------------- */
/* A toy plant in integers: the bypass valve (closure Q15, full stroke in T_travel periods at
 * full duty, 1.5 % backlash of its own, end stops), a convex closure -> boom flow curve on a
 * pump that follows the ground speed (a coupled PTO) or, once an end stop has set ffmap's frame,
 * now and then a big fixed one, a lag of a few periods and a noisy meter; the boom's pressure
 * from its nozzles (diag.c's model: P = 30 kPa of check valves + 300 kPa (Q / Q_3bar)^2, the
 * relief valve at 600 kPa). */
typedef struct {
    int32_t pos;                    /* Q15 closure */
    int32_t slack;                  /* Q15 backlash still to take up */
    int dir;
    int32_t flow;                   /* x100 L/min in the boom */
    int32_t pump;                   /* x100 L/min: a fixed PTO's pump; 0: coupled, with the speed */
    int32_t q3;                     /* x100 L/min: what the boom's nozzles pass at 3 bar */
    int32_t brk;                    /* Q15: the duty it needs to move (0: any) */
} fm_toy_t;

static uint32_t fm_rng = 1u;        /* its own sequence: the other tests' inputs stay as they were */
static int fm_rnd(int lo, int hi)
{
    fm_rng = fm_rng * 1103515245u + 12345u;
    return lo + (int)((fm_rng >> 16) % (uint32_t)(hi - lo + 1));
}

static void fm_toy_move(fm_toy_t *p, q15_t d, int travel)
{
    int s = d > 0 ? 1 : -1;
    int32_t mv = ((int32_t)abs(d) + travel / 2) / travel, take;
    if (d == 0 || abs(d) < p->brk)
        return;
    if (s != p->dir) {
        p->slack = 492;
        p->dir = s;
    }
    take = mv < p->slack ? mv : p->slack;
    p->slack -= take;
    p->pos += s * (mv - take);
    p->pos = p->pos < 0 ? 0 : p->pos > 32767 ? 32767 : p->pos;
}

static int fm_toy_flow(fm_toy_t *p, int speed_x100)
{
    int32_t pump = p->pump ? p->pump : 5000 + 4 * speed_x100;           /* 56 .. 94 L/min coupled */
    int32_t g = (p->pos * (9830 + ((22938 * p->pos) >> 15))) >> 15;     /* boom share, Q15 */
    p->flow += ((pump * g >> 15) - p->flow) / 3;
    return (int)p->flow;
}

/* the boom's pressure, kPa: the nozzles at the boom's flow, 30 .. 600 kPa, a noisy sensor */
static uint16_t fm_toy_pressure(const fm_toy_t *p)
{
    double r = p->flow > 0 ? (double)p->flow / p->q3 : 0;
    int kpa = (int)(30 + 300 * r * r + 0.5) + fm_rnd(-3, 3);
    return (uint16_t)(kpa < 30 ? 30 : kpa > 600 ? 600 : kpa);
}

static uint8_t fm_toy_stops(const fm_toy_t *p)
{
    return p->pos >= 32767 ? CTL_AT_CLOSED : p->pos <= 0 ? CTL_AT_OPEN : 0;
}

#define FM_TOL_LSB 4.0
/* The gain schedule: the firmware's Q8 gain within FM_GAIN_TOL_LSB of the twin's (times 256)
 * plus the lookups' rounding through the sum (o.gain_tab). The 2 LSB: the result rounded (0.5),
 * the products' shifts (0.1), FM_GS_K = 94 in Q10 for 94.08 (0.09 %: 0.4 at 1.6), p_hat's few
 * LSB through the opening (under 0.4 where the gain is not clamped). */
#define FM_GAIN_TOL_LSB 2.0
/* ... and p_ref (the drive: times T_travel) within FM_TOL_LSB plus |du| (the increment before the
 * gain) times that tolerance / 256 and 0.02 / 256 more (13422 for 0.2048 * 65536, the factor
 * 13422 gain / 256 rounded to an integer: 0.5 / 13422). */
#define FM_GAIN_F_LSB 0.02
#define FM_STEPS 12000
#define FM_RELIEVE Q15(0.5)         /* app.c APP_RELIEVE_DRIVE: over-pressure opens the bypass at 50 % */
#define FM_JOG Q15(0.6)             /* app.c APP_JOG_DRIVE */

typedef struct {
    double drive, drive_stroke, ref, hat, take, node, off;  /* worst |firmware - twin|, LSB */
    double b_ref, b_hat, b_drive;   /* widest rounding interval (half-width), LSB */
    double gain, gain_tol, b_gain;  /* worst |gain - twin's| (Q8 LSB), its tolerance there, widest interval */
    double ref_use, drive_use;      /* worst |p_ref|, |drive| error over its step's tolerance */
    double tol_ref;                 /* widest p_ref tolerance of a step (LSB) */
} fm_worst_t;

static double fm_wmax(double w, double x)
{
    return x > w ? x : w;
}

/* an interval of the firmware's rounding (x firmware - twin, LSB; lo .. hi stroke or duty) holds */
static int fm_in(double x, double lo, double hi)
{
    return x >= lo * 32768 - 1e-6 && x <= hi * 32768 + 1e-6;
}

/* The firmware's state after a step or a ctl_applied against the twin's: p_ref, p_hat, takeup
 * (and off, where the twin carries it) inside the intervals of the firmware's rounding; p_ref
 * within tol_ref, p_hat, takeup, every node and off within FM_TOL_LSB of Q15 stroke; dir, rest,
 * warm, hold, pend (and, map_too, calm and seen) equal. */
static void fm_compare(const char *what, int k, const fm_state_t *f, const ctltw_fm_t *tw, const ctltw_fm_out_t *o,
                       int map_too, double tol_ref, fm_worst_t *w)
{
    double dr = f->p_ref - tw->p_ref * 32768, dh = f->p_hat - tw->p_hat * 32768, dt = f->takeup - tw->takeup * 32768;
    double doff = f->off - tw->off * 32768, en = 0;
    unsigned long seen = 0;
    for (int j = 0; j < FM_NODES; j++) {
        en = fm_wmax(en, fabs(f->node[j] - tw->node[j] * 32768));
        if (f->seen[j >> 3] & (1u << (j & 7)))
            seen |= 1ul << j;
    }
    if (!map_too) {
        en = doff = 0;
        seen = tw->seen;
    }
    if (!fm_in(dr, o->ref_lo, o->ref_hi) || !fm_in(dh, o->hat_lo, o->hat_hi) || !fm_in(dt, o->take_lo, o->take_hi)
        || (map_too && o->off_iv && !fm_in(doff, o->off_lo, o->off_hi)))
        fail_msg("ffmap %s %d: outside the rounding: p_ref %d twin %.2f (%.2f .. %.2f LSB), p_hat %d twin %.2f "
                 "(%.2f .. %.2f), takeup %d twin %.2f (%.2f .. %.2f), off %d twin %.2f (%.2f .. %.2f%s)",
                 what, k, f->p_ref, tw->p_ref * 32768, o->ref_lo * 32768, o->ref_hi * 32768, f->p_hat,
                 tw->p_hat * 32768, o->hat_lo * 32768, o->hat_hi * 32768, f->takeup, tw->takeup * 32768,
                 o->take_lo * 32768, o->take_hi * 32768, f->off, tw->off * 32768, o->off_lo * 32768,
                 o->off_hi * 32768, o->off_iv ? "" : ", not carried");
    if (fabs(dr) > tol_ref || fabs(dh) > FM_TOL_LSB || fabs(dt) > FM_TOL_LSB || fabs(doff) > FM_TOL_LSB
        || en > FM_TOL_LSB || f->dir != tw->dir || f->rest != tw->rest || f->warm != tw->warm || f->hold != tw->hold
        || f->cal != tw->cal || f->stopd != tw->stopd || f->pend != tw->pend || (map_too && f->calm != tw->calm)
        || seen != tw->seen || f->stall_n != tw->stall_n || f->brk != (int16_t)lround(tw->brk * 32768)
        || f->brk_age != tw->brk_age || f->rev != tw->rev || f->hunt != tw->hunt
        || f->tk_cut != (int16_t)lround(tw->tk_cut * 32768)
        || fabs(f->stall_mv - tw->stall_mv * 32768) > FM_TOL_LSB
        || (f->stall_n == 0 && (f->stall_y != lround(tw->stall_y * 100) || f->stall_v != lround(tw->stall_v * 100))))
        fail_msg("ffmap %s %d: p_ref %d twin %.1f, p_hat %d twin %.1f, takeup %d twin %.1f, off %d twin %.1f, worst "
                 "node %.2f LSB, dir %d/%d rest %d/%d warm %d/%d hold %d/%d pend %d/%d calm %d/%d stopd %d/%d "
                 "seen %lx/%lx stall %d/%d brk %d/%.0f stall_mv %d/%.1f (path %x border %x)",
                 what, k, f->p_ref, tw->p_ref * 32768, f->p_hat, tw->p_hat * 32768, f->takeup, tw->takeup * 32768,
                 f->off, tw->off * 32768, en, f->dir, tw->dir, f->rest, tw->rest, f->warm, tw->warm, f->hold,
                 tw->hold, f->pend, tw->pend, f->calm, tw->calm, f->stopd, tw->stopd, seen, tw->seen, f->stall_n,
                 tw->stall_n, f->brk, tw->brk * 32768, f->stall_mv, tw->stall_mv * 32768, o->path, o->border);
    w->ref = fm_wmax(w->ref, fabs(dr));
    w->ref_use = fm_wmax(w->ref_use, fabs(dr) / tol_ref);
    w->hat = fm_wmax(w->hat, fabs(dh));
    w->take = fm_wmax(w->take, fabs(dt));
    w->off = fm_wmax(w->off, fabs(doff));
    w->node = fm_wmax(w->node, en);
    w->b_ref = fm_wmax(w->b_ref, fmax(-o->ref_lo, o->ref_hi) * 32768);
    w->b_hat = fm_wmax(w->b_hat, fmax(-o->hat_lo, o->hat_hi) * 32768);
}

/* ctl_applied(da, limit) on the firmware and on the twin (loaded from the firmware's state),
 * compared; the toy valve gets da. Returns the twin's paths. */
static unsigned fm_applied(int k, q15_t da, uint8_t limit, q15_t last, int travel, fm_toy_t *toy, fm_worst_t *w)
{
    ctltw_fm_t ta;
    ctltw_fm_load(&ta, &ctl_st.fm, 0, last);
    ctltw_fm_out_t oa = ctltw_fm_applied(&ta, da / 32768.0, limit, travel);
    ctl_applied(da, limit);
    fm_compare("applied", k, &ctl_st.fm, &ta, &oa, 1, FM_TOL_LSB, w);
    fm_toy_move(toy, da, travel);
    return oa.path;
}

/* ffmap against the twin (tests/helper_ctl_twin.c), step by step from the same state: 12000
 * periods of the toy plant under target steps (large, and around one period's full travel, the
 * integral's hold threshold) and ramps, targets that follow the speed or lie
 * out of reach (0, beyond the last node), speeds above and below P_MINF_SPEED, meter noise and
 * dropouts, end-stop flags (at the stops, and early near them: a stop the valve's estimate
 * finds too soon), over-pressure (CTL_NO_CLOSE), a restart half-way onto a slower valve
 * (T_travel 40, then 64 periods: backlash left to take up between steps) and two manual
 * interludes (jogs, then a bumpless restart); the map learns (warm-up passed). The boom's
 * pressure follows its nozzles (30 .. 600 kPa, a boom of 25 .. 80 L/min at 3 bar a segment), and
 * once an end stop has set the frame a third of the segments run a big fixed PTO pump (150 ..
 * 320 L/min) instead of the coupled one (56 .. 94 L/min): the gain schedule goes over its range,
 * both clamps included (the toy's valve passes more than the tables' at small openings, so the
 * low clamp needs a big pump, a high flow and a high pressure). Each segment runs, at random,
 *  - the controller alone: its drive is accounted at the start of the next step (pend);
 *  - as app.c: ctl_applied(what the valve got, its stops) after every step, the step seeing
 *    the stops a period late; the valve gets the over-pressure relief (-50 % whatever was
 *    asked), now and then half the drive (a weak supply), nothing against a stop it is at
 *    (refused); the manual jogs are ctl_applied alone.
 * On each step:
 *  - the gain schedule (ctl_st.fm.gain, Q8) within the twin's interval of the firmware's rounding
 *    (p_hat's interval through the opening, the table lookups, the shifts, FM_GS_K in Q10, the
 *    clamps in Q8) and within FM_GAIN_TOL_LSB plus the lookups' rounding (o.gain_tab) of the
 *    twin's, which computes it in double from the same tables (every step, skipped ones too: it
 *    comes before any borderline decision); 256 exactly before an end stop has set the frame;
 *  - p_ref, p_hat, takeup, off and the drive lie within the twin's interval of the firmware's
 *    rounding for that step (the map's lookups, the covered flow and the PI increment rounded,
 *    kp in Q12, the gain's interval through its factor 13422 gain / 256 rounded, the backlash at
 *    655/32768, 1/T_travel in Q15 and each move rounded; the drive is need times T_travel, a
 *    product the firmware makes exactly);
 *  - closures (p_hat, takeup, off, every node) within FM_TOL_LSB LSB of Q15 stroke; p_ref within
 *    FM_TOL_LSB plus |du| (the increment before the gain) times (the gain's tolerance +
 *    FM_GAIN_F_LSB) / 256 (an increment of 0.2 stroke with the gain off by 2 LSB of Q8 is 50 LSB
 *    off), the drive within (that + 0.5) * T_travel LSB of Q15 duty (need's error and the
 *    backlash's, times T_travel);
 *  - rest, dir, hold, pend, calm, warm, seen and the saturation flag equal.
 * Each ctl_applied is compared the same way (twin loaded from the state after the step).
 * Borderlines: where that interval lets the firmware's closure or drive lie across a threshold
 * from the twin's (integral gate, one period's full-duty move, smallest reversal, need's sign
 * with backlash pending, half the break-away duty) the step is skipped and counted (under
 * 1 %); where only the saturation flag may differ while the loop is calm, the step is compared
 * without the calm counter and the map (also under 1 %). */
static void test_ctl_ffmap_matches_twin(void **state)
{
    (void)state;
    fm_toy_t toy = {Q15(0.5), 0, 0, 0, 0, 4250, 0};  /* 36 nozzles of 1.18 L/min at 3 bar */
    fm_worst_t w;
    int travel = (int)param_v[P_VALVE_TRAVEL];
    unsigned paths = 0, paths_app = 0;
    int g_min = 0, g_max = 0, g_in = 0, g_off = 0, g_fixed = 0, g_fw_min = 0, g_fw_max = 0, g_values = 0;
    int p_min = 9999, p_max = 0;
    unsigned char g_seen[512] = {0};
    int skipped = 0, partial = 0, compared = 0, sat_edges = 0, kinds[CTLTW_B_KINDS] = {0};
    int learned = 0, rested = 0, slow = 0, forced = 0, force_left = 0, overp_left = 0, overp_steps = 0;
    int applied = 0, relief = 0, weak = 0, refused = 0, jogs = 0, calib_app = 0, pend_moves = 0, frame = 0;
    int target = 3000, seg_left = 0, seg_kind = 0, ramp_from = 0, ramp_to = 0, seg_len = 1, seg_app = 0;
    int speed = 700, rate = 8, first = 1, held_restarts = 0, out_of_reach = 0, stiff = 0, stalls = 0, hunts = 0;
    uint8_t force_flag = 0, prev_stops = 0;     /* the valve's stops the period before */
    q15_t last = 0;

    memset(&w, 0, sizeof w);
    ctl_select(CTL_BEST);           /* the valve's parameters derived (Min duty, Backlash) */
    assert_int_equal(Q15(CTLTW_FM_BACKLASH), FM_BACKLASH);
    assert_int_equal(Q15(CTLTW_STICTION), CTL_STICTION);
    assert_int_equal(FM_DEF_SLOPE, Q15(CTLTW_FM_BIN / CTL_FLOW_SCALE_LPM));   /* 5.12 L/min a 0.0512 stroke */
    assert_int_equal(FM_COVER, (1L << FM_BIN_SHIFT) * 32768L / FM_DEF_SLOPE);
    assert_int_equal(travel, 40);
    assert_int_equal(FM_GS_K, (int)(CTLTW_FM_GS_K * 1024 * 256 / 65536 + 0.5));  /* Q10 of K 256 / 65536 */
    assert_int_equal(FM_GS_MIN, Q8(CTLTW_FM_GS_MIN));
    assert_int_equal(FM_GS_MAX, Q8(CTLTW_FM_GS_MAX));
    ctl_select(CTL_BEST);
    for (int k = 0; k < FM_STEPS; k++) {
        /* the inputs: segments of steps, ramps and speed-following targets */
        if (seg_left == 0) {
            seg_len = seg_left = fm_rnd(100, 300);
            seg_kind = fm_rnd(0, 9);
            seg_app = fm_rnd(0, 1);
            speed = fm_rnd(0, 3) == 0 ? fm_rnd(200, 390) : fm_rnd(410, 1000);
            ramp_from = target;
            ramp_to = fm_rnd(1500, 7500);
            rate = fm_rnd(5, 10);
            if (seg_kind <= 1)
                target = fm_rnd(1200, 7600);
            else if (seg_kind == 6)
                target = ++out_of_reach & 1 ? 0 : fm_rnd(8200, 9000);  /* nothing, or beyond the last node */
            /* the boom's nozzles; once the frame is set, now and then a big fixed PTO pump */
            toy.q3 = fm_rnd(2500, 8000);
            toy.pump = ctl_st.fm.cal && fm_rnd(0, 2) == 0 ? fm_rnd(15000, 32000) : 0;
            /* now and then a valve stiffer than Min duty: ffmap's smallest pulses do not move it */
            toy.brk = fm_rnd(0, 2) == 0 ? Q15(0.33) : 0;
            stiff += toy.brk != 0;
        }
        seg_left--;
        if ((seg_kind == 2 || seg_kind == 5) && seg_left % 30 == 0)
            target += (target > 4500 ? -1 : 1) * fm_rnd(300, 1500);    /* steps around one period's full travel */
        if (seg_kind == 3 || seg_kind == 4) {
            target = ramp_from + (ramp_to - ramp_from) * (seg_len - seg_left) / seg_len;
        } else if (seg_kind >= 7) {
            speed += fm_rnd(-4, 4);
            speed = speed < 150 ? 150 : speed > 1100 ? 1100 : speed;
            target = speed * rate;
        }
        if (k + 1 == FM_STEPS / 4 || k + 1 == FM_STEPS / 2 || k + 1 == 3 * FM_STEPS / 4)
            target += target > 5000 ? -2500 : 2500;     /* a step just before a restart: it comes with hold */
        if (speed < (int)param_v[P_MINF_SPEED] * 10)
            slow++;
        if (k == FM_STEPS / 4 || k == FM_STEPS / 2 || k == 3 * FM_STEPS / 4)
            held_restarts += ctl_st.fm.hold > 0;
        if (k == FM_STEPS / 4 || k == 3 * FM_STEPS / 4) {
            /* manual: jogs (ctl_applied alone, the valve's stops refused), then a bumpless restart
             * from the drive the valve has */
            int n = fm_rnd(20, 40), dir = toy.pos > Q15(0.5) ? 1 : -1;    /* toward the nearer stop */
            q15_t da = 0;
            for (int j = 0; j < n; j++) {
                uint8_t stops = fm_toy_stops(&toy);
                da = j % 10 < 6 ? (q15_t)(dir * FM_JOG) : 0;
                if ((da > 0 && (stops & CTL_AT_CLOSED)) || (da < 0 && (stops & CTL_AT_OPEN))) {
                    da = 0;
                    refused++;
                }
                paths_app |= fm_applied(k, da, stops, last, travel, &toy, &w);
                fm_toy_flow(&toy, speed);
                applied++;
                jogs++;
            }
            ctl_reset(da);
            last = da;
            first = 1;
        }
        int flow = fm_toy_flow(&toy, speed) + fm_rnd(-12, 12) / (toy.brk ? 4 : 1)    /* a stiff valve: a quieter meter */
                   + (fm_rnd(0, 99) == 0 ? fm_rnd(-150, 150) : 0);
        if (fm_rnd(0, 299) == 0)
            flow = 0;               /* the meter's pulses lost for a period: a jump the P term cuts */
        uint8_t stops = fm_toy_stops(&toy), early = 0;
        if (force_left == 0 && (toy.pos > Q15(0.85) || toy.pos < Q15(0.15)) && fm_rnd(0, 24) == 0) {
            force_left = fm_rnd(1, 4);
            force_flag = toy.pos > Q15(0.5) ? CTL_AT_CLOSED : CTL_AT_OPEN;
        }
        if (force_left > 0) {
            early = force_flag;     /* near a stop: the valve's estimate finds it too soon */
            force_left--;
            forced++;
        }
        if (overp_left == 0 && fm_rnd(0, 149) == 0)
            overp_left = fm_rnd(2, 12);
        int overp = overp_left > 0;
        if (overp) {
            overp_left--;
            overp_steps++;
        }
        if (k == FM_STEPS / 2) {
            /* a restart (warm-up again, the map kept) and a slower valve: 6.4 s a stroke, so a
             * reversal's full-duty period (1/64 stroke) leaves backlash to take up; without
             * ctl_applied the last step's drive, still pending, is replaced by ctl_reset's 0 */
            assert_int_equal(param_set(P_VALVE_TRAVEL, 64), 1);
            travel = 64;
            ctl_reset(0);
            last = 0;
            first = 1;
        }
        /* as app.c the step sees the stops (the valve's, early ones too) a period late */
        uint8_t limit = (uint8_t)((seg_app ? prev_stops : stops | early) | (overp ? CTL_NO_CLOSE : 0));
        ctl_in_t in = mk(target, flow, limit);
        in.speed_kmh_x100 = (uint16_t)speed;
        in.pressure_kpa = fm_toy_pressure(&toy);
        p_min = in.pressure_kpa < p_min ? in.pressure_kpa : p_min;
        p_max = in.pressure_kpa > p_max ? in.pressure_kpa : p_max;

        /* the twin from the same state, one step */
        ctltw_fm_t tw;
        ctltw_fm_in_t ti = {target / 100.0, flow / 100.0, speed / 100.0, param_v[P_MINF_SPEED] / 10.0,
                            limit, travel, in.pressure_kpa};
        ctltw_fm_load(&tw, &ctl_st.fm, first, last);
        ctltw_fm_out_t o = ctltw_fm_step(&tw, &ti);
        q15_t d = ctl_step(&in);
        uint8_t sat = ctl_saturated();
        fm_state_t after = ctl_st.fm;
        first = 0;
        last = d;
        prev_stops = (uint8_t)(stops | early);
        if (k == 0) {
            assert_int_equal(ctl_gain(0), Q12(CTLTW_FM_KP));
            assert_int_equal(ctl_gain(1), Q12(CTLTW_FM_KI));
        }

        /* the valve: what the controller asked, or (as app.c) what it got, told with ctl_applied */
        if (seg_app) {
            q15_t da = d;
            uint8_t lim_a = (uint8_t)(stops | early);
            if (overp && da > -FM_RELIEVE) {
                da = -FM_RELIEVE;
                relief++;
            } else if (fm_rnd(0, 29) == 0 && d != 0) {
                da = (q15_t)(d / 2);
                weak++;
            }
            if ((da > 0 && (lim_a & CTL_AT_CLOSED)) || (da < 0 && (lim_a & CTL_AT_OPEN))) {
                da = 0;
                refused++;
            }
            unsigned pa = fm_applied(k, da, lim_a, d, travel, &toy, &w);
            paths_app |= pa;
            calib_app += (pa & CTLTW_P_CALIB) != 0;
            frame += (pa & CTLTW_P_FRAME) != 0;
            applied++;
        } else {
            fm_toy_move(&toy, d, travel);
        }

        /* the gain schedule: before any borderline decision, so on every step */
        double gtol = FM_GAIN_TOL_LSB + o.gain_tab, eg = after.gain - o.gain * 256;
        if (after.gain / 256.0 - o.gain < o.gain_lo - 1e-9 || after.gain / 256.0 - o.gain > o.gain_hi + 1e-9
            || fabs(eg) > gtol || tw.gain != o.gain || (!after.cal && after.gain != 256))
            fail_msg("ffmap step %d (flow %d, %u kPa, p_hat %d, cal %d): gain %d twin %.2f (%.2f .. %.2f; tolerance "
                     "%.2f LSB of Q8)", k, flow, in.pressure_kpa, after.p_hat, after.cal, after.gain, o.gain * 256,
                     o.gain_lo * 256, o.gain_hi * 256, gtol);
        if (fabs(eg) > w.gain) {
            w.gain = fabs(eg);
            w.gain_tol = gtol;
        }
        w.b_gain = fm_wmax(w.b_gain, fmax(-o.gain_lo, o.gain_hi) * 256);
        g_min += (o.path & CTLTW_P_GAIN_MIN) != 0;
        g_max += (o.path & CTLTW_P_GAIN_MAX) != 0;
        g_in += (o.path & CTLTW_P_GAIN) != 0;
        g_off += !after.cal;
        g_fixed += after.cal && toy.pump != 0;
        g_fw_min += after.gain == FM_GS_MIN;
        g_fw_max += after.gain == FM_GS_MAX;
        if (after.gain > FM_GS_MIN && after.gain < FM_GS_MAX && !g_seen[after.gain]) {
            g_seen[after.gain] = 1;
            g_values++;
        }
        /* p_ref's (and the drive's) tolerance: the gain's share of the increment (none before the frame) */
        double tol_ref = FM_TOL_LSB + fabs(o.du) * 32768 * ((after.cal ? gtol : 0) + FM_GAIN_F_LSB) / 256;
        double tol_drive = (tol_ref + 0.5) * travel;

        for (int b = 0; b < CTLTW_B_KINDS; b++)
            kinds[b] += o.border >> b & 1u;
        if (o.border & CTLTW_B_SERVO) {
            skipped++;              /* the drive itself may differ: nothing to compare */
            continue;
        }
        /* the saturation flag near full duty while calm: the servo is compared, the calm counter
         * and the map (the step's last act) are not */
        int map_too = !(o.border & CTLTW_B_SAT);
        partial += !map_too;
        compared++;
        sat_edges += o.sat_edge;
        paths |= o.path;
        learned += (o.path & CTLTW_P_LEARN) != 0;
        rested += (o.path & CTLTW_P_REST) != 0;
        pend_moves += (o.path & (CTLTW_P_PEND | CTLTW_P_MOVED)) == (CTLTW_P_PEND | CTLTW_P_MOVED);
        frame += (o.path & CTLTW_P_FRAME) != 0;
        stalls += (o.path & CTLTW_P_STALL) != 0;
        hunts += (o.path & CTLTW_P_HUNT) != 0;

        double dd = d - o.drive * 32768, ed = fabs(dd);
        if (!fm_in(dd, o.drive_lo, o.drive_hi))
            fail_msg("ffmap step %d: drive %d twin %.2f (%.2f .. %.2f LSB)", k, d, o.drive * 32768,
                     o.drive_lo * 32768, o.drive_hi * 32768);
        if (ed > tol_drive || (!o.sat_edge && sat != o.sat))
            fail_msg("ffmap step %d (target %d flow %d speed %d limit %d): drive %d twin %.1f, sat %d/%d "
                     "(path %x border %x)", k, target, flow, speed, limit, d, o.drive * 32768, sat, o.sat, o.path,
                     o.border);
        fm_compare("step", k, &after, &tw, &o, map_too, tol_ref, &w);
        w.b_drive = fm_wmax(w.b_drive, fmax(-o.drive_lo, o.drive_hi) * 32768);
        w.drive = fm_wmax(w.drive, ed);
        w.drive_stroke = fm_wmax(w.drive_stroke, ed / travel);
        w.drive_use = fm_wmax(w.drive_use, ed / tol_drive);
        w.tol_ref = fm_wmax(w.tol_ref, tol_ref);
    }
    print_message("ffmap: worst drive %.2f LSB of Q15 duty (%.2f LSB of stroke a period; %.0f %% of its step's tolerance, "
                  "(p_ref's + 0.5) T_travel), p_ref %.2f (%.0f %% of its step's, %.1f + the gain's share, up to %.1f), "
                  "p_hat %.2f, takeup %.2f, off %.2f, node %.2f LSB of Q15 (tolerance %.0f)\n",
                  w.drive, w.drive_stroke, 100 * w.drive_use, w.ref, 100 * w.ref_use, FM_TOL_LSB, w.tol_ref, w.hat,
                  w.take, w.off, w.node, FM_TOL_LSB);
    print_message("ffmap: the rounding's intervals held on every step and ctl_applied compared (widest p_ref %.2f, "
                  "p_hat %.2f, drive %.2f LSB; gain %.2f LSB of Q8)\n", w.b_ref, w.b_hat, w.b_drive, w.b_gain);
    print_message("ffmap: gain schedule: worst %.2f LSB of Q8 against the twin's double (tolerance there %.2f: %.1f + "
                  "the lookups' rounding); twin at 0.7 on %d steps, at 1.6 on %d, inside on %d (firmware at %d / %d on "
                  "%d / %d, %d values inside), off (frame not set) on %d; %d steps with a fixed PTO; %d .. %d kPa\n",
                  w.gain, w.gain_tol, FM_GAIN_TOL_LSB, g_min, g_max, g_in, FM_GS_MIN, FM_GS_MAX, g_fw_min, g_fw_max,
                  g_values, g_off, g_fixed, p_min, p_max);
    print_message("ffmap: borderline: %d of %d steps skipped (integral gate %d, reversal %d, stiction %d, hold %d, "
                  "take-up sign %d, smallest pulse %d), %d compared without calm and map (full duty while calm); "
                  "saturation flag left out on %d\n", skipped, FM_STEPS, kinds[0], kinds[1], kinds[2], kinds[4], kinds[5],
                  kinds[6], partial, sat_edges);
    print_message("ffmap: %d segments with a valve stiffer than Min duty (0.33), %d stalls found (brk now %d); "
                  "%d hunts on the toy's 1.5 %% backlash (take-up cut now %d)\n",
                  stiff, stalls, ctl_st.fm.brk, hunts, ctl_st.fm.tk_cut);
    print_message("ffmap: %d steps learned, %d at rest, %d below P_MINF_SPEED, %d with an early end stop, %d under "
                  "over-pressure, %d pending drives accounted, %d outside the stroke\n", learned, rested, slow, forced,
                  overp_steps, pend_moves, frame);
    print_message("ffmap: %d ctl_applied compared (%d jogs, %d relief, %d weak, %d refused; %d calibrated); %d of 3 "
                  "restarts with the integral on hold\n",
                  applied, jogs, relief, weak, refused, calib_app, held_restarts);
    assert_true(skipped * 100 < FM_STEPS);
    assert_true(partial * 100 < FM_STEPS);
    assert_int_equal(compared + skipped, FM_STEPS);
    /* the run went through every branch of the step, and of ctl_applied */
    const unsigned all = CTLTW_P_REST | CTLTW_P_INTEGRAL | CTLTW_P_HELD | CTLTW_P_REVERSAL | CTLTW_P_HYST
                         | CTLTW_P_ROUNDED | CTLTW_P_SAT | CTLTW_P_ENDSTOP | CTLTW_P_LEARN | CTLTW_P_ANCHOR
                         | CTLTW_P_CALIB | CTLTW_P_LEADCUT | CTLTW_P_DUCUT | CTLTW_P_TAKEUP | CTLTW_P_HOLDSET
                         | CTLTW_P_HOLDING | CTLTW_P_GATED | CTLTW_P_COVER | CTLTW_P_PEND | CTLTW_P_MOVED
                         | CTLTW_P_NOCLOSE | CTLTW_P_FRAME | CTLTW_P_GAIN | CTLTW_P_GAIN_MIN | CTLTW_P_GAIN_MAX
                         | CTLTW_P_UNLEARNED | CTLTW_P_RESTZERO | CTLTW_P_STALL | CTLTW_P_HUNT;
    const unsigned all_app = CTLTW_P_CALIB | CTLTW_P_MOVED | CTLTW_P_STILL | CTLTW_P_INTOSTOP;
    if ((paths & all) != all || (paths_app & all_app) != all_app)
        fail_msg("ffmap: branches not taken: step %x, ctl_applied %x", all & ~paths, all_app & ~paths_app);
    assert_true(learned > 100 && rested > 100 && slow > 100 && forced > 10 && overp_steps > 100);
    assert_true(pend_moves > 100 && relief > 50 && weak > 20 && refused >= 5 && calib_app >= 5 && applied > 1000);
    assert_true(held_restarts > 0);
    /* the gain schedule ran over its range: both clamps (the twin's and the firmware's) and the
     * inside, many values of it; the pressures over 30 .. 600 kPa */
    assert_true(g_min > 100 && g_max > 100 && g_in > 1000 && g_off > 0 && g_fixed > 1000);
    assert_true(g_fw_min > 100 && g_fw_max > 100 && g_values > 150);
    assert_true(p_min <= 35 && p_max >= 595);
}

/* ---- the peers: aog and raven ------------------------------------------------------------- */
#define Q15_OF(counts) ((counts) * 32767.0 / 255.0)

/* aog against its description, worked by hand at the default settings (Kp 10, min PWM 60, max
 * 255, Ki = Kd = 0) and a 30 L/min target: dead band 4 % (1.2 L/min), brake point 20 % (6 L/min);
 * within 4 LSB of Q15 (the gains' rounding to Q7 / Q8 and the shifts' floors). */
static void test_ctl_aog_hand_worked_dead_band_brake_point_and_limits(void **state)
{
    (void)state;
    ctl_select(CTL_AOG);
    ctl_in_t in = mk(3000, 2900, 0);        /* 1 L/min short: 3.3 %, inside the dead band */
    assert_int_equal(ctl_step(&in), 0);
    assert_int_equal(ctl_carry_now(), 0);
    in = mk(3000, 2850, 0);                 /* 1.5 L/min: 60 + 0.75 x 10 x 1.5 = 71.25 counts */
    assert_true(fabs(ctl_step(&in) - Q15_OF(71.25)) <= 4.0);
    in = mk(3000, 2200, 0);                 /* 8 L/min, beyond the brake point: 60 + 80 = 140 */
    assert_true(fabs(ctl_step(&in) - Q15_OF(140)) <= 4.0);
    in = mk(3000, 3800, 0);                 /* 8 L/min over: -140, the sign kept */
    assert_true(fabs(ctl_step(&in) + Q15_OF(140)) <= 4.0);
    in = mk(1000, 3500, 0);                 /* 25 L/min over a 10 L/min target: limited to -10 */
    assert_true(fabs(ctl_step(&in) + Q15_OF(160)) <= 4.0);
    param_set(P_AOG_KP, 500);               /* Kp 50: 60 + 0.75 x 50 x 5 = 247.5, held at 0.75 x 255 */
    in = mk(3000, 2500, 0);
    assert_true(fabs(ctl_step(&in) - Q15_OF(191.25)) <= 4.0);
    in = mk(3000, 1000, 0);                 /* 20 L/min: 60 + 1000, held at max PWM: full duty */
    assert_int_equal(ctl_step(&in), 32767);
    param_set(P_AOG_KP, 100);
    param_set(P_AOG_MIN, 80);               /* min PWM above what Kp asks: 80 + 0.75 x 10 x 1.5 */
    in = mk(3000, 2850, 0);
    assert_true(fabs(ctl_step(&in) - Q15_OF(91.25)) <= 4.0);
}

/* aog's integral (2 ki e a 100 ms period: two 50 ms loops) and derivative (kd / 2 of the flow
 * change over the period), by hand: Ki 0.5, Kd 1.0, 8 then 10 L/min short. */
static void test_ctl_aog_hand_worked_integral_and_derivative(void **state)
{
    (void)state;
    param_set(P_AOG_KI, 50);
    param_set(P_AOG_KD, 10);
    ctl_select(CTL_AOG);
    ctl_in_t in = mk(3000, 2200, 0);
    assert_true(fabs(ctl_step(&in) - Q15_OF(60 + 80 + 8)) <= 4.0);      /* integral 8, no kick */
    assert_true(fabs(ctl_step(&in) - Q15_OF(60 + 80 + 16)) <= 4.0);     /* integral 16 */
    in = mk(3000, 2000, 0);                 /* 10 L/min, integral 26, the flow fell 2: + 0.5 x 2 */
    assert_true(fabs(ctl_step(&in) - Q15_OF(60 + 100 + 26 + 1)) <= 4.0);
    in = mk(3000, 2980, 0);                 /* in the dead band: not driven, the integral kept */
    assert_int_equal(ctl_step(&in), 0);
    in = mk(3000, 2000, 0);                 /* integral 36, the flow fell 9.8: + 0.5 x 9.8 */
    assert_true(fabs(ctl_step(&in) - Q15_OF(60 + 100 + 36 + 4.9)) <= 4.0);
}

/* raven against its description, by hand, with the recommended standard cal 2123 (backlash 2,
 * speed 1: 0.2 duty, brake point 20 %, dead band 3 %) and a 30 L/min target, and a fast valve's 743. */
static void test_ctl_raven_hand_worked_dead_band_brake_point_and_backlash_pulse(void **state)
{
    (void)state;
    ctl_select(CTL_RAVEN);
    ctl_in_t in = mk(3000, 2920, 0);        /* 0.8 L/min: 2.7 %, inside the dead band */
    assert_int_equal(ctl_step(&in), 0);
    in = mk(3000, 2000, 0);                 /* 10 L/min, beyond the brake point (6): the speed, 0.2 */
    assert_true(abs(ctl_step(&in) - 6554) <= 2);
    in = mk(3000, 2700, 0);                 /* 3 L/min: half the brake point, half the speed: 0.1 */
    assert_int_equal(ctl_step(&in), 0);     /* ... under Min duty: kept back */
    assert_true(abs(ctl_carry_now() - 3277) <= 2);
    assert_true(abs(ctl_step(&in) - 6554) <= 3);    /* ... and sent as one pulse with the next */
    in = mk(3000, 3300, 0);                 /* 3 L/min over: the other way, 0.1 + the backlash pulse 0.2 */
    assert_true(abs(ctl_step(&in) + 9830) <= 3);
    assert_int_equal(ctl_step(&in), 0);     /* the next: 0.1 again, no pulse: kept back */
    assert_true(abs(ctl_carry_now() + 3277) <= 2);
    param_set(P_RAVEN_CAL, 743);            /* fast valve: speed 7 = 0.3, brake 40 %, dead band 3 %, no pulse */
    ctl_select(CTL_RAVEN);
    in = mk(3000, 1000, 0);                 /* 20 L/min: 67 %, beyond the brake point */
    assert_true(abs(ctl_step(&in) - 9830) <= 2);
    in = mk(3000, 3600, 0);                 /* 6 L/min over: 20 %, half the brake point: -0.15, no pulse */
    assert_int_equal(ctl_step(&in), 0);     /* ... under Min duty: kept back (the other way's carry dropped) */
    assert_true(abs(ctl_carry_now() + 4915) <= 3);
    assert_false(param_set(P_RAVEN_CAL, 2120));     /* a dead band digit 0 is refused */
    assert_int_equal(param_v[P_RAVEN_CAL], 743);
}

/* aog and raven against their double twins on random inputs with every setting in use: what
 * the output stage sends plus what it keeps back equals the twin's drive plus the carry it
 * started with (less on a reversal, where raven drops it), wherever the drive is not cut. */
static void test_ctl_peers_match_their_twins(void **state)
{
    (void)state;
    static const uint16_t aog_set[][5] = {{100, 0, 0, 60, 255}, {250, 50, 20, 40, 200}, {1500, 2000, 500, 0, 255}};
    static const uint16_t cals[] = {2123, 743, 9991, 1015, 5555};
    double worst = 0;
    int checked = 0;
    for (unsigned c = 0; c < 3; c++) {
        param_set(P_AOG_KP, aog_set[c][0]);
        param_set(P_AOG_KI, aog_set[c][1]);
        param_set(P_AOG_KD, aog_set[c][2]);
        param_set(P_AOG_MIN, aog_set[c][3]);
        param_set(P_AOG_MAX, aog_set[c][4]);
        ctl_select(CTL_AOG);
        ctltw_ag_t tw = {aog_set[c][0] / 10.0, aog_set[c][1] / 100.0, aog_set[c][2] / 10.0,
                         aog_set[c][3], aog_set[c][4], 0, 0, 1};
        for (int k = 0; k < 3000; k++) {
            int t = rnd(500, 5000), f = t + rnd(-t / 2, t / 2);
            ctl_in_t in = mk(t, f, 0);
            q15_t carry0 = ctl_carry_now();
            double i0 = tw.integ;
            q15_t d = ctl_step(&in);
            double tw_d = ctltw_ag_step(&tw, t / 100.0, f / 100.0);
            double ae = abs(t - f) / 100.0, tl = t / 100.0;
            /* the thresholds as the firmware holds them (x100 L/min, floor) may differ from the
             * twin's by 0.01 L/min: such a step is not compared, and the integrals re-synchronised */
            if (fabs(ae - 0.04 * tl) <= 0.02 || fabs(ae - 0.2 * tl) <= 0.02) {
                tw.integ = ctl_st.ag.integ / 256.0 / 32767.0 * 255.0;
                continue;
            }
            if (tw_d == 0) {
                assert_int_equal(d, 0);
                assert_int_equal(ctl_carry_now(), 0);
                assert_true(tw.integ == i0);
                continue;
            }
            if (ctl_saturated())
                continue;
            double err = fabs(d + ctl_carry_now() - (tw_d * 32767.0 + carry0));
            if (err > worst)
                worst = err;
            assert_true(err <= 6.0 + 0.002 * fabs(tw_d * 32767.0));
            checked++;
        }
    }
    print_message("aog: worst %.2f LSB of Q15 against the twin\n", worst);
    worst = 0;
    for (unsigned c = 0; c < sizeof cals / sizeof cals[0]; c++) {
        assert_true(param_set(P_RAVEN_CAL, cals[c]));
        ctl_select(CTL_RAVEN);
        ctltw_rv_t tw = {cals[c], 0};
        for (int k = 0; k < 3000; k++) {
            int t = rnd(500, 5000), f = t + rnd(-t / 2, t / 2);
            ctl_in_t in = mk(t, f, 0);
            q15_t carry0 = ctl_carry_now();
            int rev;
            q15_t d = ctl_step(&in);
            double tw_d = ctltw_rv_step(&tw, t / 100.0, f / 100.0, &rev);
            double ae = abs(t - f) / 100.0, tl = t / 100.0;
            int p = cals[c] / 10 % 10;
            if (fabs(ae - (cals[c] % 10) / 100.0 * tl) <= 0.02 || fabs(ae - (p ? p / 10.0 : 0.05) * tl) <= 0.02) {
                tw.dir = ctl_st.rv.dir;
                continue;
            }
            if (tw_d == 0) {
                assert_int_equal(d, 0);
                assert_int_equal(ctl_carry_now(), 0);
                continue;
            }
            assert_int_equal(ctl_st.rv.dir, tw.dir);
            if (ctl_saturated())
                continue;
            double err = fabs(d + ctl_carry_now() - (tw_d * 32768.0 + (rev ? 0 : carry0)));
            if (err > worst)
                worst = err;
            /* the brake point as the firmware holds it, x100 L/min floored: 1 / bk relative */
            double tol = 3.0 + (0.0005 + 1.0 / (t * (p ? p / 10.0 : 0.05))) * fabs(tw_d * 32768.0);
            if (!(err <= tol))
                print_message("raven cal %u step %d: t %d f %d d %d carry %d carry0 %d twin %f rev %d\n", cals[c], k, t, f, d, ctl_carry_now(), carry0, tw_d * 32768.0, rev);
            assert_true(err <= tol);
            checked++;
        }
    }
    print_message("raven: worst %.2f LSB of Q15 against the twin; %d steps compared\n", worst, checked);
    assert_true(checked > 20000);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_ctl_names_and_selection, setup),
        cmocka_unit_test_setup(test_ctl_pid_matches_twin_within_10_lsb_and_0_06_pct, setup),
        cmocka_unit_test_setup(test_ctl_fuzzy_gains_match_twin_within_14_lsb, setup),
        cmocka_unit_test_setup(test_ctl_bp_learns_every_period_as_the_twin, setup),
        cmocka_unit_test_setup(test_ctl_bp_gains_change_every_period_while_learning, setup),
        cmocka_unit_test_setup(test_ctl_anti_windup_at_end_stop, setup),
        cmocka_unit_test_setup(test_ctl_bumpless_reset_has_no_kick, setup),
        cmocka_unit_test_setup(test_ctl_learning_frozen_while_saturated, setup),
        cmocka_unit_test_setup(test_ctl_bp_weights_bounded_over_one_hour, setup),
        cmocka_unit_test_setup(test_ctl_ffmap_feed_forward_and_backlash, setup),
        cmocka_unit_test_setup(test_ctl_ffmap_integral_held_while_servo_travels, setup),
        cmocka_unit_test_setup(test_ctl_ffmap_deadband_hysteresis, setup),
        cmocka_unit_test_setup(test_ctl_ffmap_valve_parameters_reset_what_was_learned, setup),
        cmocka_unit_test_setup(test_ctl_ffmap_matches_twin, setup),
        cmocka_unit_test_setup(test_ctl_aog_hand_worked_dead_band_brake_point_and_limits, setup),
        cmocka_unit_test_setup(test_ctl_aog_hand_worked_integral_and_derivative, setup),
        cmocka_unit_test_setup(test_ctl_raven_hand_worked_dead_band_brake_point_and_backlash_pulse, setup),
        cmocka_unit_test_setup(test_ctl_peers_match_their_twins, setup),
    };
    return cmocka_run_group_tests_name("ctl", tests, NULL, NULL);
}

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
#include "target.h"
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
    in.pressure_kpa = FFMAP_P_REF;     /* ffmap's loop gain as learnt (no cut: ffmap_gain_at_p) */
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
    assert_string_equal(ctl_name(CTL_FFMAP), "ffmap");
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
            double err = fabs(bp_o_seen[i] - o[i] * 32768);
            wo = err > wo ? err : wo;
            assert_true(err <= 12.0);
            oo[i] = bp_o_seen[i] / 32768.0;
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

    /* ffmap: its loop gain learns nothing against a stop, and again without one */
    ctl_select(CTL_FFMAP);
    in = mk(3000, 2900, CTL_AT_CLOSED);     /* short of flow (under target >> FFMAP_BIG_SHIFT), closing refused */
    for (int k = 0; k < 3 * FFMAP_WARM; k++)
        ctl_step(&in);
    assert_int_equal(ctl_st.fm.gain, FFMAP_G_INIT);
    in.valve_limit = 0;
    for (int k = 0; k < FFMAP_SLOW_N && ctl_st.fm.gain == FFMAP_G_INIT; k++)
        ctl_step(&in);
    assert_int_equal(ctl_st.fm.gain, FFMAP_G_INIT + FFMAP_G_INIT * 3 / 32);     /* slower than told: it rises by 3/32 */
    for (int k = 0; k < 3 * FFMAP_SLOW_N; k++)
        ctl_step(&in);
    assert_true(ctl_st.fm.gain > FFMAP_G_INIT + FFMAP_G_INIT / 4);
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

/* ffmap: the output stage knows the motor's running friction. A motion m (share of full speed
 * for one period) is sent at the duty d_run + m (1 - d_run); one too small for the smallest
 * pulse (Min duty) is owed and sent with the next. */
static void test_ctl_ffmap_output_knows_the_running_friction(void **state)
{
    (void)state;
    double run = CTLTW_RUN, m;
    ctl_select(CTL_FFMAP);
    ctl_st.fm.gain = 256;                      /* the gain Valve time gives (the twin's) */
    ctl_in_t in = mk(2000, 1985, 0);        /* 0.15 L/min short of 20 L/min: outside the band */
    q15_t d = ctl_step(&in);                /* from rest: the integral alone */
    m = ctltw_drive(ctltw_pid_du_stroke(0.15, 0.15, 0.15, CTLTW_FFMAP_KP, CTLTW_FFMAP_KI, CTLTW_FFMAP_KD), 40);
    assert_true(run + m * (1 - run) < CTLTW_STICTION);  /* under Min duty: owed */
    assert_int_equal(d, 0);
    assert_true(fabs(ctl_carry_now() / 32768.0 - m) < 3e-4);
    d = ctl_step(&in);                      /* twice that is worth a pulse */
    assert_true(run + 2 * m * (1 - run) >= CTLTW_STICTION);
    assert_true(fabs(d / 32768.0 - (run + 2 * m * (1 - run))) < 5e-4);
    assert_int_equal(ctl_carry_now(), 0);
    print_message("ffmap: motion %.4f owed, then sent at duty %.4f (d_run %.3f)\n", m, d / 32768.0, run);
}

/* ffmap: above FFMAP_P_REF (200 kPa) the loop gain is cut by sqrt(FFMAP_P_REF / P): the bypass's hold
 * on the boom's flow grows with the pressure. The same error from rest asks 2/3 of the motion at
 * 450 kPa, the same at 100 kPa as at 200 (no boost below). */
static void test_ctl_ffmap_cuts_its_gain_above_the_reference_pressure(void **state)
{
    (void)state;
    static const uint16_t p[3] = {200, 450, 100};
    double run = CTLTW_RUN, m[3];
    for (int i = 0; i < 3; i++) {
        ctl_select(CTL_FFMAP);
        ctl_in_t in = mk(2000, 1800, 0);    /* 2 L/min short: a pulse at once */
        in.pressure_kpa = p[i];
        q15_t d = ctl_step(&in);
        assert_true(d > 0);
        m[i] = (d / 32768.0 - run) / (1 - run);     /* the motion asked */
    }
    print_message("ffmap: motion at 450 kPa %.3f of that at 200, at 100 kPa %.3f\n", m[1] / m[0], m[2] / m[0]);
    assert_true(fabs(m[1] / m[0] - sqrt(200.0 / 450)) < 0.01);
    assert_true(fabs(m[2] / m[0] - 1) < 1e-3);
}

/* ffmap: a deadband with hysteresis on the error filtered over 4 periods. Within target/256 the
 * valve rests (only a slow integral: a pulse now and then, the same way); it wakes beyond
 * target/128, or at once when the target moves. */
static void test_ctl_ffmap_deadband_hysteresis(void **state)
{
    (void)state;
    ctl_select(CTL_FFMAP);
    ctl_in_t in = mk(4000, 4000, 0);
    ctl_step(&in);
    assert_int_equal(ctl_st.fm.rest, 1);
    int pulses = 0;
    for (int k = 0; k < 600; k++) {         /* 60 s at 0.3 % too much, with +-0.3 % of noise */
        in.flow_lpm_x100 = (int16_t)(4012 + rnd(-12, 12));
        q15_t d = ctl_step(&in);
        assert_int_equal(ctl_st.fm.rest, 1);
        assert_true(d <= 0);                /* never the wrong way */
        pulses += d != 0;
    }
    assert_true(pulses >= 1);
    in.flow_lpm_x100 = 4026;                /* 0.65 % too much: still resting */
    for (int k = 0; k < 20; k++)
        ctl_step(&in);
    assert_int_equal(ctl_st.fm.rest, 1);
    in.flow_lpm_x100 = 4040;                /* 1 % too much: wakes */
    for (int k = 0; k < 10 && ctl_st.fm.rest; k++)
        ctl_step(&in);
    assert_int_equal(ctl_st.fm.rest, 0);
    in = mk(4000, 4000, 0);
    for (int k = 0; k < 10; k++)
        ctl_step(&in);
    assert_int_equal(ctl_st.fm.rest, 1);
    in.target_lpm_x100 = 4100;              /* the target moves 2.5 %: wakes at once */
    ctl_step(&in);
    assert_int_equal(ctl_st.fm.rest, 0);
    print_message("ffmap: %d pulses in 60 s inside the band\n", pulses);
}

/* ffmap: a valve stiffer than Min duty. Small pulses one way that leave the flow where it was
 * are a stall: the smallest pulse grows, step by step, up to its bound. */
static void test_ctl_ffmap_learns_a_stiffer_break_away(void **state)
{
    (void)state;
    ctl_select(CTL_FFMAP);
    ctl_in_t in = mk(2000, 1985, 0);        /* the valve never moves: the error stays */
    for (int k = 0; k < 1000; k++)
        ctl_step(&in);
    assert_true(ctl_st.fm.brk_extra >= 3 * FFMAP_BRK_STEP && ctl_st.fm.brk_extra <= FFMAP_BRK_MAX);
    /* a valve that answers: the flow moves after each pulse (by less than the deadband, while
     * the target keeps running away from it), nothing is learnt */
    ctl_select(CTL_FFMAP);
    in = mk(2000, 1970, 0);
    for (int k = 0; k < 400; k++) {
        if (ctl_step(&in) > 0)
            in.flow_lpm_x100 += 5;
        if (in.flow_lpm_x100 >= in.target_lpm_x100 - 5)
            in.target_lpm_x100 += 25;       /* the target ran away again */
    }
    assert_int_equal(ctl_st.fm.brk_extra, 0);
}

/* ffmap: a valve faster than told hunts: reversals in quick succession near the target lower the
 * loop gain (to where the pulses are near the smallest: the valve's resolution); in the first
 * FFMAP_WARM periods only at a steady target (not while the speed moves the target). Mode 0: the
 * flow holds the target through the start and swings after it; 1: it swings from the start, the
 * target steady; 2: likewise, the target moving 2 % a period in the start. */
static void test_ctl_ffmap_learns_the_loop_gain(void **state)
{
    (void)state;
    for (int mode = 0; mode < 3; mode++) {
        ctl_select(CTL_FFMAP);
        ctl_st.fm.gain = 256;                  /* the full gain (a new valve starts at 3/4 of it: */
        ctl_in_t in = mk(3000, 3000, 0);    /* there this swing of the flow sends no reversals) */
        int g_warm = 0;
        for (int k = 0; k < 2000; k++) {    /* the flow swings +-5 % every 3 periods */
            in.target_lpm_x100 = (int16_t)(mode == 2 && k < FFMAP_WARM && k % 2 ? 3060 : 3000);
            in.flow_lpm_x100 = (int16_t)(mode == 0 && k < FFMAP_WARM ? 3000 : (k / 3) % 2 ? 3150 : 2850);
            ctl_step(&in);
            if (k == FFMAP_WARM - 2)
                g_warm = ctl_st.fm.gain;
        }
        print_message("ffmap: gain after 10 s %.3f, 200 s %.3f (mode %d)\n",
                      g_warm / 256.0, ctl_st.fm.gain / 256.0, mode);
        if (mode == 1) {
            assert_true(g_warm < 256);
        } else {
            assert_int_equal(g_warm, 256);
        }
        if (mode == 0)
            assert_true(ctl_st.fm.gain < 128);
        else
            assert_true(ctl_st.fm.gain <= g_warm);
    }
}

/* ffmap: swings of the flow beyond target >> FFMAP_BIG_SHIFT, two in a row, cut the loop gain. In
 * a start (the first FFMAP_WARM periods) a half cycle that ended in FFMAP_TOP_N periods or more at the
 * top duty takes half at once: a valve much faster than told swings at full duty from its first
 * closing, and quarters came three swings late (family plant 192 of SEED=236). Shorter runs at
 * the top duty (a stiff valve's stick-slip, a target that ramps) and any swing after the start
 * take a quarter: a gain cut that deep leaves a stiff valve creeping at drives near its running
 * friction (OFF_RATE). The flow is a triangle of +-amp around the target, `half` periods a way. */
static int swing_cut(int amp, int half, int warm)
{
    ctl_in_t in = mk(3000, 3000, 0);
    int g0, k;
    ctl_select(CTL_FFMAP);
    ctl_st.fm.gain = 256;
    while (ctl_st.fm.warm < warm) {         /* a start that is over, at the start's gain */
        ctl_step(&in);
        ctl_st.fm.gain = 256;
    }
    g0 = ctl_st.fm.gain;
    for (k = 0; k < FFMAP_WARM - 10 && ctl_st.fm.gain == g0; k++) {
        int ph = k % (2 * half);
        in.flow_lpm_x100 = (int16_t)(3000 - amp + 2 * amp * (ph < half ? ph : 2 * half - ph) / half);
        ctl_step(&in);
    }
    print_message("ffmap: the flow +-%d %% every %d periods%s: gain %d -> %d after %d periods\n", amp / 30,
                  half, warm ? ", after the start" : "", g0, ctl_st.fm.gain, k);
    return ctl_st.fm.gain;
}

static void test_ctl_ffmap_halves_a_start_gain_on_full_duty_swings(void **state)
{
    (void)state;
    assert_int_equal(swing_cut(1500, 8, 0), 128);       /* 4 periods at full duty, then turned */
    assert_int_equal(swing_cut(300, 3, 0), 192);        /* 1 period at full duty */
    assert_int_equal(swing_cut(1500, 8, FFMAP_WARM), 192); /* after the start */
}

/* ffmap: a gain cut in a start's first periods (a stiff valve's stick-slip looks like a fast
 * one's swings) comes back at once while the error stays one way, by 3/32 every 5 periods of a
 * big error (it waited for FFMAP_WARM before); a gain where the start found it is not raised then
 * (the line fills); and a refusal to close holds the raise only while the error asks to close. */
static void test_ctl_ffmap_raises_a_gain_cut_in_the_start_at_once(void **state)
{
    (void)state;
    ctl_in_t in = mk(3000, 2500, 0);
    ctl_select(CTL_FFMAP);
    for (int k = 0; k < 40; k++)            /* the start's own gain: nothing raised while warm */
        ctl_step(&in);
    assert_int_equal(ctl_st.fm.gain, FFMAP_G_INIT);
    ctl_st.fm.gain = 64;                       /* cut by the start's swings */
    for (int k = 0; k < 20; k++)
        ctl_step(&in);
    assert_true(ctl_st.fm.warm < FFMAP_WARM);
    print_message("ffmap: a gain cut to 0.25 in the start, 2 s of a 17 %% error later %.3f\n", ctl_st.fm.gain / 256.0);
    assert_int_equal(ctl_st.fm.gain, 89);      /* 64 -> 70 -> 76 -> 82 -> 89 */
    ctl_select(CTL_FFMAP);
    ctl_step(&in);
    ctl_st.fm.gain = 64;
    in.valve_limit = CTL_NO_CLOSE;          /* the error asks to close: refused, no raise */
    for (int k = 0; k < 20; k++)
        ctl_step(&in);
    assert_int_equal(ctl_st.fm.gain, 64);
    in.flow_lpm_x100 = 3500;                /* ... it asks to open: raised */
    for (int k = 0; k < 21; k++)
        ctl_step(&in);
    assert_int_equal(ctl_st.fm.gain, 89);
}

/* ffmap: the slow rule raises no gain at or over FFMAP_G_INIT while the drive is at its top (no
 * gain moves the valve faster there: on a slow valve whose slack is taken up at full duty each
 * way those raises end in a cycle at full duty); under FFMAP_G_INIT, or off the
 * top, a long error one way raises it as before. */
static void test_ctl_ffmap_raises_no_gain_at_full_duty(void **state)
{
    static const struct { int flow, gain, top; } c[] = {
        {2500, FFMAP_G_INIT, 1}, {2500, FFMAP_G_INIT - 1, 1}, {2940, FFMAP_G_INIT, 0},
    };
    (void)state;
    for (unsigned i = 0; i < sizeof c / sizeof c[0]; i++) {
        ctl_in_t in = mk(3000, 3000, 0);
        int top = 0, k;
        ctl_select(CTL_FFMAP);
        do                                  /* the start over, at the target */
            ctl_step(&in);
        while (ctl_st.fm.warm < FFMAP_WARM);
        ctl_st.fm.gain = (int16_t)c[i].gain;
        in.flow_lpm_x100 = (int16_t)c[i].flow;
        for (k = 0; k < 40; k++) {          /* 4 s of the error one way */
            q15_t d = ctl_step(&in);
            top += d >= 32700;
        }
        print_message("ffmap: 4 s %.1f %% under the target from a gain of %d, %d periods at full duty: gain %d\n",
                      (3000 - c[i].flow) / 30.0, c[i].gain, top, ctl_st.fm.gain);
        assert_true(c[i].top ? top >= 35 : top == 0);
        if (c[i].top && c[i].gain >= FFMAP_G_INIT)
            assert_int_equal(ctl_st.fm.gain, c[i].gain);
        else
            assert_true(ctl_st.fm.gain > c[i].gain);
    }
}

/* A toy valve and line for the duty cap: the motor runs at (duty - 0.12) / 0.88 of full speed
 * over a stroke of `travel` periods, the flow follows `lpm_per_stroke` times the closure beyond
 * 0.5 of it with a lag, and the meter reads it two periods late. Returns the largest duty and
 * the flow's swing (largest - smallest, x100 L/min) over the last 300 of `periods`. */
static void cap_toy(int periods, double travel, double lpm_per_stroke, int target, double *duty_max, int *swing)
{
    double pos = 0.5, flow = 0, seen[3] = {0, 0, 0};
    int lo = 32767, hi = 0;
    *duty_max = 0;
    for (int k = 0; k < periods; k++) {
        ctl_in_t in = mk(target, (int)(seen[0] * 100), 0);
        double d = ctl_step(&in) / 32768.0, a = fabs(d);
        if (k >= periods - 300) {
            *duty_max = a > *duty_max ? a : *duty_max;
            lo = in.flow_lpm_x100 < lo ? in.flow_lpm_x100 : lo;
            hi = in.flow_lpm_x100 > hi ? in.flow_lpm_x100 : hi;
        }
        if (a > 0.2)
            pos += (d > 0 ? 1 : -1) * (a - 0.12) / 0.88 / travel;
        pos = pos < 0 ? 0 : pos > 1 ? 1 : pos;
        flow += ((pos > 0.5 ? (pos - 0.5) * lpm_per_stroke : 0) - flow) * 0.5;
        seen[0] = seen[1];
        seen[1] = seen[2];
        seen[2] = flow;
    }
    *swing = hi - lo;
}

/* ffmap: a valve that moves the flow by more than a quarter of the target in one period at full
 * duty (here a 1.6 s valve told 4 s, where a fifth of the stroke swings the flow by 60 L/min
 * around a 15 L/min target) gets its top duty cut, and the swing from nothing to twice the
 * target stops; a valve that moves it by less keeps full duty (a 20 % step of the target
 * answered at full duty). */
static void test_ctl_ffmap_caps_the_duty_of_a_valve_that_swings_the_flow(void **state)
{
    (void)state;
    double duty;
    int swing;
    ctl_select(CTL_FFMAP);
    assert_int_equal(ctl_st.fm.cap, 255);
    cap_toy(1200, 16, 300, 1500, &duty, &swing);
    print_message("ffmap: a fast valve's duty cap %d/256, largest duty %.2f, the flow's swing %.2f L/min\n",
                  ctl_st.fm.cap, duty, swing / 100.0);
    assert_true(ctl_st.fm.cap < 128);
    assert_true(duty < 0.6);
    assert_true(swing < 1500);
    ctl_select(CTL_FFMAP);
    cap_toy(200, 40, 60, 1500, &duty, &swing);
    cap_toy(300, 40, 60, 2500, &duty, &swing);      /* a step of the target */
    assert_int_equal(ctl_st.fm.cap, 255);
    assert_true(duty > 0.99);
}

/* A toy fast valve (a stroke in 15 periods) that breaks away at `brk` and runs from 0.6 of it,
 * its motor keeping a third of its speed into the next period; the flow goes as 70 L/min a stroke
 * around a 20 L/min target with a lag, read two periods late, with +-0.05 L/min of noise, on
 * a line whose flow sinks by 0.01 L/min a period, which the valve keeps up with by closing.
 * `start` puts it at the target; runs `periods` periods and returns the flow's largest minus
 * smallest (x100 L/min) over them. */
static struct { double pos, v, flow, sink, seen[3]; } lt;
static int lone_toy(int start, int periods, double brk)
{
    int lo = 32767, hi = 0;
    if (start) {
        lt.pos = 0.5;
        lt.v = lt.sink = 0;
        lt.flow = lt.seen[0] = lt.seen[1] = lt.seen[2] = 20;
    }
    for (int k = 0; k < periods; k++) {
        ctl_in_t in = mk(2000, (int)(lt.seen[0] * 100) + rnd(-5, 5), 0);
        double d = ctl_step(&in) / 32768.0, a = fabs(d), run = 0.6 * brk;
        lo = in.flow_lpm_x100 < lo ? in.flow_lpm_x100 : lo;
        hi = in.flow_lpm_x100 > hi ? in.flow_lpm_x100 : hi;
        lt.v = a >= brk ? (d > 0 ? 1 : -1) * (a - run) / (1 - run) : lt.v / 3;
        lt.pos += lt.v / 15;
        lt.pos = lt.pos < 0 ? 0 : lt.pos > 1 ? 1 : lt.pos;
        lt.sink += 0.01;
        lt.flow += (20 + (lt.pos - 0.5) * 70 - lt.sink - lt.flow) * 0.5;
        lt.seen[0] = lt.seen[1];
        lt.seen[1] = lt.seen[2];
        lt.seen[2] = lt.flow;
    }
    return hi - lo;
}

/* ffmap: on a fast valve that breaks away at half its Min duty (told 0.2), each smallest pulse
 * steps the flow by ~5 % of the target (0.15 of full speed for a tenth of a 1.5 s stroke, and the
 * motor's run-on, at 70 L/min a stroke), three times the band: lone pulses take the smallest
 * pulse down to half Min duty, and the flow's saw-tooth shrinks. A valve that breaks away at its
 * Min duty is taken at most one step under it (there a stall sends it back); one told 15 s keeps
 * it (each pulse a tenth as far, under 1/64 of the target). */
static void test_ctl_ffmap_lone_pulses_take_the_smallest_pulse_down(void **state)
{
    (void)state;
    int early, late;
    assert_int_equal(param_set(P_VALVE_TRAVEL, 15), 1);     /* 1.5 s, as the toy */
    ctl_select(CTL_FFMAP);
    (void)lone_toy(1, FFMAP_WARM, 0.1);                     /* the start */
    early = lone_toy(0, 600, 0.1);
    (void)lone_toy(0, 1200, 0.1);
    late = lone_toy(0, 600, 0.1);
    print_message("ffmap: a valve breaking away at 0.1, told 0.2: the smallest pulse %+d (Q15), "
                  "the flow's swing %.2f then %.2f L/min\n", ctl_st.fm.brk_extra, early / 100.0, late / 100.0);
    assert_true(ctl_st.fm.brk_extra < -FFMAP_BRK_DN && ctl_st.fm.brk_extra >= -(ctl_stiction >> 1));
    assert_true(late < early / 3);
    ctl_select(CTL_FFMAP);
    (void)lone_toy(1, 3000, 0.2);
    print_message("ffmap: one breaking away at 0.2: the smallest pulse %+d\n", ctl_st.fm.brk_extra);
    assert_true(ctl_st.fm.brk_extra >= -FFMAP_BRK_DN);
    assert_int_equal(param_set(P_VALVE_TRAVEL, 150), 1);
    ctl_select(CTL_FFMAP);
    (void)lone_toy(1, 3000, 0.1);
    print_message("ffmap: told 15 s: the smallest pulse %+d\n", ctl_st.fm.brk_extra);
    assert_true(ctl_st.fm.brk_extra >= 0);
}

/* A toy valve twice as fast as told (a stroke in 20 periods, told 4 s): the motor runs at
 * (duty - 0.12) / 0.88 of full speed, the flow follows 60 L/min a stroke of closure beyond 0.3
 * with a lag, the meter reads it two periods late. From a flow settled on 30 L/min (the start's
 * gain, `g`), the target steps to 33 L/min; returns the flow's largest overshoot past 33 L/min
 * (x100 L/min) over the next 60 periods. */
static int fast_step(int g)
{
    double pos = 0.3 + 30.0 / 60, flow = 30, seen[3] = {30, 30, 30};
    int target = 3000, over = 0;
    ctl_select(CTL_FFMAP);
    ctl_st.fm.gain = (int16_t)g;
    for (int k = 0; k < 80; k++) {
        if (k == 20)
            target = 3300;
        ctl_in_t in = mk(target, (int)(seen[0] * 100), 0);
        double d = ctl_step(&in) / 32768.0, a = fabs(d);
        if (a > 0.2)
            pos += (d > 0 ? 1 : -1) * (a - 0.12) / 0.88 / 20;
        pos = pos < 0 ? 0 : pos > 1 ? 1 : pos;
        flow += ((pos > 0.3 ? (pos - 0.3) * 60 : 0) - flow) * 0.5;
        seen[0] = seen[1];
        seen[1] = seen[2];
        seen[2] = flow;
        if (k > 20 && flow * 100 - 3300 > over)
            over = (int)(flow * 100 - 3300);
    }
    return over;
}

/* ffmap: a valve nothing was learnt of starts at 3/4 of the gain Valve time gives (FFMAP_G_INIT):
 * the family's valves run 1.5-12 s, and one much faster than told overshot its first changes
 * at the full gain (OVERPRESSURE at targets near P max); a slower one's gain rises by 3/32 every FFMAP_SLOW_N periods it lags. */
static void test_ctl_ffmap_starts_a_new_valve_under_the_full_gain(void **state)
{
    (void)state;
    int full = fast_step(256), start = fast_step(FFMAP_G_INIT);
    print_message("ffmap: a valve twice as fast as told, a 10 %% step: overshoot %.2f L/min at the full "
                  "gain, %.2f at the start's\n", full / 100.0, start / 100.0);
    assert_true(start < full * 3 / 4);
    /* a newly told valve (Valve time) starts there: 3/4 of the full gain's 256 */
    ctl_select(CTL_FFMAP);
    ctl_st.fm.gain = 256;
    assert_int_equal(param_set(P_VALVE_TRAVEL, 50), 1);
    ctl_in_t in = mk(3000, 3000, 0);
    ctl_step(&in);
    assert_int_equal(ctl_st.fm.gain, 256 * 3 / 4);
    params_defaults();
    ctl_reset(0);                   /* the defaults derived again for the tests after this one */
}

/* ffmap: what it learnt of the valve (break-away, loop gain) stays through other settings'
 * changes, and goes when the operator tells new Min duty, Backlash or Valve time values: they
 * are taken as given. */
static void test_ctl_ffmap_valve_parameters_reset_what_was_learned(void **state)
{
    (void)state;
    ctl_select(CTL_FFMAP);
    ctl_in_t in = mk(3000, 3000, 0);
    ctl_step(&in);
    for (int p = 0; p < 3; p++) {
        ctl_st.fm.brk_extra = FFMAP_BRK_STEP;
        ctl_st.fm.gain = 128;
        ctl_st.fm.cap = 100;
        assert_int_equal(param_set(P_RATE, 1400 + p), 1);
        ctl_step(&in);
        assert_int_equal(ctl_st.fm.brk_extra, FFMAP_BRK_STEP);
        assert_int_equal(ctl_st.fm.gain, 128);
        assert_int_equal(ctl_st.fm.cap, 100);
        if (p == 0)
            assert_int_equal(param_set(P_VALVE_SLACK, 15), 1);
        else if (p == 1)
            assert_int_equal(param_set(P_VALVE_BRK, 30), 1);
        else
            assert_int_equal(param_set(P_VALVE_TRAVEL, 60), 1);
        ctl_step(&in);
        assert_int_equal(ctl_st.fm.brk_extra, 0);
        assert_int_equal(ctl_st.fm.gain, FFMAP_G_INIT);
        assert_int_equal(ctl_st.fm.cap, 255);
    }
    assert_int_equal(CTL_STICTION, Q15(0.3));
    params_defaults();
    ctl_reset(0);                   /* the defaults derived again for the tests after this one */
    assert_int_equal(CTL_STICTION, CTL_STICTION_DEF);
}

/* ffmap: a reversal waits for a motion worth 3/4 of the told backlash. The backlash b (a share
 * of the stroke) is b x Valve time / 0.1 s periods at full duty: the defaults' 2 % of 4 s is 0.8,
 * 3/4 of it FFMAP_REV_MIN; 2 % of 1.7 s 0.34, 3/4 of it 0.255; no backlash gives the floor, a slow
 * valve's 4 % of 10 s (3.0) the ceiling. */
static void test_ctl_ffmap_a_reversal_waits_for_the_told_backlash(void **state)
{
    static const struct { int travel, slack; double want; } told[] = {
        {40, 20, 0.6}, {17, 20, 0.255}, {17, 0, FFMAP_REV_LOW / 32768.0}, {100, 40, FFMAP_REV_MIN / 32768.0},
    };
    (void)state;
    for (unsigned i = 0; i < sizeof told / sizeof told[0]; i++) {
        ctl_select(CTL_FFMAP);
        assert_int_equal(param_set(P_VALVE_TRAVEL, told[i].travel), 1);
        assert_int_equal(param_set(P_VALVE_SLACK, told[i].slack), 1);
        ctl_in_t in = mk(3000, 3000, 0);
        ctl_step(&in);
        print_message("ffmap: Valve time %.1f s, Backlash %.1f %%: a reversal after %.4f of a period\n",
                      told[i].travel / 10.0, told[i].slack / 10.0, ctl_st.fm.rev_min / 32768.0);
        assert_true(fabs(ctl_st.fm.rev_min / 32768.0 - told[i].want) < 0.0005);
        params_defaults();
    }
    ctl_reset(0);                   /* the defaults derived again for the tests after this one */
}

/* ---- ffmap against its double-precision twin ----------------------------------------------- */
/* A toy plant: the valve moves by the running-friction law of a valve stiffer or faster than
 * told, the flow follows the closure with a lag, the meter is noisy, the target steps and ramps;
 * end stops now and then. Each step the twin starts from the firmware's state and must give the
 * same drive within 12 LSB and 0.2 %; steps where a decision of the law lies within rounding of its
 * threshold may differ and are counted (they must be rare: about one in ten here, as the toy's
 * target steps and ramps keep the law near its thresholds). Sections are shut and opened again
 * now and then: the gain's factor moves and the step holds (ffmap.c). */
static void test_ctl_ffmap_matches_twin(void **state)
{
    (void)state;
    /* (the fourth: a valve three times as fast as told moving the flow by 250 L/min a stroke,
     * read two periods late: its duty is capped; the fifth: a valve that breaks away at half its
     * Min duty, moving the flow by 120 L/min a stroke: its smallest pulse is taken down) */
    static const int travels[5] = {40, 15, 100, 40, 15}, brks[5] = {20, 30, 12, 20, 20};
    static const double gains[5] = {50, 50, 50, 250, 120};
    static const uint8_t noz_qs[5] = {4, 6, 8, 4, 4};
    double worst = 0;
    int checked = 0, near = 0, pulses = 0, rests = 0, g_moved = 0, brk_moved = 0, capped = 0, switches = 0, held = 0;
    int brk_under = 0;
    for (int c = 0; c < 5; c++) {
        assert_int_equal(param_set(P_VALVE_TRAVEL, (uint16_t)travels[c]), 1);
        assert_int_equal(param_set(P_VALVE_BRK, (uint16_t)brks[c]), 1);
        ctl_select(CTL_FFMAP);
        target_noz_q = noz_qs[c];       /* some sections shut: the gain's factor (target.c) */
        double pos = 0.5, flow = 30, target = 30, t_true = travels[c] * (c % 2 ? 0.5 : 1.5);
        double brk_true = c == 4 ? brks[c] / 200.0 : (brks[c] + 8) / 100.0, run_true = brk_true * 0.6, v = 0;
        double seen[3] = {30, 30, 30};
        int first = 1;
        if (c == 3)
            t_true = travels[c] / 3.0;
        for (int k = 0; k < 12000; k++) {
            if (k % 400 == 0)
                target = 15 + rnd(0, 3000) / 100.0;
            else if (k % 400 < 60)
                target += (rnd(0, 100) - 50) / 500.0;
            if (k % 400 == 200 || k % 400 == 230) {
                /* sections shut and opened again: the factor moves and the step holds (target.c,
                 * ffmap.c) */
                target_noz_q = target_noz_q == noz_qs[c] ? (uint8_t)(noz_qs[c] + 2) : noz_qs[c];
                target_noz_new = 1;
                switches++;
            }
            uint8_t lim = pos >= 1 ? CTL_AT_CLOSED : pos <= 0 ? CTL_AT_OPEN : 0;
            ctl_in_t in = mk((int)(target * 100), (int)((c == 3 ? seen[0] : flow) * 100 + rnd(-20, 20)), lim);
            in.pressure_kpa = (uint16_t)(flow * flow / 4);  /* 56-506 kPa: both sides of FFMAP_P_REF */
            ctltw_ffmap_t tw;
            ctltw_ffmap_load(&tw, &ctl_st.fm, first, ctl_carry_now());
            ctltw_ffmap_in_t ti = {in.target_lpm_x100 / 100.0, in.flow_lpm_x100 / 100.0, travels[c], lim,
                                in.pressure_kpa, target_noz_q, target_noz_new};
            ctltw_ffmap_out_t o = ctltw_ffmap_step(&tw, &ti);
            q15_t d = ctl_step(&in);
            first = 0;
            if (o.near) {
                near++;
            } else {
                /* the rounding of du to 1/16 x100 L/min, of T x 0.2048 to Q8 and of the gain */
                double err = fabs(d / 32768.0 - o.drive) - 0.002 * fabs(o.drive);
                worst = err > worst ? err : worst;
                assert_true(err < 12.0 / 32768);
                assert_int_equal(ctl_st.fm.rest, o.rest);
                assert_true(fabs(tw.gain - ctl_st.fm.gain / 256.0) < 1e-9);     /* the gain's rules */
                assert_int_equal(ffmap_rlim, tw.rlim);     /* the last reversal near the smallest */
                assert_int_equal(ffmap_rl1, tw.rl1);
                assert_true(fabs(tw.brk_extra - ctl_st.fm.brk_extra / 32768.0) < 1e-9);  /* the smallest pulse's */
                checked++;
            }
            pulses += d != 0;
            held += ctl_st.fm.hold != 0;
            rests += ctl_st.fm.rest;
            g_moved |= ctl_st.fm.gain != FFMAP_G_INIT;
            brk_moved |= ctl_st.fm.brk_extra != 0;
            brk_under += ctl_st.fm.brk_extra < 0;
            capped += ctl_st.fm.cap != 255;
            /* the toy valve and line */
            double a = fabs(d / 32768.0);
            v = (a >= (v ? run_true : brk_true)) ? (d > 0 ? 1 : -1) * (a - run_true) / (1 - run_true) : 0;
            pos += v / t_true;
            pos = pos < 0 ? 0 : pos > 1 ? 1 : pos;
            flow += (8 + gains[c] * pos - flow) * 0.4;
            seen[0] = seen[1];
            seen[1] = seen[2];
            seen[2] = flow;
        }
    }
    target_noz_q = 4;
    params_defaults();
    ctl_reset(0);
    print_message("ffmap vs twin: %d steps checked, worst %.1f LSB beyond 0.2 %%; %d near a threshold; %d pulses, %d resting, %d capped, %d under Min duty; %d section switches, %d steps held\n",
                  checked, worst * 32768, near, pulses, rests, capped, brk_under, switches, held);
    assert_true(checked > 30000 && near < checked / 8);
    assert_true(pulses > 1000 && rests > 3000 && g_moved && brk_moved && capped > 100 && brk_under > 1000);
    assert_true(switches >= 200 && held >= 4 * switches);
}

/* ---- the peers: aog and raven ------------------------------------------------------------- */
#define Q15_OF(counts) ((counts) * 32767.0 / 255.0)

/* what a step asked for: what it sent and what the output stage kept back since the last */
static double asked(ctl_in_t *in)
{
    q15_t c0 = ctl_carry_now();
    q15_t d = ctl_step(in);
    return d + ctl_carry_now() - c0;
}

/* aog against RateControl's valve PID, worked by hand at the release's defaults (Kp 45 and Ki 70
 * as the app sets them: 0.45, 0.70; brake point 35 %, slow adjust 60 %, min PWM 5, max 255: an
 * authority of 250 counts), Ki 0 first, and a 30 L/min target (dead band 1.5 %: 0.45 L/min);
 * within 8 LSB of Q15 (Kp rounded to Q11: 0.05 % of the drive, and the shifts' floors). */
static void test_ctl_aog_hand_worked_dead_band_brake_point_and_limits(void **state)
{
    (void)state;
    param_set(P_AOG_KI, 0);
    ctl_select(CTL_AOG);
    ctl_in_t in = mk(3000, 2960, 0);        /* 0.4 L/min short: 1.3 %, inside the dead band */
    assert_int_equal(ctl_step(&in), 0);
    assert_int_equal(ctl_carry_now(), 0);
    in = mk(3000, 2850, 0);                 /* 1.5 short: f 0.05, inside the brake point: 5 + 0.05 x 0.45 x 0.6 x 250 */
    assert_true(fabs(asked(&in) - Q15_OF(5 + 3.375)) <= 8.0);
    in = mk(3000, 1500, 0);                 /* 15 short: f 0.5, beyond it: 5 + 0.5 x 0.45 x 250 */
    assert_true(fabs(asked(&in) - Q15_OF(5 + 56.25)) <= 8.0);
    in = mk(3000, 4500, 0);                 /* 15 over: the other way */
    assert_true(fabs(asked(&in) + Q15_OF(5 + 56.25)) <= 8.0);
    in = mk(3000, 9000, 0);                 /* 60 over: limited to the target, f -1 */
    assert_true(fabs(asked(&in) + Q15_OF(5 + 112.5)) <= 8.0);
    /* sections closed: a 15 L/min target keeps the 30 L/min reference, 3 short is f 0.1 */
    in = mk(1500, 1200, 0);
    assert_true(fabs(asked(&in) - Q15_OF(5 + 0.1 * 0.45 * 0.6 * 250)) <= 8.0);
    param_set(P_AOG_KP, 500);               /* Kp 5.0: 15 short asks 625 counts, held at max PWM */
    in = mk(3000, 1500, 0);
    assert_int_equal(ctl_step(&in), 32767);
    param_set(P_AOG_KP, 45);
    param_set(P_AOG_BRAKE, 100);            /* brake point 10 %: 4.5 short (15 %) is beyond it now */
    in = mk(3000, 2550, 0);
    assert_true(fabs(asked(&in) - Q15_OF(5 + 0.15 * 0.45 * 250)) <= 8.0);
}

/* aog's integral, by hand at the defaults: only inside the brake point (2/3 of f x 0.70 x 250 a
 * period, a 100 ms period of the 150 ms loop, at most 2/3 of 25 counts), cleared when the flow
 * crosses the target beyond the dead band. */
static void test_ctl_aog_hand_worked_integral(void **state)
{
    (void)state;
    ctl_select(CTL_AOG);
    ctl_in_t in = mk(3000, 1500, 0);        /* beyond the brake point: no integral */
    assert_true(fabs(asked(&in) - Q15_OF(5 + 56.25)) <= 8.0);
    in = mk(3000, 2850, 0);                 /* f 0.05: integral 0.05 x 0.70 x 250 x 2/3 = 5.833 */
    assert_true(fabs(asked(&in) - Q15_OF(5 + 3.375 + 5.8333)) <= 8.0);
    assert_true(fabs(asked(&in) - Q15_OF(5 + 3.375 + 11.6667)) <= 8.0);
    in = mk(3000, 2100, 0);                 /* f 0.3: 0.3 x 0.7 x 250 x 2/3 = 35, held at 16.67 a period */
    assert_true(fabs(asked(&in) - Q15_OF(5 + 20.25 + 28.3333)) <= 8.0);
    in = mk(3000, 3150, 0);                 /* 1.5 over: crossed beyond the dead band, cleared, then -5.833 */
    assert_true(fabs(asked(&in) + Q15_OF(5 + 3.375 + 5.8333)) <= 8.0);
    in = mk(3000, 3010, 0);                 /* in the dead band: not driven, the integral cleared */
    assert_int_equal(ctl_step(&in), 0);
    assert_int_equal(ctl_st.ag.integ, 0);
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
    static const uint16_t aog_set[][6] = {{45, 70, 350, 60, 5, 255}, {250, 300, 100, 30, 40, 200},
                                          {1500, 2000, 500, 100, 0, 255}};
    static const uint16_t cals[] = {2123, 743, 9991, 1015, 5555};
    double worst = 0;
    int checked = 0;
    for (unsigned c = 0; c < 3; c++) {
        param_set(P_AOG_KP, aog_set[c][0]);
        param_set(P_AOG_KI, aog_set[c][1]);
        param_set(P_AOG_BRAKE, aog_set[c][2]);
        param_set(P_AOG_SLOW, aog_set[c][3]);
        param_set(P_AOG_MIN, aog_set[c][4]);
        param_set(P_AOG_MAX, aog_set[c][5]);
        ctl_select(CTL_AOG);
        ctltw_ag_t tw = {aog_set[c][0], aog_set[c][1], aog_set[c][2] / 1000.0, aog_set[c][3] / 100.0,
                         aog_set[c][4], aog_set[c][5], 0, 0, 1, 1};
        for (int k = 0; k < 3000; k++) {
            int t = rnd(500, 5000), f = t + rnd(-t / 2, t / 2);
            ctl_in_t in = mk(t, f, 0);
            q15_t carry0 = ctl_carry_now();
            double i0 = tw.integ;
            if (k) {                /* each step from the firmware's integral: the law compared, not the sum's rounding */
                tw.integ = ctl_st.ag.integ / 32767.0 * 255.0;
                tw.pos = ctl_st.ag.pos;
            }
            q15_t d = ctl_step(&in);
            double tw_d = ctltw_ag_step(&tw, t / 100.0, f / 100.0);
            double ae = abs(t - f) / 100.0, tl = t / 100.0;
            /* the thresholds as the firmware holds them (x100 L/min and Q15, floor) may differ from
             * the twin's a little: such a step is not compared, and the integrals re-synchronised */
            if (fabs(ae - 0.015 * tl) <= 0.02 || fabs(ae / tw.ref - tw.brake) <= 0.001) {
                tw.integ = ctl_st.ag.integ / 32767.0 * 255.0;
                tw.pos = ctl_st.ag.pos;
                continue;
            }
            if (tw_d == 0) {
                assert_int_equal(d, 0);
                assert_int_equal(ctl_carry_now(), 0);
                (void)i0;                   /* (a dead band, or a change under 0.1 count) */
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
        cmocka_unit_test_setup(test_ctl_ffmap_output_knows_the_running_friction, setup),
        cmocka_unit_test_setup(test_ctl_ffmap_cuts_its_gain_above_the_reference_pressure, setup),
        cmocka_unit_test_setup(test_ctl_ffmap_deadband_hysteresis, setup),
        cmocka_unit_test_setup(test_ctl_ffmap_learns_a_stiffer_break_away, setup),
        cmocka_unit_test_setup(test_ctl_ffmap_learns_the_loop_gain, setup),
        cmocka_unit_test_setup(test_ctl_ffmap_halves_a_start_gain_on_full_duty_swings, setup),
        cmocka_unit_test_setup(test_ctl_ffmap_raises_a_gain_cut_in_the_start_at_once, setup),
        cmocka_unit_test_setup(test_ctl_ffmap_raises_no_gain_at_full_duty, setup),
        cmocka_unit_test_setup(test_ctl_ffmap_lone_pulses_take_the_smallest_pulse_down, setup),
        cmocka_unit_test_setup(test_ctl_ffmap_caps_the_duty_of_a_valve_that_swings_the_flow, setup),
        cmocka_unit_test_setup(test_ctl_ffmap_starts_a_new_valve_under_the_full_gain, setup),
        cmocka_unit_test_setup(test_ctl_ffmap_valve_parameters_reset_what_was_learned, setup),
        cmocka_unit_test_setup(test_ctl_ffmap_a_reversal_waits_for_the_told_backlash, setup),
        cmocka_unit_test_setup(test_ctl_ffmap_matches_twin, setup),
        cmocka_unit_test_setup(test_ctl_aog_hand_worked_dead_band_brake_point_and_limits, setup),
        cmocka_unit_test_setup(test_ctl_aog_hand_worked_integral, setup),
        cmocka_unit_test_setup(test_ctl_raven_hand_worked_dead_band_brake_point_and_backlash_pulse, setup),
        cmocka_unit_test_setup(test_ctl_peers_match_their_twins, setup),
    };
    return cmocka_run_group_tests_name("ctl", tests, NULL, NULL);
}

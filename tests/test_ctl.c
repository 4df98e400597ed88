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

/* ---- ffmap against its double-precision twin ----------------------------------------------- */
/* A toy plant in integers: the bypass valve (closure Q15, full stroke in T_travel periods at
 * full duty, 1.5 % backlash of its own, end stops), a convex closure -> boom flow curve on a
 * pump that follows the ground speed, a lag of a few periods and a noisy meter. */
typedef struct {
    int32_t pos;                    /* Q15 closure */
    int32_t slack;                  /* Q15 backlash still to take up */
    int dir;
    int32_t flow;                   /* x100 L/min in the boom */
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
    if (d == 0)
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
    int32_t pump = 5000 + 4 * speed_x100;                               /* 56 .. 94 L/min */
    int32_t g = (p->pos * (9830 + ((22938 * p->pos) >> 15))) >> 15;     /* boom share, Q15 */
    p->flow += ((pump * g >> 15) - p->flow) / 3;
    return (int)p->flow;
}

/* ffmap against the twin (tests/helper_ctl_twin.c), step by step from the same state: 6000
 * periods of the toy plant under target steps and ramps, targets that follow the speed or lie
 * out of reach (0, beyond the last node), speeds above and below P_MINF_SPEED, meter noise and
 * dropouts, end-stop flags (at the stops, and early near them: a switch, the relief's
 * overpressure), a restart half-way onto a slower valve (T_travel 40, then 64 periods: backlash
 * left to take up between steps); the map learns (warm-up passed). On each step:
 *  - p_ref and the drive lie within the twin's interval of the firmware's rounding for that
 *    step (the map's lookups and the PI increment rounded, kp in Q12, the closed stop and the
 *    stroke's top at 32767, the backlash at 655/32768; the drive is need times T_travel, a
 *    product the firmware makes exactly);
 *  - closures (p_ref, p_hat, takeup, every node) within FM_TOL_LSB LSB of Q15 stroke (p_ref's
 *    interval reaches about 3.3 LSB; p_hat adds the move's rounding), the drive within
 *    (FM_TOL_LSB + 0.5) * T_travel LSB of Q15 duty (need's error and the backlash's, times
 *    T_travel);
 *  - rest, dir, calm, warm, seen and the saturation flag equal.
 * Borderlines: where that interval lets the firmware's closure or drive lie across a threshold
 * from the twin's (integral gate, smallest reversal, half the break-away duty) the step is
 * skipped and counted (under 1 %); where only the saturation flag may differ while the loop is
 * calm, the step is compared without the calm counter and the map (also under 1 %). */
#define FM_TOL_LSB 4.0
#define FM_STEPS 6000
static void test_ctl_ffmap_matches_twin(void **state)
{
    (void)state;
    fm_toy_t toy = {Q15(0.5), 0, 0, 0};
    int travel = (int)param_v[P_VALVE_TRAVEL];
    double tol_drive = (FM_TOL_LSB + 0.5) * travel;
    double w_drive = 0, w_drive_stroke = 0, w_ref = 0, w_hat = 0, w_take = 0, w_node = 0, b_ref = 0, b_drive = 0;
    unsigned paths = 0;
    int skipped = 0, partial = 0, compared = 0, sat_edges = 0, kinds[4] = {0};
    int learned = 0, rested = 0, slow = 0, forced = 0, force_left = 0;
    int target = 3000, seg_left = 0, seg_kind = 0, ramp_from = 0, ramp_to = 0, seg_len = 1;
    int speed = 700, rate = 8, first = 1;
    uint8_t force_flag = 0;

    assert_int_equal(Q15(CTLTW_FM_BACKLASH), FM_BACKLASH);
    assert_int_equal(Q15(CTLTW_STICTION), CTL_STICTION);
    assert_int_equal(travel, 40);
    ctl_select(CTL_BEST);
    for (int k = 0; k < FM_STEPS; k++) {
        /* the inputs: segments of steps, ramps and speed-following targets */
        if (seg_left == 0) {
            seg_len = seg_left = fm_rnd(100, 300);
            seg_kind = fm_rnd(0, 9);
            speed = fm_rnd(0, 3) == 0 ? fm_rnd(200, 390) : fm_rnd(410, 1000);
            ramp_from = target;
            ramp_to = fm_rnd(1500, 7500);
            rate = fm_rnd(5, 10);
            if (seg_kind <= 2)
                target = fm_rnd(1200, 7600);
            else if (seg_kind == 6)
                target = fm_rnd(0, 1) ? 0 : fm_rnd(8200, 9000);    /* nothing, or beyond the last node */
        }
        seg_left--;
        if (seg_kind == 3 || seg_kind == 4) {
            target = ramp_from + (ramp_to - ramp_from) * (seg_len - seg_left) / seg_len;
        } else if (seg_kind >= 7) {
            speed += fm_rnd(-4, 4);
            speed = speed < 150 ? 150 : speed > 1100 ? 1100 : speed;
            target = speed * rate;
        }
        if (speed < (int)param_v[P_MINF_SPEED] * 10)
            slow++;
        int flow = fm_toy_flow(&toy, speed) + fm_rnd(-12, 12) + (fm_rnd(0, 99) == 0 ? fm_rnd(-150, 150) : 0);
        if (fm_rnd(0, 299) == 0)
            flow = 0;               /* the meter's pulses lost for a period: a jump the P term cuts */
        uint8_t limit = toy.pos >= 32767 ? CTL_AT_CLOSED : toy.pos <= 0 ? CTL_AT_OPEN : 0;
        if (force_left == 0 && (toy.pos > Q15(0.85) || toy.pos < Q15(0.15)) && fm_rnd(0, 49) == 0) {
            force_left = fm_rnd(1, 4);
            force_flag = toy.pos > Q15(0.5) ? CTL_AT_CLOSED : CTL_AT_OPEN;
        }
        if (force_left > 0) {
            limit |= force_flag;    /* near a stop: a switch that trips early, the relief's overpressure */
            force_left--;
            forced++;
        }
        if (k == FM_STEPS / 2) {
            /* a restart (warm-up again, the map kept) and a slower valve: 6.4 s a stroke, so a
             * reversal's full-duty period (1/64 stroke) leaves backlash to take up */
            assert_int_equal(param_set(P_VALVE_TRAVEL, 64), 1);
            travel = 64;
            tol_drive = (FM_TOL_LSB + 0.5) * travel;
            ctl_reset(0);
            first = 1;
        }
        ctl_in_t in = mk(target, flow, limit);
        in.speed_kmh_x100 = (uint16_t)speed;

        /* the twin from the same state, one step */
        ctltw_fm_t tw;
        ctltw_fm_in_t ti = {target / 100.0, flow / 100.0, speed / 100.0, param_v[P_MINF_SPEED] / 10.0,
                            limit, travel};
        /* fm_map takes the difference of two neighbouring nodes in an int16: it wraps if the
         * learning leaves them more than a stroke apart (a node driven under 0 beside one near
         * 1, as end-stop flags anywhere mid-stroke make). The run must not go there. */
        for (int j = 0; j + 1 < FM_NODES; j++)
            if (abs(ctl_st.fm.node[j + 1] - ctl_st.fm.node[j]) > 32767)
                fail_msg("ffmap step %d: nodes %d and %d differ by more than fm_map's int16 holds (%d, %d)", k, j,
                         j + 1, ctl_st.fm.node[j], ctl_st.fm.node[j + 1]);
        ctltw_fm_load(&tw, &ctl_st.fm, first);
        ctltw_fm_out_t o = ctltw_fm_step(&tw, &ti);
        q15_t d = ctl_step(&in);
        first = 0;
        fm_toy_move(&toy, d, travel);
        if (k == 0) {
            assert_int_equal(ctl_gain(0), Q12(CTLTW_FM_KP));
            assert_int_equal(ctl_gain(1), Q12(CTLTW_FM_KI));
        }
        for (int b = 0; b < 4; b++)
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

        const fm_state_t *m = &ctl_st.fm;
        double ed = fabs(d - o.drive * 32768), er = fabs(m->p_ref - tw.p_ref * 32768);
        double eh = fabs(m->p_hat - tw.p_hat * 32768), et = fabs(m->takeup - tw.takeup * 32768), en = 0;
        unsigned long seen = 0;
        for (int j = 0; j < FM_NODES; j++) {
            double a = fabs(m->node[j] - tw.node[j] * 32768);
            en = a > en ? a : en;
            if (m->seen[j >> 3] & (1u << (j & 7)))
                seen |= 1ul << j;
        }
        if (!map_too) {
            en = 0;
            seen = tw.seen;
        }
        /* the intervals of the firmware's rounding, which decide the borderlines, hold */
        double dr = m->p_ref - tw.p_ref * 32768, dd = d - o.drive * 32768;
        if (dr < o.ref_lo * 32768 - 1e-6 || dr > o.ref_hi * 32768 + 1e-6 || dd < o.drive_lo * 32768 - 1e-6
            || dd > o.drive_hi * 32768 + 1e-6)
            fail_msg("ffmap step %d: p_ref %d twin %.2f (%.2f .. %.2f LSB), drive %d twin %.2f (%.2f .. %.2f LSB)", k,
                     m->p_ref, tw.p_ref * 32768, o.ref_lo * 32768, o.ref_hi * 32768, d, o.drive * 32768,
                     o.drive_lo * 32768, o.drive_hi * 32768);
        double wr = fmax(-o.ref_lo, o.ref_hi) * 32768, wd = fmax(-o.drive_lo, o.drive_hi) * 32768;
        b_ref = wr > b_ref ? wr : b_ref;
        b_drive = wd > b_drive ? wd : b_drive;
        if (ed > tol_drive || er > FM_TOL_LSB || eh > FM_TOL_LSB || et > FM_TOL_LSB || en > FM_TOL_LSB
            || m->rest != tw.rest || m->dir != tw.dir || m->warm != tw.warm || (map_too && m->calm != tw.calm)
            || seen != tw.seen || (!o.sat_edge && ctl_saturated() != o.sat))
            fail_msg("ffmap step %d (target %d flow %d speed %d limit %d): drive %d twin %.1f, p_ref %d twin %.1f, "
                     "p_hat %d twin %.1f, takeup %d twin %.1f, worst node %.2f LSB, rest %d/%d dir %d/%d calm %d/%d "
                     "warm %d/%d seen %lx/%lx sat %d/%d (path %x border %x)",
                     k, target, flow, speed, limit, d, o.drive * 32768, m->p_ref, tw.p_ref * 32768, m->p_hat,
                     tw.p_hat * 32768, m->takeup, tw.takeup * 32768, en, m->rest, tw.rest, m->dir, tw.dir, m->calm,
                     tw.calm, m->warm, tw.warm, seen, tw.seen, ctl_saturated(), o.sat, o.path, o.border);
        w_drive = ed > w_drive ? ed : w_drive;
        w_drive_stroke = ed / travel > w_drive_stroke ? ed / travel : w_drive_stroke;
        w_ref = er > w_ref ? er : w_ref;
        w_hat = eh > w_hat ? eh : w_hat;
        w_take = et > w_take ? et : w_take;
        w_node = en > w_node ? en : w_node;
    }
    print_message("ffmap: worst drive %.2f LSB of Q15 duty (%.2f LSB of stroke a period; tolerance %.1f), p_ref %.2f, "
                  "p_hat %.2f, takeup %.2f, node %.2f LSB of Q15 (tolerance %.0f)\n",
                  w_drive, w_drive_stroke, FM_TOL_LSB + 0.5, w_ref, w_hat, w_take, w_node, FM_TOL_LSB);
    print_message("ffmap: the rounding's intervals held on every step compared (widest p_ref %.2f, drive %.2f LSB)\n",
                  b_ref, b_drive);
    print_message("ffmap: borderline: %d of %d steps skipped (integral gate %d, reversal %d, stiction %d), %d compared "
                  "without calm and map (full duty while calm); saturation flag left out on %d\n",
                  skipped, FM_STEPS, kinds[0], kinds[1], kinds[2], partial, sat_edges);
    print_message("ffmap: %d steps learned, %d at rest, %d below P_MINF_SPEED, %d with a forced end stop\n", learned,
                  rested, slow, forced);
    assert_true(skipped * 100 < FM_STEPS);
    assert_true(partial * 100 < FM_STEPS);
    assert_int_equal(compared + skipped, FM_STEPS);
    /* the run went through every branch of the step */
    const unsigned all = CTLTW_P_REST | CTLTW_P_INTEGRAL | CTLTW_P_HELD | CTLTW_P_REVERSAL | CTLTW_P_HYST
                         | CTLTW_P_ROUNDED | CTLTW_P_SAT | CTLTW_P_ENDSTOP | CTLTW_P_LEARN | CTLTW_P_ANCHOR
                         | CTLTW_P_VISIT | CTLTW_P_LEADCUT | CTLTW_P_DUCUT | CTLTW_P_TAKEUP;
    assert_int_equal(paths & all, all);
    assert_true(learned > 100 && rested > 100 && slow > 100 && forced > 10);
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
        cmocka_unit_test_setup(test_ctl_ffmap_matches_twin, setup),
    };
    return cmocka_run_group_tests_name("ctl", tests, NULL, NULL);
}

/* test_pgn_sim.c: runs driven by AgOpenGPS at 10 Hz (speed and sections from frames, the wheel 10 % off, the frames stopping) and by RateControl (a prescription of rates), through the simulator. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <stdio.h>
#include <string.h>
#include <stdlib.h>
#include <math.h>
#include <cmocka.h>
#include "sim.h"
#include "hal_host.h"
#include "params.h"
#include "app.h"
#include "diag.h"
#include "target.h"

static scenario_t scn;
static sim_t sim;
static char err[512];

static void load(const char *path)
{
    if (scenario_load(&scn, path, err, sizeof err) != 0)
        fail_msg("%s", err);
}

static double now_s(void)
{
    return sim.t_ns * 1e-9;
}

/* a tick, the link's output dropped (nobody on the line) */
static void tick(void)
{
    sim_step(&sim);
    while (hal_host_uart_tx_pop() >= 0)
        ;
}

static void run_to(double t)
{
    while (now_s() < t - 1e-9)
        tick();
}

/* tests/scripts/data/aog_10hz_150.scn: 10 Hz of 254 and 239 from the start */
static void test_pgn_sim_agopengps_speed_sections_and_frames_stopping(void **state)
{
    (void)state;
    load("tests/scripts/data/aog_10hz_150.scn");
    sim_init(&sim, &scn);
    /* the speed the target follows is the GPS's (the true speed in 0.1 km/h), not the wheel's
     * 10 % over it; and "both" has told of the wheel (WHEEL_NOISE) by the time the tractor works */
    double raised = -1;
    while (now_s() < 20.0) {
        tick();
        if (raised < 0 && (app_status.alarms & (1u << AL_WHEEL_NOISE)))
            raised = now_s();
    }
    printf("# WHEEL_NOISE at %.1f s\n", raised);
    assert_true(raised > 0 && raised < 10.0);
    double truth = sim.plant.v_mps * 3.6;
    assert_true(fabs(app_status.in.speed_kmh_x100 * 0.01 - truth) <= 0.1);
    assert_true(app_status.spraying);
    assert_int_equal(app_status.open_nozzles, 36);
    /* 30 s: AgOpenGPS closes two sections; the first frame carrying it goes at t_f; the
     * firmware's boom follows within 0.2 s of it */
    run_to(30.0);
    uint64_t next = sim.aog_next_ns;
    while (sim.aog_next_ns == next)
        tick();
    double t_f = now_s();
    while (app_status.open_nozzles != 24 && now_s() < t_f + 1.0)
        tick();
    printf("# the boom followed the frame in %.3f s\n", now_s() - t_f);
    assert_int_equal(app_status.open_nozzles, 24);
    assert_true(now_s() - t_f <= 0.2);
    /* 70 s: the frames stop; the boom shuts within Frames lost (1.0 s) of the last one, not
     * before, and SPEED_LOST tells */
    double last = 0;
    next = sim.aog_next_ns;
    while (now_s() < 70.5) {
        tick();
        if (sim.aog_next_ns != next) {      /* a frame went this tick */
            next = sim.aog_next_ns;
            last = now_s();
        }
        if (!sim.aog_period_ns)
            break;
    }
    printf("# the last frame at %.3f s\n", last);
    while (app_status.spraying && now_s() < 75.0)
        tick();
    printf("# the boom shut %.3f s after the last frame\n", now_s() - last);
    assert_false(app_status.spraying);
    assert_true(now_s() >= last + 1.0);
    assert_true(now_s() <= last + 1.0 + 0.2);
    run_to(now_s() + 0.2);
    assert_true(app_status.alarms & (1u << AL_SPEED_LOST));
    sim_free(&sim);
}

/* tests/scripts/data/rc_prescription_150.scn: RateControl's target units a minute for 150, 120,
 * 180, 100 and 150 L/ha: the firmware's rate follows each (derived back over its own speed and
 * width) within 1 % and a second, and the dose over the run is the prescription's */
static void test_pgn_sim_ratecontrol_prescription(void **state)
{
    (void)state;
    load("tests/scripts/data/rc_prescription_150.scn");
    sim_init(&sim, &scn);
    static const struct { double t; int rate_x10; } want[] = {
        {21, 1500}, {31, 1200}, {51, 1800}, {71, 1000}, {91, 1500}, {109, 1500},
    };
    for (size_t i = 0; i < sizeof want / sizeof want[0]; i++) {
        run_to(want[i].t);
        printf("# %.0f s: rate %u (want %d)\n", want[i].t, target_rate_x10(), want[i].rate_x10);
        assert_true(target_rate_remote());
        assert_true(abs((int)target_rate_x10() - want[i].rate_x10) * 100 <= want[i].rate_x10);
    }
    sim_free(&sim);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pgn_sim_agopengps_speed_sections_and_frames_stopping),
        cmocka_unit_test(test_pgn_sim_ratecontrol_prescription),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

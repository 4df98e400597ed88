/* test_sim.c: the lock-step simulator: determinism by seed, events, exact edge times, docs/SCENARIOS.md's example run unchanged. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <cmocka.h>
#include "sim.h"
#include "hal_host.h"
#include "params.h"
#include "target.h"
#include "ctl.h"
#include "app.h"

static scenario_t scn;
static sim_t sim;
static char err[512];

#define ROWS 300                                /* 30 s at one row every 0.1 s */
static sim_row_t ra[ROWS], rb[ROWS];

static void load(const char *path)
{
    if (scenario_load(&scn, path, err, sizeof err) != 0)
        fail_msg("%s", err);
}

/* 30 s of a scenario, one row every 100 ms. */
static void record(sim_row_t *rows)
{
    int i;
    sim_init(&sim, &scn);
    for (i = 0; i < ROWS; i++) {
        sim_run(&sim, (i + 1) * 0.1);
        sim_row(&sim, &rows[i]);
    }
    sim_free(&sim);
}

/* Same scenario, same seed: the same trace bit for bit (every double of every row). */
static void test_sim_same_seed_same_trace_bit_for_bit(void **state)
{
    (void)state;
    load("scenarios/paper_dynamic_150.scn");
    record(ra);
    record(rb);
    assert_int_equal(memcmp(ra, rb, sizeof ra), 0);
    assert_true(ra[ROWS - 1].v_true_kmh > 5.0);          /* the run did something */
    assert_true(ra[ROWS - 1].p_bar > 0.5);
}

/* Another seed: the sensor noise differs (the ADC reads), the driver's commands do not. */
static void test_sim_other_seed_other_noise(void **state)
{
    int i, differ = 0;
    (void)state;
    load("scenarios/paper_dynamic_150.scn");
    record(ra);
    scn.seed = 8;
    record(rb);
    for (i = 0; i < ROWS; i++) {
        assert_true(ra[i].v_cmd_kmh == rb[i].v_cmd_kmh);
        /* the [drive] table, to rounding (the simulator interpolates along the row's slope) */
        assert_true(fabs(ra[i].v_cmd_kmh - scenario_drive_kmh(&scn, ra[i].t_s)) <= 1e-12 * (1.0 + ra[i].v_cmd_kmh));
        differ += ra[i].adc_pressure != rb[i].adc_pressure || ra[i].adc_level != rb[i].adc_level;
    }
    /* 1 LSB of noise on two channels: most of 300 pairs of reads differ somewhere */
    assert_true(differ > ROWS / 2);
}

/* Every edge the plant hands over lies inside the tick just simulated: after the clock moved to
 * its end, never in the future of the HAL's time. */
static uint64_t tick_start;
static unsigned long n_flow, n_wheel, late;
static void flow_edge(uint64_t t)
{
    late += t <= tick_start || t > hal_host_io.time_ns;
    n_flow++;
    hal_host_flow_edge(t);
}
static void wheel_edge(uint64_t t)
{
    late += t <= tick_start || t > hal_host_io.time_ns;
    n_wheel++;
    hal_host_wheel_edge(t);
}

static void test_sim_edges_carry_times_inside_their_tick(void **state)
{
    int i;
    (void)state;
    load("scenarios/paper_dynamic_150.scn");
    sim_init(&sim, &scn);
    sim.plant.flow_edge = flow_edge;
    sim.plant.wheel_edge = wheel_edge;
    n_flow = n_wheel = late = 0;
    for (i = 0; i < 20000; i++) {
        tick_start = sim.t_ns;
        sim_step(&sim);
    }
    sim_free(&sim);
    assert_true(n_flow > 1000);
    assert_true(n_wheel > 50);
    assert_int_equal(late, 0);
}

/* Events applied now, checked like the file's; a bad one changes nothing. */
static void test_sim_events_now(void **state)
{
    (void)state;
    load("scenarios/paper_dynamic_150.scn");
    sim_init(&sim, &scn);
    assert_int_equal(hal_host_io.sections, 0x3F);        /* 6 sections, all on at start */
    assert_int_equal(sim.plant.open_nozzles, 36);
    assert_int_equal(sim_event(&sim, EV_SECTIONS_OPEN, 25), -1);
    assert_int_equal(sim.plant.open_nozzles, 36);
    assert_int_equal(sim_event(&sim, EV_SECTIONS_OPEN, 12), 0);
    assert_int_equal(sim.plant.open_nozzles, 12);
    assert_int_equal(hal_host_io.sections, 0x03);
    assert_int_equal(sim_event_name(&sim, "leak_lpm", 2.5), 0);
    assert_true(sim.plant.leak_lpm == 2.5);
    assert_int_equal(sim_event_name(&sim, "rate_l_ha", 100), 0);
    assert_int_equal(param_v[P_RATE], 1000);
    assert_int_equal(sim_event_name(&sim, "given_speed_kmh", 6.5), 0);
    assert_int_equal(param_v[P_GIVEN_SPEED], 65);
    assert_int_equal(sim_event_name(&sim, "rate_l_ha", 5), -1);
    assert_int_equal(param_v[P_RATE], 1000);
    assert_int_equal(sim_event_name(&sim, "meter_fail", 0), 0);
    assert_int_equal(sim.plant.meter_fail, 1);
    assert_int_equal(sim_event_name(&sim, "no_such_event", 0), -1);
    sim_free(&sim);
}

/* The example of docs/SCENARIOS.md, verbatim: runs to its end; the sections event opens 24 nozzles (4 of
 * the 6 switches) at 100 s, the meter sends nothing after 150 s; the JSON line has every key
 * docs/SCENARIOS.md names. */
static void test_sim_plant_md_example_runs_unchanged(void **state)
{
    metrics_result_t r;
    uint64_t pulses;
    static const char *const keys[] = {
        "\"applied_l_ha\":", "\"dose_error_pct\":", "\"dose_error_all_pct\":", "\"cv_pct\":", "\"cv_all_pct\":",
        "\"zone_error_min_pct\":", "\"zone_error_max_pct\":", "\"steps\":[", "\"overshoot_mean_pct\":",
        "\"overshoot_max_pct\":", "\"settle_mean_s\":", "\"settle_max_s\":", "\"pressure_min_bar\":",
        "\"pressure_max_bar\":", "\"volume_l\":", "\"area_ha\":", "\"alarms\":[", "\"sim_s\":", "\"wall_s\":",
        "\"t_s\":", "\"from_lpm\":", "\"to_lpm\":", "\"rise_s\":", "\"overshoot_pct\":", "\"settle_5pct_s\":",
        "\"settle_2pct_s\":", "\"sse_pct\":", "\"silent_wrong_s\":", "\"silent_wrong_total_s\":",
        "\"ripple_p95_pct\":",
    };
    char *buf = NULL;
    size_t len = 0, i;
    FILE *f;
    (void)state;
    load("scenarios/plant_md_example.scn");
    sim_init(&sim, &scn);
    assert_string_equal(ctl_name((uint8_t)param_v[P_CONTROLLER]), "bp_pid");
    sim_run(&sim, 99.9);
    assert_int_equal(sim.plant.open_nozzles, 36);
    sim_run(&sim, 100.1);
    assert_int_equal(sim.plant.open_nozzles, 24);
    assert_int_equal(hal_host_io.sections, 0x0F);
    sim_run(&sim, 150.1);
    pulses = sim.plant.flow_pulses;
    sim_run(&sim, 300);
    assert_true(sim_done(&sim));
    assert_true(sim.plant.flow_pulses == pulses);
    sim_finish(&sim, &r);
    assert_true(r.sim_s > 299.99 && r.sim_s < 300.01);
    assert_true(r.volume_l > 10);
    f = open_memstream(&buf, &len);
    assert_non_null(f);
    sim_json(&sim, &r, f);
    fclose(f);
    for (i = 0; i < sizeof keys / sizeof keys[0]; i++)
        if (!strstr(buf, keys[i]))
            fail_msg("%s missing from %s", keys[i], buf);
    assert_non_null(strstr(buf, "\"controller\":\"bp_pid\""));
    assert_int_equal(strchr(buf, '\n') - buf, (long)len - 1);   /* one line */
    free(buf);
    sim_free(&sim);
}

/* The given-speed bench scenario: true steps of the target at 40, 80, 120 and 160 s. By hand,
 * eq. (1) at 150 L/ha, 50 cm, 36 nozzles: 6 km/h 27.0 L/min, 8 km/h 36.0, 7 km/h 31.5; the steps'
 * times count from the step itself. */
static void test_sim_target_steps_found_where_the_scenario_puts_them(void **state)
{
    static const double t[] = {40, 80, 120, 160}, from[] = {27, 36, 31.5, 27}, to[] = {36, 31.5, 27, 36};
    metrics_result_t r;
    int i;
    (void)state;
    load("scenarios/target_step_150.scn");
    sim_init(&sim, &scn);
    sim_run(&sim, scn.duration_s);
    sim_finish(&sim, &r);
    assert_int_equal(r.n_steps, 4);
    for (i = 0; i < 4; i++) {
        assert_true(r.steps[i].t_s > t[i] - 1e-9 && r.steps[i].t_s < t[i] + 0.1 + 1e-9);
        assert_true(r.steps[i].from_lpm > from[i] - 0.011 && r.steps[i].from_lpm < from[i] + 0.011);
        assert_true(r.steps[i].to_lpm > to[i] - 0.011 && r.steps[i].to_lpm < to[i] + 0.011);
    }
    sim_free(&sim);
}

/* docs/SCENARIOS.md's sanity point: with the PTO coupled, on the paper's dynamic run the bypass position an
 * ideal controller needs (the one that holds the boom at the reference target, steady state, at
 * the pump's speed of the moment) stays within 0.55-0.70 wherever the tractor does 4 km/h or more,
 * also while the speed changes. */
static void test_sim_paper_run_needs_the_bypass_within_055_070(void **state)
{
    plant_t *pl = malloc(sizeof *pl);
    plant_in_t in = {0, 1};
    double lo = 1, hi = 0, width_m;
    long i, n;
    (void)state;
    load("scenarios/paper_dynamic_150.scn");
    plant_init(pl, &scn.plant, scn.seed);
    width_m = scn.plant.nozzles * scn.plant.spacing_m;
    n = (long)(scn.duration_s * 1000);
    for (i = 0; i < n; i++) {
        double v;
        pl->v_cmd_kmh = scenario_drive_kmh(&scn, (i + 1) * 1e-3);
        plant_step(pl, &in, 1000000u);
        v = plant_speed_kmh(pl);
        if (v >= 4.0 && i % 100 == 0) {
            double th = plant_bypass_needed(pl, scn.param[P_RATE] * 0.1 * width_m * v / 600.0);
            lo = th < lo ? th : lo;
            hi = th > hi ? th : hi;
        }
    }
    free(pl);
    printf("# paper's coupled run: the bypass position needed at >= 4 km/h %.3f .. %.3f\n", lo, hi);
    if (!(lo >= 0.55 && hi <= 0.70))
        fail_msg("needed bypass %.4f..%.4f, not within 0.55-0.70", lo, hi);
}

/* The fast mode's ticks: divisors of the 100 ms sample period up to SIM_TICK_MAX_MS, an idle tick
 * a longer multiple of the tick, set before the first step. A fast run (sim --fast's ticks)
 * keeps the control steps and samples on their grid: the bench scenario's four target steps at
 * the same times, and its volume within 1 % of the 1 ms run's. */
static void test_sim_fast_mode_keeps_the_grid(void **state)
{
    metrics_result_t exact, fast;
    double t_steps[8], volume;
    int i, n_steps;
    (void)state;
    load("scenarios/target_step_150.scn");
    sim_init(&sim, &scn);
    assert_int_equal(sim_set_tick_ms(&sim, 0, 0), -1);
    assert_int_equal(sim_set_tick_ms(&sim, 3, 0), -1);
    assert_int_equal(sim_set_tick_ms(&sim, 2 * SIM_TICK_MAX_MS, 0), -1);
    assert_int_equal(sim_set_tick_ms(&sim, 10, 10), -1);
    assert_int_equal(sim_set_tick_ms(&sim, 10, 25), -1);
    assert_int_equal(sim_set_tick_ms(&sim, 1, 0), 0);
    sim_run(&sim, scn.duration_s);
    sim_finish(&sim, &exact);
    assert_int_equal(sim_set_tick_ms(&sim, 10, 0), -1);       /* not once it ran */
    n_steps = exact.n_steps;
    assert_true(n_steps >= 1 && n_steps <= 8);
    for (i = 0; i < n_steps; i++)
        t_steps[i] = exact.steps[i].t_s;
    volume = exact.volume_l;
    sim_free(&sim);

    sim_init(&sim, &scn);
    assert_int_equal(sim_set_tick_ms(&sim, SIM_FAST_TICK_MS, SIM_FAST_IDLE_MS), 0);
    while (!sim_done(&sim)) {
        uint64_t t0 = sim.t_ns;
        sim_step(&sim);
        assert_true(sim.t_ns - t0 == SIM_FAST_TICK_MS * 1000000ull || sim.t_ns - t0 == SIM_FAST_IDLE_MS * 1000000ull);
        assert_int_equal(hal_host_io.time_ns, sim.t_ns);
    }
    sim_finish(&sim, &fast);
    assert_true(fast.sim_s > scn.duration_s - 1e-9 && fast.sim_s < scn.duration_s + 1e-9);
    assert_int_equal(fast.n_steps, n_steps);
    for (i = 0; i < n_steps; i++)
        assert_true(fabs(fast.steps[i].t_s - t_steps[i]) < 1e-9);
    if (!(fabs(fast.volume_l / volume - 1.0) < 0.01))
        fail_msg("volume %.3f L at %d/%d ms ticks, %.3f L at 1 ms", fast.volume_l, SIM_FAST_TICK_MS, SIM_FAST_IDLE_MS, volume);
    sim_free(&sim);
}

/* The UART's output so far, as text (BOOT and OK lines among the LOG lines). */
static void uart_text(char *buf, size_t n)
{
    size_t k = 0;
    int c;
    while ((c = hal_host_uart_tx_pop()) >= 0)
        if (k + 1 < n)
            buf[k++] = (char)c;
    buf[k] = 0;
}

static int count_of(const char *hay, const char *needle)
{
    int n = 0;
    for (; (hay = strstr(hay, needle)) != NULL; hay++)
        n++;
    return n;
}

/* Key and serial events reach the firmware as --input's do; a power cut stops it (outputs off,
 * no watchdog kick, app_status zero, the valve where it was), then it boots as at power-on
 * (a second BOOT POWER) with the scenario's settings from the EEPROM, not from the simulator;
 * the operator's rate (the metrics' set rate) is what the link set, not what the reboot loaded. */
static void test_sim_key_serial_and_power_cut(void **state)
{
    static const char text[] =
        "[run]\nduration_s = 40\n[config]\nrate_l_ha = 125\n[drive]\n0 0\n2 0\n10 8\n"
        "[events]\n15 serial SET 0 1000*18\n17 key #\n20 power_cut 2\n";
    static char out[200000];
    uint8_t kicks;
    double theta;
    (void)state;
    if (scenario_parse(&scn, text, "cut.scn", err, sizeof err) != 0)
        fail_msg("%s", err);
    sim_init(&sim, &scn);
    assert_int_equal(param_v[P_RATE], 1250);
    sim_run(&sim, 14.9);
    assert_int_equal(hal_host_io.spray_on, 1);
    sim_run(&sim, 15.5);
    assert_int_equal(param_v[P_RATE], 1000);
    assert_true(sim.set_rate == 100);
    sim_run(&sim, 17.05);
    assert_int_not_equal(hal_host_io.keys, 0);              /* '#' held ... */
    sim_run(&sim, 17.2);
    assert_int_equal(hal_host_io.keys, 0);                  /* ... 100 ms */
    assert_int_equal(param_v[P_MODE], 1);                   /* the run screen's '#': manual */
    sim_run(&sim, 20.0);
    uart_text(out, sizeof out);
    assert_int_equal(count_of(out, "BOOT POWER"), 1);
    assert_int_equal(count_of(out, "OK 0 1000"), 1);
    sim_run(&sim, 20.5);
    kicks = hal_host_io.wdt_kicks;
    theta = sim.plant.theta;
    assert_int_equal(hal_host_io.spray_on, 0);
    assert_int_equal(hal_host_io.valve_dir, HAL_VALVE_OFF);
    assert_int_equal(app_status.in.target_lpm_x100, 0);
    assert_true(sim.plant.v_mps > 7.9 / 3.6);               /* the tractor drives on */
    sim_run(&sim, 21.9);
    assert_int_equal(hal_host_io.wdt_kicks, kicks);
    assert_true(sim.plant.theta == theta);
    uart_text(out, sizeof out);
    assert_int_equal(out[0], 0);                            /* a dead chip sends nothing */
    sim_run(&sim, 22.5);
    assert_int_not_equal(hal_host_io.wdt_kicks, kicks);
    uart_text(out, sizeof out);
    assert_int_equal(count_of(out, "BOOT POWER"), 1);
    assert_int_equal(param_v[P_RATE], 1000);                 /* saved 2 s after the SET (app.c) */
    assert_true(sim.set_rate == 100);
    assert_int_equal(param_v[P_MODE], 0);                   /* the '#' did not survive: AUTO */
    assert_false(app_status.manual);
    sim_free(&sim);
    /* without the SET, the scenario's 125 comes back from the EEPROM (the RAM's defaults are 150) */
    scn.n_events = 1;
    scn.events[0] = scn.events[2];
    sim_init(&sim, &scn);
    sim_run(&sim, 23.0);
    assert_int_equal(param_v[P_RATE], 1250);
    assert_int_not_equal(param_info(P_RATE)->def, 1250);
    sim_free(&sim);
}

/* A setting changed on the link survives a power cut with the boom never shut: saved 2 s after
 * the change (APP_SET_SAVE_PERIODS), the reboot loads it and says nothing fell back; a cut 1 s
 * after the change, before its save, gives the scenario's value back. */
static void test_sim_a_set_then_a_power_cut_keeps_the_setting(void **state)
{
    static char text[256], out[200000];
    (void)state;
    for (int cut_s = 8; cut_s >= 6; cut_s -= 2) {
        snprintf(text, sizeof text, "[run]\nduration_s = 20\n[config]\nrate_l_ha = 125\n[drive]\n0 0\n2 0\n4 8\n"
                 "[events]\n5 serial SET 0 1000*18\n%d power_cut 1\n", cut_s);
        if (scenario_parse(&scn, text, "set_cut.scn", err, sizeof err) != 0)
            fail_msg("%s", err);
        sim_init(&sim, &scn);
        sim_run(&sim, 5.5);
        assert_int_equal(param_v[P_RATE], 1000);
        assert_int_equal(hal_host_io.spray_on, 1);          /* spraying all along: no shut's save */
        sim_run(&sim, cut_s + 1.5);
        uart_text(out, sizeof out);
        assert_int_equal(count_of(out, "BOOT POWER"), 1);  /* the reboot's (the queue went with the power) */
        assert_int_equal(param_v[P_RATE], cut_s == 8 ? 1000 : 1250);
        assert_int_equal(count_of(out, "EE "), 0);          /* a good record loaded either way */
        sim_free(&sim);
    }
}

/* sim_run with the PC reading the link (the host UART's transmit queue would fill and hold the
 * commands that come in). */
static void run_read(double until_s)
{
    static char out[20000];
    while (sim_time_s(&sim) < until_s - 1e-9) {
        double t = sim_time_s(&sim) + 1.0;
        sim_run(&sim, t < until_s ? t : until_s);
        uart_text(out, sizeof out);
    }
}

/* The operator's nudge and preset as scenario events (the serial NUD line and the Preset
 * setting): the metrics score the dose against the rate in use. 8 km/h on 18 m: 150 L/ha is
 * 36 L/min; two nudges at a 10 % step: 180 L/ha; back, then Rate 2: 200 L/ha. No stretch of a
 * wrong dose: the rate in use is applied. Bad values are refused when the file is read. */
static void test_sim_nudge_and_preset_events_score_against_the_rate_in_use(void **state)
{
    static const char text[] =
        "[run]\nduration_s = 180\n[config]\nrate_step_pct = 10\n[drive]\n0 8\n180 8\n"
        "[events]\n60 rate_nudge 1\n60.5 rate_nudge 1\n120 rate_nudge 0\n121 rate_preset 2\n";
    metrics_result_t r;
    (void)state;
    if (scenario_parse(&scn, text, "nudge.scn", err, sizeof err) != 0)
        fail_msg("%s", err);
    sim_init(&sim, &scn);
    run_read(59.0);
    assert_true(fabs(sim.set_rate - 150.0) < 1e-9);
    assert_true(abs(app_status.in.target_lpm_x100 - 3600) <= 2);
    run_read(61.0);
    assert_true(fabs(sim.set_rate - 180.0) < 1e-9);
    assert_true(abs(app_status.in.target_lpm_x100 - 4320) <= 2);
    run_read(119.0);
    assert_true(fabs(sim.plant.q_boom - 43.2) < 43.2 * 0.05);    /* the plant applies it */
    assert_int_equal(app_status.alarms, 0);     /* 20 % over the preset: no OFF_RATE, judged by the rate in use */
    run_read(122.0);
    assert_true(fabs(sim.set_rate - 200.0) < 1e-9);
    assert_true(abs(app_status.in.target_lpm_x100 - 4800) <= 2);
    run_read(180.0);
    sim_finish(&sim, &r);
    printf("# dose error %.2f %%, silent wrong %.1f s\n", r.dose_error_pct, r.silent_wrong_s);
    assert_true(fabs(r.dose_error_pct) < 2.0);
    assert_true(r.silent_wrong_s == 0.0);
    sim_free(&sim);
    static const char *const bad[] = {
        "[drive]\n0 8\n[events]\n10 rate_nudge 2\n", "[drive]\n0 8\n[events]\n10 rate_preset 3\n",
        "[drive]\n0 8\n[events]\n10 rate_preset 0\n",
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
        assert_int_not_equal(scenario_parse(&scn, bad[i], "bad.scn", err, sizeof err), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sim_a_set_then_a_power_cut_keeps_the_setting),
        cmocka_unit_test(test_sim_paper_run_needs_the_bypass_within_055_070),
        cmocka_unit_test(test_sim_same_seed_same_trace_bit_for_bit),
        cmocka_unit_test(test_sim_other_seed_other_noise),
        cmocka_unit_test(test_sim_edges_carry_times_inside_their_tick),
        cmocka_unit_test(test_sim_events_now),
        cmocka_unit_test(test_sim_plant_md_example_runs_unchanged),
        cmocka_unit_test(test_sim_target_steps_found_where_the_scenario_puts_them),
        cmocka_unit_test(test_sim_fast_mode_keeps_the_grid),
        cmocka_unit_test(test_sim_key_serial_and_power_cut),
        cmocka_unit_test(test_sim_nudge_and_preset_events_score_against_the_rate_in_use),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

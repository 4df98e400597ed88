/* test_plaus.c: the operator is told whenever the dose is wrong: the minimum-flow warning, the wheel's plausibility and SPEED_LOST at low speed, manual mode's safety, the valve at its stop, the machines the cross-checks accept; the rules at their period counts and on the simulated sprayer. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <stdlib.h>
#include <unistd.h>
#include <cmocka.h>
#include "sim.h"
#include "helper_sim.h"
#include "hal_host.h"
#include "app.h"
#include "diag.h"
#include "diag_wheel.h"
#include "speed.h"
#include "flow.h"
#include "analog.h"
#include "target.h"
#include "valve.h"
#include "ctl.h"
#include "params.h"

static sim_t sim;
static int sim_live;

static int teardown(void **state)
{
    (void)state;
    helper_sim_end(&sim, &sim_live);
    return 0;
}

/* ---- the rules on synthetic inputs, period by period ---- */

static app_status_t in;

/* the modules diag reads, from rest; a pressure reading of 0 kPa, a full tank */
static int setup_rules(void **state)
{
    (void)state;
    hal_host_reset();
    params_defaults();
    speed_init();
    flow_init();
    hal_host_io.adc[HAL_ADC_PRESSURE] = 205;        /* 4 mA: 0 kPa */
    hal_host_io.adc[HAL_ADC_LEVEL] = 1000;
    analog_init();
    analog_step();
    target_init();
    valve_init();
    diag_init();
    memset(&in, 0, sizeof in);
    in.tank_l = 900;
    return 0;
}

/* n periods of diag_step on `in`; the alarm bits after the last */
static uint32_t periods(int n, uint8_t settled)
{
    uint32_t a = 0;
    for (int i = 0; i < n; i++)
        a = diag_step(&in, settled, 0);
    return a;
}

/* Creeping at 2 km/h in auto with the boom spraying: Table 1 holds 18 L/min, the flow of 4
 * km/h, so the dose is twice Dose: MIN_FLOW after 3 s (30 periods), not one period sooner, and
 * cleared 1 s after the speed is back over MinQ speed / 1.1 (3.64 km/h). At 3.7 km/h (8 % over
 * Dose) and in manual mode it is not raised. */
static void test_plaus_min_flow_warning_at_its_period_count(void **state)
{
    (void)state;
    in.spraying = 1;
    in.open_nozzles = 36;
    in.in.speed_kmh_x100 = 200;
    in.in.target_lpm_x100 = 1800;
    in.in.flow_lpm_x100 = 1800;
    assert_false(periods(DIAG_MIN_FLOW_PERIODS - 1, 1) & (1u << AL_MIN_FLOW));
    assert_true(periods(1, 1) & (1u << AL_MIN_FLOW));
    assert_true(DIAG_QUIET_BITS & (1u << AL_MIN_FLOW));                  /* a warning: never sounded */
    in.in.speed_kmh_x100 = 370;                                            /* 4 / 3.7 = 1.08 */
    assert_true(periods(DIAG_CLEAR_PERIODS - 1, 1) & (1u << AL_MIN_FLOW));
    assert_false(periods(1, 1) & (1u << AL_MIN_FLOW));
    assert_false(periods(100, 1) & (1u << AL_MIN_FLOW));
    in.in.speed_kmh_x100 = 200;
    in.manual = 1;
    assert_false(periods(100, 1) & (1u << AL_MIN_FLOW));
    /* the edge, MinQ speed / 1.1 = 3.636 km/h: 3.63 under it (x 11 = 3993 < 4000), 3.64 not (4004) */
    in.manual = 0;
    in.in.speed_kmh_x100 = 364;
    assert_false(periods(100, 1) & (1u << AL_MIN_FLOW));
    in.in.speed_kmh_x100 = 363;
    assert_false(periods(DIAG_MIN_FLOW_PERIODS - 1, 1) & (1u << AL_MIN_FLOW));
    assert_true(periods(1, 1) & (1u << AL_MIN_FLOW));
    in.in.speed_kmh_x100 = 364;
    assert_false(periods(DIAG_CLEAR_PERIODS, 1) & (1u << AL_MIN_FLOW));
    /* at a standstill nothing creeps: no warning, whatever the boom does */
    in.in.speed_kmh_x100 = 0;
    assert_false(periods(100, 1) & (1u << AL_MIN_FLOW));
    /* the boom shut: nothing goes on the ground */
    in.spraying = 0;
    in.in.speed_kmh_x100 = 200;
    assert_false(periods(100, 1) & (1u << AL_MIN_FLOW));
    /* MinQ speed 4.4 km/h: 4.00 km/h is its / 1.1 exactly (x 11 = 4400): not under it, 3.99 is */
    in.spraying = 1;
    assert_true(param_set(P_MINF_SPEED, 44));
    in.in.speed_kmh_x100 = 400;
    assert_false(periods(100, 1) & (1u << AL_MIN_FLOW));
    in.in.speed_kmh_x100 = 399;
    assert_false(periods(DIAG_MIN_FLOW_PERIODS - 1, 1) & (1u << AL_MIN_FLOW));
    assert_true(periods(1, 1) & (1u << AL_MIN_FLOW));
    assert_int_equal(strlen(diag_text(AL_MIN_FLOW)) <= 16, 1);
}

/* Manual mode: the rate is still watched. 27 % under the target at 11 km/h: OFF_RATE after
 * DIAG_MANUAL_PERIODS (2 s), not a period sooner; app.c does not sound it in manual. Under the
 * working speed too: 36 L/min at 2 km/h against the minimum flow's 18. In auto the same error
 * waits Off-rate t (5 s), and under the working speed is not judged. */
static void test_plaus_manual_rate_off_is_told(void **state)
{
    (void)state;
    in.spraying = 1;
    in.manual = 1;
    in.open_nozzles = 36;
    in.in.speed_kmh_x100 = 1100;
    in.in.target_lpm_x100 = 4950;
    in.in.flow_lpm_x100 = 3600;                                            /* -27 % */
    assert_false(periods(DIAG_MANUAL_PERIODS - 1, 1) & (1u << AL_OFFRATE));
    assert_true(periods(1, 1) & (1u << AL_OFFRATE));
    in.in.flow_lpm_x100 = 4950;
    assert_false(periods(DIAG_CLEAR_PERIODS, 1) & (1u << AL_OFFRATE));
    in.in.speed_kmh_x100 = 200;
    in.in.target_lpm_x100 = 1800;
    in.in.flow_lpm_x100 = 3600;
    assert_false(periods(DIAG_MANUAL_PERIODS - 1, 1) & (1u << AL_OFFRATE));
    assert_true(periods(1, 1) & (1u << AL_OFFRATE));
    in.manual = 0;                                                      /* auto */
    assert_false(periods(DIAG_CLEAR_PERIODS, 1) & (1u << AL_OFFRATE));
    assert_false(periods(200, 1) & (1u << AL_OFFRATE));
    in.in.speed_kmh_x100 = 1100;
    in.in.target_lpm_x100 = 4950;
    uint16_t n = (uint16_t)(param_v[P_OFFRATE_S] * 10u);
    assert_false(periods(n - 1, 1) & (1u << AL_OFFRATE));
    assert_true(periods(1, 1) & (1u << AL_OFFRATE));
}

/* SPEED_LOST from the pump: the wheel reads standstill, the boom shut, the line under 10 kPa for
 * 3 s: the pump stands with the wheels (learnt). Once the wheel has pulsed, a line held at 50 kPa
 * or more for 3 s (30 periods) through a bypass opened half a stroke, with the sections on, says
 * the wheels turn: SPEED_LOST on the 30th period, not the 29th. Without the learning (a fixed
 * PTO's pump runs at a standstill), with the sections off, or with the bypass shut (a line the
 * check valves trap), never. */
static void test_plaus_speed_lost_when_the_coupled_pump_runs_at_a_wheel_standstill(void **state)
{
    (void)state;
    in.open_nozzles = 36;
    in.in.pressure_kpa = 150;
    for (int i = 1; i <= 3; i++) {                  /* the wheel has measured a speed */
        hal_host_wheel_edge((uint64_t)i * 100000000u);
        hal_host_set_time_ns((uint64_t)i * 100000000u + 50000000u);
        speed_step();
    }
    assert_true(speed_at_last_pulse_x100() > 0);
    assert_false(periods(200, 0) & (1u << AL_SPEED_LOST));            /* not learnt: a fixed PTO */
    in.in.pressure_kpa = 5;
    assert_false(periods(DIAG_PUMP_PERIODS, 0) & (1u << AL_SPEED_LOST));  /* learnt: it stops */
    in.in.pressure_kpa = 120;
    in.open_nozzles = 0;
    assert_false(periods(200, 0) & (1u << AL_SPEED_LOST));            /* sections off */
    in.open_nozzles = 36;
    assert_false(periods(200, 0) & (1u << AL_SPEED_LOST));            /* a line trapped by a shut bypass */
    for (int i = 0; i < 25; i++)                                        /* the hold opens it 0.6 stroke */
        valve_set(-Q15_MAX);
    assert_true(valve_opened_by(DIAG_PUMP_OPEN_Q15));
    assert_false(periods(DIAG_PUMP_PERIODS - 1, 0) & (1u << AL_SPEED_LOST));
    assert_true(periods(1, 0) & (1u << AL_SPEED_LOST));
}

/* ---- the wheel's plausibility, on pulse trains ---- */

static uint64_t now_ns;

/* edges every `period` s from *next up to the next 100 ms; one speed step */
static uint16_t wheel_period(double *next, double period)
{
    now_ns += 100000000ull;
    hal_host_set_time_ns(now_ns);
    while (*next * 1e9 <= (double)now_ns) {
        hal_host_wheel_edge((uint64_t)(*next * 1e9));
        *next += period;
    }
    return speed_step();
}

static double span_s(double kmh)
{
    return 0.3927 / (kmh / 3.6);
}

/* The wheel's pulses doubling at 8 km/h (a second magnet): 8 -> 16 km/h in one span, a rise no
 * tractor makes (speed.h, 3 m/s^2): speed_jumped within SPEED_JUMP_PERIODS + 2 periods, held
 * while the doubled speed holds, gone at a standstill; half of it (8 -> 12 km/h) as soon. A
 * tractor accelerating at 1 m/s^2 from 4 to 11 km/h on a wheel whose spans differ by a quarter,
 * never. */
static void test_plaus_a_wheel_doubling_is_a_jump_and_an_acceleration_is_not(void **state)
{
    (void)state;
    now_ns = 0;
    double t = 0.05;
    for (int i = 0; i < 100; i++)
        wheel_period(&t, span_s(8));
    assert_false(speed_jumped());
    int k = 0;
    while (!speed_jumped() && k < 50) {
        wheel_period(&t, span_s(16));
        k++;
    }
    printf("# pulses doubled at 8 km/h: a jump after %d periods\n", k);
    assert_true(k <= (int)SPEED_JUMP_PERIODS + 2);
    for (int i = 0; i < 100; i++)
        wheel_period(&t, span_s(16));
    assert_true(speed_jumped());
    for (int i = 0; i < 60; i++)
        wheel_period(&t, 1e9);                      /* pulses stop: standstill */
    assert_false(speed_jumped());
    /* half the fault: every other edge doubled, 8 -> 12 km/h (from a fresh start) */
    setup_rules(NULL);
    now_ns = 0;
    t = 0.05;
    for (int i = 0; i < 100; i++)
        wheel_period(&t, span_s(8));
    assert_false(speed_jumped());
    k = 0;
    while (!speed_jumped() && k < 50) {
        wheel_period(&t, span_s(12));
        k++;
    }
    printf("# pulses x1.5 at 8 km/h: a jump after %d periods\n", k);
    assert_true(k <= (int)SPEED_JUMP_PERIODS + 2);

    /* 1 m/s^2 (3.6 km/h a second) from 4 to 11 km/h, spans alternately 25 % long and short */
    setup_rules(NULL);
    now_ns = 0;
    t = 0.05;
    double v = 4.0;
    int odd = 0;
    for (int i = 0; i < 300; i++) {
        now_ns += 100000000ull;
        hal_host_set_time_ns(now_ns);
        while (t * 1e9 <= (double)now_ns) {
            hal_host_wheel_edge((uint64_t)(t * 1e9));
            t += span_s(v) * (odd ? 1.125 : 0.875);
            odd = !odd;
        }
        speed_step();
        if (i >= 50 && v < 11.0)
            v += 0.36;
        assert_false(speed_jumped());
    }
}

/* ---- the cross-check: every machine the settings accept is within the meter's and the
 * target's ranges ---- */

/* The machine, 72 nozzles of 5.2 L/min at 3 bar: at P max (4.8 bar) they pass
 * 72 x 5.2 x sqrt(4.8 / 3) = 473.6 L/min, over the meter's 300: refused, naming why. 36 nozzles:
 * 6.56 L/min passes 298.7 L/min (accepted), 6.60 passes 300.5 (refused). */
static void test_plaus_a_boom_beyond_the_meters_range_is_refused(void **state)
{
    (void)state;
    params_defaults();
    assert_int_equal(param_try(P_NOZZLES, 72), PARAM_OK);
    assert_int_equal(param_try(P_NOZZLE_Q3, 520), PARAM_X_FLOW);
    assert_int_equal(param_v[P_NOZZLE_Q3], 118);
    assert_string_equal(param_why_text(PARAM_X_FLOW), "Boom Q>300L/min");
    assert_true(strlen(param_why_text(PARAM_X_FLOW)) <= 16);
    params_defaults();
    assert_int_equal(param_try(P_NOZZLE_Q3, 656), PARAM_OK);
    assert_int_equal(param_try(P_NOZZLE_Q3, 660), PARAM_X_FLOW);
    /* P max is part of it: 656 at 5.0 bar is 305 L/min */
    assert_int_equal(param_try(P_NOZZLE_Q3, 656), PARAM_OK);
    assert_int_equal(param_try(P_P_MAX, 500), PARAM_X_FLOW);
    assert_int_equal(param_try(P_P_MAX, 470), PARAM_OK);
}

/* ---- on the simulated sprayer ---- */

typedef struct {
    double first[AL_COUNT];         /* first time each bit was active from `from_s`, -1 never */
    double from_s;
    double buzz_s;                  /* time the buzzer sounded */
    double spray_s;                 /* time the boom valve was open */
} seen_t;

static void seen_init(seen_t *s, double from_s)
{
    memset(s, 0, sizeof *s);
    s->from_s = from_s;
    for (int b = 0; b < AL_COUNT; b++)
        s->first[b] = -1;
}

static void run_to(seen_t *s, double t_s)
{
    sim_row_t row;
    while (sim_time_s(&sim) < t_s - 1e-9) {
        for (int i = 0; i < 10; i++)
            sim_step(&sim);
        sim_row(&sim, &row);
        if (row.t_s < s->from_s)
            continue;
        for (int b = 0; b < AL_COUNT; b++)
            if ((row.alarms >> b) & 1u && s->first[b] < 0)
                s->first[b] = row.t_s;
        if (hal_host_io.buzzer)
            s->buzz_s += 0.01;
        if (row.spray_on)
            s->spray_s += 0.01;
    }
}

static double after(const seen_t *s, int bit)
{
    return s->first[bit] < 0 ? 1e9 : s->first[bit] - s->from_s;
}

static void load(const char *ctl, const char *plant, const char *drive, const char *events)
{
    static char text[2048];
    snprintf(text, sizeof text, "[run]\nduration_s = 200\nseed = 3\n[config]\ncontroller = %s\n"
             "[plant]\n%s\n[drive]\n%s\n[events]\n%s\n", ctl, plant, drive, events);
    helper_sim_load(&sim, &sim_live, text, "test_plaus");
}

/* Creeping at 2 km/h after a pass at 8 (150 L/ha, MinQ speed 4 km/h): 18 L/min at 2 km/h is
 * 300 L/ha. MIN_FLOW within 5 s of the tractor reaching 3.6 km/h on its way down, never
 * sounded; no alarm. */
static void test_plaus_creeping_raises_the_min_flow_warning(void **state)
{
    seen_t s;
    (void)state;
    load("ffmap", "pto_coupled = 1", "0 0\n2 0\n12 8\n40 8\n46 2\n120 2", "");
    seen_init(&s, 0);
    run_to(&s, 40);
    seen_init(&s, 40);
    run_to(&s, 90);
    printf("# creeping at 2 km/h: MIN_FLOW %.2f s after the slow-down began, buzzer %.2f s\n",
           after(&s, AL_MIN_FLOW), s.buzz_s);
    /* 8 -> 2 km/h over 6 s: 3.64 km/h at 44.4 s */
    assert_true(after(&s, AL_MIN_FLOW) <= 4.4 + 5.0);
    assert_true(after(&s, AL_MIN_FLOW) >= 4.4);
    assert_true(s.buzz_s == 0);
    for (int b = 0; b < AL_COUNT; b++)
        if (b != AL_MIN_FLOW)
            assert_true(after(&s, b) > 1000);
}

/* The row: the wheel sensor dies at 2 km/h on a headland, the tractor goes back to 8 km/h,
 * the pump on the wheels. The speed falls to zero with no pulse and the boom shuts; the pump
 * keeps the line up: SPEED_LOST within 10 s of the boom shutting (3 s of the pump's evidence).
 * The same drive with a real stop instead: nothing; and a real stop on a fixed PTO: nothing. */
static void test_plaus_a_wheel_lost_at_headland_speed_is_speed_lost(void **state)
{
    static const char *ctl[2] = {"ffmap", "bp_pid"};
    seen_t s;
    (void)state;
    for (int c = 0; c < 2; c++) {
        load(ctl[c], "pto_coupled = 1", "0 0\n2 0\n12 8\n40 8\n46 2\n55 2\n60 8\n200 8", "52 speed_sensor_fail");
        seen_init(&s, 0);
        run_to(&s, 52);
        assert_true(after(&s, AL_SPEED_LOST) > 1000);
        seen_init(&s, 52);
        double shut = -1;
        sim_row_t row;
        while (sim_time_s(&sim) < 80) {
            run_to(&s, sim_time_s(&sim) + 0.1);
            sim_row(&sim, &row);
            if (shut < 0 && !row.spray_on)
                shut = row.t_s;
        }
        printf("# %s: wheel lost at 2 km/h: boom shut %.2f s later, SPEED_LOST %.2f s after the fault\n",
               ctl[c], shut - 52, after(&s, AL_SPEED_LOST));
        assert_true(shut > 0);
        assert_true(after(&s, AL_SPEED_LOST) <= shut - 52 + 10.0);
    }
    static const char *plants[2] = {"pto_coupled = 1", "pto_coupled = 0"};
    for (int p = 0; p < 2; p++) {
        load("ffmap", plants[p], "0 0\n2 0\n12 8\n40 8\n46 2\n52 2\n53 0\n80 0\n86 8\n200 8", "");
        seen_init(&s, 0);
        run_to(&s, 120);
        printf("# a real stop, %s, sections on 27 s: SPEED_LOST %s\n", plants[p],
               after(&s, AL_SPEED_LOST) > 1000 ? "not raised" : "raised");
        assert_true(after(&s, AL_SPEED_LOST) > 1000);
    }
}

/* The bypass at its closed stop and the rate not reached: a fixed PTO's pump at 30 % (162 rpm,
 * 36 L/min against 49.5 at 11 km/h): OFF_RATE after Off-rate t (5 s), with ffmap and bp_pid. (The
 * valve at its stop is OFF_RATE's: VALVE_STOP, which no controller ever raised, is removed.) */
static void test_plaus_off_rate_when_the_pump_cannot_give_the_rate(void **state)
{
    static const char *ctl[2] = {"ffmap", "bp_pid"};
    seen_t s;
    (void)state;
    for (int c = 0; c < 2; c++) {
        load(ctl[c], "pto_coupled = 0", "0 0\n2 0\n12 11\n200 11", "40 pto_rpm 162");
        seen_init(&s, 0);
        run_to(&s, 40);
        assert_true(after(&s, AL_OFFRATE) > 1000);
        seen_init(&s, 40);
        run_to(&s, 80);
        printf("# %s, pump at 30 %%: OFF_RATE %.2f s after\n", ctl[c], after(&s, AL_OFFRATE));
        assert_true(after(&s, AL_OFFRATE) <= param_v[P_OFFRATE_S] + 1.0);
        assert_true(app_status.alarms & (1u << AL_OFFRATE));
    }
}

/* Manual mode, then a power-up at a standstill: `#` on the run screen at 8 km/h sets MANUAL (and
 * the record keeps it); the tractor stops: the boom shuts in manual too. A power-up (app_init with
 * the EEPROM as it was) comes back in AUTO with the boom shut; the relay stays off while the
 * tractor stands. */
static void test_plaus_manual_never_survives_a_power_up(void **state)
{
    seen_t s;
    (void)state;
    load("ffmap", "pto_coupled = 0", "0 0\n2 0\n12 8\n30 8\n35 0\n200 0", "");
    char path[] = "/tmp/test_plaus_keys_XXXXXX", err[128];
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    assert_true(write(fd, "20 key #\n", 9) == 9);
    close(fd);
    assert_int_equal(sim_input_load(&sim, path, err, sizeof err), 0);
    unlink(path);
    seen_init(&s, 0);
    run_to(&s, 25);                                     /* `#` on the run screen at 20 s */
    assert_true(app_status.manual);
    assert_true(app_status.spraying);
    seen_init(&s, 42);                                  /* 7 s after the stop: the speed is 0 */
    run_to(&s, 50);
    assert_true(app_status.manual);
    assert_true(s.spray_s == 0);                        /* standing in manual: shut */
    app_init();                                         /* a power-up */
    seen_init(&s, 50);
    run_to(&s, 60);
    assert_false(app_status.manual);
    assert_int_equal(param_v[P_MODE], 0);
    assert_true(s.spray_s == 0);
}

/* The row: `#` at 8 km/h, then the tractor goes to 11 km/h: in manual the flow stays where
 * the valve is, 27 % under the target. OFF_RATE, as a warning (never sounded), within 2 s
 * (DIAG_MANUAL_PERIODS) and 3 s of the speed change. */
static void test_plaus_manual_rate_off_on_the_sprayer_is_a_warning(void **state)
{
    seen_t s;
    (void)state;
    load("ffmap", "pto_coupled = 0", "0 0\n2 0\n12 8\n40 8\n43 11\n200 11", "");
    char path[] = "/tmp/test_plaus_keys_XXXXXX", err[128];
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    assert_true(write(fd, "30 key #\n", 9) == 9);
    close(fd);
    assert_int_equal(sim_input_load(&sim, path, err, sizeof err), 0);
    unlink(path);
    seen_init(&s, 0);
    run_to(&s, 40);
    assert_true(app_status.manual);
    assert_true(after(&s, AL_OFFRATE) > 1000);
    seen_init(&s, 40);
    run_to(&s, 60);
    printf("# manual, 8 -> 11 km/h: OFF_RATE %.2f s after the speed change began, buzzer %.2f s\n",
           after(&s, AL_OFFRATE), s.buzz_s);
    assert_true(after(&s, AL_OFFRATE) <= 3.0 + DIAG_MANUAL_PERIODS / 10.0 + 3.0);
    assert_true(s.buzz_s == 0);
}

/* The simulator's own events: the wheel's pulses doubled mid-run at 8 km/h (wheel_pulse_mult 2):
 * WHEEL_NOISE within 1 s, held while the pulses stay doubled. `#` at 8 km/h, the tractor stops,
 * then a power cut of 2 s (power_cut): the firmware boots in AUTO and the boom stays shut. */
static void test_plaus_the_simulators_wheel_and_power_events(void **state)
{
    seen_t s;
    (void)state;
    load("ffmap", "pto_coupled = 1", "0 0\n2 0\n12 8\n200 8", "40 wheel_pulse_mult 2");
    seen_init(&s, 0);
    run_to(&s, 40);
    assert_true(after(&s, AL_WHEEL_NOISE) > 1000);
    seen_init(&s, 40);
    run_to(&s, 60);
    printf("# wheel_pulse_mult 2 at 8 km/h: WHEEL_NOISE after %.2f s\n", after(&s, AL_WHEEL_NOISE));
    assert_true(after(&s, AL_WHEEL_NOISE) <= 1.0);
    assert_true(app_status.alarms & (1u << AL_WHEEL_NOISE));

    load("ffmap", "pto_coupled = 0", "0 0\n2 0\n12 8\n30 8\n35 0\n200 0", "20 key #\n45 power_cut 2");
    seen_init(&s, 0);
    run_to(&s, 44);
    assert_true(app_status.manual);
    seen_init(&s, 44);
    run_to(&s, 60);
    assert_false(app_status.manual);
    assert_int_equal(param_v[P_MODE], 0);
    assert_true(s.spray_s == 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_plaus_min_flow_warning_at_its_period_count, setup_rules),
        cmocka_unit_test_setup(test_plaus_manual_rate_off_is_told, setup_rules),
        cmocka_unit_test_setup(test_plaus_speed_lost_when_the_coupled_pump_runs_at_a_wheel_standstill, setup_rules),
        cmocka_unit_test_setup(test_plaus_a_wheel_doubling_is_a_jump_and_an_acceleration_is_not, setup_rules),
        cmocka_unit_test(test_plaus_a_boom_beyond_the_meters_range_is_refused),
        cmocka_unit_test_teardown(test_plaus_creeping_raises_the_min_flow_warning, teardown),
        cmocka_unit_test_teardown(test_plaus_a_wheel_lost_at_headland_speed_is_speed_lost, teardown),
        cmocka_unit_test_teardown(test_plaus_off_rate_when_the_pump_cannot_give_the_rate, teardown),
        cmocka_unit_test_teardown(test_plaus_manual_never_survives_a_power_up, teardown),
        cmocka_unit_test_teardown(test_plaus_manual_rate_off_on_the_sprayer_is_a_warning, teardown),
        cmocka_unit_test_teardown(test_plaus_the_simulators_wheel_and_power_events, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* test_diag_line.c: the line's rules (pump dry from the line, the pressure sensor's zero, the tank balance) called period by period with synthetic inputs, each edge on both sides. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <string.h>
#include <cmocka.h>
#include "hal_host.h"
#include "params.h"
#include "ops.h"
#include "flow.h"
#include "valve.h"
#include "ctl.h"
#include "analog.h"
#include "diag_line.h"

#define PERIOD_NS 100000000ull

/* the inputs: the status the rules read, a meter pulse train, the 4-20 mA loops */
static struct {
    uint64_t now_ns;
    uint64_t meter_ns, meter_next;  /* 0 ns: no pulses */
    app_status_t st;
    uint8_t settled;
} sy;

static uint16_t adc_counts[2];      /* 614: 12 mA; 179: 3.5 mA, the loop open */

static uint16_t adc(uint8_t ch)
{
    return ch < 2 ? adc_counts[ch] : 0;
}

/* Meter K 100.0 p/L: q (L/min x100) = 6e10 / the pulse interval in ns. Intervals that are
 * whole multiples of 78125 ns are whole PCA ticks (921600 Hz), read exactly: 20 ms is 30.00
 * L/min, 40 ms 15.00, 80 ms 7.50. */
#define METER_K 1000u

static int setup(void **state)
{
    (void)state;
    hal_host_reset();
    params_defaults();
    assert_true(param_set(P_METER_K, METER_K));
    flow_init();
    analog_init();
    valve_init();
    diag_line_init();
    adc_counts[0] = adc_counts[1] = 614;
    hal_host_adc_source(adc);
    memset(&sy, 0, sizeof sy);
    sy.settled = 1;
    sy.st.tank_l = 500;
    sy.st.open_nozzles = 36;
    return 0;
}

static void meter_every(uint64_t ns)
{
    sy.meter_ns = ns;
    if (sy.meter_next <= sy.now_ns)
        sy.meter_next = sy.now_ns + ns;
}

/* one period's inputs measured: the pulses up to its end, the loops */
static void measure(void)
{
    sy.now_ns += PERIOD_NS;
    hal_host_set_time_ns(sy.now_ns);
    while (sy.meter_ns && sy.meter_next <= sy.now_ns) {
        hal_host_flow_edge(sy.meter_next);
        sy.meter_next += sy.meter_ns;
    }
    flow_step();
    analog_step();
}

static uint8_t dry(void)
{
    measure();
    diag_period(&sy.st, sy.settled);
    return diag_dry_line();
}

static uint8_t zero(void)
{
    measure();
    diag_period(&sy.st, sy.settled);
    return diag_zero();
}


static uint8_t bal(uint16_t l)
{
    measure();
    sy.st.tank_l = l;
    diag_period(&sy.st, sy.settled);
    return diag_balance();
}

/* ---- pump dry from the line -------------------------------------------------------------------- */
/* spraying at working speed, nothing metered, the line under P start: dry on the 10th period */
static void dry_line_raised(uint16_t tank)
{
    setup(NULL);
    sy.st.spraying = 1;
    sy.st.in.speed_kmh_x100 = 800;
    sy.st.in.target_lpm_x100 = 3000;
    sy.st.in.pressure_kpa = 0;
    sy.st.tank_l = tank;
    for (int n = 1; n <= 9; n++)
        assert_int_equal(dry(), 0);
    assert_int_equal(dry(), 1);
}

static void test_dry_line_under_p_start_on_the_10th_period(void **state)
{
    (void)state;
    /* at P start (100 kPa) the check valves may be open: not dry; 99 kPa is */
    for (int k = 0; k < 2; k++) {
        setup(NULL);
        sy.st.spraying = 1;
        sy.st.in.speed_kmh_x100 = 800;
        sy.st.in.target_lpm_x100 = 3000;
        sy.st.in.pressure_kpa = (uint16_t)(param_v[P_P_MIN] - k);
        int n;
        for (n = 1; n <= 30; n++)
            if (dry())
                break;
        assert_int_equal(n, k ? 10 : 31);
    }
    /* a failed pressure sensor says nothing of the line (its last reading was 0) */
    setup(NULL);
    sy.st.spraying = 1;
    sy.st.in.speed_kmh_x100 = 800;
    sy.st.in.target_lpm_x100 = 3000;
    adc_counts[0] = 179;
    for (int n = 1; n <= 30; n++)
        assert_int_equal(dry(), 0);
}

/* Under a quarter of the target metered: 7.50 L/min is a quarter of 30.00 (not under it), of
 * 30.01 it is; nothing metered is under a quarter of 0.04 L/min, 0.01 L/min is not. */
static void test_dry_line_under_a_quarter_of_the_target_metered(void **state)
{
    (void)state;
    static const struct { int16_t target; uint8_t dry; } e[] = {{3000, 0}, {3001, 1}};
    for (int k = 0; k < 2; k++) {
        setup(NULL);
        sy.st.spraying = 1;
        sy.st.in.speed_kmh_x100 = 800;
        sy.st.in.target_lpm_x100 = e[k].target;
        meter_every(80000000u);                 /* 7.50 L/min */
        for (int i = 0; i < 5; i++)
            dry();
        int n;
        for (n = 1; n <= 30; n++)
            if (dry())
                break;
        assert_int_equal(flow_lpm_x100(), 750);
        assert_int_equal(n, e[k].dry ? 10 - 5 : 31);
    }
    setup(NULL);
    sy.st.spraying = 1;
    sy.st.in.speed_kmh_x100 = 800;
    sy.st.in.target_lpm_x100 = 4;
    for (int n = 1; n <= 9; n++)
        assert_int_equal(dry(), 0);
    assert_int_equal(dry(), 1);
    /* Meter K 6000.0 p/L and a pulse a second: 921600 / 921600 ticks = 0.01 L/min, held (the
     * meter reads 0 after 10 periods without a pulse only) */
    setup(NULL);
    assert_true(param_set(P_NOZZLES, 1));         /* (the meter's pulse rate in its range) */
    assert_true(param_set(P_METER_K, 60000));
    sy.st.spraying = 1;
    sy.st.in.target_lpm_x100 = 4;
    meter_every(1000000000u);
    for (int n = 1; n <= 25; n++)
        dry();                                  /* standing: the meter's first two pulses */
    sy.st.in.speed_kmh_x100 = 800;
    for (int n = 1; n <= 40; n++) {
        assert_int_equal(dry(), 0);
        assert_int_equal(flow_lpm_x100(), 1);
    }
}

/* Held until the pump pushes liquid with the boom shut (P start or more on a working sensor),
 * a refill by more than Tank size / 64 (15 L) on a working level sensor, or the sections off. */
static void test_dry_line_held_until_the_pump_pushes_a_refill_or_the_sections_off(void **state)
{
    (void)state;
    dry_line_raised(100);
    sy.st.in.pressure_kpa = param_v[P_P_MIN];          /* pushing, but still spraying */
    assert_int_equal(dry(), 1);
    sy.st.spraying = 0;
    sy.st.in.pressure_kpa = (uint16_t)(param_v[P_P_MIN] - 1u);
    assert_int_equal(dry(), 1);
    sy.st.in.pressure_kpa = param_v[P_P_MIN];          /* the boom shut, P start: it pushes */
    assert_int_equal(dry(), 0);
    /* the boom shut at P start on a failed sensor: its reading says nothing */
    dry_line_raised(100);
    adc_counts[0] = 179;
    for (int i = 0; i < 3; i++)
        dry();
    assert_false(analog_pressure_ok());
    sy.st.spraying = 0;
    sy.st.in.pressure_kpa = 2u * param_v[P_P_MIN];
    for (int i = 0; i < 20; i++)
        assert_int_equal(dry(), 1);
    /* a refill: 115 L is 15 over the 100 L it ran dry at, 116 clears */
    dry_line_raised(100);
    sy.st.tank_l = 115;
    for (int i = 0; i < 20; i++)
        assert_int_equal(dry(), 1);
    sy.st.tank_l = 116;
    assert_int_equal(dry(), 0);
    /* the level it ran dry at is the one of the period it was raised, not of the ones after */
    dry_line_raised(100);
    for (int l = 101; l <= 115; l++) {
        sy.st.tank_l = (uint16_t)l;
        assert_int_equal(dry(), 1);
    }
    sy.st.tank_l = 116;
    assert_int_equal(dry(), 0);
    /* on a failed level sensor a reading of 300 L is no refill */
    dry_line_raised(100);
    adc_counts[1] = 179;
    for (int i = 0; i < 3; i++)
        dry();
    assert_false(analog_level_ok());
    sy.st.tank_l = 300;
    for (int i = 0; i < 20; i++)
        assert_int_equal(dry(), 1);
    /* the sections switched off */
    sy.st.open_nozzles = 0;
    assert_int_equal(dry(), 0);
}

/* Not while the boom settles (start-up, a section switched): 30 periods dry on the line say
 * nothing; settled, the 10th period after does. */
static void test_dry_line_only_with_the_boom_settled(void **state)
{
    (void)state;
    setup(NULL);
    sy.settled = 0;
    sy.st.spraying = 1;
    sy.st.in.speed_kmh_x100 = 800;
    sy.st.in.target_lpm_x100 = 3000;
    for (int n = 1; n <= 30; n++)
        assert_int_equal(dry(), 0);
    sy.settled = 1;
    for (int n = 1; n <= 9; n++)
        assert_int_equal(dry(), 0);
    assert_int_equal(dry(), 1);
}

/* ---- the pressure sensor's zero ---------------------------------------------------------------- */
/* sprayed at 300 kPa at working speed (the spraying pressure taken at once, then filtered),
 * the bypass at its open stop, then shut and standing in auto; settled: sy.settled from then on */
static void sprayed_then_at_rest(uint8_t settled)
{
    setup(NULL);
    for (int i = 0; i < 145; i++) {             /* 3.6 strokes open: the open stop */
        valve_set(-Q15_MAX);
        valve_set(0);
    }
    assert_int_equal(valve_limit(), CTL_AT_OPEN);
    sy.settled = settled;                       /* diag_settled: the start-up over (1) or not */
    sy.st.spraying = 1;
    sy.st.in.speed_kmh_x100 = 800;
    sy.st.in.pressure_kpa = 300;
    for (int i = 0; i < 20; i++)
        assert_int_equal(zero(), 0);
    sy.st.spraying = 0;
    sy.st.in.speed_kmh_x100 = 0;
}

/* periods at rest with this reading until the zero is judged off (max + 1: never) */
static int zero_after(uint16_t kpa, int max)
{
    sy.st.in.pressure_kpa = kpa;
    for (int n = 1; n <= max; n++)
        if (zero())
            return n;
    return max + 1;
}

/* 5 s at rest (50 periods) reading over 25 kPa: off its zero; 25 kPa is not; judged again each
 * 50 periods, so a reading back at 0 clears it after the next window */
static void test_zero_off_over_25_kpa_after_50_periods_at_rest(void **state)
{
    (void)state;
    sprayed_then_at_rest(1);
    assert_int_equal(zero_after(DIAG_ZERO_KPA, 120), 121);
    sprayed_then_at_rest(1);
    assert_int_equal(zero_after(DIAG_ZERO_KPA + 1u, 120), 50);
    sy.st.in.pressure_kpa = 0;
    for (int n = 1; n <= 49; n++)
        assert_int_equal(zero(), 1);
    assert_int_equal(zero(), 0);
}

/* The window's reading steady within 12 kPa: 20 and 32 alternately judge (32 is over 25), 20
 * and 33 never; the highest of the window is what is judged (20 then 26s: off). */
static void test_zero_needs_a_reading_steady_within_12_kpa(void **state)
{
    (void)state;
    for (int k = 0; k < 2; k++) {
        sprayed_then_at_rest(1);
        int n;
        for (n = 1; n <= 120; n++) {
            sy.st.in.pressure_kpa = (uint16_t)(n % 2 ? 20 : 32 + k);
            if (zero())
                break;
        }
        assert_int_equal(n, k ? 121 : 50);
    }
    sprayed_then_at_rest(1);
    sy.st.in.pressure_kpa = 20;
    assert_int_equal(zero(), 0);
    assert_int_equal(zero_after(26, 60), 49);
}

/* At rest means a reading under half the spraying pressure: 150 of 300 kPa is not, 149 is. */
static void test_zero_at_rest_under_half_the_spraying_pressure(void **state)
{
    (void)state;
    sprayed_then_at_rest(1);
    assert_int_equal(zero_after(150, 120), 121);
    sprayed_then_at_rest(1);
    assert_int_equal(zero_after(149, 120), 50);
}

/* The spraying pressure is taken at working speed on a working sensor in auto only: one taken
 * at 2 km/h (40 kPa) would make a 30 kPa rest no rest; manual, or a failed sensor, forgets it
 * (the zero is not judged until the boom sprays in auto again). */
static void test_zero_spraying_pressure_at_working_speed_in_auto_only(void **state)
{
    (void)state;
    sprayed_then_at_rest(1);
    sy.st.spraying = 1;
    sy.st.in.speed_kmh_x100 = 200;
    sy.st.in.pressure_kpa = 40;
    for (int i = 0; i < 400; i++)
        assert_int_equal(zero(), 0);
    sy.st.spraying = 0;
    sy.st.in.speed_kmh_x100 = 0;
    assert_int_equal(zero_after(30, 60), 50);
    /* manual at rest */
    sprayed_then_at_rest(1);
    sy.st.manual = 1;
    assert_int_equal(zero_after(30, 120), 121);
    /* the sensor failed for a while, then good again, at rest */
    sprayed_then_at_rest(1);
    adc_counts[0] = 179;
    sy.st.in.pressure_kpa = 30;
    for (int i = 0; i < 5; i++)
        assert_int_equal(zero(), 0);
    adc_counts[0] = 614;
    assert_int_equal(zero_after(30, 120), 121);
}

/* The spraying pressure is taken with the boom settled only: sprayed at 300 kPa while it
 * settles, a rest reading 26 kPa is never judged (no spraying pressure to go by). */
static void test_zero_spraying_pressure_with_the_boom_settled_only(void **state)
{
    (void)state;
    sprayed_then_at_rest(0);
    assert_int_equal(zero_after(DIAG_ZERO_KPA + 1u, 120), 121);
}

/* Not at rest while the boom sprays, the wheels turn, or the bypass is not open by a tenth of
 * its stroke (3277) as far as valve.c knows: unknown (no stop found yet) is not open. */
static void test_zero_needs_the_boom_shut_and_the_bypass_known_open(void **state)
{
    (void)state;
    sprayed_then_at_rest(1);
    sy.st.spraying = 1;
    assert_int_equal(zero_after(30, 120), 121);
    sprayed_then_at_rest(1);
    sy.st.in.speed_kmh_x100 = 1;
    assert_int_equal(zero_after(30, 120), 121);
    /* the position unknown: no stop found since power-up */
    setup(NULL);
    sy.st.spraying = 1;
    sy.st.in.speed_kmh_x100 = 800;
    sy.st.in.pressure_kpa = 300;
    for (int i = 0; i < 20; i++)
        zero();
    sy.st.spraying = 0;
    sy.st.in.speed_kmh_x100 = 0;
    assert_int_equal(valve_position(), VALVE_POS_UNKNOWN);
    assert_int_equal(zero_after(30, 120), 121);
    /* from the closed stop, 3276 open (4 x 819: valve.c's full period at the defaults) is not a
     * tenth; 3277 (819 x 3 + 797 + 23) is */
    for (int k = 0; k < 2; k++) {
        sprayed_then_at_rest(1);
        for (int i = 0; i < 145; i++) {
            valve_set(Q15_MAX);
            valve_set(0);
        }
        static const q15_t open4[2][5] = {{-Q15_MAX, -Q15_MAX, -Q15_MAX, -Q15_MAX, 0},
                                          {-Q15_MAX, -Q15_MAX, -Q15_MAX, -31998, -VALVE_MOVE_Q15}};
        for (int i = 0; i < 5; i++) {
            valve_set(open4[k][i]);
            valve_set(0);
        }
        assert_int_equal(valve_position(), 3276 + k);
        assert_int_equal(valve_limit(), 0);
        assert_int_equal(zero_after(30, 120), k ? 50 : 121);
    }
}

/* ---- the tank balance ------------------------------------------------------------------------- */
/* Tank size 1000 L: m = 1000 / 256 + 1 = 4 L; judged from a fall of 8 m = 32 L; a stretch's fall
 * counts from its 100th period, a stretch closes at a fall of 32 m = 128 L, the sums are
 * halved from 64 m = 256 L; OFF when 10 |V - 10 F| > 5 F + 100 m (F in L, V in 0.1 L: the
 * meter off the fall by more than 5 % of it and m). At 30.00 L/min (a pulse every 20 ms) the
 * meter sums 0.05 L a period: after c periods of a stretch, V = c / 2 (floored). Call 1 is
 * the first (it starts anew; a stretch opens in it at the level given). */
static void bal_start(uint16_t l, uint64_t meter_ns)
{
    setup(NULL);
    meter_every(meter_ns);
    measure();                                  /* the meter's first pulses: no reading yet */
    assert_int_equal(bal(l), DIAG_BAL_ANEW);
}

/* calls `from` to `to` at level l, each NONE */
static void bal_none(int from, int to, uint16_t l)
{
    for (int c = from; c <= to; c++)
        assert_int_equal(bal(l), DIAG_BAL_NONE);
}

/* 32 L fallen by 4 L a period (a step of m is not a step), at call 101 the stretch's fall
 * counts: F 32, V 50: the meter far off, OFF; not a call before. */
static void test_balance_from_a_stretch_of_100_periods_and_32_l(void **state)
{
    (void)state;
    static const uint64_t every[2] = {20000000u, 40000000u};    /* 30.00, 15.00 L/min */
    for (int k = 0; k < 2; k++) {
        bal_start(800, every[k]);
        assert_int_equal(flow_lpm_x100(), k ? 1500 : 3000);
        uint16_t l = 800;
        for (int c = 2; c <= 100; c++) {
            if (c <= 9)
                l = (uint16_t)(l - 4u);
            assert_int_equal(bal(l), DIAG_BAL_NONE);
        }
        assert_int_equal(l, 768);
        assert_int_equal(bal(l), DIAG_BAL_OFF);
    }
}

/* a rise of m (4 L) over the level a period ago and over the stretch's lowest is no step: the
 * stretch goes on (judged at 101 as above); a rise to 810 with no stretch open is a step: the
 * balance waits 30 periods before a stretch may open */
static void test_balance_a_step_is_more_than_m(void **state)
{
    (void)state;
    bal_start(800, 20000000u);
    bal_none(2, 50, 800);
    assert_int_equal(bal(804), DIAG_BAL_NONE);
    uint16_t l = 804;
    for (int c = 52; c <= 100; c++) {
        if (c <= 60)
            l = (uint16_t)(l - 4u);
        assert_int_equal(bal(l), DIAG_BAL_NONE);
    }
    assert_int_equal(l, 768);
    assert_int_equal(bal(l), DIAG_BAL_OFF);
    /* the meter off (no stretch), a refill of 10 L at call 2, the meter on: the 30 periods from
     * the step no stretch opens (the fall before it opens never counts); the 30th (call 31) it
     * opens at 778 L, and 32 L below that, once it has run 100 periods, is judged */
    setup(NULL);
    assert_int_equal(bal(800), DIAG_BAL_ANEW);
    assert_int_equal(bal(810), DIAG_BAL_NONE);
    meter_every(20000000u);
    l = 810;
    for (int c = 3; c <= 130; c++) {
        if (c >= 5 && c <= 12)
            l = (uint16_t)(l - 4u);
        assert_int_equal(bal(l), DIAG_BAL_NONE);
    }
    for (int c = 131; c <= 137; c++) {
        l = (uint16_t)(l - 4u);
        assert_int_equal(bal(l), DIAG_BAL_NONE);
    }
    assert_int_equal(bal(746), DIAG_BAL_OFF);   /* 778 - 746 = 32 */
}

/* A stretch runs with the boom settled only: the 32 L fall judged OFF at call 101 above says
 * nothing while it settles. */
static void test_balance_stretches_need_the_boom_settled(void **state)
{
    (void)state;
    bal_start(800, 20000000u);
    sy.settled = 0;
    uint16_t l = 800;
    for (int c = 2; c <= 300; c++) {
        if (c <= 9)
            l = (uint16_t)(l - 4u);
        assert_int_equal(bal(l), DIAG_BAL_NONE);
    }
}

/* A stretch runs only at 15.00 L/min or more, on a working level sensor, with a pulse in the
 * period, below the span's top (level + m under Tank size). */
static void test_balance_stretches_need_flow_pulses_a_level_and_room(void **state)
{
    (void)state;
    /* 14.99 L/min: a pulse every 40.0174 ms (36880.0 ticks: 1499.35, whatever the rounding) */
    bal_start(800, 40017361u);
    uint16_t l = 800;
    for (int c = 2; c <= 300; c++) {
        if (c <= 9)
            l = (uint16_t)(l - 4u);
        assert_int_equal(bal(l), DIAG_BAL_NONE);
        assert_int_equal(flow_lpm_x100(), 1499);
    }
    /* the level sensor judged failed (its 3rd period open) */
    bal_start(800, 20000000u);
    adc_counts[1] = 179;
    l = 800;
    for (int c = 2; c <= 300; c++) {
        if (c <= 9)
            l = (uint16_t)(l - 4u);
        assert_int_equal(bal(l), DIAG_BAL_NONE);
    }
    /* Meter K 10.0 p/L at 30 L/min: a pulse every 200 ms, every other period without one (its
     * reading held at 30.00): the stretches close at each */
    setup(NULL);
    assert_true(param_set(P_METER_K, 100));
    meter_every(200000000u);
    for (int c = 0; c < 4; c++)
        measure();
    assert_int_equal(bal(800), DIAG_BAL_ANEW);
    l = 800;
    for (int c = 2; c <= 300; c++) {
        if (c <= 9)
            l = (uint16_t)(l - 4u);
        assert_int_equal(bal(l), DIAG_BAL_NONE);
        assert_int_equal(flow_lpm_x100(), 3000);
    }
    /* at 996 L of 1000 the level is at the span's top (996 + 4 is not under 1000): no stretch
     * there; one opened at 993 has not run 100 periods when the fall from 996 is 33 L */
    bal_start(996, 20000000u);
    bal_none(2, 150, 996);
    for (l = 993; l >= 963; l = (uint16_t)(l - 3u))
        assert_int_equal(bal(l), DIAG_BAL_NONE);
}

/* A stretch that stops before its 100th period is dropped, at its 100th it goes into the sums;
 * a level over the stretch's start (within m) is no fall. */
static void test_balance_sums_stretches_of_100_periods_only(void **state)
{
    (void)state;
    /* 100 periods, 32 L fallen, then the meter stops: summed, F 32 and V 50: OFF */
    bal_start(800, 20000000u);
    uint16_t l = 800;
    for (int c = 2; c <= 100; c++) {
        if (c <= 9)
            l = (uint16_t)(l - 4u);
        assert_int_equal(bal(l), DIAG_BAL_NONE);
    }
    meter_every(0);
    assert_int_equal(bal(l), DIAG_BAL_OFF);
    /* 99 periods metering 4.9 L with no fall, dropped; then a stretch of 710 periods (35.5 L
     * metered) with 32 L fallen at its end: ON (a 4.9 L more, 40.4 L, would be OFF) */
    bal_start(800, 20000000u);
    bal_none(2, 99, 800);
    meter_every(0);
    assert_int_equal(bal(800), DIAG_BAL_NONE);
    meter_every(20000000u);
    l = 800;
    uint8_t r = DIAG_BAL_NONE;
    for (int c = 101; c <= 811; c++) {
        if (c > 803)
            l = (uint16_t)(l - 4u);
        r = bal(l);
        if (c < 811)
            assert_int_equal(r, DIAG_BAL_NONE);
    }
    assert_int_equal(l, 768);
    assert_int_equal(flow_lpm_x100(), 3000);
    assert_int_equal(r, DIAG_BAL_ON);
    /* a level 2 L over the stretch's start, after its 100th period: no fall, NONE */
    bal_start(800, 20000000u);
    bal_none(2, 110, 800);
    bal_none(111, 130, 802);
}

/* A pause of the meter closes the stretch: what the level loses while nothing is metered (40 L
 * here) is in no stretch. */
static void test_balance_a_pause_closes_the_stretch(void **state)
{
    (void)state;
    bal_start(800, 20000000u);
    bal_none(2, 150, 800);
    meter_every(0);
    uint16_t l = 800;
    for (int c = 151; c <= 160; c++) {
        l = (uint16_t)(l - 4u);
        assert_int_equal(bal(l), DIAG_BAL_NONE);
    }
    meter_every(20000000u);
    bal_none(161, 400, l);
}

/* The threshold, F 31 not judged, 32 judged; at F 35 a meter 5.7 L off is within 5 % and m
 * (10 x 57 = 570, not over 5 x 35 + 400 = 575), at F 36 5.9 L off is not (590 over 580). */
static void test_balance_off_by_5_percent_and_m(void **state)
{
    (void)state;
    /* call 586: V 293 (29.3 L) against 35 L */
    bal_start(800, 20000000u);
    bal_none(2, 573, 800);
    uint16_t l = 800;
    for (int c = 574; c <= 583; c++) {
        l = (uint16_t)(l - 3u);
        bal(l);
    }
    assert_int_equal(bal(769), DIAG_BAL_NONE);          /* 584: F 31 */
    assert_int_equal(bal(768), DIAG_BAL_ON);            /* 585: F 32, V 292: 280 within 560 */
    assert_int_equal(bal(765), DIAG_BAL_ON);            /* 586: F 35, V 293 */
    /* call 602: V 301 (30.1 L) against 36 L */
    bal_start(800, 20000000u);
    bal_none(2, 590, 800);
    l = 800;
    for (int c = 591; c <= 601; c++) {
        l = (uint16_t)(l - 3u);
        bal(l);
    }
    assert_int_equal(l, 767);
    assert_int_equal(bal(764), DIAG_BAL_OFF);           /* 602: F 36, V 301 */
}

/* A stretch closes at a fall of 128 L (into the sums; the next one's fall counts from its own
 * 100th period); the sums are halved once the fall summed reaches 256 L. */
static void test_balance_long_stretches_and_the_halving(void **state)
{
    (void)state;
    /* 128 L fallen at call 2361 (V 1180 summed: ON, 10 x 100 within 1040), 4 L more the call
     * after, in the next stretch: still F 128, ON (at F 132 it would be OFF: 1400 over 1060) */
    bal_start(900, 20000000u);
    bal_none(2, 2329, 900);
    uint16_t l = 900;
    for (int c = 2330; c <= 2361; c++) {
        l = (uint16_t)(l - 4u);
        bal(l);
    }
    assert_int_equal(l, 772);
    assert_int_equal(bal(768), DIAG_BAL_ON);
    /* 128 L at call 2301 (V 1150: 10 x 130 = 1300 over 1040, OFF; halved it would be F 64, V
     * 575, ON); then 2404 calls more (V 1202) and 128 L more: 256 summed, halved: F 128, V
     * 1176, ON (1040, not over 1040; unhalved F 256, V 2352: 2080 over 1680, OFF) */
    bal_start(900, 20000000u);
    bal_none(2, 2269, 900);
    l = 900;
    uint8_t r = 0;
    for (int c = 2270; c <= 2301; c++) {
        l = (uint16_t)(l - 4u);
        r = bal(l);
    }
    assert_int_equal(l, 772);
    assert_int_equal(r, DIAG_BAL_OFF);
    for (int c = 2302; c <= 4673; c++)
        assert_int_equal(bal(l), DIAG_BAL_OFF);
    for (int c = 4674; c <= 4705; c++) {
        l = (uint16_t)(l - 4u);
        r = bal(l);
    }
    assert_int_equal(l, 644);
    assert_int_equal(r, DIAG_BAL_ON);
}

/* The metered volume in whole 0.1 L (6000 of L/min x100 periods each), the rest carried: 30.00
 * L/min in call 1, 29.99 in call 2 (5999: not yet 0.1 L), 30.00 after. At an even call c the
 * meter has summed 3000 c - 1: c / 2 - 1 tenths. At call 816, 40.7 L against a fall of 35 L:
 * 5.7 L off, within 5 % and m (570, not over 575): ON (40.8 L would be OFF). */
static void test_balance_counts_whole_tenths_of_a_litre(void **state)
{
    (void)state;
    bal_start(800, 20000000u);
    assert_int_equal(flow_lpm_x100(), 3000);
    uint64_t last = sy.meter_next - sy.meter_ns;        /* the pulses of call 2 at 29.99 */
    sy.meter_ns = 20005001u;                            /* 6e10 / 2999.25 */
    sy.meter_next = last + sy.meter_ns;
    assert_int_equal(bal(800), DIAG_BAL_NONE);
    assert_int_equal(flow_lpm_x100(), 2999);
    last = sy.meter_next - sy.meter_ns;
    sy.meter_ns = 20000000u;
    sy.meter_next = last + sy.meter_ns;
    bal_none(3, 803, 800);
    assert_int_equal(flow_lpm_x100(), 3000);
    uint16_t l = 800;
    for (int c = 804; c <= 813; c++) {
        l = (uint16_t)(l - 3u);
        bal(l);
    }
    assert_int_equal(bal(769), DIAG_BAL_NONE);          /* 814: F 31 */
    bal(768);
    assert_int_equal(bal(765), DIAG_BAL_ON);            /* 816: F 35, V 407 */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_dry_line_under_p_start_on_the_10th_period),
        cmocka_unit_test(test_dry_line_under_a_quarter_of_the_target_metered),
        cmocka_unit_test(test_dry_line_held_until_the_pump_pushes_a_refill_or_the_sections_off),
        cmocka_unit_test(test_dry_line_only_with_the_boom_settled),
        cmocka_unit_test(test_zero_off_over_25_kpa_after_50_periods_at_rest),
        cmocka_unit_test(test_zero_needs_a_reading_steady_within_12_kpa),
        cmocka_unit_test(test_zero_at_rest_under_half_the_spraying_pressure),
        cmocka_unit_test(test_zero_spraying_pressure_at_working_speed_in_auto_only),
        cmocka_unit_test(test_zero_spraying_pressure_with_the_boom_settled_only),
        cmocka_unit_test(test_zero_needs_the_boom_shut_and_the_bypass_known_open),
        cmocka_unit_test(test_balance_from_a_stretch_of_100_periods_and_32_l),
        cmocka_unit_test(test_balance_a_step_is_more_than_m),
        cmocka_unit_test(test_balance_stretches_need_the_boom_settled),
        cmocka_unit_test(test_balance_stretches_need_flow_pulses_a_level_and_room),
        cmocka_unit_test(test_balance_sums_stretches_of_100_periods_only),
        cmocka_unit_test(test_balance_a_pause_closes_the_stretch),
        cmocka_unit_test(test_balance_off_by_5_percent_and_m),
        cmocka_unit_test(test_balance_long_stretches_and_the_halving),
        cmocka_unit_test(test_balance_counts_whole_tenths_of_a_litre),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

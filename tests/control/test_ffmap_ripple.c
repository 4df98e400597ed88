/* test_ffmap_ripple.c: the project's own controller (ffmap) does not hunt on a held target: a fast valve told 4 s. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <stdio.h>
#include <cmocka.h>
#include "ctl.h"
#include "ctl_int.h"
#include "sim.h"
#include "helper_ffmap.h"

/* ripple_p95_pct (sim/metrics.h), the family's bound (issue 51): on this 40 s run 4.0-5.0 % over
 * seeds 1-6 (6.8-11.5 % with every pulse sent after a reversal) */
#define RIPPLE_BOUND_PCT 5.0

/* A 1.65 s valve with a 0.12 s motor the firmware believes 4 s, its break-away 0.12 (told 0.2),
 * a fixed PTO (plant 174 of `make family SEED=1`), held at 6.8 km/h from the start, seeds 1-6.
 * The start cuts the gain to its floor; each reversal (0.6 of a period at full duty) then moved
 * the flow by itself, and the two smallest pulses sent before the meter showed it carried the
 * flow as far past the target: a cycle of +-12 % (ripple 10.5 % on the family's run). After a
 * reversal nothing more is sent that way until the flow can show it (ffmap.c ffmap_out). */
static void test_ffmap_ripple_a_fast_valve_told_4_s_does_not_hunt(void **state)
{
    double worst = 0;
    int alarms = 0;
    (void)state;
    for (int seed = 1; seed <= 6; seed++) {
        char text[1024];
        metrics_result_t r;
        snprintf(text, sizeof text,
                 "[run]\nduration_s = 40\nseed = %d\n[config]\ncontroller = ffmap\nrate_l_ha = 101\n[plant]\n"
                 "valve_travel_s = 1.65\nvalve_stiction_duty = 0.122\nvalve_running_duty = 0.072\n"
                 "valve_backlash = 0.0192\nvalve_motor_tau_s = 0.122\npump_lpm_at_540 = 126.4\n"
                 "pump_pulsation_pct = 7.62\npto_coupled = 0\npto_rpm = 560\nmeter_k_ppl = 380.17\n"
                 "meter_blade_jitter_pct = 1.44\nwheel_spacing_jitter_pct = 3.79\nwheel_slip_pct = 1.01\n"
                 "speed_bounce_pct = 1.54\npressure_noise_lsb = 1.88\nnozzle_wear_pct = 4.0\n"
                 "check_valve_bar = 0.604\nvalve_cv_open = 231.3\n[drive]\n0 0\n2 0\n2 6.8\n40 6.8\n", seed);
        ffmap_anew();
        alarms += ffmap_run(text, &r);
        print_message("ffmap, a fast valve told 4 s, seed %d: ripple %.2f %%, gain %d\n", seed, r.ripple_p95_pct,
                      ctl_st.fm.gain);
        worst = r.ripple_p95_pct > worst ? r.ripple_p95_pct : worst;
    }
    assert_true(worst <= RIPPLE_BOUND_PCT);
    assert_int_equal(alarms, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ffmap_ripple_a_fast_valve_told_4_s_does_not_hunt),
    };
    return cmocka_run_group_tests_name("ffmap_ripple", tests, NULL, NULL);
}

/* test_totals.c: area and volume count the time a step really covers, a late one (a held CPU) included. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include "totals.h"

/* 7.20 km/h over 12 m for t ms: 2 m/s * t * 12 m; 30 L/min: 0.5 ml a ms */
#define V 720u
#define W 1200u
#define Q 3000
static double area_dm2(uint32_t ms) { return 2.0 * ms / 1000.0 * 12.0 * 100.0; }

static void test_totals_a_period_of_100_ms(void **state)
{
    (void)state;
    totals_init();
    for (int i = 0; i < 1000; i++)
        totals_step(V, W, Q, 100);
    const totals_t *t = totals_get();
    assert_true(t->job_dm2 >= area_dm2(100000) * 0.9999 && t->job_dm2 <= area_dm2(100000) * 1.0001);
    assert_true(t->job_ml >= 50000 * 0.9999 && t->job_ml <= 50000 * 1.0001);
}

/* a step 350 ms after the last one (the CPU was held) counts 350 ms, not 100 */
static void test_totals_a_late_step_counts_all_of_its_time(void **state)
{
    (void)state;
    totals_init();
    for (int i = 0; i < 200; i++) {
        totals_step(V, W, Q, 100);
        totals_step(V, W, Q, 350);
        totals_step(V, W, Q, 121);
    }
    uint32_t ms = 200u * (100u + 350u + 121u);
    const totals_t *t = totals_get();
    assert_true(t->job_dm2 >= area_dm2(ms) * 0.999 && t->job_dm2 <= area_dm2(ms) * 1.0001);
    assert_true(t->job_ml >= ms / 2 * 0.999 && t->job_ml <= ms / 2 * 1.0001);
    /* nothing at all for a step of no time */
    uint32_t a = t->job_dm2, v = t->job_ml;
    totals_step(V, W, Q, 0);
    assert_int_equal(t->job_dm2, a);
    assert_int_equal(t->job_ml, v);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_totals_a_period_of_100_ms),
        cmocka_unit_test(test_totals_a_late_step_counts_all_of_its_time),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

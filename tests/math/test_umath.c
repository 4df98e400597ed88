/* test_umath.c: the divide-free arithmetic of the per-period work against exact quotients. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <math.h>
#include <stdio.h>
#include <cmocka.h>
#include "umath.h"

static uint32_t rng = 99;
static uint32_t rnd(void)
{
    rng = rng * 1664525u + 1013904223u;
    return rng;
}

/* a * n / d against the exact quotient: within 2e-4 (plus the integer's rounding) everywhere */
static void test_umath_muldiv_is_within_2e_4_of_the_quotient(void **state)
{
    double worst = 0;
    (void)state;
    for (int i = 0; i < 200000; i++) {
        uint32_t a = rnd() >> (rnd() % 32), d = (rnd() >> (rnd() % 32)) | 1u;
        uint16_t n = (uint16_t)(rnd() >> (16 + rnd() % 16));
        double exact = (double)a * n / d;
        uint32_t r = um_muldiv(a, n, d);
        if (exact >= 4294967295.0) {
            assert_true(r == 0xFFFFFFFFu);
        } else {
            assert_true(fabs(r - exact) <= 0.5 + exact * 2e-4);
            if (exact >= 1e5 && fabs(r - exact) / exact > worst)
                worst = fabs(r - exact) / exact;
        }
    }
    printf("# um_muldiv worst relative error %.2e\n", worst);
    assert_true(worst < 2e-4);
    assert_true(um_muldiv(5, 3, 0) == 0xFFFFFFFFu);
    assert_true(um_muldiv(0, 3, 7) == 0);
    for (uint32_t x = 0; x < 200000; x += 7)
        assert_int_equal(um_sqrt32(x), (int)floor(sqrt((double)x)));
    assert_int_equal(um_sqrt32(0xFFFFFFFFu), 65535);
    assert_true(um_mul32x16_shr16(0xFFFFFFFFu, 65535) == 0xFFFEFFFFu);
}

/* um_scaled_div is the rounded (num * m + d / 2) / d of 64-bit arithmetic wherever its
 * remainder's share fits 32 bits: the meter's constant for every K, eq. (1)'s for random sums */
static void test_umath_scaled_div_is_the_rounded_quotient(void **state)
{
    (void)state;
    for (uint32_t kk = 1; kk < 65536u; kk++)
        assert_true(um_scaled_div(1382400000UL, 40u, kk)
                    == (uint32_t)((1382400000ULL * 40u + kk / 2u) / kk));
    for (int i = 0; i < 200000; i++) {
        uint32_t num = rnd(), d = rnd() >> 16 | 1u;
        uint16_t m = (uint16_t)(rnd() >> 16);
        uint64_t exact = ((uint64_t)num * m + d / 2u) / d;
        assert_true(um_scaled_div(num, m, d) == (uint32_t)exact);
    }
    assert_true(um_scaled_div(192000000UL, 4096u, 37500u) == (uint32_t)((192000000ULL * 4096u + 18750u) / 37500u));
}

/* 4, 7 and 11 km/h with the default 0.3927 m a pulse: within 1 LSB (0.01 km/h) every period
 * after the second pulse, though at 4 km/h a period holds 0 or 1 pulse */
int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_umath_muldiv_is_within_2e_4_of_the_quotient),
        cmocka_unit_test(test_umath_scaled_div_is_the_rounded_quotient),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

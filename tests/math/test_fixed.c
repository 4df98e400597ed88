/* test_fixed.c: the fixed-point routines against double-precision twins, edges included. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <math.h>
#include <cmocka.h>
#include "fixed.h"
#include "mul.h"

static double sat(double x, double lo, double hi)
{
    return x < lo ? lo : x > hi ? hi : x;
}

/* The twin of a rounded, saturated product, in LSB of the result. */
static double mul_twin(int16_t a, int16_t b, int shift)
{
    return sat(floor((double)a * b / ldexp(1.0, shift) + 0.5), -32768, 32767);
}

static const int16_t edges[] = {0, 1, -1, 2, -2, 4095, 4096, -4096, 16384, -16384, 24575, 24576,
                                -24577, 32766, 32767, -32767, -32768};
#define N_EDGES (sizeof edges / sizeof edges[0])

static uint32_t rng = 12345u;
static int16_t rnd16(void)
{
    rng = rng * 1103515245u + 12345u;
    return (int16_t)(rng >> 16);
}

static void test_fixed_add_saturates_instead_of_wrapping(void **state)
{
    (void)state;
    assert_int_equal(fx_add_sat(32767, 1), 32767);
    assert_int_equal(fx_add_sat(-32768, -1), -32768);
    assert_int_equal(fx_sub_sat(-32768, 1), -32768);
    assert_int_equal(fx_sub_sat(32767, -1), 32767);
    assert_int_equal(fx_sub_sat(0, -32768), 32767);
    assert_int_equal(fx_add_sat(100, -101), -1);
    for (int i = 0; i < 20000; i++) {
        int16_t a = rnd16(), b = rnd16();
        assert_int_equal(fx_add_sat(a, b), (int)sat((double)a + b, -32768, 32767));
        assert_int_equal(fx_sub_sat(a, b), (int)sat((double)a - b, -32768, 32767));
    }
}

static void test_fixed_mul32_is_exact(void **state)
{
    (void)state;
    assert_int_equal(fx_mul32(-32768, -32768), 1073741824L);
    assert_int_equal(fx_mul32(32767, -32768), -1073709056L);
    for (int i = 0; i < 20000; i++) {
        int16_t a = rnd16(), b = rnd16();
        assert_true(fx_mul32(a, b) == (int32_t)a * (int32_t)b);
    }
}

/* Products: exact to the rounded twin (tolerance 0 LSB), saturating at the edges. */
static void test_fixed_products_round_to_nearest_and_saturate(void **state)
{
    (void)state;
    assert_int_equal(q15_mul(-32768, -32768), 32767);          /* -1 * -1 saturates */
    assert_int_equal(q15_mul(16384, 16384), 8192);             /* 0.5 * 0.5 = 0.25 */
    assert_int_equal(q15_mul(1, 16384), 1);                    /* 0.5 LSB rounds up */
    assert_int_equal(q15_mul(-1, 16384), 0);                   /* -0.5 LSB rounds up to 0 */
    assert_int_equal(q12_mul(Q12(2.0), Q12(3.0)), Q12(6.0));
    assert_int_equal(q12_mul(Q12(4.0), Q12(4.0)), 32767);      /* 16 saturates to 8 - LSB */
    assert_int_equal(q12_mul(Q12(-4.0), Q12(4.0)), -32768);
    for (size_t i = 0; i < N_EDGES; i++)
        for (size_t j = 0; j < N_EDGES; j++) {
            int16_t a = edges[i], b = edges[j];
            assert_int_equal(q15_mul(a, b), (int)mul_twin(a, b, 15));
            assert_int_equal(q12_mul(a, b), (int)mul_twin(a, b, 12));
            for (int s = 0; s < 16; s++)
                assert_int_equal(fx_mul_shift(a, b, (uint8_t)s), (int)mul_twin(a, b, s));
        }
    for (int i = 0; i < 20000; i++) {
        int16_t a = rnd16(), b = rnd16();
        assert_int_equal(q15_mul(a, b), (int)mul_twin(a, b, 15));
        assert_int_equal(q12_mul(a, b), (int)mul_twin(a, b, 12));
    }
}

/* tanh: every Q12 input within 2 LSB of Q15 of the double tanh (table rounding 0.5 + interpolation
 * 0.77 + result rounding 0.5 at most, 1.53 measured); odd; monotonic. */
static void test_fixed_tanh_within_two_lsb_everywhere(void **state)
{
    (void)state;
    double worst = 0;
    int16_t prev = -32767;
    for (int32_t x = -32768; x <= 32767; x++) {
        int16_t y = fx_tanh((q12_t)x);
        double twin = sat(tanh(x / 4096.0) * 32768.0, -32767, 32767);
        double err = fabs(y - twin);
        if (err > worst)
            worst = err;
        assert_true(err < 2.0);
        assert_true(y >= prev);
        prev = y;
        if (x > -32768)
            assert_int_equal(fx_tanh((q12_t)-x), -y);
    }
    print_message("tanh: worst error %.3f LSB of Q15 over all 65536 Q12 inputs\n", worst);
    assert_int_equal(fx_tanh(0), 0);
    assert_int_equal(fx_tanh(1), 8);          /* tanh(1/4096) * 32768 = 8.0 */
    assert_int_equal(fx_tanh(-1), -8);
    assert_int_equal(fx_tanh(32767), 32767);
    assert_int_equal(fx_tanh(-32768), -32767);
}

/* (1 + tanh)/2: within 2 LSB (half of tanh's error plus half an LSB of rounding), in [0, 32767], 0.5 at 0. */
static void test_fixed_sigmoid_is_nonnegative_and_within_two_lsb(void **state)
{
    (void)state;
    for (int32_t x = -32768; x <= 32767; x++) {
        int16_t y = fx_sigmoid((q12_t)x);
        double twin = sat((1.0 + tanh(x / 4096.0)) / 2.0 * 32768.0, 0, 32767);
        assert_true(y >= 0);
        assert_true(fabs(y - twin) < 2.0);
    }
    assert_int_equal(fx_sigmoid(0), 16384);
    assert_int_equal(fx_sigmoid(-32768), 1);
    assert_int_equal(fx_sigmoid(32767), 32767);
}

static void test_fixed_constant_macros_round(void **state)
{
    (void)state;
    assert_int_equal(Q15(0.5), 16384);
    assert_int_equal(Q15(1.0), 32767);
    assert_int_equal(Q15(-1.0), -32768);
    assert_int_equal(Q12(-0.2), -819);
    assert_int_equal(Q8(1.5), 384);
    assert_int_equal(Q16(-1.0), -65536);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fixed_add_saturates_instead_of_wrapping),
        cmocka_unit_test(test_fixed_mul32_is_exact),
        cmocka_unit_test(test_fixed_products_round_to_nearest_and_saturate),
        cmocka_unit_test(test_fixed_tanh_within_two_lsb_everywhere),
        cmocka_unit_test(test_fixed_sigmoid_is_nonnegative_and_within_two_lsb),
        cmocka_unit_test(test_fixed_constant_macros_round),
    };
    return cmocka_run_group_tests_name("fixed", tests, NULL, NULL);
}

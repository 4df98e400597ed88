/* test_fmt.c: the one number formatter (the LCD's and the serial link's) against printf. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>
#include "fmt.h"

static void test_fmt_numbers_are_formatted_with_their_decimals(void **state)
{
    char s[12];
    (void)state;
    assert_int_equal(fmt_u32(s, 3927, 1, 0), 5);
    assert_string_equal(s, "392.7");
    fmt_u32(s, 5, 2, 0);
    assert_string_equal(s, "0.05");
    fmt_u32(s, 0, 0, 0);
    assert_string_equal(s, "0");
    fmt_u32(s, 0, 1, 1);
    assert_string_equal(s, "0");
    fmt_u32(s, 1230, 2, 1);
    assert_string_equal(s, "12.3");
    assert_int_equal(fmt_u32(s, 100, 1, 1), 2);
    assert_string_equal(s, "10");
    fmt_u32(s, 10, 2, 1);
    assert_string_equal(s, "0.1");
    fmt_u32(s, 60000, 1, 1);
    assert_string_equal(s, "6000");
    fmt_u32(s, 4294967295u, 0, 0);
    assert_string_equal(s, "4294967295");
    fmt_u32(s, 7, 3, 0);
    assert_string_equal(s, "0.007");
}

/* printf's digits, the point put in, then trimmed as fmt_u32 documents */
static void reference(char *out, uint32_t v, unsigned decimals, int trim)
{
    char d[16];
    int n = snprintf(d, sizeof d, "%0*lu", (int)decimals + 1, (unsigned long)v);
    int k = 0, i;
    for (i = 0; i < n; i++) {
        if (decimals && i == n - (int)decimals)
            out[k++] = '.';
        out[k++] = d[i];
    }
    if (trim && decimals) {
        while (out[k - 1] == '0')
            k--;
        if (out[k - 1] == '.')
            k--;
    }
    out[k] = 0;
}

static void test_fmt_agrees_with_printf_on_a_million_values(void **state)
{
    char a[FMT_MAX], b[24];
    uint32_t v = 1;
    unsigned i, dec;
    (void)state;
    for (i = 0; i < 250000u; i++) {
        v = v * 1664525u + 1013904223u;
        for (dec = 0; dec < 4; dec++) {
            uint32_t x = i & 1 ? v >> (i % 32) : v;
            uint8_t n = fmt_u32(a, x, (uint8_t)dec, (uint8_t)(i & 2));
            reference(b, x, dec, i & 2);
            assert_string_equal(a, b);
            assert_int_equal(n, strlen(b));
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fmt_numbers_are_formatted_with_their_decimals),
        cmocka_unit_test(test_fmt_agrees_with_printf_on_a_million_values),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

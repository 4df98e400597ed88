/* test_keypad.c: the keypad scan: debounce, one event a press, auto-repeat, chords ignored. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <string.h>
#include <cmocka.h>
#include "hal_host.h"
#include "keypad.h"

static uint32_t now_ms;

/* Run the main loop for ms milliseconds (a poll every ms); the keys it returned, in order. */
static void run(uint32_t ms, char *got, size_t cap)
{
    size_t n = strlen(got);
    for (uint32_t i = 0; i < ms; i++) {
        now_ms++;
        hal_host_set_time_ns((uint64_t)now_ms * 1000000u);
        char k = keypad_poll();
        if (k != KEY_NONE && n + 1 < cap)
            got[n++] = k;
    }
    got[n] = 0;
}

static uint16_t bit(uint8_t row, uint8_t col)
{
    return (uint16_t)(1u << (4 * row + col));
}

static int setup(void **state)
{
    (void)state;
    hal_host_reset();
    now_ms = 0;
    keypad_init();
    return 0;
}

static void test_keypad_layout_is_the_documented_one(void **state)
{
    static const char *rows[4] = {"123A", "456B", "789C", "*0#D"};
    (void)state;
    for (uint8_t r = 0; r < 4; r++)
        for (uint8_t c = 0; c < 4; c++) {
            char got[8] = "";
            hal_host_io.keys = bit(r, c);
            run(60, got, sizeof got);
            hal_host_io.keys = 0;
            run(60, got, sizeof got);
            assert_int_equal(strlen(got), 1);
            assert_int_equal(got[0], rows[r][c]);
        }
}

static void test_keypad_bounces_shorter_than_the_debounce_are_ignored(void **state)
{
    char got[8] = "";
    (void)state;
    for (int i = 0; i < 10; i++) {          /* contact chatter: 7 ms on, 6 ms off */
        hal_host_io.keys = bit(0, 0);
        run(7, got, sizeof got);
        hal_host_io.keys = 0;
        run(6, got, sizeof got);
    }
    assert_string_equal(got, "");
    hal_host_io.keys = bit(0, 0);           /* then a real press: one key, within 40 ms */
    run(40, got, sizeof got);
    assert_string_equal(got, "1");
    run(300, got, sizeof got);
    assert_string_equal(got, "1");
}

static void test_keypad_a_held_key_repeats_after_the_delay(void **state)
{
    char got[32] = "";
    (void)state;
    hal_host_io.keys = bit(1, 3);           /* B */
    run(30 + KEYPAD_DELAY_MS - 20, got, sizeof got);
    assert_string_equal(got, "B");
    run(20 + 3 * KEYPAD_REPEAT_MS + 5, got, sizeof got);
    assert_string_equal(got, "BBBBB");      /* the press, at the delay, then 3 repeats */
    hal_host_io.keys = 0;
    run(500, got, sizeof got);
    assert_string_equal(got, "BBBBB");
}

static void test_keypad_enter_clear_ack_and_point_never_repeat(void **state)
{
    static const uint8_t keys[4][2] = {{3, 3}, {2, 3}, {3, 0}, {3, 2}};
    (void)state;
    for (int i = 0; i < 4; i++) {
        char got[8] = "";
        hal_host_io.keys = bit(keys[i][0], keys[i][1]);
        run(2000, got, sizeof got);
        hal_host_io.keys = 0;
        run(50, got, sizeof got);
        assert_int_equal(strlen(got), 1);
    }
}

static void test_keypad_two_keys_at_once_are_ignored(void **state)
{
    char got[8] = "";
    (void)state;
    hal_host_io.keys = bit(0, 0) | bit(2, 1);
    run(1000, got, sizeof got);
    assert_string_equal(got, "");
    hal_host_io.keys = bit(2, 1);           /* one released: the other is a press */
    run(50, got, sizeof got);
    assert_string_equal(got, "8");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_keypad_layout_is_the_documented_one, setup),
        cmocka_unit_test_setup(test_keypad_bounces_shorter_than_the_debounce_are_ignored, setup),
        cmocka_unit_test_setup(test_keypad_a_held_key_repeats_after_the_delay, setup),
        cmocka_unit_test_setup(test_keypad_enter_clear_ack_and_point_never_repeat, setup),
        cmocka_unit_test_setup(test_keypad_two_keys_at_once_are_ignored, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

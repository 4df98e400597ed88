/* test_lcd.c: the ST7920 driver and the screen model against the emulator: text lands at the right place, only changes are sent. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>
#include "hal_host.h"
#include "st7920_emu.h"
#include "screen.h"
#include "lcd.h"

static void at_ms(uint32_t ms)
{
    hal_host_set_time_ns((uint64_t)ms * 1000000u);
}

static int setup(void **state)
{
    (void)state;
    hal_host_reset();
    st7920_emu_reset();
    hal_host_lcd_sink(st7920_emu_write);
    screen_clear();
    lcd_init();
    return 0;
}

static void flush(void)
{
    for (int i = 0; i < 10; i++)
        lcd_poll();
}

static void test_lcd_waits_for_power_up_then_initialises(void **state)
{
    (void)state;
    at_ms(10);
    lcd_poll();
    assert_int_equal(st7920_emu_stats()->instructions, 0);
    at_ms(LCD_POWERUP_MS);
    lcd_poll();
    assert_true(st7920_emu_stats()->initialised);
    assert_true(st7920_emu_stats()->display_on);
    assert_int_equal(st7920_emu_stats()->unsupported, 0);
}

static void test_lcd_text_appears_on_the_right_line_and_column(void **state)
{
    char line[17];
    (void)state;
    at_ms(100);
    screen_line("Line one", 0);
    screen_line("  second line", 1);
    screen_line("third", 2);
    screen_puts(3, 10, "fourth");
    flush();
    st7920_emu_line(0, line);
    assert_string_equal(line, "Line one        ");
    st7920_emu_line(1, line);
    assert_string_equal(line, "  second line   ");
    st7920_emu_line(2, line);
    assert_string_equal(line, "third           ");
    st7920_emu_line(3, line);
    assert_string_equal(line, "          fourth");
    /* an odd column: the pair is rewritten with its left neighbour */
    screen_putc(2, 7, 'X');
    flush();
    st7920_emu_line(2, line);
    assert_string_equal(line, "third  X        ");
    assert_int_equal(st7920_emu_stats()->unsupported, 0);
}

static void test_lcd_sends_only_the_changed_pairs(void **state)
{
    (void)state;
    at_ms(100);
    screen_line("steady text here", 1);
    flush();
    uint32_t before = st7920_emu_stats()->data + st7920_emu_stats()->instructions;
    screen_line("steady text here", 1);             /* unchanged: nothing sent */
    flush();
    assert_int_equal(st7920_emu_stats()->data + st7920_emu_stats()->instructions, before);
    screen_putc(1, 5, 'Y');                         /* one pair: address + 2 bytes */
    flush();
    assert_int_equal(st7920_emu_stats()->data + st7920_emu_stats()->instructions, before + 3);
    screen_puts(1, 8, "ABCD");                      /* two adjacent pairs: one address */
    flush();
    assert_int_equal(st7920_emu_stats()->data + st7920_emu_stats()->instructions, before + 3 + 5);
}

static void test_lcd_a_poll_sends_a_bounded_amount(void **state)
{
    (void)state;
    at_ms(100);
    lcd_poll();                                     /* init */
    for (int r = 0; r < 4; r++)
        screen_line("0123456789abcdef", (uint8_t)r);
    uint32_t d0 = st7920_emu_stats()->data;
    lcd_poll();
    assert_int_equal(st7920_emu_stats()->data - d0, 2 * LCD_WORDS_PER_POLL);
    flush();
    assert_int_equal(st7920_emu_stats()->data - d0, 2 * 32);
}

static void test_lcd_render_draws_the_font_glyph_at_its_cell(void **state)
{
    static uint8_t px[ST7920_H][ST7920_W];
    (void)state;
    at_ms(100);
    screen_putc(2, 5, 'W');
    screen_putc(3, 15, '7');
    flush();
    st7920_emu_render(px);
    int lit = 0;
    for (int y = 0; y < 16; y++)
        for (int x = 0; x < 8; x++) {
            assert_int_equal(px[32 + y][40 + x], (st7920_font8x16['W' - 0x20][y] >> (7 - x)) & 1);
            assert_int_equal(px[48 + y][120 + x], (st7920_font8x16['7' - 0x20][y] >> (7 - x)) & 1);
            lit += px[32 + y][40 + x];
        }
    assert_true(lit > 10);
    /* everything else is blank */
    int others = 0;
    for (int y = 0; y < ST7920_H; y++)
        for (int x = 0; x < ST7920_W; x++)
            if (!((y >= 32 && y < 48 && x >= 40 && x < 48) || (y >= 48 && x >= 120)))
                others += px[y][x];
    assert_int_equal(others, 0);
}

static void test_lcd_font_has_a_distinct_glyph_for_every_printable_character(void **state)
{
    (void)state;
    for (int c = 0x21; c < 0x7F; c++) {
        int lit = 0;
        for (int y = 0; y < 16; y++)
            lit += st7920_font8x16[c - 0x20][y] != 0;
        assert_true(lit > 0);
        for (int d = 0x21; d < c; d++)
            assert_true(memcmp(st7920_font8x16[c - 0x20], st7920_font8x16[d - 0x20], 16) != 0);
    }
}

static void test_lcd_png_has_the_signature_and_size(void **state)
{
    unsigned char hdr[24];
    (void)state;
    at_ms(100);
    screen_line("PNG", 0);
    flush();
    const char *path = "lcd_test.png";
    assert_int_equal(st7920_emu_png(path, 2), 0);
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    assert_int_equal(fread(hdr, 1, 24, f), 24);
    fclose(f);
    remove(path);
    assert_memory_equal(hdr, "\x89PNG\r\n\x1a\n", 8);
    assert_memory_equal(hdr + 12, "IHDR", 4);
    assert_int_equal((hdr[16] << 24) | (hdr[17] << 16) | (hdr[18] << 8) | hdr[19], (128 + 8) * 2);
    assert_int_equal((hdr[20] << 24) | (hdr[21] << 16) | (hdr[22] << 8) | hdr[23], (64 + 8) * 2);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_lcd_waits_for_power_up_then_initialises, setup),
        cmocka_unit_test_setup(test_lcd_text_appears_on_the_right_line_and_column, setup),
        cmocka_unit_test_setup(test_lcd_sends_only_the_changed_pairs, setup),
        cmocka_unit_test_setup(test_lcd_a_poll_sends_a_bounded_amount, setup),
        cmocka_unit_test_setup(test_lcd_render_draws_the_font_glyph_at_its_cell, setup),
        cmocka_unit_test_setup(test_lcd_font_has_a_distinct_glyph_for_every_printable_character, setup),
        cmocka_unit_test_setup(test_lcd_png_has_the_signature_and_size, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* lcd.c: ST7920 driver over hal_lcd_write: init sequence, text-mode DDRAM addressing, only changed character pairs sent. */
#include "hal.h"
#include "screen.h"
#include "lcd.h"

/*
 * ST7920 basic instruction set (RE = 0), as used here:
 *   0x30  function set: 8-bit interface (serial mode ignores it), basic set
 *   0x0C  display on, cursor off, blink off
 *   0x01  clear DDRAM to spaces, address 0 (over 10 ms: the next byte waits for it)
 *   0x06  entry mode: address increments, no shift
 *   0x80 | a  set DDRAM word address a
 * Text mode shows 4 lines of 16 half-width characters from 32 DDRAM words of 2 characters:
 * line 1 = words 0x00-0x07, line 2 = 0x10-0x17, line 3 = 0x08-0x0F, line 4 = 0x18-0x1F.
 * A word is written high byte (left character) first; writing only the low byte is not
 * possible, so the screen model marks changes per pair of columns.
 */
static __code const uint8_t line_word[4] = {0x00, 0x10, 0x08, 0x18};
static __code const uint8_t init_seq[5] = {0x30, 0x30, 0x0C, 0x01, 0x06};

static uint8_t init_sent;           /* bytes of init_seq sent (all: the display is ready) */

void lcd_init(void)
{
    init_sent = 0;
}

void lcd_poll(void) __reentrant
{
    uint8_t row, pair, d, prev, half, budget = LCD_WORDS_PER_POLL;
    if (init_sent < sizeof init_seq) {
        /* the init sequence's bytes while the display is ready for them; the passes go on while
         * it executes one (the clear takes over 10 ms), then the whole screen */
        if (hal_ms() < LCD_POWERUP_MS)
            return;
        while (init_sent < sizeof init_seq && !hal_lcd_busy())
            hal_lcd_write(0, init_seq[init_sent++]);
        if (init_sent == sizeof init_seq)
            screen_touch_all();
        return;
    }
    if (!screen_any_dirty())
        return;                     /* the usual pass: nothing changed since the last one */
    /* a word (3 bytes) while the LCD is ready: the rest of the screen in the next passes, so
     * that a pass waits at most for the bytes within a word (hal_lcd_busy, time-paced) */
    for (row = 0; row < 4 && budget && !hal_lcd_busy(); row++) {
        /* d: the row's dirty pairs from `pair` on (an unchanged row costs one test); prev: the
         * pair before was dirty */
        d = screen_dirty(row);
        for (pair = 0, prev = 0; d && budget && !hal_lcd_busy(); pair++, prev = d & 1u, d >>= 1) {
            if (!(d & 1u))
                continue;
            /* consecutive pairs need no new address: the counter steps after each word */
            if (!prev || budget == LCD_WORDS_PER_POLL)
                hal_lcd_write(0, (uint8_t)(0x80 | (line_word[row] + pair)));
            for (half = 0; half < 2u; half++)   /* the word's two characters, left first */
                hal_lcd_write(1, (uint8_t)screen_char(row, (uint8_t)(2 * pair + half)));
            screen_take(row, pair);
            budget--;
        }
    }
}

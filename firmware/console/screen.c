/* screen.c: the screen model: a 4 x 16 character buffer with a changed-bit per character pair, and number formatting. */
#if defined(__SDCC)
#pragma stackauto           /* locals on the stack, not each its own XRAM (docs/MEMORY.md) */
#endif
#include "screen.h"

static char buf[SCREEN_ROWS][SCREEN_COLS];
static uint8_t dirty[SCREEN_ROWS];  /* bit p: columns 2p, 2p+1 changed */

void screen_putc(uint8_t row, uint8_t col, char c)
{
    if (row >= SCREEN_ROWS || col >= SCREEN_COLS)
        return;
    if (buf[row][col] != c) {
        buf[row][col] = c;
        dirty[row] |= (uint8_t)(1u << (col >> 1));
    }
}

void screen_clear(void)
{
    uint8_t r, c;
    for (r = 0; r < SCREEN_ROWS; r++)
        for (c = 0; c < SCREEN_COLS; c++)
            screen_putc(r, c, ' ');
}

uint8_t screen_puts(uint8_t row, uint8_t col, const char *s)
{
    while (*s && col < SCREEN_COLS)
        screen_putc(row, col++, *s++);
    return col;
}

void screen_pad(uint8_t row, uint8_t col)
{
    while (col < SCREEN_COLS)
        screen_putc(row, col++, ' ');
}

void screen_line(const char *s, uint8_t row)
{
    screen_pad(row, screen_puts(row, 0, s));
}

char screen_char(uint8_t row, uint8_t col)
{
    return (row < SCREEN_ROWS && col < SCREEN_COLS) ? buf[row][col] : 0;
}

uint8_t screen_dirty(uint8_t row)
{
    return row < SCREEN_ROWS ? dirty[row] : 0;
}

uint8_t screen_any_dirty(void)
{
    return (uint8_t)(dirty[0] | dirty[1] | dirty[2] | dirty[3]);
}

void screen_take(uint8_t row, uint8_t pair)
{
    if (row < SCREEN_ROWS)
        dirty[row] &= (uint8_t)~(1u << (pair & 7));
}

void screen_touch_all(void)
{
    uint8_t r;
    for (r = 0; r < SCREEN_ROWS; r++)
        dirty[r] = 0xFF;
}

/* hal_lcd.c: the LCD12864 on the STC12C5A60S2: the ST7920 in serial mode, with the waits of its initialisation flowchart. */
#include <stc12.h>
#include "hal.h"
#include "pins.h"

/* Sync byte, then the high and low nibbles. */
static void lcd_shift(uint8_t b) __reentrant
{
    uint8_t i;
    for (i = 0; i < 8; i++) {
        PIN_LCD_SID = (b & 0x80) ? 1 : 0;
        PIN_LCD_SCLK = 1;
        PIN_LCD_SCLK = 0;
        b <<= 1;
    }
}

/* The waits are timed by the PCA counter (SYSCLK/12, HAL_PCA_HZ, running from hal_init), not
 * by counted instructions: the 1T core's instruction times vary (a loop of eight NOPs and a
 * 16-bit counter in XRAM took about 42 clocks, near 4 us, a turn). */
#define US_TICKS(us) ((uint16_t)(((us) * (HAL_PCA_HZ / 1000UL) + 999UL) / 1000UL))
static uint16_t ready_at;           /* PCA time (low 16 bits) the ST7920 has done the last byte */

static uint16_t pca16(void) __reentrant
{
    uint8_t h, l;
    do {
        h = CH;
        l = CL;
    } while (h != CH);
    return (uint16_t)h << 8 | l;
}

uint8_t hal_lcd_busy(void)
{
    return (uint16_t)(ready_at - pca16()) - 1u < US_TICKS(11000);  /* (a wait long past reads as none) */
}

/* A byte goes out at once when the last one's execution time has passed (the caller did other
 * work meanwhile), else when it has: the wait is paced by time and only what is left of it. */
void hal_lcd_write(uint8_t rs, uint8_t b) __reentrant
{
    uint16_t wait;
    while (hal_lcd_busy())
        ;
    PIN_LCD_CS = 1;
    lcd_shift(rs ? 0xFA : 0xF8);
    lcd_shift(b & 0xF0);
    lcd_shift((uint8_t)(b << 4));
    PIN_LCD_CS = 0;
    /* the ST7920's initialisation flowchart: more than 100 us after function set (0x30) and
     * display control, more than 10 ms after clear (0x01), 72 us after a data write or entry
     * mode; return home (0x02/0x03) 1.6 ms */
    if (rs)
        wait = US_TICKS(80);
    else if (b == 0x01)
        wait = US_TICKS(11000);
    else if (b < 0x04)
        wait = US_TICKS(1600);
    else
        wait = US_TICKS(120);
    ready_at = pca16() + wait;
}

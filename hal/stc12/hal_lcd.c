/* hal_lcd.c: the LCD12864 on the STC12C5A60S2: the ST7920 in serial mode, with the waits of its initialisation flowchart. */
#include <stc12.h>
#include "hal.h"
#include "pins.h"

/* Sync byte, then the high and low nibbles. */
static void lcd_shift(uint8_t b)
{
    uint8_t i;
    for (i = 0; i < 8; i++) {
        PIN_LCD_SID = (b & 0x80) ? 1 : 0;
        PIN_LCD_SCLK = 1;
        PIN_LCD_SCLK = 0;
        b <<= 1;
    }
}

static void delay_us(uint16_t us)   /* at least us microseconds at 11.0592 MHz in 1T mode */
{
    while (us--) {
        NOP(); NOP(); NOP(); NOP(); NOP(); NOP(); NOP(); NOP();
    }
}

void hal_lcd_write(uint8_t rs, uint8_t b) __reentrant
{
    PIN_LCD_CS = 1;
    lcd_shift(rs ? 0xFA : 0xF8);
    lcd_shift(b & 0xF0);
    lcd_shift((uint8_t)(b << 4));
    PIN_LCD_CS = 0;
    /* the ST7920's initialisation flowchart: more than 100 us after function set (0x30) and
     * display control, more than 10 ms after clear (0x01), 72 us after a data write or entry
     * mode; return home (0x02/0x03) 1.6 ms */
    if (rs)
        delay_us(80);
    else if (b == 0x01)
        delay_us(11000);
    else if (b < 0x04)
        delay_us(1600);
    else
        delay_us(120);
}

/* lcd.h: the LCD12864 (ST7920, serial mode, text mode) driver: copies the screen model's changed characters to the display. */
#ifndef LCD_H
#define LCD_H

#include "compiler.h"

/* The ST7920 needs 40 ms after power-up before its first instruction. */
#define LCD_POWERUP_MS 50
/* DDRAM words (2 characters) written per lcd_poll(), at most: bounds the main loop's pause
 * (3 bytes of about 100 us each on the chip: a full screen takes 4 polls). */
#define LCD_WORDS_PER_POLL 8

/* Start (again): the init sequence is sent by the first lcd_poll() after LCD_POWERUP_MS. */
void lcd_init(void);
/* Call from the main loop: init when due, then send changed characters. */
void lcd_poll(void);

#endif

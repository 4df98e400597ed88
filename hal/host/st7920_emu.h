/* st7920_emu.h: an emulator of the ST7920 LCD controller (128x64): decodes the driver's bytes, renders pixels, writes PNG. */
#ifndef ST7920_EMU_H
#define ST7920_EMU_H

#include <stdint.h>

#define ST7920_W 128
#define ST7920_H 64

/* What the emulator saw that it does not model (tests expect 0). */
typedef struct {
    uint32_t instructions;          /* instruction bytes (rs = 0) */
    uint32_t data;                  /* data bytes (rs = 1) */
    uint32_t unsupported;           /* extended-mode or unknown instructions, data in graphics mode */
    uint8_t display_on;
    uint8_t initialised;            /* a function set (0x30) came before the first data byte */
} st7920_stats_t;

/* Power-on state: DDRAM blank (spaces), display off, address 0. */
void st7920_emu_reset(void);
/* One byte from the driver; install with hal_host_lcd_sink(st7920_emu_write). */
void st7920_emu_write(uint8_t rs, uint8_t b);
/* Text line 0..3 as shown (16 half-width characters, NUL terminated). */
void st7920_emu_line(uint8_t line, char out[17]);
/* The 128x64 image (1 = dark pixel); blank when the display is off. */
void st7920_emu_render(uint8_t px[ST7920_H][ST7920_W]);
const st7920_stats_t *st7920_emu_stats(void);
/* Write the image as a PNG (scale x scale pixels a dot, LCD colours); 0 on success. */
int st7920_emu_png(const char *path, int scale);

extern const unsigned char st7920_font8x16[95][16];

#endif

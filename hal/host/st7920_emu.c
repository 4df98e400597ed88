/* st7920_emu.c: the ST7920 as the firmware's LCD driver sees it: basic instruction set, text DDRAM, 8x16 ASCII font. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "st7920_emu.h"

/*
 * The ST7920's text DDRAM: 32 words of two half-width characters (high byte left). Word
 * addresses 0x00-0x07 show on line 1, 0x10-0x17 on line 2, 0x08-0x0F on line 3 and
 * 0x18-0x1F on line 4 (the 128x64 module is a 256x32 panel folded in two). Data bytes go
 * high then low; the address counter steps one word after the low byte.
 */
static uint8_t ddram[32][2];
static uint8_t ac;                  /* word address */
static uint8_t half;                /* 0: next data byte is the high one */
static uint8_t re;                  /* extended instruction set selected */
static st7920_stats_t st;

void st7920_emu_reset(void)
{
    memset(ddram, ' ', sizeof ddram);
    ac = 0;
    half = 0;
    re = 0;
    memset(&st, 0, sizeof st);
}

static void instruction(uint8_t b)
{
    if (b & 0x20 && !(b & 0xC0)) {          /* function set 001D X RE G X: both sets */
        re = (b >> 2) & 1;
        st.initialised = 1;
        if (re && (b & 0x02))
            st.unsupported++;               /* graphics display on: not modelled */
        return;
    }
    if (re) {                               /* extended set: standby, scroll, reverse, GDRAM */
        st.unsupported++;
        return;
    }
    if (b & 0x80) {                         /* set DDRAM address */
        ac = b & 0x1F;
        half = 0;
    } else if (b & 0x40) {                  /* set CGRAM address */
        st.unsupported++;
    } else if (b & 0x10) {                  /* cursor / display shift: address only */
        if ((b & 0x0C) == 0x04)
            ac = (uint8_t)((ac + 1) & 0x1F);
        else if ((b & 0x0C) == 0x00)
            ac = (uint8_t)((ac - 1) & 0x1F);
        else
            st.unsupported++;
    } else if (b & 0x08) {                  /* display on/off, cursor, blink */
        st.display_on = (b >> 2) & 1;
    } else if (b & 0x04) {                  /* entry mode: only increment without shift */
        if ((b & 0x03) != 0x02)
            st.unsupported++;
    } else if (b & 0x02) {                  /* home */
        ac = 0;
        half = 0;
    } else if (b == 0x01) {                 /* clear */
        memset(ddram, ' ', sizeof ddram);
        ac = 0;
        half = 0;
    }
}

void st7920_emu_write(uint8_t rs, uint8_t b)
{
    if (!rs) {
        st.instructions++;
        instruction(b);
        return;
    }
    st.data++;
    if (re) {
        st.unsupported++;
        return;
    }
    ddram[ac][half] = b;
    if (half) {
        ac = (uint8_t)((ac + 1) & 0x1F);
        half = 0;
    } else {
        half = 1;
    }
}

static uint8_t word_of_line(uint8_t line)
{
    static const uint8_t start[4] = {0x00, 0x10, 0x08, 0x18};
    return start[line & 3];
}

void st7920_emu_line(uint8_t line, char out[17])
{
    uint8_t w = word_of_line(line);
    for (int i = 0; i < 16; i++) {
        uint8_t c = ddram[w + i / 2][i & 1];
        out[i] = (c >= 0x20 && c < 0x7F) ? (char)c : '?';
    }
    out[16] = 0;
}

void st7920_emu_render(uint8_t px[ST7920_H][ST7920_W])
{
    memset(px, 0, ST7920_H * ST7920_W);
    if (!st.display_on)
        return;
    for (int line = 0; line < 4; line++) {
        uint8_t w = word_of_line((uint8_t)line);
        for (int i = 0; i < 16; i++) {
            uint8_t c = ddram[w + i / 2][i & 1];
            for (int y = 0; y < 16; y++) {
                uint8_t bits;
                if (c >= 0x20 && c < 0x7F)
                    bits = st7920_font8x16[c - 0x20][y];
                else                        /* outside ASCII (a GB2312 half): a box */
                    bits = (y == 1 || y == 14) ? 0xFE : (y > 1 && y < 14) ? 0x82 : 0;
                for (int x = 0; x < 8; x++)
                    px[line * 16 + y][i * 8 + x] = (bits >> (7 - x)) & 1;
            }
        }
    }
}

const st7920_stats_t *st7920_emu_stats(void)
{
    return &st;
}

/* ---- a small PNG writer: 8-bit RGB, zlib stream of stored (uncompressed) deflate blocks ---- */
static uint32_t crc_table[256];

static uint32_t crc32_update(uint32_t c, const uint8_t *p, size_t n)
{
    if (!crc_table[1])
        for (uint32_t i = 0; i < 256; i++) {
            uint32_t k = i;
            for (int j = 0; j < 8; j++)
                k = (k & 1) ? 0xEDB88320u ^ (k >> 1) : k >> 1;
            crc_table[i] = k;
        }
    for (size_t i = 0; i < n; i++)
        c = crc_table[(c ^ p[i]) & 0xFF] ^ (c >> 8);
    return c;
}

static void put32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)(v >> 24);
    p[1] = (uint8_t)(v >> 16);
    p[2] = (uint8_t)(v >> 8);
    p[3] = (uint8_t)v;
}

static int chunk(FILE *f, const char *type, const uint8_t *data, uint32_t n)
{
    uint8_t hdr[8], tail[4];
    uint32_t c;
    put32(hdr, n);
    memcpy(hdr + 4, type, 4);
    c = crc32_update(0xFFFFFFFFu, hdr + 4, 4);
    c = crc32_update(c, data, n) ^ 0xFFFFFFFFu;
    put32(tail, c);
    return fwrite(hdr, 1, 8, f) != 8 || (n && fwrite(data, 1, n, f) != n) || fwrite(tail, 1, 4, f) != 4;
}

int st7920_emu_png(const char *path, int scale)
{
    static const uint8_t sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    static const uint8_t bg[3] = {0x9C, 0xC8, 0x3C}, fg[3] = {0x1E, 0x2A, 0x14};  /* yellow-green LCD */
    static uint8_t px[ST7920_H][ST7920_W];
    const int border = 4;
    int w, h, err;
    uint32_t raw_n, z_n, pos, a = 1, b = 0;
    uint8_t *raw, *z, ihdr[13];
    FILE *f;
    if (scale < 1 || scale > 16)
        return -1;
    w = (ST7920_W + 2 * border) * scale;
    h = (ST7920_H + 2 * border) * scale;
    st7920_emu_render(px);
    raw_n = (uint32_t)h * (uint32_t)(1 + 3 * w);
    raw = malloc(raw_n);
    z_n = 2 + raw_n + 5 * (raw_n / 65535 + 1) + 4;
    z = malloc(z_n);
    if (!raw || !z) {
        free(raw);
        free(z);
        return -1;
    }
    for (int y = 0; y < h; y++) {
        uint8_t *row = raw + (uint32_t)y * (uint32_t)(1 + 3 * w);
        int py = y / scale - border;
        row[0] = 0;                             /* filter: none */
        for (int x = 0; x < w; x++) {
            int pxx = x / scale - border;
            int on = py >= 0 && py < ST7920_H && pxx >= 0 && pxx < ST7920_W && px[py][pxx];
            memcpy(row + 1 + 3 * x, on ? fg : bg, 3);
        }
    }
    /* zlib: header, stored blocks of at most 65535 bytes, Adler-32 */
    z[0] = 0x78;
    z[1] = 0x01;
    pos = 2;
    for (uint32_t off = 0; off < raw_n;) {
        uint32_t n = raw_n - off > 65535u ? 65535u : raw_n - off;
        z[pos++] = off + n == raw_n ? 1 : 0;
        z[pos++] = (uint8_t)n;
        z[pos++] = (uint8_t)(n >> 8);
        z[pos++] = (uint8_t)~n;
        z[pos++] = (uint8_t)(~n >> 8);
        memcpy(z + pos, raw + off, n);
        pos += n;
        off += n;
    }
    for (uint32_t i = 0; i < raw_n; i++) {
        a = (a + raw[i]) % 65521u;
        b = (b + a) % 65521u;
    }
    put32(z + pos, (b << 16) | a);
    pos += 4;
    put32(ihdr, (uint32_t)w);
    put32(ihdr + 4, (uint32_t)h);
    ihdr[8] = 8;                                /* bit depth */
    ihdr[9] = 2;                                /* RGB */
    ihdr[10] = ihdr[11] = ihdr[12] = 0;
    f = fopen(path, "wb");
    err = !f;
    if (f) {
        err |= fwrite(sig, 1, 8, f) != 8;
        err |= chunk(f, "IHDR", ihdr, 13);
        err |= chunk(f, "IDAT", z, pos);
        err |= chunk(f, "IEND", NULL, 0);
        err |= fclose(f) != 0;
    }
    free(raw);
    free(z);
    return err ? -1 : 0;
}

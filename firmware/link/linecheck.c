/* linecheck.c: the serial link's CRC-8 and a command line's check and layout (linecheck.h). */
#include "linecheck.h"
#include "mul.h"

/* the CRC a nibble at a time: the same bits as bit by bit at a fraction of the cycles */
static const __code uint8_t crc8_nibble[16] = {
    0x00, 0x65, 0xCA, 0xAF, 0xF1, 0x94, 0x3B, 0x5E, 0x87, 0xE2, 0x4D, 0x28, 0x76, 0x13, 0xBC, 0xD9
};

uint8_t line_crc8(const __xdata char *p, uint8_t n) __reentrant
{
    uint8_t c = 0, b;
    while (n--) {
        b = (uint8_t)*p++;
        c = (uint8_t)(c << 4) ^ crc8_nibble[(c >> 4) ^ (b >> 4)];
        c = (uint8_t)(c << 4) ^ crc8_nibble[(c >> 4) ^ (b & 15u)];
    }
    return c;
}

/* a hex digit's value, either case; 0xFF for any other byte */
static uint8_t hexval(char c) __reentrant
{
    if (c >= '0' && c <= '9')
        return (uint8_t)(c - '0');
    c |= 0x20;
    return c >= 'a' && c <= 'f' ? (uint8_t)(c - 'a' + 10) : 0xFF;
}

const __xdata char *line_number(const __xdata char *p, __idata uint16_t *v, char sep) __reentrant
{
    uint16_t x = 0;
    uint8_t n = 0, d;
    while ((d = (uint8_t)(*p - '0')) <= 9u) {
        if (++n > 5 || x > 6553u || (x == 6553u && d > 5))
            return 0;               /* above 65535 */
        x = (uint16_t)(UMUL(x, 10u) + d);
        p++;
    }
    if (n == 0 || (*p != sep && *p != 0))
        return 0;
    *v = x;
    return p;
}

uint8_t line_check(__xdata char *p, uint8_t n) __reentrant
{
    uint8_t i, checked = 0, h1, h2;
    char last;
    for (i = 0; i < n && p[i] != '*'; i++)
        ;
    if (i < n) {
        /* "*HH" ends the line (a digit not hex: 0xFF, over 15 either way) */
        if ((uint8_t)(n - i) != 3u || ((h1 = hexval(p[i + 1])) | (h2 = hexval(p[i + 2]))) > 15u
            || (uint8_t)(h1 << 4 | h2) != line_crc8(p, i))
            return LINE_E_CSUM;
        n = i;
        checked = LINE_CHECKED;
    }
    p[n] = 0;
    /* words single-spaced: no space first (one after the start's "space"), last or after another */
    last = ' ';
    for (i = 0; i < n; i++) {
        if (p[i] == ' ' && last == ' ')
            return LINE_E_ARG;
        last = p[i];
    }
    if (last == ' ')
        return LINE_E_ARG;          /* (an empty line too) */
    return (uint8_t)(n | checked);
}

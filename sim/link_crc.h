/* link_crc.h: the serial link's line check on the PC side: CRC-8, polynomial 0x65, initial 0,
 * most significant bit first, bit by bit from its definition (firmware/link/serial.h). */
#ifndef LINK_CRC_H
#define LINK_CRC_H

#include <stddef.h>
#include <stdint.h>

static inline uint8_t link_crc8(const char *p, size_t n)
{
    uint8_t c = 0;
    for (size_t i = 0; i < n; i++) {
        c ^= (uint8_t)p[i];
        for (int k = 0; k < 8; k++)
            c = (uint8_t)(c & 0x80 ? (c << 1) ^ 0x65 : c << 1);
    }
    return c;
}

#endif

/* record.c: a record's check, a few bytes at a time: its header, its CRC and every value in range (store.h, store_int.h). */
#if defined(__SDCC)
#pragma stackauto           /* locals on the stack, not each its own XRAM (docs/MEMORY.md) */
#endif
#include "hal.h"
#include "params.h"
#include "store_int.h"

__data uint8_t sv_slot, sv_at;
uint16_t sv_crc;
uint8_t ck_ver;
static struct {
    uint8_t n;                      /* the values of the record being checked */
    uint8_t end;                    /* where its CRC is */
} ck;
static __data uint8_t ck_lo;        /* the byte the next is read with: the version before the count, a
                                     * value's low byte before its high one, the CRC's low byte */

/* CRC-16/CCITT (polynomial 0x1021, MSB first) a nibble at a time from a 16-entry table: the
 * same CRC as bit by bit at a fraction of the cycles (a save computes it over 118 bytes) */
static const __code uint16_t crc_nibble[16] = {
    0x0000, 0x1021, 0x2042, 0x3063, 0x4084, 0x50A5, 0x60C6, 0x70E7,
    0x8108, 0x9129, 0xA14A, 0xB16B, 0xC18C, 0xD1AD, 0xE1CE, 0xF1EF
};

uint16_t store_crc_byte(uint16_t crc, uint8_t b)
{
    crc = (uint16_t)(crc << 4) ^ crc_nibble[(uint8_t)(crc >> 12) ^ (b >> 4)];
    return (uint16_t)(crc << 4) ^ crc_nibble[(uint8_t)(crc >> 12) ^ (b & 0x0F)];
}

/* a record's bytes between its lifetime totals and its CRC, by version from 2: the learnt
 * figures (STORE_LEARN_V6 in version 6, STORE_LEARN_BYTES from 7), the job totals (from 8) */
static const __code uint8_t tail_bytes[PARAMS_VERSION - 1u] = {
    0, 0, 0, 0, STORE_LEARN_V6, STORE_LEARN_BYTES, STORE_LEARN_BYTES + STORE_JOB_BYTES,
    STORE_LEARN_BYTES + STORE_JOB_BYTES, STORE_LEARN_BYTES + STORE_JOB_BYTES, STORE_LEARN_BYTES + STORE_JOB_BYTES};
typedef char store_tail_bytes[(PARAMS_VERSION == 11) ? 1 : -1];   /* a new version: its tail here */

void store_ck_begin(uint8_t slot)
{
    sv_slot = slot;
    sv_at = 0;
    ck.end = 0xFFu;                 /* until the count is read */
    sv_crc = 0xFFFFu;
}

uint8_t store_ck_more(uint8_t budget) __reentrant
{
    uint16_t base = store_slot_base(sv_slot);
    uint8_t b;
    while (budget--) {
        b = hal_eeprom_read(base + sv_at);
        if (sv_at == 0) {
            if (b != STORE_MAGIC)
                return 0;
        } else if (sv_at == 2) {       /* the count; ck_lo: the version before it */
            if (ck_lo < 2u || ck_lo > PARAMS_VERSION || b != params_version_count[ck_lo - 2u])
                return 0;
            ck_ver = ck_lo;
            ck.n = b;
            ck.end = (uint8_t)(CRC_N(b) + tail_bytes[ck_lo - 2u]);
        } else if (!(sv_at & 1u) && sv_at > HDR_VALUES && sv_at < LIFE_N(ck.n)) {
            /* a value's high byte (HDR_VALUES is odd) */
            if (!param_stored_ok(ck_ver, (uint8_t)((sv_at - HDR_VALUES) >> 1), (uint16_t)(ck_lo | (uint16_t)b << 8)))
                return 0;
        } else if (sv_at == ck.end) {
            if (b != (uint8_t)(sv_crc >> 8))
                return 0;
            ck_lo = (uint8_t)sv_crc;    /* the CRC's low byte next */
            sv_at++;
            continue;
        } else if (sv_at > ck.end) {
            return b == ck_lo ? ck.n : 0;
        }
        ck_lo = b;
        sv_crc = store_crc_byte(sv_crc, b);
        sv_at++;
    }
    return CK_MORE;
}

uint8_t store_record_valid(uint8_t slot) __reentrant
{
    uint8_t r;
    store_ck_begin(slot);
    while ((r = store_ck_more(255)) == CK_MORE)
        ;
    return r;
}

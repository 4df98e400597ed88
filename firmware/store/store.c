/* store.c: parameters and lifetime totals in the IAP EEPROM as a log of CRC-checked records (see store.h). */
#if defined(__SDCC)
#pragma stackauto           /* locals on the stack, not each its own XRAM (docs/MEMORY.md) */
#endif
#include "hal.h"
#include "params.h"
#include "store.h"
#include "totals.h"

#define STORE_MAGIC 0x5A
#define HDR_SEQ 3u
#define HDR_VALUES 5u
#define HDR_LIFE (HDR_VALUES + 2u * P_COUNT)
#define HDR_LEARN (HDR_LIFE + 8u)
#define CRC_AT (HDR_LEARN + STORE_LEARN_BYTES)
/* the same for a copy of n values (an older version's shorter table) */
#define LIFE_N(n) (HDR_VALUES + 2u * (uint16_t)(n))
#define CRC_N(n) (LIFE_N(n) + 8u)
typedef char store_record_fits_a_slot[(STORE_COPY_BYTES <= STORE_SLOT_BYTES) ? 1 : -1];

static uint8_t status;              /* STORE_* */
#define newest store_newest         /* slot (0..STORE_SLOTS-1) of the record loaded or saved last, NO_SLOT (learnt.c) */
static uint16_t seq;                /* its sequence number */
#define NO_SLOT STORE_NO_SLOT
#define slot_base store_slot_base
typedef char store_learnt_at[(STORE_AT_LEARNT == HDR_LEARN) ? 1 : -1];

static const char __code *const __code status_texts[] = {
    "", "EE: older copy", "EE: defaults", "EE: write error", "EE: low supply"
};

/* CRC-16/CCITT (polynomial 0x1021, MSB first) a nibble at a time from a 16-entry table: the
 * same CRC as bit by bit at a fraction of the cycles (a save computes it over 118 bytes) */
static const __code uint16_t crc_nibble[16] = {
    0x0000, 0x1021, 0x2042, 0x3063, 0x4084, 0x50A5, 0x60C6, 0x70E7,
    0x8108, 0x9129, 0xA14A, 0xB16B, 0xC18C, 0xD1AD, 0xE1CE, 0xF1EF
};

static uint16_t crc_byte(uint16_t crc, uint8_t b)
{
    crc = (uint16_t)(crc << 4) ^ crc_nibble[(uint8_t)(crc >> 12) ^ (b >> 4)];
    return (uint16_t)(crc << 4) ^ crc_nibble[(uint8_t)(crc >> 12) ^ (b & 0x0F)];
}

static uint16_t read16(uint16_t a)
{
    return (uint16_t)(hal_eeprom_read(a) | ((uint16_t)hal_eeprom_read(a + 1u) << 8));
}

static uint32_t read32(uint16_t a)
{
    return (uint32_t)read16(a) | ((uint32_t)read16(a + 2u) << 16);
}

/* The number of values the copy in sector s holds when it has a known header, its CRC and every
 * value in range; 0 otherwise. Known: this version's table, or version 2's, 3's or 4's
 * (PARAMS_V2_COUNT, PARAMS_V3_COUNT, PARAMS_V4_COUNT values, the later ones appended since: they keep their
 * defaults). */
static uint8_t record_valid(uint16_t base) __reentrant
{
    uint16_t crc = 0xFFFFu;
    uint16_t i, at;
    uint8_t n = hal_eeprom_read(base + 2u), ver = hal_eeprom_read(base + 1u);
    if (hal_eeprom_read(base) != STORE_MAGIC
        || !((ver >= 5u && ver <= PARAMS_VERSION && n == P_COUNT) || (ver == 2u && n == PARAMS_V2_COUNT)
             || (ver == 3u && n == PARAMS_V3_COUNT) || (ver == 4u && n == PARAMS_V4_COUNT)))
        return 0;
    at = CRC_N(n);
    if (ver == PARAMS_VERSION)
        at += STORE_LEARN_BYTES;    /* the learnt figures (versions 2-5 have none) */
    for (i = 0; i < at; i++)
        crc = crc_byte(crc, hal_eeprom_read(base + i));
    if (hal_eeprom_read(base + at) != (uint8_t)(crc >> 8) || hal_eeprom_read(base + at + 1u) != (uint8_t)crc)
        return 0;
    for (i = 0; i < n; i++)
        if (!param_in_range((uint8_t)i, read16(base + HDR_VALUES + 2u * i)))
            return 0;
    return n;
}

/* 1 when every byte of a slot reads erased */
static uint8_t slot_blank(uint8_t slot) __reentrant
{
    uint16_t base = slot_base(slot), i;
    for (i = 0; i < STORE_SLOT_BYTES; i++)
        if (hal_eeprom_read(base + i) != 0xFFu)
            return 0;
    return 1;
}

uint8_t store_load(void) __reentrant
{
    uint8_t s, best = NO_SLOT, n;
    uint16_t q, best_q = 0, base;
    for (s = 0; s < STORE_SLOTS; s++) {
        if (!record_valid(slot_base(s)))
            continue;
        q = read16(slot_base(s) + HDR_SEQ);
        if (best == NO_SLOT || (int16_t)(q - best_q) > 0) {
            best = s;
            best_q = q;
        }
    }
    newest = best;                  /* the next save goes after it, above its sequence */
    seq = best_q;
    if (best == NO_SLOT) {
        params_defaults();
        status = STORE_DEFAULTS;
        return status;
    }
    /* its values and totals (a shorter, older table: the values after it at their defaults) */
    base = slot_base(best);
    n = record_valid(base);
    params_defaults();
    for (s = 0; s < n; s++)
        param_put(s, read16(base + HDR_VALUES + 2u * s));
    totals_set_life(read32(base + LIFE_N(n)), read32(base + LIFE_N(n) + 4u));
    n = params_cross();
    if (n != PARAM_OK) {
        /* written by a firmware without the cross-checks: its set cannot run (a tank minimum
         * above the tank stops the boom for good); the defaults, and the reason shown */
        params_defaults();
        totals_set_life(0, 0);
        status = (uint8_t)(STORE_CROSS + n - PARAM_X_TANK);
        return status;
    }
    status = STORE_OK;
    /* a started write after it (magic there, its sequence seq + 1 or not yet programmed):
     * a cut save, the previous values are loaded and the operator is told */
    s = (uint8_t)((best + 1u) % STORE_SLOTS);
    q = read16(slot_base(s) + HDR_SEQ);
    if (hal_eeprom_read(slot_base(s)) == STORE_MAGIC && !record_valid(slot_base(s))
        && (q == (uint16_t)(seq + 1u) || q == 0xFFFFu))
        status = STORE_OLDER;
    return status;
}

/* The slot the next record goes to: the first erased one after the newest, erasing the next
 * sector when the current one is full; NO_SLOT when the erase did not take. */
static uint8_t next_slot(void) __reentrant
{
    uint8_t s = newest == NO_SLOT ? 0 : (uint8_t)((newest + 1u) % STORE_SLOTS);
    while (!slot_blank(s)) {
        if (s % STORE_SLOTS_PER_SECTOR == 0) {
            /* the start of the other sector, which holds only records older than the
             * current sector's: erased as a whole */
            hal_eeprom_erase(slot_base(s));
            return slot_blank(s) ? s : NO_SLOT;
        }
        s = (uint8_t)((s + 1u) % STORE_SLOTS);
        if (s % STORE_SLOTS_PER_SECTOR == 0 && newest != NO_SLOT
            && s / STORE_SLOTS_PER_SECTOR == newest / STORE_SLOTS_PER_SECTOR)
            return NO_SLOT;         /* back at the newest's sector: nothing to erase safely */
    }
    return s;
}

uint8_t store_save(void) __reentrant
{
    uint16_t base;
    uint16_t crc = 0xFFFFu;
    uint16_t next = (uint16_t)(seq + 1u);
    uint8_t i, b, s, ok = 1;
    const __xdata totals_t *t = totals_get();
    if (hal_supply_low()) {
        status = STORE_LOW_SUPPLY;  /* a write that the supply may cut: not started */
        return 0;
    }
    s = next_slot();
    if (s == NO_SLOT) {
        status = STORE_WRITE_ERR;
        return 0;
    }
    base = slot_base(s);
    for (i = 0; i < CRC_AT; i++) {
        if (i == 0)
            b = STORE_MAGIC;
        else if (i == 1)
            b = PARAMS_VERSION;
        else if (i == 2)
            b = P_COUNT;
        else if (i == HDR_SEQ)
            b = (uint8_t)next;
        else if (i == HDR_SEQ + 1u)
            b = (uint8_t)(next >> 8);
        else if (i >= HDR_LEARN)
            b = store_learnt_byte((uint8_t)(i - HDR_LEARN));
        else if (i >= HDR_LIFE + 4u)
            b = (uint8_t)(t->life_ml >> (8u * (i - HDR_LIFE - 4u)));
        else if (i >= HDR_LIFE)
            b = (uint8_t)(t->life_m2 >> (8u * (i - HDR_LIFE)));
        else if ((i - HDR_VALUES) & 1u)
            b = (uint8_t)(param_v[(i - HDR_VALUES) >> 1] >> 8);
        else
            b = (uint8_t)param_v[(i - HDR_VALUES) >> 1];
        crc = crc_byte(crc, b);
        ok &= hal_eeprom_write(base + i, b);
    }
    ok &= hal_eeprom_write(base + CRC_AT, (uint8_t)(crc >> 8));
    ok &= hal_eeprom_write(base + CRC_AT + 1u, (uint8_t)crc);
    if (ok && record_valid(base)) {
        newest = s;
        seq = next;
        status = STORE_OK;
        return 1;
    }
    status = STORE_WRITE_ERR;
    return 0;
}

uint8_t store_status(void)
{
    return status;
}

void store_status_clear(void)
{
    status = STORE_OK;
}

const char *store_status_text(uint8_t st)
{
    if (st >= STORE_CROSS)
        return param_why_text((uint8_t)(st - STORE_CROSS + PARAM_X_TANK));
    return status_texts[st];
}

/* store.c: parameters in the IAP EEPROM: versioned layout, CRC, two copies written alternately (see store.h). */
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
#define CRC_AT (HDR_LIFE + 8u)
/* the same for a copy of n values (an older version's shorter table) */
#define LIFE_N(n) (HDR_VALUES + 2u * (uint16_t)(n))
#define CRC_N(n) (LIFE_N(n) + 8u)

static uint8_t status;              /* STORE_* */
static uint8_t newest;              /* sector (0, 1) holding the copy loaded or saved last */
static uint16_t seq;                /* its sequence number */

static const char __code *const __code status_texts[] = {
    "", "EE: older copy", "EE: defaults", "EE: write error"
};

static uint16_t crc_byte(uint16_t crc, uint8_t b)
{
    uint8_t i;
    crc ^= (uint16_t)b << 8;
    for (i = 0; i < 8; i++)
        crc = (crc & 0x8000u) ? (uint16_t)((crc << 1) ^ 0x1021u) : (uint16_t)(crc << 1);
    return crc;
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
 * value in range; 0 otherwise. Known: this version's table, or version 2's or 3's
 * (PARAMS_V2_COUNT, PARAMS_V3_COUNT values, the later ones appended since: they keep their
 * defaults). */
static uint8_t copy_valid(uint8_t s)
{
    uint16_t base = s ? HAL_EEPROM_SECTOR : 0u;
    uint16_t crc = 0xFFFFu;
    uint16_t i, at;
    uint8_t n = hal_eeprom_read(base + 2u), ver = hal_eeprom_read(base + 1u);
    if (hal_eeprom_read(base) != STORE_MAGIC
        || !((ver == PARAMS_VERSION && n == P_COUNT) || (ver == 2u && n == PARAMS_V2_COUNT)
             || (ver == 3u && n == PARAMS_V3_COUNT)))
        return 0;
    at = CRC_N(n);
    for (i = 0; i < at; i++)
        crc = crc_byte(crc, hal_eeprom_read(base + i));
    if (hal_eeprom_read(base + at) != (uint8_t)(crc >> 8) || hal_eeprom_read(base + at + 1u) != (uint8_t)crc)
        return 0;
    for (i = 0; i < n; i++)
        if (!param_in_range((uint8_t)i, read16(base + HDR_VALUES + 2u * i)))
            return 0;
    return n;
}

uint8_t store_load(void) __reentrant
{
    uint8_t v0 = copy_valid(0), v1 = copy_valid(1);
    uint8_t s, i, n;
    uint16_t base;
    uint8_t both = v0 && v1;
    uint16_t q0 = read16(HDR_SEQ), q1 = read16(HAL_EEPROM_SECTOR + HDR_SEQ);
    params_defaults();
    if (!v0 && !v1) {
        status = STORE_DEFAULTS;
        newest = 1;                 /* the first save goes to sector 0 */
        seq = 0;
        return status;
    }
    if (both)
        s = ((int16_t)(q1 - q0) > 0) ? 1 : 0;
    else
        s = v1 ? 1 : 0;
    base = s ? HAL_EEPROM_SECTOR : 0u;
    n = s ? v1 : v0;
    for (i = 0; i < n; i++)
        param_set(i, read16(base + HDR_VALUES + 2u * i));
    totals_set_life(read32(base + LIFE_N(n)), read32(base + LIFE_N(n) + 4u));
    newest = s;
    seq = s ? q1 : q0;
    /* One copy bad. It was the newer one when it shows a started write of the next sequence
     * (magic there, sequence seq + 1 or not yet programmed): a cut save, the previous values
     * are loaded and the operator is told. Otherwise (a fresh second sector) all is well. */
    status = STORE_OK;
    if (!both) {
        uint16_t ob = s ? 0u : HAL_EEPROM_SECTOR;
        uint16_t oq = read16(ob + HDR_SEQ);
        if (hal_eeprom_read(ob) == STORE_MAGIC && (oq == (uint16_t)(seq + 1u) || oq == 0xFFFFu))
            status = STORE_OLDER;
    }
    return status;
}

uint8_t store_save(void) __reentrant
{
    uint8_t s = newest ? 0 : 1;
    uint16_t base = s ? HAL_EEPROM_SECTOR : 0u;
    uint16_t crc = 0xFFFFu;
    uint16_t next = (uint16_t)(seq + 1u);
    uint8_t i, b, ok = 1;
    const totals_t *t = totals_get();
    hal_eeprom_erase(base);
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
    if (ok && copy_valid(s)) {
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
    return st < 4 ? status_texts[st] : "";
}

/* learnt.c: the figures learnt from the sprayer: as the newest EEPROM record holds them (store.h), read where they lie, and where a save takes them from. */
#include "hal.h"
#include "params.h"
#include "store.h"

/*
 * A module of its own, apart from store.c: the controllers and the alarms read their learnt
 * figures back when they start, and need neither the writing of the log nor what it writes.
 */

typedef char learnt_after_values[(STORE_AT_LEARNT == 13u + 2u * P_COUNT) ? 1 : -1];
uint8_t store_newest;               /* slot of the record loaded or saved last, STORE_NO_SLOT */
static store_learnt_fn learnt_fn;           /* store_learnt_from's */

void store_learnt_from(store_learnt_fn fn) __reentrant
{
    learnt_fn = fn;
}

uint8_t store_learnt_now(uint8_t i) __reentrant
{
    return learnt_fn ? learnt_fn(i) : 0xFFu;
}

uint16_t store_slot_base(uint8_t slot)
{
    return (uint16_t)((slot / STORE_SLOTS_PER_SECTOR) * HAL_EEPROM_SECTOR
                      + (slot % STORE_SLOTS_PER_SECTOR) * STORE_SLOT_BYTES);
}

uint8_t store_learnt(uint8_t i)
{
    uint16_t base = store_slot_base(store_newest);
    if (store_newest == STORE_NO_SLOT || hal_eeprom_read(base + 1u) < STORE_LEARN_VERSION)
        return 0xFFu;
    /* after the record's own count of values (an older record's table is shorter) */
    return hal_eeprom_read(base + 13u + 2u * hal_eeprom_read(base + 2u) + i);
}

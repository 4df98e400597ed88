/* store.h: the parameters in the IAP EEPROM: two CRC-checked copies, written alternately, so a power cut never loses both. */
#ifndef STORE_H
#define STORE_H

#include "compiler.h"

/*
 * Layout of one copy (one per 512-byte sector, at 0x000 and 0x200):
 *   0      magic 0x5A
 *   1      PARAMS_VERSION (version 2's shorter table still loads, the values appended since at
 *          their defaults; any other version is not loaded: defaults instead)
 *   2      P_COUNT (PARAMS_V2_COUNT in a version 2 copy)
 *   3..4   sequence number, little endian (the newer of two valid copies is the one whose
 *          sequence is ahead by 1..32767, so it may wrap)
 *   5..    P_COUNT values, uint16 little endian, in the order of params.h
 *   then   the lifetime totals: area m^2 and volume ml, uint32 little endian each
 *   then   CRC-16/CCITT (poly 0x1021, init 0xFFFF) of all the bytes before it, high byte first
 * A save erases the sector that does not hold the newest copy and writes there, CRC last:
 * a cut during the erase or at any byte leaves the previous copy untouched and the new one
 * failing its CRC. A copy is loaded only when its CRC matches and every value passes
 * param_in_range(); otherwise the other copy, otherwise the defaults.
 */
#define STORE_COPY_BYTES (5u + 2u * P_COUNT + 8u + 2u)

/* What store_load() found (store_status()). */
#define STORE_OK 0          /* the newest copy is good */
#define STORE_OLDER 1       /* the newest copy was bad (a cut write): the previous one is loaded */
#define STORE_DEFAULTS 2    /* no valid copy (first boot, both corrupt, other version): defaults */
#define STORE_WRITE_ERR 3   /* the last save did not read back */

/* Load the newest valid copy into param_v and the lifetime totals (totals.c; call after
 * totals_init) -- defaults and zero totals when none is valid; returns the status. */
uint8_t store_load(void) __reentrant;
/* Write param_v and the lifetime totals as a new copy (into the other sector); 1 when it reads back. */
uint8_t store_save(void) __reentrant;
/* Status of the last load or save; store_status_clear() once the operator has seen it. */
uint8_t store_status(void);
void store_status_clear(void);
/* One line (at most 16 characters) explaining a status, "" for STORE_OK. */
const char *store_status_text(uint8_t st);

#endif

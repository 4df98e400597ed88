/* store.h: the parameters and lifetime totals in the IAP EEPROM: a log of CRC-checked records that a power cut never loses whole. */
#ifndef STORE_H
#define STORE_H

#include "compiler.h"

/*
 * The EEPROM is a log. Each record (one slot of STORE_SLOT_BYTES; STORE_SLOTS_PER_SECTOR
 * slots in each of the two 512-byte sectors, slot 0 of a sector at its start):
 *   0      magic 0x5A
 *   1      PARAMS_VERSION (version 2's shorter table still loads, the values appended since at
 *          their defaults; any other version is not loaded)
 *   2      P_COUNT (PARAMS_V2_COUNT in a version 2 record, PARAMS_V8_COUNT in versions 5-8);
 *          what follows the values is found after the record's own count of them
 *   3..4   sequence number, little endian (the newest record is the one whose sequence is
 *          ahead of the others by 1..32767, so it may wrap)
 *   5..    P_COUNT values, uint16 little endian, in the order of params.h (before version 9
 *          Rate 1 was whole L/ha: loaded times 10)
 *   then   the lifetime totals: area m^2 and volume ml, uint32 little endian each
 *   then   (version 7) the figures learnt from the sprayer, STORE_LEARN_BYTES: ffmap's valve
 *          (ctl_learnt_byte: loop gain, break-away, reversal threshold, the speed's feed-forward)
 *          and the nozzle model (diag_learnt_byte), 0xFF where none is learnt; a version 5 copy
 *          (no such bytes) or a version 6 one (STORE_LEARN_V6 of them, without the feed-forward)
 *          still loads, and nothing learnt is restored from it
 *   then   (version 8) the job totals: area dm^2 x100 and volume ml, uint32 little endian each
 *          (an older copy loads with the job at zero)
 *   then   CRC-16/CCITT (poly 0x1021, init 0xFFFF) of all the bytes before it, high byte first
 * A save appends a record to the first erased slot after the newest one, CRC last; only when
 * a sector is full does the next save erase the other sector (which holds only older
 * records) and start there: one erase every STORE_SLOTS_PER_SECTOR saves, the two sectors
 * taking turns. A cut during the erase or at any byte leaves the newest record untouched and
 * the new one failing its CRC (a half-written slot is passed over by the next save).
 * A record is loaded only when its CRC matches and every value passes param_in_range(),
 * otherwise the next older one, otherwise the defaults; a newest record whose set breaks a
 * cross-check (params_cross: written by a firmware without them) gives the defaults and the
 * reason (STORE_CROSS).
 * No save starts while the supply is low (hal_supply_low): STORE_LOW_SUPPLY.
 *
 * The erase budget: the chip's EEPROM is rated STORE_ERASE_LIFE erases a sector; over ten
 * seasons a season may spend a tenth. An erase takes a token of a bucket that holds at most
 * STORE_ERASE_BURST and gains one every STORE_ERASE_MS, empty at power-up (so that power
 * cycles buy none): whatever asks for saves, a day costs at most 86400000 / STORE_ERASE_MS +
 * STORE_ERASE_BURST = 1448 erases, 724 a sector, 7.2 % of a season's share (10,000). Normal
 * work needs a quarter of the rate: a save a minute of spraying, 4 to an erase. A save that
 * needs an erase while the bucket is empty waits for its token (store_poll returns 0
 * meanwhile): after power-up, one save in four may wait up to STORE_ERASE_MS.
 */
#define STORE_ERASE_LIFE 100000UL
#define STORE_ERASE_MS 60000UL
#define STORE_ERASE_BURST 8u
#define STORE_LEARN_CTL 8u          /* learnt bytes: ffmap's valve and speed feed-forward ... */
#define STORE_LEARN_BYTES (STORE_LEARN_CTL + 4u)   /* ... and the nozzle model */
#define STORE_LEARN_V6 10u          /* a version 6 record's learnt bytes */
#define STORE_LEARN_VERSION 7u      /* the first version whose learnt bytes are this layout's */
#define STORE_JOB_BYTES 8u          /* the job totals (version 8) */
#define STORE_COPY_BYTES (5u + 2u * P_COUNT + 8u + STORE_LEARN_BYTES + STORE_JOB_BYTES + 2u)
#define STORE_SLOT_BYTES 128u       /* a record of 45 values, the learnt figures and the job is 125 bytes */
#define STORE_SLOTS_PER_SECTOR 4u
#define STORE_SLOTS 8u
#define STORE_NO_SLOT 0xFFu
#define STORE_AT_LEARNT (5u + 2u * P_COUNT + 8u)  /* where the learnt bytes start in a record */

/* What store_load() found, or a save that failed since (store_status(), the operator's notice
 * until store_status_clear()); a save's own result (store_result()): STORE_OK, _WRITE_ERR or
 * _LOW_SUPPLY. */
#define STORE_OK 0          /* the newest record is good */
#define STORE_OLDER 1       /* the newest record was bad (a cut write): the previous one is loaded */
#define STORE_DEFAULTS 2    /* no valid record (first boot, all corrupt, other version): defaults */
#define STORE_WRITE_ERR 3   /* the last save did not read back */
#define STORE_LOW_SUPPLY 4  /* the last save was not started: the supply was low */
#define STORE_CROSS 5       /* STORE_CROSS + (PARAM_X_* - PARAM_X_TANK): the newest record broke a
                             * cross-check (params.h): the defaults loaded */

/* Load the newest valid record into param_v and the lifetime totals (totals.c; call after
 * totals_init) -- defaults and zero totals when none is valid; returns the status. */
uint8_t store_load(void) __reentrant;
/* A save appends param_v and the lifetime totals as a new record, a few bytes a pass (an
 * erase in a pass of its own): store_save_start asks for one (0, and STORE_LOW_SUPPLY, when
 * the supply is low); the main loop calls store_poll, which returns 1 while it had work;
 * store_done(who) is 1 once after the save asked for by who has ended, store_status() then
 * says how. A save asked for while one runs: the values written so far are left (a half-
 * written slot, a cut write to the load) and the newest ones go to the next slot; asked for
 * while the record's CRC is out: that one is read back, then another one runs. */
#define STORE_BY_CONSOLE 0x10u
#define STORE_BY_SERIAL 0x20u
#define STORE_BY_ALL (STORE_BY_CONSOLE | STORE_BY_SERIAL)
uint8_t store_save_start(uint8_t who);
uint8_t store_poll(void) __reentrant;
uint8_t store_done(uint8_t who);
uint8_t store_asked(uint8_t who);  /* 1 from store_save_start(who) until store_done(who) */
uint8_t store_busy(void);           /* 1 while a save runs (or waits for the erase budget) */
/* A whole save at once (its passes in one call); 1 when it reads back. */
uint8_t store_save(void) __reentrant;
/* Byte i of the learnt figures in the record loaded or saved last; 0xFF when it has none
 * (learnt.c: the slot of that record and the address of a slot). */
uint8_t store_learnt(uint8_t i);
extern uint8_t store_newest;
uint16_t store_slot_base(uint8_t slot);
/* Where a save takes byte i of the learnt figures: the layer that owns them registers it at its
 * init (ops/diag.c diag_init: ffmap's valve through ctl.h, then the nozzle model); the store
 * calls nothing above it by name. None registered: 0xFF bytes, nothing learnt. */
typedef uint8_t (*store_learnt_fn)(uint8_t i) __reentrant;
void store_learnt_from(store_learnt_fn fn) __reentrant;
/* Byte i of the learnt figures a save writes now: the registered source's (learnt.c). */
uint8_t store_learnt_now(uint8_t i) __reentrant;
/* The notice of the last load, or of a save that failed since; store_status_clear() once the
 * operator has seen it (a save that succeeds does not clear it). */
uint8_t store_status(void);
void store_status_clear(void);
/* How the last save ended (store_done says when): STORE_OK, STORE_WRITE_ERR, STORE_LOW_SUPPLY. */
uint8_t store_result(void);
/* The param_generation (params.h) of the values loaded, or of those the last save that ended
 * well wrote: a different one means settings changed and not yet saved. */
uint8_t store_generation(void);
/* One line (at most 16 characters) explaining a status, "" for STORE_OK (the cross-check's
 * reason for STORE_CROSS + n). */
const __code char *store_status_text(uint8_t st);

#endif

/* store_int.h: what the log (store.c: load and save) and a record's check (record.c) share: the record's layout and the slot being worked on. */
#ifndef STORE_INT_H
#define STORE_INT_H

#include "compiler.h"
#include "params.h"
#include "store.h"

/* where each part of a record starts (store.h) */
#define STORE_MAGIC 0x5A
#define HDR_SEQ 3u
#define HDR_VALUES 5u
#define HDR_LIFE (HDR_VALUES + 2u * P_COUNT)
#define HDR_LEARN (HDR_LIFE + 8u)
#define HDR_JOB (HDR_LEARN + STORE_LEARN_BYTES)
#define CRC_AT (HDR_JOB + STORE_JOB_BYTES)
/* the same for a copy of n values (an older version's shorter table) */
#define LIFE_N(n) (HDR_VALUES + 2u * (uint16_t)(n))
#define CRC_N(n) (LIFE_N(n) + 8u)

/* The slot being found, written, checked or loaded and its next byte (the most used bytes of
 * the save and the check, in the direct RAM), and the CRC of the bytes written or checked so
 * far. */
extern __data uint8_t sv_slot, sv_at;
extern uint16_t sv_crc;
/* The version of the record checked last (its header's). */
extern uint8_t ck_ver;

/* CRC-16/CCITT (poly 0x1021, MSB first) of the bytes so far, b added. */
uint16_t store_crc_byte(uint16_t crc, uint8_t b) __reentrant;
/* Check the record in a slot a few bytes at a time: store_ck_begin, then store_ck_more until
 * it returns other than CK_MORE: the number of values the record holds when it has a known
 * header, its CRC and every value in range; 0 otherwise. Known: this version's table, or an
 * older one's (params_version_count: the values appended since keep their defaults). */
#define CK_MORE 0xFFu
void store_ck_begin(uint8_t slot);
uint8_t store_ck_more(uint8_t budget) __reentrant;
/* The check at once (store_load). */
uint8_t store_record_valid(uint8_t slot) __reentrant;

#endif

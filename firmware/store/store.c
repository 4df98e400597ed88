/* store.c: parameters and lifetime totals in the IAP EEPROM as a log of CRC-checked records (see store.h). */
#if defined(__SDCC)
#pragma stackauto           /* locals on the stack, not each its own XRAM (docs/MEMORY.md) */
#endif
#include <stddef.h>
#include "hal.h"
#include "params.h"
#include "store.h"
#include "totals.h"
#include "store_int.h"

typedef char store_record_fits_a_slot[(STORE_COPY_BYTES <= STORE_SLOT_BYTES) ? 1 : -1];

static uint8_t status;              /* STORE_*: the operator's notice (store_status) */
static uint8_t result;              /* how the last save ended (store_result) */
static uint8_t saved_gen;           /* param_generation of the newest record's values */
static struct {
    uint32_t next_ms;               /* when the bucket gains its next token */
    uint8_t tokens;                 /* erases allowed now, at most STORE_ERASE_BURST */
} eb;
static uint16_t seq;                /* the sequence number of the newest record (store_newest) */
typedef char store_learnt_at[(STORE_AT_LEARNT == HDR_LEARN) ? 1 : -1];

static const char __code *const __code status_texts[] = {
    "", "EE: older copy", "EE: defaults", "EE: write error", "EE: low supply"
};

/* The load reads the record in sv_slot front to back: the byte at sv_at, then the next */
static uint8_t ee_u8(void)
{
    return hal_eeprom_read(store_slot_base(sv_slot) + sv_at++);
}

static uint16_t ee_u16(void)
{
    uint8_t lo = ee_u8();
    return (uint16_t)(lo | ((uint16_t)ee_u8() << 8));
}

static uint32_t ee_u32(void)
{
    uint16_t lo = ee_u16();
    return (uint32_t)lo | ((uint32_t)ee_u16() << 16);
}

/*
 * A save runs a few bytes a pass (store_poll: STORE_BYTES_PER_POLL bytes read or written, or
 * one erase), so that no pass of the main loop holds it whole: find the first erased slot
 * after the newest (erasing the other sector when the current one is full), write the record,
 * its CRC last, and read it back with the same check a load makes. The bytes go out in the
 * order they did in one pass, so a power cut anywhere still leaves the newest record or the
 * previous one. The values are written over several passes: a settings change before the
 * CRC abandons the half-written slot (it reads as a cut write) and starts again in the next
 * one, so that a record never mixes two sets. The lifetime totals start a pass of their own
 * and are written within it, so both are from the same step.
 */
#define STORE_BYTES_PER_POLL 16u
/* the learnt figures start a pass's bytes of their own: read from their owners at one time */
typedef char store_learnt_in_one_pass[(STORE_LEARN_BYTES <= STORE_BYTES_PER_POLL) ? 1 : -1];
typedef char store_totals_in_one_pass[(8u <= STORE_BYTES_PER_POLL) ? 1 : -1];
/* record_byte reads the two lifetime totals as one run of 8 bytes, and the job's so */
typedef char store_life_adjacent[(offsetof(totals_t, life_ml) == offsetof(totals_t, life_m2) + 4u) ? 1 : -1];
typedef char store_job_adjacent[(offsetof(totals_t, job_ml) == offsetof(totals_t, job_dm2) + 4u) ? 1 : -1];
enum { SV_IDLE, SV_FIND, SV_ERASE, SV_WRITE, SV_CHECK };
/* sv.flags: who asked for the save running (STORE_BY_*), who asked for the next one (SV_NEXT),
 * whose save has ended (SV_DONE, store_done), SV_AGAIN: a save was asked for while this one's
 * CRC was out; SV_ERASED: the slot being found was just erased */
#define SV_ERASED 0x01u
#define SV_AGAIN 0x02u
#define SV_DONE(who) ((uint8_t)((who) >> 2))
#define SV_NEXT(who) ((uint8_t)((who) << 2))
#define SV_ENDED (SV_DONE(STORE_BY_ALL))
static struct {
    uint8_t flags;                  /* below */
    uint8_t gen;                    /* the param_generation the record being written comes from */
} sv;
static __data uint8_t sv_state;     /* SV_* (direct RAM: the most used byte of the save) */

/* Byte i of the record of the values and totals now, sequence next (the values and totals
 * are little endian in memory as in the record: SDCC's 8051 and the host's x86 or ARM) */
static const __code uint8_t header[HDR_SEQ] = {STORE_MAGIC, PARAMS_VERSION, P_COUNT};

static uint8_t record_byte(uint8_t i, uint16_t next) __reentrant
{
    if (i < HDR_SEQ)                /* the magic, the version, the count */
        return header[i];
    if (i == HDR_SEQ)
        return (uint8_t)next;
    if (i == HDR_SEQ + 1u)
        return (uint8_t)(next >> 8);
    if (i >= HDR_JOB)               /* job_dm2, then job_ml (totals_t) */
        return ((const __xdata uint8_t *)&totals.job_dm2)[i - HDR_JOB];
    if (i >= HDR_LEARN)
        return store_learnt_now((uint8_t)(i - HDR_LEARN));
    if (i >= HDR_LIFE)              /* life_m2, then life_ml (totals_t) */
        return ((const __xdata uint8_t *)&totals.life_m2)[i - HDR_LIFE];
    return ((const __xdata uint8_t *)param_v)[i - HDR_VALUES];
}

/* 1 when the slot after `slot` (the newest) begins as the next save writes a record
 * (record_byte's header with the sequence after seq), each byte as written or, after the
 * magic, still erased (a cut leaves the rest unprogrammed) */
static uint8_t started_after(uint8_t slot) __reentrant
{
    uint16_t base = store_slot_base((uint8_t)((slot + 1u) % STORE_SLOTS));
    uint16_t next = (uint16_t)(seq + 1u);
    uint8_t i, b;
    for (i = 0; i < HDR_VALUES; i++) {
        b = hal_eeprom_read(base + i);
        if (b != record_byte(i, next) && (i == 0 || b != 0xFFu))
            return 0;
    }
    return 1;
}

/* The newest record's values and totals (a shorter, older table: the values after it at their
 * defaults); what the operator is told of it */
static uint8_t load_newest(void) __reentrant
{
    uint8_t s, n = store_record_valid(store_newest), ver = ck_ver;     /* (the check's version) */
    uint16_t v;
    sv_slot = store_newest;
    sv_at = HDR_VALUES;
    params_defaults();
    for (s = 0; s < n; s++) {       /* (before version 9 the aog settings were another loop's) */
        v = ee_u16();
        if (ver >= 9u || s < P_AOG_KP || s > P_AOG_MAX)
            param_put(s, param_of_version(ver, s, v));
    }
    {
        uint32_t life_m2 = ee_u32(), life_ml = ee_u32();
        totals_set_life(life_m2, life_ml);
    }
    if (ver >= 8u) {                /* the job after the learnt figures */
        uint32_t job_dm2, job_ml;
        sv_at += STORE_LEARN_BYTES;
        job_dm2 = ee_u32();
        job_ml = ee_u32();
        totals_set_job(job_dm2, job_ml);
    } else
        totals_job_reset();         /* an older copy has none */
    n = params_cross();
    if (n != PARAM_OK) {
        /* written by a firmware without the cross-checks: its set cannot run (a tank minimum
         * above the tank stops the boom for good); the defaults, and the reason shown */
        params_defaults();
        totals_set_life(0, 0);
        totals_job_reset();
        return (uint8_t)(STORE_CROSS + n - PARAM_X_TANK);
    }
    /* a started write after it that did not end: a cut save, the previous values are loaded
     * and the operator is told */
    s = (uint8_t)((store_newest + 1u) % STORE_SLOTS);
    return started_after(store_newest) && !store_record_valid(s) ? STORE_OLDER : STORE_OK;
}

uint8_t store_load(void) __reentrant
{
    uint8_t s, newest_slot = STORE_NO_SLOT;
    uint16_t q, newest_q = 0;
    sv_state = SV_IDLE;             /* no save runs from before */
    sv.flags = 0;
    result = STORE_OK;
    eb.tokens = 0;                  /* none at power-up: a power cycle buys no erase */
    eb.next_ms = hal_ms() + STORE_ERASE_MS;
    for (s = 0; s < STORE_SLOTS; s++) {
        if (!store_record_valid(s))
            continue;
        sv_slot = s;
        sv_at = HDR_SEQ;
        q = ee_u16();
        if (newest_slot == STORE_NO_SLOT || (int16_t)(q - newest_q) > 0) {
            newest_slot = s;
            newest_q = q;
        }
    }
    store_newest = newest_slot;     /* the next save goes after it, above its sequence */
    seq = newest_q;
    if (newest_slot == STORE_NO_SLOT) {
        params_defaults();
        status = STORE_DEFAULTS;
    } else
        status = load_newest();
    saved_gen = param_generation;   /* the values loaded (or the defaults): no save until they change */
    return status;
}

/* Look for the slot the next record goes to from slot on, the first erased one (sv_find_more);
 * 0 when slot starts the newest's sector: nothing to erase safely. */
static uint8_t sv_find(uint8_t slot)
{
    sv_state = SV_FIND;
    sv.flags &= (uint8_t)~SV_ERASED;
    sv_slot = slot;
    sv_at = 0;
    return !(slot % STORE_SLOTS_PER_SECTOR == 0 && store_newest != STORE_NO_SLOT
             && slot / STORE_SLOTS_PER_SECTOR == store_newest / STORE_SLOTS_PER_SECTOR);
}

/* The next slot after the newest: never the start of the newest's sector */
static void sv_start(void)
{
    sv_find(store_newest == STORE_NO_SLOT ? 0 : (uint8_t)((store_newest + 1u) % STORE_SLOTS));
}

/* The save has ended (st: STORE_OK or STORE_WRITE_ERR): those who asked are told
 * (store_done); the one asked for while its CRC was out starts. */
static void sv_end(uint8_t st)
{
    uint8_t f = sv.flags;
    result = st;
    /* the operator is told of a failed save; a good one clears that, never what the load found */
    if (st != STORE_OK || status == STORE_WRITE_ERR || status == STORE_LOW_SUPPLY)
        status = st;
    sv_state = SV_IDLE;
    sv.flags = (uint8_t)((f & SV_ENDED) | SV_DONE(f & STORE_BY_ALL));
    if (f & SV_AGAIN) {
        sv.flags |= (uint8_t)((f >> 2) & STORE_BY_ALL);
        sv_start();
    }
}

/* The slot after this one, from its start: a write error back at the newest's sector */
static void sv_find_next(void)
{
    if (!sv_find((uint8_t)((sv_slot + 1u) % STORE_SLOTS)))
        sv_end(STORE_WRITE_ERR);
}

/* The free slot: STORE_BYTES_PER_POLL bytes of the one looked at. A written byte passes
 * over the slot, or erases the other sector when the slot starts it (it holds only records
 * older than the current sector's); back at the newest's sector, or a slot written after its
 * erase: a write error. */
static void sv_find_more(void) __reentrant
{
    uint16_t base = store_slot_base(sv_slot);
    uint8_t k;
    for (k = 0; k < STORE_BYTES_PER_POLL; k++, sv_at++) {
        if (sv_at == STORE_SLOT_BYTES) {
            sv_state = SV_WRITE;    /* erased: the record goes here */
            sv_at = 0;
            sv_crc = 0xFFFFu;
            sv.gen = param_generation;
            return;
        }
        if (hal_eeprom_read(base + sv_at) == 0xFFu)
            continue;
        if (sv.flags & SV_ERASED) {
            sv_end(STORE_WRITE_ERR);    /* the erase did not take */
        } else if (sv_slot % STORE_SLOTS_PER_SECTOR == 0) {
            sv_state = SV_ERASE;
        } else {
            sv_find_next();
        }
        return;
    }
}

/* The record: STORE_BYTES_PER_POLL bytes, then the CRC when the values are still the ones
 * the record started with. */
static void sv_write_more(void) __reentrant
{
    uint16_t base = store_slot_base(sv_slot);
    uint16_t next = (uint16_t)(seq + 1u);
    uint8_t k, b;
    if (sv_at == CRC_AT) {
        if (sv.gen != param_generation) {
            sv_find_next();         /* a mixed set: left without its CRC, the values again */
            return;
        }
        if (!hal_eeprom_write(base + CRC_AT, (uint8_t)(sv_crc >> 8))
            || !hal_eeprom_write(base + CRC_AT + 1u, (uint8_t)sv_crc)) {
            sv_end(STORE_WRITE_ERR);
            return;
        }
        sv_state = SV_CHECK;
        store_ck_begin(sv_slot);
        return;
    }
    for (k = 0; k < STORE_BYTES_PER_POLL && sv_at < CRC_AT && !(k && (sv_at == HDR_LIFE || sv_at == HDR_LEARN || sv_at == HDR_JOB));
         k++, sv_at++) {
        b = record_byte(sv_at, next);
        sv_crc = store_crc_byte(sv_crc, b);
        if (!hal_eeprom_write(base + sv_at, b)) {
            sv_end(STORE_WRITE_ERR);
            return;
        }
    }
}

uint8_t store_save_start(uint8_t who)
{
    if (hal_supply_low()) {
        status = result = STORE_LOW_SUPPLY;     /* a write that the supply may cut: not started */
        sv.flags |= SV_DONE(who);
        return 0;
    }
    if (sv_state == SV_CHECK) {
        sv.flags |= SV_AGAIN | SV_NEXT(who);    /* its CRC is out: finish it, then save again */
        return 1;
    }
    sv.flags |= who;
    if (sv_state == SV_IDLE) {
        sv_start();
    } else if (sv_state == SV_WRITE) {
        sv_find_next();             /* the half-written slot is left (a cut write to the load) */
    }                               /* (a slot being found: it goes on from there) */
    return 1;
}

/* The erase budget's bucket: a token every STORE_ERASE_MS up to STORE_ERASE_BURST (a full
 * bucket gains none: its clock restarts) */
static void eb_fill(void)
{
    uint32_t now = hal_ms();
    if (eb.tokens >= STORE_ERASE_BURST)
        eb.next_ms = now + STORE_ERASE_MS;
    else if ((int32_t)(now - eb.next_ms) >= 0) {
        eb.tokens++;
        eb.next_ms += STORE_ERASE_MS;
    }
}

uint8_t store_poll(void) __reentrant
{
    uint8_t r;
    eb_fill();
    switch (sv_state) {
    case SV_IDLE:
        return 0;
    case SV_FIND:
        sv_find_more();
        break;
    case SV_ERASE:
        if (!eb.tokens)
            return 0;               /* the budget: waiting for a token */
        eb.tokens--;
        hal_eeprom_erase(store_slot_base(sv_slot));
        sv_state = SV_FIND;
        sv_at = 0;
        sv.flags |= SV_ERASED;
        break;
    case SV_WRITE:
        sv_write_more();
        break;
    default:
        r = store_ck_more(STORE_BYTES_PER_POLL);
        if (r == P_COUNT) {
            store_newest = sv_slot;
            seq = (uint16_t)(seq + 1u);
            saved_gen = sv.gen;
            /* a header in the next slot that reads as this save's successor is stale (this
             * save has ended, none started since): its magic cleared, the next load would
             * take it for a cut save */
            if (started_after(store_newest))
                hal_eeprom_write(store_slot_base((uint8_t)((store_newest + 1u) % STORE_SLOTS)), 0);
            sv_end(STORE_OK);
        } else if (r != CK_MORE) {
            sv_end(STORE_WRITE_ERR);
        }
        break;
    }
    return 1;
}

uint8_t store_asked(uint8_t who)
{
    return (sv.flags & (who | SV_NEXT(who) | SV_DONE(who))) != 0;
}

uint8_t store_busy(void)
{
    return sv_state != SV_IDLE;
}

uint8_t store_done(uint8_t who)
{
    if (!(sv.flags & SV_DONE(who)))
        return 0;
    sv.flags &= (uint8_t)~SV_DONE(who);
    return 1;
}

#if FW_PROBES
uint8_t store_save(void) __reentrant
{
    if (!store_save_start(0))
        return 0;
    while (store_poll())
        ;
    return sv_state == SV_IDLE && result == STORE_OK;   /* (not when it waits for the budget) */
}
#endif

uint8_t store_result(void)
{
    return result;
}

uint8_t store_generation(void)
{
    return saved_gen;
}

uint8_t store_status(void)
{
    return status;
}

void store_status_clear(void)
{
    status = STORE_OK;
}

const __code char *store_status_text(uint8_t st)
{
    if (st >= STORE_CROSS)
        return param_why_text((uint8_t)(st - STORE_CROSS + PARAM_X_TANK));
    return status_texts[st];
}

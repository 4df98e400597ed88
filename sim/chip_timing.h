/* chip_timing.h: the field image's time in the STC12C5A60S2 model: its passes, control steps, interrupt handlers, stack, resets and a wheel sweep's speeds. */
#ifndef SIM_CHIP_TIMING_H
#define SIM_CHIP_TIMING_H

#include <stdint.h>
#include <stdio.h>

/* What the model reported slot by slot (chip_host.c reads its frames into here). */
typedef struct {
    uint64_t passes, pass_sum;      /* main-loop passes, their 1T clocks in all */
    uint32_t pass_max, step_max;    /* the longest pass, the longest control step's pass */
    uint64_t pass_max_tick, step_max_tick;
    uint8_t max_adc, max_iap;       /* conversions and IAP operations the longest pass started */
    uint32_t *slot_max;             /* each slot's longest pass (slots with passes) */
    size_t n_slot, cap_slot;
    struct { unsigned v; uint32_t count, max, own_max; uint64_t sum; } vec[8];
    int n_vec;                      /* interrupt vectors the model timed */
    uint8_t sp_max;                 /* the stack's high-water mark (SP), from the model */
    unsigned resets;
    uint8_t cause;                  /* WDT_CONTR after the last reset */
    uint16_t early;                 /* output pins driven high between a reset and its first pass */
    uint32_t *speeds;               /* a wheel sweep's speeds (km/h x100), every 0.1 s */
    size_t n_speed, cap_speed;
} chip_timing_t;

/* A slot's passes from the report's bytes 8..23 (count, longest, sum, its conversions and IAP
 * operations, the longest control step) at this tick; -1 when memory ran out. */
int chip_timing_slot(chip_timing_t *t, const uint8_t *r, uint64_t tick);
/* A speed of the wheel sweep; -1 when memory ran out. */
int chip_timing_speed(chip_timing_t *t, uint16_t kmh_x100);
/* An interrupt handler's figures from the model's last frame (a record of 22 bytes). */
void chip_timing_handler(chip_timing_t *t, const uint8_t *v);
/* "chip:" lines: passes and interrupt handlers in 1T clocks and us, stack, resets, the sweep. */
void chip_timing_report(const chip_timing_t *t, FILE *f);
void chip_timing_free(chip_timing_t *t);

#endif

/* chip_timing.c: the field image's time in the STC12C5A60S2 model: its passes, control steps, interrupt handlers, stack, resets and a wheel sweep's speeds. */
#include <stdlib.h>
#include "chip_timing.h"
#include "lockstep.h"
#include "ucsim/stc12_link.h"

int chip_timing_slot(chip_timing_t *t, const uint8_t *r, uint64_t tick)
{
    unsigned np = (unsigned)lockstep_get(r + 8, 2);
    uint32_t mx = (uint32_t)lockstep_get(r + 10, 4), st = (uint32_t)lockstep_get(r + 20, 4);
    t->passes += np;
    t->pass_sum += lockstep_get(r + 14, 4);
    if (mx > t->pass_max) {
        t->pass_max = mx;
        t->pass_max_tick = tick;
        t->max_adc = r[18];
        t->max_iap = r[19];
    }
    if (st > t->step_max) {
        t->step_max = st;
        t->step_max_tick = tick;
    }
    if (lockstep_grow((void **)&t->slot_max, &t->cap_slot, t->n_slot, sizeof *t->slot_max) < 0)
        return -1;
    if (np)
        t->slot_max[t->n_slot++] = mx;
    return 0;
}

int chip_timing_speed(chip_timing_t *t, uint16_t kmh_x100)
{
    if (lockstep_grow((void **)&t->speeds, &t->cap_speed, t->n_speed, sizeof *t->speeds) < 0)
        return -1;
    t->speeds[t->n_speed++] = kmh_x100;
    return 0;
}

void chip_timing_handler(chip_timing_t *t, const uint8_t *v)
{
    if (t->n_vec == (int)(sizeof t->vec / sizeof t->vec[0]))
        return;
    t->vec[t->n_vec].v = (unsigned)lockstep_get(v, 2);
    t->vec[t->n_vec].count = (uint32_t)lockstep_get(v + 2, 4);
    t->vec[t->n_vec].max = (uint32_t)lockstep_get(v + 6, 4);
    t->vec[t->n_vec].own_max = (uint32_t)lockstep_get(v + 10, 4);
    t->vec[t->n_vec].sum = lockstep_get(v + 14, 8);
    t->n_vec++;
}

#define US(clk) ((clk) * 1e6 / STC12_SYSCLK_HZ)

/* the passes: their mean, a millisecond's longest at p99, the worst pass and control step */
static void report_passes(const chip_timing_t *t, FILE *f)
{
    fprintf(f, "chip: %llu passes, 1T clocks at 11.0592 MHz: mean %.0f (%.1f us)",
            (unsigned long long)t->passes, t->passes ? (double)t->pass_sum / t->passes : 0.0,
            t->passes ? US((double)t->pass_sum / t->passes) : 0.0);
    if (t->n_slot) {
        uint32_t *s = lockstep_sorted_u32(t->slot_max, t->n_slot);
        if (s) {
            fprintf(f, ", a millisecond's longest p99 %u (%.0f us)", s[(size_t)(0.99 * (t->n_slot - 1))],
                    US((double)s[(size_t)(0.99 * (t->n_slot - 1))]));
            free(s);
        }
    }
    fprintf(f, "\nchip: worst pass %u clocks = %.3f ms at tick %llu (%.3f s); it started %u conversions, %u IAP operations\n",
            t->pass_max, US((double)t->pass_max) / 1000, (unsigned long long)t->pass_max_tick, t->pass_max_tick * 1e-3,
            t->max_adc, t->max_iap);
    fprintf(f, "chip: worst control step pass (8 conversions) %u clocks = %.3f ms at %.3f s\n", t->step_max,
            US((double)t->step_max) / 1000, t->step_max_tick * 1e-3);
}

void chip_timing_report(const chip_timing_t *t, FILE *f)
{
    static const char *const name[8] = { "INT0 (wheel)", "timer 0 (tick)", "INT1", "timer 1", "UART", "ADC",
                                         "LVD", "PCA (meter, overflow)" };
    int i;
    report_passes(t, f);
    for (i = 0; i < t->n_vec; i++)
        if (t->vec[i].count)
            fprintf(f, "chip: handler %-22s vector 0x%02x: %u times, its own time max %u clocks = %.1f us, "
                       "mean %.0f; with the handlers preempting it max %u = %.1f us\n",
                    name[i], t->vec[i].v, t->vec[i].count, t->vec[i].own_max, US((double)t->vec[i].own_max),
                    (double)t->vec[i].sum / t->vec[i].count, t->vec[i].max, US((double)t->vec[i].max));
    if (t->sp_max)
        fprintf(f, "chip: stack high-water mark 0x%02x (SP, with the handlers' pushes): %d B below the top (0xff)\n",
                t->sp_max, 0xFF - t->sp_max);
    fprintf(f, "chip: %u resets (cause WDT_CONTR 0x%02x after the last); board driver pins driven high "
               "between a reset and its first pass: 0x%04x (P3 high byte, P1 low; 0x3070 the bridge, relay, buzzer)\n",
            t->resets, t->cause, t->early & 0x3070);
    if (t->n_speed) {
        uint32_t *s = lockstep_sorted_u32(t->speeds, t->n_speed);
        if (s) {
            fprintf(f, "chip: wheel sweep: %zu speeds every 0.1 s, km/h x100 min %u median %u max %u\n", t->n_speed,
                    s[0], s[t->n_speed / 2], s[t->n_speed - 1]);
            free(s);
        }
    }
}

void chip_timing_free(chip_timing_t *t)
{
    free(t->slot_max);
    free(t->speeds);
    t->slot_max = NULL;
    t->speeds = NULL;
}

/* pil_host.c: processor in the loop, host side: s51 driven through its console, frames through its simulator interface. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "pil_host.h"
#include "lockstep.h"
#include "pil_proto.h"
#include "hal_host.h"
#include "params.h"
#include "app.h"
#include "target.h"
#include "ctl_int.h"

/* What a pass did, from the HAL calls it made (the names of pil_report's worst pass). */
enum { K_ADC, K_LCD, K_TX, K_RX, K_EE_READ, K_EE_WRITE, K_EE_ERASE, K_VALVE, K_WDT, K_COUNT };
static const char *const k_name[K_COUNT] = {
    "ADC conversions", "LCD bytes", "UART bytes sent", "UART bytes received", "EEPROM reads",
    "EEPROM writes", "EEPROM erases", "valve outputs", "watchdog kicks"
};
#define PIL_STEP_ADC 8              /* a control step converts pressure and level 4 times each */

/* When something happened a pass at a time: how often, and the longest time between two */
typedef struct {
    size_t n;
    uint64_t last, gap_max, gap_at;  /* ticks (ms) */
} pil_every_t;

#define PIL_TOP 5                   /* the worst passes pil_report lists */
typedef struct {
    uint32_t cycles;
    uint64_t tick;
    unsigned k[K_COUNT];
    int key, setting;               /* a key changed at the tick; the pass changed a setting */
} pil_pass_t;

struct pil {
    sim_t *sim;
    lockstep_t link;                /* s51's process and the simulator interface's frames */
    uint16_t sent[P_COUNT];         /* the settings the firmware was given */
    uint32_t *cycles;               /* of each pass */
    size_t n_pass, cap;
    pil_pass_t top[PIL_TOP];        /* the worst passes, worst first */
    unsigned k[K_COUNT];            /* this pass's HAL calls */
    uint16_t keys_prev;
    int stack_hwm, stack_start;
    pil_every_t steps, kicks;       /* control steps, watchdog kicks */
};

static void every(pil_every_t *e, uint64_t tick)
{
    if (e->n && tick - e->last > e->gap_max) {
        e->gap_max = tick - e->last;
        e->gap_at = tick;
    }
    e->last = tick;
    e->n++;
}

static int rd(pil_t *p)
{
    return lockstep_byte(&p->link);
}

static unsigned rd16(pil_t *p)
{
    return lockstep_u16(&p->link);
}

static void wr(pil_t *p, const uint8_t *b, size_t n)
{
    lockstep_write(&p->link, b, n);
}

static size_t put16(uint8_t *b, unsigned v)
{
    return lockstep_put(b, v, 2);
}

static size_t put32(uint8_t *b, uint32_t v)
{
    return lockstep_put(b, v, 4);
}

/* the settings that differ from what the firmware was last given (all of them: every one) */
static size_t settings(pil_t *p, uint8_t *b, int every)
{
    size_t n = 1;
    uint8_t i, count = 0;
    for (i = 0; i < P_COUNT; i++)
        if (every || param_v[i] != p->sent[i]) {
            b[n++] = i;
            n += put16(b + n, param_v[i]);
            p->sent[i] = param_v[i];
            count++;
        }
    b[0] = count;
    return n;
}

/* A HAL call that drives an output or changes a setting of the machine (no answer): 0, or -1
 * when c is none of them. */
static int serve_out(pil_t *p, int c)
{
    unsigned a, v;
    switch (c) {
    case PIL_VALVE:
        a = (unsigned)rd(p);
        v = (unsigned)rd(p);
        hal_valve_out((int8_t)a, (uint8_t)v);
        p->k[K_VALVE]++;
        break;
    case PIL_SPRAY: hal_spray_enable((uint8_t)rd(p)); break;
    case PIL_BUZZER: hal_buzzer((uint8_t)rd(p)); break;
    case PIL_WDT:
        hal_wdt_kick();
        p->k[K_WDT]++;
        break;
    case PIL_LCD:
        a = (unsigned)rd(p);
        v = (unsigned)rd(p);
        hal_lcd_write((uint8_t)a, (uint8_t)v);
        p->k[K_LCD]++;
        break;
    case PIL_WHEEL_MIN:
        a = rd16(p);
        hal_wheel_min_interval(a | (uint32_t)rd16(p) << 16);
        break;
    case PIL_EE_ERASE:
        hal_eeprom_erase((uint16_t)rd16(p));
        p->k[K_EE_ERASE]++;
        break;
    default:
        return -1;
    }
    return 0;
}

/* A HAL call the host answers (a conversion, a capture, a byte): 0, or -1 when c is none of them. */
static int serve_in(pil_t *p, int c)
{
    uint8_t out[8];
    unsigned a;
    hal_capture_t cap;
    switch (c) {
    case PIL_ADC:
        wr(p, out, put16(out, hal_adc_read((uint8_t)rd(p))));
        p->k[K_ADC]++;
        return 0;
    case PIL_FLOW:
    case PIL_WHEEL:
        if (c == PIL_FLOW)
            hal_flow_capture_take(&cap);
        else
            hal_wheel_capture_take(&cap);
        put16(out, cap.count);
        put32(out + 2, cap.last);
        out[6] = cap.rejected;
        wr(p, out, 7);
        return 0;
    case PIL_UART_GET: {
        int16_t b = hal_uart_get();
        wr(p, out, put16(out, (uint16_t)b));
        p->k[K_RX] += b >= 0;
        return 0;
    }
    case PIL_RESET_CAUSE: out[0] = hal_reset_cause(); break;
    case PIL_SUPPLY_LOW: out[0] = hal_supply_low(); break;
    case PIL_UART_PUT:
        out[0] = hal_uart_put((uint8_t)rd(p));
        p->k[K_TX]++;
        break;
    case PIL_UART_FRAMING: out[0] = hal_uart_framing((uint8_t)rd(p)); break;
    case PIL_EE_READ:
        out[0] = hal_eeprom_read((uint16_t)rd16(p));
        p->k[K_EE_READ]++;
        break;
    case PIL_EE_WRITE:
        a = rd16(p);
        out[0] = hal_eeprom_write((uint16_t)a, (uint8_t)rd(p));
        p->k[K_EE_WRITE]++;
        break;
    default:
        return -1;
    }
    wr(p, out, 1);
    return 0;
}

/* Serve the firmware's HAL calls until `until` arrives (PIL_READY, PIL_DONE, PIL_REPORT). */
static int serve(pil_t *p, int until)
{
    for (;;) {
        int c = rd(p);
        if (c < 0)
            return -1;
        if (c == until)
            return 0;
        if (serve_out(p, c) < 0 && serve_in(p, c) < 0) {
            p->link.failed = 1;
            return -1;
        }
    }
}

/* a setting the firmware changed (console, serial link) into the host's copy, which the
 * simulator's reference and metrics read; param_set so that the host's rate target re-derives */
static void mirror(pil_t *p, uint8_t id, unsigned v)
{
    if (param_v[id] != v)
        param_set(id, (uint16_t)v);
    p->sent[id] = (uint16_t)v;
}

static void pass(void *ctx)
{
    pil_t *p = ctx;
    uint8_t b[16 + 3 * P_COUNT];
    size_t n = 0;
    uint32_t cyc;
    int fresh = 0;
    if (p->link.failed)
        return;
    b[n++] = PIL_TICK;
    n += put32(b + n, hal_ms());
    n += put32(b + n, hal_pca_now());
    n += put16(b + n, hal_host_io.keys);
    b[n++] = hal_host_io.sections;
    b[n++] = (uint8_t)(hal_host_uart_rx_waiting() > 255 ? 255 : hal_host_uart_rx_waiting());
    n += settings(p, b + n, 0);
    wr(p, b, n);
    memset(p->k, 0, sizeof p->k);
    if (serve(p, PIL_DONE) < 0)
        return;
    cyc = rd16(p);
    cyc |= (uint32_t)rd16(p) << 16;
    fresh = rd(p);
    if (!fresh)
        goto timing;
    app_status.in.speed_kmh_x100 = (uint16_t)rd16(p);
    app_status.in.target_lpm_x100 = (int16_t)rd16(p);
    app_status.in.flow_lpm_x100 = (int16_t)rd16(p);
    app_status.in.pressure_kpa = (uint16_t)rd16(p);
    app_status.tank_l = (uint16_t)rd16(p);
    app_status.drive = (int16_t)rd16(p);
    ctl_k[0] = (int16_t)rd16(p);    /* the host's copy of the gains (ctl_gain), idle in PIL */
    ctl_k[1] = (int16_t)rd16(p);
    ctl_k[2] = (int16_t)rd16(p);
    app_status.alarms = (uint16_t)rd16(p);
    mirror(p, P_RATE, rd16(p));
    mirror(p, P_METER_K, rd16(p));
    /* the host's copy of the rate target follows the settings when the firmware's does: in its
     * control step (the simulator's reference reads it) */
    if (fresh & 2)
        target_update(hal_sections());
timing:
    if (lockstep_grow((void **)&p->cycles, &p->cap, p->n_pass, sizeof *p->cycles) < 0) {
        p->link.failed = 1;
        return;
    }
    p->cycles[p->n_pass++] = cyc;
    if (p->k[K_ADC] >= PIL_STEP_ADC)
        every(&p->steps, p->sim->t_ns / SIM_TICK_NS);
    if (p->k[K_WDT])
        every(&p->kicks, p->sim->t_ns / SIM_TICK_NS);
    if (cyc > p->top[PIL_TOP - 1].cycles) {
        int i = PIL_TOP - 1;
        while (i > 0 && cyc > p->top[i - 1].cycles) {
            p->top[i] = p->top[i - 1];
            i--;
        }
        p->top[i].cycles = cyc;
        p->top[i].tick = p->sim->t_ns / SIM_TICK_NS;
        memcpy(p->top[i].k, p->k, sizeof p->k);
        p->top[i].key = hal_host_io.keys != p->keys_prev;
        p->top[i].setting = fresh == 1;
    }
    p->keys_prev = hal_host_io.keys;
}

/* NULL with the message in err, the run's traces removed */
static pil_t *pil_fail(pil_t *p, char *err, size_t n, const char *what)
{
    snprintf(err, n, "%s (%s/s51.log)", what, p->link.dir);
    pil_free(p);
    return NULL;
}

pil_t *pil_start(sim_t *sim, const char *ihx, char *err, size_t n)
{
    pil_t *p = calloc(1, sizeof *p);
    char iface[256];
    char *argv[] = { "s51", "-t", "C52", "-X", "11.0592M", "-I", iface, (char *)ihx, NULL };
    uint8_t b[8 + 3 * P_COUNT];
    size_t k;
    if (!p) {
        snprintf(err, n, "out of memory");
        return NULL;
    }
    p->sim = sim;
    lockstep_init(&p->link);
    if (access(ihx, R_OK) != 0) {
        snprintf(err, n, "%s: %s", ihx, strerror(errno));
        free(p);
        return NULL;
    }
    if (lockstep_fifos(&p->link, "/tmp/pil.XXXXXX", err, n) < 0) {
        pil_free(p);
        return NULL;
    }
    snprintf(iface, sizeof iface, "if=xram[0xffff],in=%s,out=%s", p->link.fifo_in, p->link.fifo_out);
    if (lockstep_spawn(&p->link, argv, 0) < 0)
        return pil_fail(p, err, n, "s51 did not open the simulator interface");
    lockstep_erase_eeprom();
    lockstep_drop_uart();
    if (rd(p) != PIL_HELLO)
        return pil_fail(p, err, n, "the firmware in s51 did not say hello");
    b[0] = PIL_CONFIG;
    k = 1 + settings(p, b + 1, 1);
    wr(p, b, k);
    if (serve(p, PIL_READY) < 0)
        return pil_fail(p, err, n, "the firmware in s51 did not start");
    k = 1 + settings(p, b + 1, 1);
    wr(p, b, k);
    sim->pass = pass;
    sim->pass_ctx = p;
    return p;
}

int pil_finish(pil_t *p)
{
    uint8_t q = PIL_QUIT;
    p->sim->pass = NULL;
    if (!p->link.failed) {
        wr(p, &q, 1);
        if (serve(p, PIL_REPORT) == 0) {
            p->stack_hwm = rd(p);
            p->stack_start = rd(p);
        }
    }
    if (p->link.console >= 0) {
        if (write(p->link.console, "quit\n", 5) != 5)
            p->link.failed = 1;
        close(p->link.console);
        p->link.console = -1;
    }
    if (lockstep_wait(&p->link, 1) < 0)
        return -1;
    return p->link.failed ? -1 : 0;
}

/* the worst passes, worst first, and what each did */
static void report_worst(const pil_t *p, FILE *f)
{
    size_t i, j;
    for (i = 0; i < PIL_TOP && p->top[i].cycles; i++) {
        const pil_pass_t *w = &p->top[i];
        int any = 0;
        if (i == 0)
            fprintf(f, "pil: worst pass at tick %llu (%.3f s): %u cycles = %.2f ms at 12T; it did:",
                    (unsigned long long)w->tick, w->tick * 1e-3, w->cycles, w->cycles / PIL_CYCLES_PER_MS);
        else
            fprintf(f, "pil: worst pass %zu at tick %llu (%.3f s): %u cycles; it did:", i + 1,
                    (unsigned long long)w->tick, w->tick * 1e-3, w->cycles);
        for (j = 0; j < K_COUNT; j++)
            if (w->k[j]) {
                fprintf(f, "%s %u %s", any ? "," : "", w->k[j], k_name[j]);
                any = 1;
            }
        if (w->key)
            fprintf(f, "%s a key change", any ? "," : "");
        if (w->setting)
            fprintf(f, "%s a settings change", any || w->key ? "," : "");
        fprintf(f, "%s\n", any || w->key || w->setting ? "" : " no HAL calls");
    }
}

void pil_report(const pil_t *p, FILE *f)
{
    uint32_t *s;
    size_t i, n = p->n_pass, per = 100, periods;
    double sum = 0, share_max = 0, share_sum = 0, period_cycles = PIL_CYCLES_PER_MS * per;
    if (!n) {
        fprintf(f, "pil: no passes\n");
        return;
    }
    s = lockstep_sorted_u32(p->cycles, n);
    if (!s)
        return;
    for (i = 0; i < n; i++)
        sum += p->cycles[i];
    /* the control period's share: a period's passes (one a millisecond) against its cycles */
    periods = n / per;
    for (i = 0; i < periods; i++) {
        double c = 0;
        size_t j;
        for (j = 0; j < per; j++)
            c += p->cycles[i * per + j];
        share_sum += c / period_cycles;
        if (c / period_cycles > share_max)
            share_max = c / period_cycles;
    }
    fprintf(f, "pil: %zu passes, machine cycles (classic 12T) mean %.0f, p99 %u, max %u "
               "(the 1T chip's own: make chip, docs/PIL.md)\n",
            n, sum / n, s[(size_t)(0.99 * (n - 1))], s[n - 1]);
    report_worst(p, f);
    if (periods)
        fprintf(f, "pil: control period (%zu ms) used: mean %.1f %%, max %.1f %% at 12T\n",
                per, 100 * share_sum / periods, 100 * share_max);
    fprintf(f, "pil: %zu control steps, the longest time between two %llu ms (at %.3f s); %zu watchdog kicks, "
               "the longest time between two %llu ms (at %.3f s)\n",
            p->steps.n, (unsigned long long)p->steps.gap_max, p->steps.gap_at * 1e-3, p->kicks.n,
            (unsigned long long)p->kicks.gap_max, p->kicks.gap_at * 1e-3);
    if (p->stack_hwm)
        fprintf(f, "pil: stack from 0x%02x, high-water mark 0x%02x: %d B used, %d B below the top (0xff)\n",
                p->stack_start, p->stack_hwm, p->stack_hwm - p->stack_start, 0xFF - p->stack_hwm);
    free(s);
}

void pil_free(pil_t *p)
{
    if (!p)
        return;
    lockstep_close(&p->link);
    free(p->cycles);
    free(p);
}

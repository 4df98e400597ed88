/* pil_host.c: processor in the loop, host side: s51 driven through its console, frames through its simulator interface. */
#define _GNU_SOURCE
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include "pil_host.h"
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
    pid_t pid;
    int to_fw, from_fw, console;
    char dir[64];
    uint8_t rbuf[4096];
    size_t rn, ri;
    uint16_t sent[P_COUNT];         /* the settings the firmware was given */
    uint32_t *cycles;               /* of each pass */
    size_t n_pass, cap;
    pil_pass_t top[PIL_TOP];        /* the worst passes, worst first */
    unsigned k[K_COUNT];            /* this pass's HAL calls */
    uint16_t keys_prev;
    int stack_hwm, stack_start;
    int failed;
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
    if (p->ri == p->rn) {
        ssize_t r;
        do
            r = read(p->from_fw, p->rbuf, sizeof p->rbuf);
        while (r < 0 && errno == EINTR);
        if (r <= 0) {
            p->failed = 1;
            return -1;
        }
        p->rn = (size_t)r;
        p->ri = 0;
    }
    return p->rbuf[p->ri++];
}

static unsigned rd16(pil_t *p)
{
    unsigned lo = (unsigned)rd(p) & 0xFF;
    return lo | ((unsigned)rd(p) & 0xFF) << 8;
}

static void wr(pil_t *p, const uint8_t *b, size_t n)
{
    while (n && !p->failed) {
        ssize_t w = write(p->to_fw, b, n);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0) {
            p->failed = 1;
            return;
        }
        b += w;
        n -= (size_t)w;
    }
}

static size_t put16(uint8_t *b, unsigned v)
{
    b[0] = (uint8_t)v;
    b[1] = (uint8_t)(v >> 8);
    return 2;
}

static size_t put32(uint8_t *b, uint32_t v)
{
    put16(b, v & 0xFFFF);
    return 2 + put16(b + 2, v >> 16);
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

/* Serve the firmware's HAL calls until `until` arrives (PIL_READY, PIL_DONE, PIL_REPORT). */
static int serve(pil_t *p, int until)
{
    uint8_t out[8];
    for (;;) {
        int c = rd(p);
        unsigned a, v;
        hal_capture_t cap;
        if (c < 0)
            return -1;
        if (c == until)
            return 0;
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
        case PIL_ADC:
            v = hal_adc_read((uint8_t)rd(p));
            wr(p, out, put16(out, v));
            p->k[K_ADC]++;
            break;
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
            break;
        case PIL_RESET_CAUSE:
            out[0] = hal_reset_cause();
            wr(p, out, 1);
            break;
        case PIL_SUPPLY_LOW:
            out[0] = hal_supply_low();
            wr(p, out, 1);
            break;
        case PIL_WHEEL_MIN:
            a = rd16(p);
            hal_wheel_min_interval(a | (uint32_t)rd16(p) << 16);
            break;
        case PIL_UART_PUT:
            out[0] = hal_uart_put((uint8_t)rd(p));
            wr(p, out, 1);
            p->k[K_TX]++;
            break;
        case PIL_UART_FRAMING:
            out[0] = hal_uart_framing((uint8_t)rd(p));
            wr(p, out, 1);
            break;
        case PIL_UART_GET: {
            int16_t b = hal_uart_get();
            wr(p, out, put16(out, (uint16_t)b));
            p->k[K_RX] += b >= 0;
            break;
        }
        case PIL_EE_READ:
            out[0] = hal_eeprom_read((uint16_t)rd16(p));
            wr(p, out, 1);
            p->k[K_EE_READ]++;
            break;
        case PIL_EE_ERASE:
            hal_eeprom_erase((uint16_t)rd16(p));
            p->k[K_EE_ERASE]++;
            break;
        case PIL_EE_WRITE:
            a = rd16(p);
            out[0] = hal_eeprom_write((uint16_t)a, (uint8_t)rd(p));
            wr(p, out, 1);
            p->k[K_EE_WRITE]++;
            break;
        default:
            p->failed = 1;
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
    if (p->failed)
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
    if (p->n_pass == p->cap) {
        p->cap = p->cap ? 2 * p->cap : 65536;
        p->cycles = realloc(p->cycles, p->cap * sizeof *p->cycles);
        if (!p->cycles) {
            p->failed = 1;
            return;
        }
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

pil_t *pil_start(sim_t *sim, const char *ihx, char *err, size_t n)
{
    pil_t *p = calloc(1, sizeof *p);
    char fin[96], fout[96], iface[256];
    int cons[2];
    uint8_t b[8 + 3 * P_COUNT];
    size_t k;
    if (!p) {
        snprintf(err, n, "out of memory");
        return NULL;
    }
    p->sim = sim;
    p->pid = -1;
    p->to_fw = p->from_fw = p->console = -1;
    snprintf(p->dir, sizeof p->dir, "/tmp/pil.XXXXXX");
    if (access(ihx, R_OK) != 0 || !mkdtemp(p->dir)) {
        snprintf(err, n, "%s: %s", access(ihx, R_OK) != 0 ? ihx : "mkdtemp", strerror(errno));
        free(p);
        return NULL;
    }
    snprintf(fin, sizeof fin, "%s/to_fw", p->dir);
    snprintf(fout, sizeof fout, "%s/from_fw", p->dir);
    snprintf(iface, sizeof iface, "if=xram[0xffff],in=%s,out=%s", fin, fout);
    if (mkfifo(fin, 0600) < 0 || mkfifo(fout, 0600) < 0 || pipe(cons) < 0) {
        snprintf(err, n, "fifo: %s", strerror(errno));
        pil_free(p);
        return NULL;
    }
    p->pid = fork();
    if (p->pid == 0) {
        char log[96];
        int fd;
        snprintf(log, sizeof log, "%s/s51.log", p->dir);
        fd = open(log, O_WRONLY | O_CREAT | O_TRUNC, 0600);
        dup2(cons[0], 0);
        if (fd >= 0) {
            dup2(fd, 1);
            dup2(fd, 2);
        }
        close(cons[1]);
        execlp("s51", "s51", "-t", "C52", "-X", "11.0592M", "-I", iface, ihx, (char *)NULL);
        _exit(127);
    }
    close(cons[0]);
    p->console = cons[1];
    if (p->pid < 0) {
        snprintf(err, n, "fork: %s", strerror(errno));
        pil_free(p);
        return NULL;
    }
    /* s51 opens its input file first, then its output file */
    p->to_fw = open(fin, O_WRONLY);
    p->from_fw = p->to_fw >= 0 ? open(fout, O_RDONLY) : -1;
    if (p->from_fw < 0 || write(p->console, "run\n", 4) != 4) {
        snprintf(err, n, "s51 did not open the simulator interface (%s/s51.log)", p->dir);
        pil_free(p);
        return NULL;
    }
    /* the host build's own start (sim_init) left its traces in the shared HAL: the firmware
     * in s51 starts from the same erased EEPROM and an empty UART queue */
    memset(hal_host_eeprom(), 0xFF, HAL_EEPROM_SIZE);
    hal_host_eeprom_cut_after(-1);
    while (hal_host_uart_tx_pop() >= 0)
        ;
    if (rd(p) != PIL_HELLO) {
        snprintf(err, n, "the firmware in s51 did not say hello (%s/s51.log)", p->dir);
        pil_free(p);
        return NULL;
    }
    b[0] = PIL_CONFIG;
    k = 1 + settings(p, b + 1, 1);
    wr(p, b, k);
    if (serve(p, PIL_READY) < 0) {
        snprintf(err, n, "the firmware in s51 did not start (%s/s51.log)", p->dir);
        pil_free(p);
        return NULL;
    }
    k = 1 + settings(p, b + 1, 1);
    wr(p, b, k);
    sim->pass = pass;
    sim->pass_ctx = p;
    return p;
}

int pil_finish(pil_t *p)
{
    uint8_t q = PIL_QUIT;
    int st = 0;
    p->sim->pass = NULL;
    if (!p->failed) {
        wr(p, &q, 1);
        if (serve(p, PIL_REPORT) == 0) {
            p->stack_hwm = rd(p);
            p->stack_start = rd(p);
        }
    }
    if (p->console >= 0) {
        if (write(p->console, "quit\n", 5) != 5)
            p->failed = 1;
        close(p->console);
        p->console = -1;
    }
    if (p->pid > 0) {
        waitpid(p->pid, &st, 0);
        p->pid = -1;
    }
    return p->failed || !WIFEXITED(st) ? -1 : 0;
}

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return x < y ? -1 : x > y;
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
    s = malloc(n * sizeof *s);
    if (!s)
        return;
    memcpy(s, p->cycles, n * sizeof *s);
    for (i = 0; i < n; i++)
        sum += s[i];
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
    qsort(s, n, sizeof *s, cmp_u32);
    fprintf(f, "pil: %zu passes, machine cycles (classic 12T) mean %.0f, p99 %u, max %u "
               "(the 1T chip's own: make chip, docs/PIL.md)\n",
            n, sum / n, s[(size_t)(0.99 * (n - 1))], s[n - 1]);
    for (i = 0; i < PIL_TOP && p->top[i].cycles; i++) {
        const pil_pass_t *w = &p->top[i];
        size_t j;
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
    char f[128];
    if (!p)
        return;
    if (p->console >= 0)
        close(p->console);
    if (p->pid > 0) {
        kill(p->pid, SIGTERM);
        waitpid(p->pid, NULL, 0);
    }
    if (p->to_fw >= 0)
        close(p->to_fw);
    if (p->from_fw >= 0)
        close(p->from_fw);
    snprintf(f, sizeof f, "%s/to_fw", p->dir);
    unlink(f);
    snprintf(f, sizeof f, "%s/from_fw", p->dir);
    unlink(f);
    snprintf(f, sizeof f, "%s/s51.log", p->dir);
    unlink(f);
    rmdir(p->dir);
    free(p->cycles);
    free(p);
}

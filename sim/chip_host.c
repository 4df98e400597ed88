/* chip_host.c: chip in the loop, host side: the STC12C5A60S2 model in uCsim in lock step with the plant, one 1 ms slot a tick. */
#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "chip_host.h"
#include "chip_timing.h"
#include "lockstep.h"
#include "ucsim/stc12_link.h"
#include "hal_host.h"
#include "link_crc.h"
#include "params.h"
#include "store.h"
#include "app.h"
#include "ops.h"
#include "target.h"

#define CHIP_EV_MAX 4096
#define CHIP_RXQ 256
#define APP_STATUS_BYTES 27         /* app_status_t as SDCC lays it out: packed, little-endian, in first */

struct chip {
    sim_t *sim;
    lockstep_t link;                /* the model's process and its frames */
    uint64_t slot_start;            /* clock the current slot began */
    uint8_t ev[CHIP_EV_MAX * 13];
    unsigned n_ev;
    uint16_t keys;
    int sections;                   /* -1: not sent yet */
    uint8_t rxq[CHIP_RXQ];          /* operator bytes not yet on the wire */
    unsigned rx_head, rx_tail;
    uint64_t rx_next;               /* the wire is free from this clock */
    uint16_t sent[P_COUNT];         /* the settings the image was given or reported */
    uint16_t fw_rate, fw_k;         /* P_RATE, P_METER_K as the image last reported them */
    uint16_t a_status, a_param;     /* XRAM addresses */
    chip_timing_t time;             /* the image's passes, handlers, stack, resets */
    struct { uint64_t ns; uint8_t kind; uint32_t value; } at[8];  /* chip_at's inputs */
    int n_at, next_at;
    uint64_t sweep_from;            /* the sweep's speeds are taken from here (ns; 0: no sweep) */
};

static chip_t *active;              /* the plant's edge callbacks take no context */

static void event(chip_t *c, uint64_t clock, uint8_t kind, uint32_t value)
{
    uint8_t *e;
    if (c->n_ev == CHIP_EV_MAX) {
        c->link.failed = 1;
        return;
    }
    if (clock < c->slot_start)
        clock = c->slot_start;
    e = c->ev + 13 * c->n_ev++;
    lockstep_put(e, clock, 8);
    e[8] = kind;
    lockstep_put(e + 9, value, 4);
}

static void wheel_edge(uint64_t t_ns)
{
    event(active, STC12_CLK_OF_NS(t_ns), STC12_EV_WHEEL, 0);
}

static void flow_edge(uint64_t t_ns)
{
    event(active, STC12_CLK_OF_NS(t_ns), STC12_EV_METER, 0);
}

/* bit time of the host's side of the link in clocks (HAL_UART_BAUD, 8N1) */
#define HOST_BIT_CLOCKS ((unsigned)(STC12_SYSCLK_HZ / HAL_UART_BAUD))

/* A frame the image sent, as the host's receiver samples it at its own baud: the byte, or -1
 * for a framing error (the stop bit read 0). */
static int decode(unsigned fb, uint8_t byte)
{
    unsigned hb = HOST_BIT_CLOCKS, i, k;
    int v = 0;
    if (!fb)
        return -1;
    for (i = 0; i <= 8; i++) {
        int level;
        k = (unsigned)(((2u * i + 3u) * (uint64_t)hb) / (2u * fb));  /* the image's bit under the sample */
        level = k == 0 ? 0 : k <= 8 ? (byte >> (k - 1)) & 1 : 1;
        if (i < 8)
            v |= level << i;
        else if (!level)
            return -1;
    }
    return v;
}

/* the settings a scenario event changed, as the PC sends them over the link */
static void settings(chip_t *c)
{
    uint8_t i;
    for (i = 0; i < P_COUNT; i++)
        if (param_v[i] != c->sent[i]) {
            char line[32];
            const char *p;
            int k = snprintf(line, sizeof line, "SET %u %u", (unsigned)i, (unsigned)param_v[i]);
            snprintf(line + k, sizeof line - (size_t)k, "*%02X\r\n", link_crc8(line, (size_t)k));
            for (p = line; *p; p++)
                if ((c->rx_head + 1) % CHIP_RXQ != c->rx_tail) {
                    c->rxq[c->rx_head] = (uint8_t)*p;
                    c->rx_head = (c->rx_head + 1) % CHIP_RXQ;
                }
            c->sent[i] = param_v[i];
        }
}

static void status(chip_t *c, const uint8_t *s, const uint8_t *pv)
{
    uint16_t rate = (uint16_t)lockstep_get(pv + 2 * P_RATE, 2), k = (uint16_t)lockstep_get(pv + 2 * P_METER_K, 2);
    int fresh = 0;
    app_status.in.target_lpm_x100 = (int16_t)lockstep_get(s + 0, 2);
    app_status.in.flow_lpm_x100 = (int16_t)lockstep_get(s + 2, 2);
    app_status.in.speed_kmh_x100 = (uint16_t)lockstep_get(s + 4, 2);
    app_status.in.pressure_kpa = (uint16_t)lockstep_get(s + 6, 2);
    app_status.in.valve_limit = s[8];
    app_status.tank_l = (uint16_t)lockstep_get(s + 9, 2);
    app_status.applied_l_ha_x10 = (uint16_t)lockstep_get(s + 11, 2);
    app_status.drive = (int16_t)lockstep_get(s + 13, 2);
    app_status.alarms = (uint16_t)lockstep_get(s + 15, 2);
    app_status.alarms_unacked = (uint16_t)lockstep_get(s + 17, 2);
    app_status.spraying = s[19];
    app_status.manual = s[20];
    app_status.open_nozzles = s[21];
    app_status.boom_wait = s[22];
    app_status.job_area_m2 = (uint32_t)lockstep_get(s + 23, 4);
    /* a setting the image changed (keys, link) into the host's copy, which the reference reads */
    if (rate != c->fw_rate) {
        c->fw_rate = rate;
        if (param_set(P_RATE, rate))
            fresh = 1;
        c->sent[P_RATE] = param_v[P_RATE];
    }
    if (k != c->fw_k) {
        c->fw_k = k;
        if (param_set(P_METER_K, k))
            fresh = 1;
        c->sent[P_METER_K] = param_v[P_METER_K];
    }
    if (fresh)
        target_update(hal_sections());
}

/* the slot's inputs: conversions as the plant gives them now, keys, switches, link bytes, the
 * chip_at inputs due; then all of them in time order (the edges came while the plant stepped) */
static void inputs(chip_t *c, uint64_t end)
{
    int16_t v;
    event(c, c->slot_start, STC12_EV_ADC, (uint32_t)hal_adc_read(HAL_ADC_PRESSURE) & 0x3FF);
    event(c, c->slot_start, STC12_EV_ADC, 1u << 12 | ((uint32_t)hal_adc_read(HAL_ADC_LEVEL) & 0x3FF));
    if (hal_host_io.keys != c->keys) {
        c->keys = hal_host_io.keys;
        event(c, c->slot_start, STC12_EV_KEYS, c->keys);
    }
    if (hal_host_io.sections != c->sections) {
        c->sections = hal_host_io.sections;
        event(c, c->slot_start, STC12_EV_P0, (uint8_t)~c->sections);
    }
    settings(c);
    while (c->next_at < c->n_at && c->at[c->next_at].ns <= c->sim->t_ns) {
        event(c, c->slot_start, c->at[c->next_at].kind, c->at[c->next_at].value);
        if (c->at[c->next_at].kind == STC12_EV_WHEEL_SWEEP)
            c->sweep_from = c->at[c->next_at].ns + 2000000000ull;   /* the speed settled on the sweep */
        c->next_at++;
    }
    while ((v = hal_uart_get()) != -1)
        if (v >= 0 && (c->rx_head + 1) % CHIP_RXQ != c->rx_tail) {
            c->rxq[c->rx_head] = (uint8_t)v;
            c->rx_head = (c->rx_head + 1) % CHIP_RXQ;
        }
    while (c->rx_tail != c->rx_head) {
        uint64_t at = c->rx_next > c->slot_start ? c->rx_next : c->slot_start;
        if (at >= end)
            break;
        event(c, at, STC12_EV_RX, c->rxq[c->rx_tail] | HOST_BIT_CLOCKS << 8 | 1u << 24);
        c->rx_tail = (c->rx_tail + 1) % CHIP_RXQ;
        c->rx_next = at + 10u * HOST_BIT_CLOCKS;
    }
    {
        unsigned a, z;
        for (a = 1; a < c->n_ev; a++)
            for (z = a; z > 0 && lockstep_get(c->ev + 13 * (z - 1), 8) > lockstep_get(c->ev + 13 * z, 8); z--) {
                uint8_t t[13];
                memcpy(t, c->ev + 13 * z, 13);
                memcpy(c->ev + 13 * z, c->ev + 13 * (z - 1), 13);
                memcpy(c->ev + 13 * (z - 1), t, 13);
            }
    }
}

/* the pins the board's drivers see into the host's outputs (report's first bytes) */
static void pins(const uint8_t *r)
{
    uint8_t p1 = r[0], p3 = r[1];
    unsigned pwm = (unsigned)lockstep_get(r + 4, 2);
    int dir = (p1 & 0x20) && !(p1 & 0x40) ? HAL_VALVE_OPEN : (p1 & 0x40) && !(p1 & 0x20) ? HAL_VALVE_CLOSE : 0;
    /* the bridge runs only while its enable (P1.4) drives: the PWM on a push-pull pin */
    hal_host_io.valve_dir = (int8_t)((p1 & 0x10) ? dir : 0);
    hal_host_io.valve_duty = (uint8_t)((p1 & 0x10) && dir ? (pwm > 255 ? 255 : pwm) : 0);
    if (!hal_host_io.valve_duty)
        hal_host_io.valve_dir = 0;
    hal_host_io.spray_on = (p3 & 0x10) ? 1 : 0;
    hal_host_io.buzzer = (p3 & 0x20) ? 1 : 0;
}

/* the slot's report: the pins into the host's outputs, resets, passes, the UART's frames, the
 * status; 0, or -1 when the model did not answer */
static int report(chip_t *c)
{
    uint8_t r[28], *b;
    unsigned n_tx, i;
    if (lockstep_read(&c->link, r, 1) < 0 || r[0] != 'R' || lockstep_read(&c->link, r, 27) < 0) {
        c->link.failed = 1;
        return -1;
    }
    pins(r);
    if (r[6]) {
        c->time.resets += r[6];
        c->time.cause = r[7];
    }
    if (chip_timing_slot(&c->time, r, c->sim->t_ns / SIM_TICK_NS) < 0) {
        c->link.failed = 1;
        return -1;
    }
    c->time.early |= (uint16_t)lockstep_get(r + 24, 2);
    n_tx = r[26];
    for (i = 0; i < n_tx; i++) {
        uint8_t t[12];
        int d;
        if (lockstep_read(&c->link, t, 12) < 0)
            return -1;
        d = decode((unsigned)lockstep_get(t + 9, 2), t[8]);
        if (d >= 0)
            hal_uart_put((uint8_t)d);
    }
    b = malloc(APP_STATUS_BYTES + 2 * P_COUNT);
    if (!b || lockstep_read(&c->link, b, APP_STATUS_BYTES + 2 * P_COUNT) < 0) {
        free(b);
        c->link.failed = 1;
        return -1;
    }
    status(c, b, b + APP_STATUS_BYTES);
    free(b);
    if (c->sweep_from && c->sim->t_ns >= c->sweep_from && c->sim->t_ns % 100000000u == 0
        && chip_timing_speed(&c->time, app_status.in.speed_kmh_x100) < 0) {
        c->link.failed = 1;
        return -1;
    }
    return 0;
}

/* one tick: the slot's inputs out, the model runs to the slot's end, its report back */
static void pass(void *ctx)
{
    chip_t *c = ctx;
    uint64_t end = STC12_CLK_OF_NS(c->sim->t_ns);
    uint8_t hdr[11];
    if (c->link.failed)
        return;
    inputs(c, end);
    hdr[0] = 'S';
    lockstep_put(hdr + 1, end, 8);
    lockstep_put(hdr + 9, c->n_ev, 2);
    lockstep_write(&c->link, hdr, sizeof hdr);
    lockstep_write(&c->link, c->ev, 13u * c->n_ev);
    c->n_ev = 0;
    c->slot_start = end;
    report(c);
}

int chip_at(chip_t *c, double t_s, int kind, uint32_t value)
{
    int i;
    if (c->n_at == (int)(sizeof c->at / sizeof c->at[0]) || t_s < 0)
        return -1;
    for (i = c->n_at++; i > 0 && c->at[i - 1].ns > (uint64_t)(t_s * 1e9); i--)
        c->at[i] = c->at[i - 1];
    c->at[i].ns = (uint64_t)(t_s * 1e9 + 0.5);
    c->at[i].kind = (uint8_t)kind;
    c->at[i].value = value;
    return 0;
}

/* the address of a symbol in the image's map file */
static int map_addr(const char *map, const char *sym, uint16_t *a)
{
    FILE *f = fopen(map, "r");
    char line[256];
    if (!f)
        return -1;
    while (fgets(line, sizeof line, f)) {
        char area[8], name[128];
        unsigned long v;
        if (sscanf(line, " %7[A-Z]: %lx %127s", area, &v, name) == 3 && !strcmp(name, sym)) {
            *a = (uint16_t)v;
            fclose(f);
            return 0;
        }
    }
    fclose(f);
    return -1;
}

/* the operator's set-up: the scenario's settings saved by the host build, the image's EEPROM at
 * power-on; the addresses of app_poll and of what each slot's report copies (app_status,
 * param_v) */
static void configure(chip_t *c, uint16_t a_poll)
{
    uint8_t cfg[1 + HAL_EEPROM_SIZE + 3 + 2 * 3];
    size_t k = 0;
    lockstep_erase_eeprom();
    store_save();
    cfg[k++] = 'C';
    memcpy(cfg + k, hal_host_eeprom(), HAL_EEPROM_SIZE);
    k += HAL_EEPROM_SIZE;
    k += lockstep_put(cfg + k, a_poll, 2);
    cfg[k++] = 2;
    lockstep_put(cfg + k, c->a_status, 2);
    cfg[k + 2] = APP_STATUS_BYTES;
    k += 3;
    lockstep_put(cfg + k, c->a_param, 2);
    cfg[k + 2] = 2 * P_COUNT;
    k += 3;
    lockstep_write(&c->link, cfg, k);
}

chip_t *chip_start(sim_t *sim, const char *ihx, const char *s51, char *err, size_t n)
{
    chip_t *c = calloc(1, sizeof *c);
    char map[512];
    char *argv[] = { (char *)s51, "-t", "STC12", "-X", "11.0592M", (char *)ihx, NULL };
    uint16_t a_poll;
    if (!c) {
        snprintf(err, n, "out of memory");
        return NULL;
    }
    c->sim = sim;
    lockstep_init(&c->link);
    c->sections = -1;
    snprintf(map, sizeof map, "%.*s.map", (int)(strlen(ihx) > 4 ? strlen(ihx) - 4 : strlen(ihx)), ihx);
    if (access(ihx, R_OK) != 0 || access(s51, X_OK) != 0) {
        snprintf(err, n, "%s: %s", access(ihx, R_OK) != 0 ? ihx : s51, strerror(errno));
        free(c);
        return NULL;
    }
    if (map_addr(map, "_app_status", &c->a_status) < 0 || map_addr(map, "_param_v", &c->a_param) < 0
        || map_addr(map, "_app_poll", &a_poll) < 0) {
        snprintf(err, n, "%s: no _app_status, _param_v or _app_poll", map);
        free(c);
        return NULL;
    }
    if (lockstep_fifos(&c->link, "/tmp/chip.XXXXXX", err, n) < 0) {
        chip_free(c);
        return NULL;
    }
    if (lockstep_spawn(&c->link, argv, 1) < 0) {
        snprintf(err, n, "the model did not open its link (%s/s51.log)", c->link.dir);
        chip_free(c);
        return NULL;
    }
    configure(c, a_poll);
    /* then the host's queues as the image finds the machine */
    lockstep_drop_uart();
    memcpy(c->sent, param_v, sizeof c->sent);
    c->fw_rate = param_v[P_RATE];
    c->fw_k = param_v[P_METER_K];
    active = c;
    sim->plant.flow_edge = flow_edge;
    sim->plant.wheel_edge = wheel_edge;
    sim->pass = pass;
    sim->pass_ctx = c;
    return c;
}

int chip_finish(chip_t *c)
{
    uint8_t q = 'Q', h[3];
    int i, n_vec;
    c->sim->pass = NULL;
    if (!c->link.failed) {
        lockstep_write(&c->link, &q, 1);
        if (lockstep_read(&c->link, h, 3) == 0 && h[0] == 'X') {
            c->time.sp_max = h[1];
            n_vec = h[2] > 8 ? 8 : h[2];
            for (i = 0; i < n_vec; i++) {
                uint8_t v[22];
                if (lockstep_read(&c->link, v, 22) < 0)
                    break;
                chip_timing_handler(&c->time, v);
            }
        } else {
            c->link.failed = 1;
        }
    }
    if (lockstep_wait(&c->link, 0) < 0)
        return -1;
    return c->link.failed ? -1 : 0;
}

void chip_report(const chip_t *c, FILE *f)
{
    chip_timing_report(&c->time, f);
}

void chip_free(chip_t *c)
{
    if (!c)
        return;
    if (active == c)
        active = NULL;
    lockstep_close(&c->link);
    chip_timing_free(&c->time);
    free(c);
}

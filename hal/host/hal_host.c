/* hal_host.c: the host backend: hal.h over simulated time and the plant's sensor signals. */
#include <string.h>
#include "hal_host.h"

hal_host_io_t hal_host_io;

typedef struct {
    uint32_t t[HAL_HOST_EDGES];     /* PCA time of each edge not yet taken */
    uint32_t n;                     /* edges waiting */
    uint32_t last;                  /* PCA time of the newest edge ever */
    uint32_t min;                   /* edges sooner than this after the last are dropped (wheel) */
    uint8_t rejected, seen;
} edge_q_t;

static edge_q_t flow_q, wheel_q;
static uint8_t eeprom[HAL_EEPROM_SIZE];
static int32_t eeprom_ops_left = -1;
static uint8_t eeprom_cut;
static void (*lcd_sink)(uint8_t rs, uint8_t b);
static uint16_t (*adc_source)(uint8_t ch);
static hal_hil_t *hil;              /* hal_hil: the inputs from the PC's frames */
static uint32_t now_ms;             /* hal_host_io.time_ns in ms, kept by hal_host_set_time_ns */

void hal_host_reset(void)
{
    memset(&hal_host_io, 0, sizeof hal_host_io);
    memset(&flow_q, 0, sizeof flow_q);
    memset(&wheel_q, 0, sizeof wheel_q);
    hal_host_uart_reset();
    hal_host_uart_pc_framing(-1);
    memset(eeprom, 0xFF, sizeof eeprom);
    eeprom_ops_left = -1;
    eeprom_cut = 0;
    lcd_sink = 0;
    adc_source = 0;
    hil = 0;
    now_ms = 0;
}

void hal_host_power_on(void)
{
    memset(&flow_q, 0, sizeof flow_q);
    memset(&wheel_q, 0, sizeof wheel_q);
    hal_host_uart_reset();
    hal_host_io.valve_dir = HAL_VALVE_OFF;
    hal_host_io.valve_duty = 0;
    hal_host_io.spray_on = 0;
    hal_host_io.buzzer = 0;
    hal_host_io.keys = 0;
    hal_host_io.wdt_kicks = 0;
    hal_host_io.wdt_last_kick_ms = now_ms;
    hal_host_io.reset_cause = HAL_RESET_POWER;
    hal_host_io.supply_low = 0;
}

void hal_init(void)
{
    hal_host_uart_init();
    hal_host_io.valve_dir = HAL_VALVE_OFF;
    hal_host_io.valve_duty = 0;
    hal_host_io.spray_on = 0;
    hal_host_io.buzzer = 0;
}

void hal_host_set_time_ns(uint64_t t_ns)
{
    if (t_ns > hal_host_io.time_ns) {
        hal_host_io.time_ns = t_ns;
        now_ms = (uint32_t)(t_ns / 1000000u);
    }
}

uint32_t hal_ms(void)
{
    return now_ms;
}

uint32_t hal_host_pca_of_ns(uint64_t t_ns)
{
    /* 921600 Hz: ticks = ns * 921600 / 1e9 = ns * 4608 / 5000000; 64-bit, wraps at 32 bits */
    return (uint32_t)((t_ns / 5000000u) * 4608u + (t_ns % 5000000u) * 4608u / 5000000u);
}

uint32_t hal_pca_now(void)
{
    return hil ? hil->pca_now : hal_host_pca_of_ns(hal_host_io.time_ns);
}

static void edge_push(edge_q_t *q, uint64_t t_ns)
{
    uint32_t t = hal_host_pca_of_ns(t_ns);
    if (q->min && q->seen && t - q->last < q->min) {
        if (q->rejected < 255)
            q->rejected++;          /* as the INT0 handler does: too early to be a pulse */
        return;
    }
    q->seen = 1;
    if (q->n < HAL_HOST_EDGES)
        q->t[q->n++] = t;
    else
        q->n++;                     /* the count keeps going, as the ISR's would */
    q->last = t;
}

void hal_host_flow_edge(uint64_t t_ns)
{
    edge_push(&flow_q, t_ns);
}

void hal_host_wheel_edge(uint64_t t_ns)
{
    edge_push(&wheel_q, t_ns);
}

static void edge_take(edge_q_t *q, hal_capture_t *c)
{
    c->count = (uint16_t)(q->n > 0xFFFFu ? 0xFFFFu : q->n);
    c->last = q->last;
    c->rejected = q->rejected;
    q->n = 0;
    q->rejected = 0;
}

void hal_wheel_min_interval(uint32_t min_ticks)
{
    if (hil)
        hil->wheel_min = min_ticks;
    else
        wheel_q.min = min_ticks;
}

void hal_flow_capture_take(hal_capture_t *c)
{
    if (hil) {
        *c = hil->meter;
        hil->meter.count = 0;       /* taken: the next take sees only the next frame's */
        hil->meter.rejected = 0;
    } else
        edge_take(&flow_q, c);
}

void hal_wheel_capture_take(hal_capture_t *c)
{
    if (hil) {
        *c = hil->wheel;
        hil->wheel.count = 0;
        hil->wheel.rejected = 0;
    } else
        edge_take(&wheel_q, c);
}

void hal_host_adc_source(uint16_t (*source)(uint8_t ch))
{
    adc_source = source;
}

uint16_t hal_adc_read(uint8_t ch)
{
    if (hil) {
        /* the frame carries the sum of the period's four conversions: four reads in a row return
         * its quarters, rounded so that they add up to it (analog.c reads four a period) */
        static uint8_t k;
        return ch < 2 ? (uint16_t)((hil->adc[ch] + (k++ & 3u)) >> 2) : 0;
    }
    if (adc_source && ch < 8)
        hal_host_io.adc[ch] = adc_source(ch);
    return ch < 8 ? hal_host_io.adc[ch] & 0x3FF : 0;
}

uint8_t hal_sections(void)
{
    return hil ? hil->sections : hal_host_io.sections;
}

uint8_t hal_hil_active(void)
{
    return hil != 0;
}

void hal_hil(hal_hil_t *s)
{
    hil = s;
    if (s) {                        /* the pins held off while the PC's plant stands in */
        hal_host_io.valve_dir = HAL_VALVE_OFF;
        hal_host_io.valve_duty = 0;
        hal_host_io.spray_on = 0;
        hal_host_io.buzzer = 0;
    }
}

uint8_t hal_keypad_row(uint8_t row)
{
    return (uint8_t)((hal_host_io.keys >> (4 * (row & 3))) & 0x0F);
}

void hal_valve_out(int8_t dir, uint8_t duty)
{
    if (dir == HAL_VALVE_OFF || duty == 0 || hil) {
        hal_host_io.valve_dir = HAL_VALVE_OFF;
        hal_host_io.valve_duty = 0;
    } else {
        hal_host_io.valve_dir = dir > 0 ? HAL_VALVE_OPEN : HAL_VALVE_CLOSE;
        hal_host_io.valve_duty = duty;
    }
}

void hal_spray_enable(uint8_t on)
{
    hal_host_io.spray_on = on && !hil ? 1 : 0;
}

void hal_buzzer(uint8_t on)
{
    hal_host_io.buzzer = on && !hil ? 1 : 0;
}

uint8_t hal_reset_cause(void)
{
    return hal_host_io.reset_cause;
}

uint8_t hal_supply_low(void)
{
    return hal_host_io.supply_low;
}

/* one EEPROM operation may proceed unless the power is (or now goes) out */
static uint8_t eeprom_power(void)
{
    if (eeprom_cut)
        return 0;
    if (eeprom_ops_left == 0) {
        eeprom_cut = 1;
        return 0;
    }
    if (eeprom_ops_left > 0)
        eeprom_ops_left--;
    return 1;
}

uint8_t hal_eeprom_read(uint16_t addr)
{
    return addr < HAL_EEPROM_SIZE ? eeprom[addr] : 0xFF;
}

void hal_eeprom_erase(uint16_t addr)
{
    if (addr >= HAL_EEPROM_SIZE || !eeprom_power())
        return;
    hal_host_uart_hold(hal_host_io.time_ns, hal_host_io.time_ns + HAL_HOST_IAP_ERASE_NS);
    hal_host_io.eeprom_erases++;
    memset(eeprom + (addr & ~(HAL_EEPROM_SECTOR - 1)), 0xFF, HAL_EEPROM_SECTOR);
}

uint8_t hal_eeprom_write(uint16_t addr, uint8_t b)
{
    if (addr >= HAL_EEPROM_SIZE || !eeprom_power())
        return 0;
    eeprom[addr] &= b;              /* flash programming only clears bits */
    return eeprom[addr] == b;
}

uint8_t *hal_host_eeprom(void)
{
    return eeprom;
}

void hal_host_eeprom_cut_after(int32_t n)
{
    eeprom_ops_left = n;
    eeprom_cut = 0;
}

uint8_t hal_host_eeprom_cut(void)
{
    return eeprom_cut;
}

void hal_host_lcd_sink(void (*sink)(uint8_t rs, uint8_t b))
{
    lcd_sink = sink;
}

void hal_lcd_write(uint8_t rs, uint8_t b)
{
    if (lcd_sink)
        lcd_sink(rs, b);
}

uint8_t hal_lcd_busy(void)
{
    return 0;                       /* the emulated ST7920 takes each byte at once */
}

void hal_wdt_kick(void)
{
    hal_host_io.wdt_kicks++;
    hal_host_io.wdt_last_kick_ms = hal_ms();
}

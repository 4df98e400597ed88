/* hal_pil.c: hal.h inside s51 (processor in the loop): every input and output is a frame to the host's plant model. */
#include <8051.h>
#include "hal.h"
#include "pil_proto.h"
#include "pil.h"

/* uCsim's simulator interface (s51 -I if=xram[0xffff],in=FIFO,out=FIFO) */
static volatile __xdata __at(0xFFFF) uint8_t simif;

static uint32_t tick_ms;            /* the host's clock, from its tick frame */
static uint32_t pca_now;
static uint16_t keys;               /* bit 4 row + col: key held */
static uint8_t sections;
static uint8_t rx_waiting;          /* bytes in the host's UART queue at the tick */
uint8_t pil_measured;               /* the pass measured (a control step): its status is fresh */
static volatile uint16_t t0_hi;     /* timer 0 overflows: the cycle counter's high word */

void pil_put(uint8_t b)
{
    simif = 'w';
    simif = b;
}

/* Wait for the host's next byte with the cycle counter stopped (waiting is not the pass's work). */
uint8_t pil_get(void)
{
    uint8_t run = TR0;
    TR0 = 0;
    for (;;) {
        simif = 'f';
        if (simif)
            break;
    }
    simif = 'r';
    TR0 = run;
    return simif;
}

static uint16_t get16(void)
{
    uint8_t lo = pil_get();
    return (uint16_t)pil_get() << 8 | lo;
}

static uint32_t get32(void)
{
    uint16_t lo = get16();
    return (uint32_t)get16() << 16 | lo;
}

void pil_put16(uint16_t v)
{
    pil_put((uint8_t)v);
    pil_put((uint8_t)(v >> 8));
}

/* PIL_TICK's inputs; the settings that follow are the caller's (pil_main.c) */
void pil_tick_inputs(void)
{
    tick_ms = get32();
    pca_now = get32();
    keys = get16();
    sections = pil_get();
    rx_waiting = pil_get();
}

uint8_t pil_get8(void)
{
    return pil_get();
}

uint16_t pil_get16(void)
{
    return get16();
}

/* ---- the cycle counter: timer 0, 16 bits, counts machine cycles; its overflows in t0_hi ---- */
void pil_timer0_isr(void) __interrupt(1)
{
    t0_hi++;
}

void pil_cycles_start(void)
{
    TR0 = 0;
    TMOD = (TMOD & 0xF0) | 0x01;
    TH0 = 0;
    TL0 = 0;
    TF0 = 0;
    t0_hi = 0;
    ET0 = 1;
    EA = 1;
    TR0 = 1;
}

uint32_t pil_cycles_stop(void)
{
    uint16_t lo;
    TR0 = 0;
    lo = (uint16_t)TH0 << 8 | TL0;
    if (TF0) {                      /* an overflow not yet serviced */
        TF0 = 0;
        t0_hi++;
    }
    return (uint32_t)t0_hi << 16 | lo;
}

/* ---- hal.h ----------------------------------------------------------------------------------- */
void hal_init(void)
{
    hal_valve_out(HAL_VALVE_OFF, 0);
    hal_spray_enable(0);
    hal_buzzer(0);
}

uint32_t hal_ms(void)
{
    return tick_ms;
}

uint32_t hal_pca_now(void)
{
    return pca_now;
}

static void take(uint8_t what, __idata hal_capture_t *c)
{
    pil_measured = 1;
    pil_put(what);
    c->count = get16();
    c->last = get32();
    c->rejected = pil_get();
}

void hal_flow_capture_take(__idata hal_capture_t *c)
{
    take(PIL_FLOW, c);
}

void hal_wheel_capture_take(__idata hal_capture_t *c)
{
    take(PIL_WHEEL, c);
}

void hal_wheel_min_interval(uint32_t min_ticks)
{
    pil_put(PIL_WHEEL_MIN);
    pil_put16((uint16_t)min_ticks);
    pil_put16((uint16_t)(min_ticks >> 16));
}

uint16_t hal_adc_read(uint8_t ch)
{
    pil_measured = 1;
    pil_put(PIL_ADC);
    pil_put(ch);
    return get16();
}

uint8_t hal_reset_cause(void)
{
    pil_put(PIL_RESET_CAUSE);
    return pil_get();
}

uint8_t hal_supply_low(void)
{
    pil_put(PIL_SUPPLY_LOW);
    return pil_get();
}

uint8_t hal_sections(void)
{
    return sections;
}

uint8_t hal_keypad_row(uint8_t row)
{
    return (uint8_t)(keys >> (4 * (row & 3))) & 0x0F;
}

void hal_valve_out(int8_t dir, uint8_t duty) __reentrant
{
    pil_put(PIL_VALVE);
    pil_put((uint8_t)dir);
    pil_put(duty);
}

void hal_spray_enable(uint8_t on)
{
    pil_put(PIL_SPRAY);
    pil_put(on);
}

void hal_buzzer(uint8_t on)
{
    pil_put(PIL_BUZZER);
    pil_put(on);
}

uint8_t hal_uart_put(uint8_t b)
{
    pil_put(PIL_UART_PUT);
    pil_put(b);
    return pil_get();
}

uint8_t hal_uart_framing(uint8_t f)
{
    pil_put(PIL_UART_FRAMING);
    pil_put(f);
    return pil_get();
}

int16_t hal_uart_get(void)
{
    if (!rx_waiting)
        return -1;                  /* the host's queue was empty at the tick and stays so */
    rx_waiting--;
    pil_put(PIL_UART_GET);
    return (int16_t)get16();
}

uint8_t hal_eeprom_read(uint16_t addr)
{
    pil_put(PIL_EE_READ);
    pil_put16(addr);
    return pil_get();
}

void hal_eeprom_erase(uint16_t addr)
{
    pil_put(PIL_EE_ERASE);
    pil_put16(addr);
}

uint8_t hal_eeprom_write(uint16_t addr, uint8_t b) __reentrant
{
    pil_put(PIL_EE_WRITE);
    pil_put16(addr);
    pil_put(b);
    return pil_get();
}

void hal_lcd_write(uint8_t rs, uint8_t b) __reentrant
{
    pil_put(PIL_LCD);
    pil_put(rs);
    pil_put(b);
}

uint8_t hal_lcd_busy(void)
{
    return 0;                       /* the host's LCD takes each byte at once */
}

void hal_wdt_kick(void)
{
    pil_put(PIL_WDT);
}

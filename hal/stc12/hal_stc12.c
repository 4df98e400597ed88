/* hal_stc12.c: the STC12C5A60S2 backend: tick, PCA capture and PWM, ADC, I/O, supply, watchdog, start-up (UART and EEPROM in hal_serial.c, the LCD in hal_lcd.c). */
#include <stc12.h>
#include "hal.h"
#include "pins.h"
#include "isr.h"


/* ---- start-up: before the C runtime clears and initialises RAM ---------------------------- */
/*
 * Safe states first. From reset until here every pin is quasi-bidirectional with its latch at 1:
 * a weak pull-up. The board's pull-downs at the relay, buzzer and H-bridge driver inputs
 * (docs/bringup.md) hold those lines low against it; now the latches go to 0 and the output
 * pins to push-pull, so "off" is driven and "on" has the strong drive a driver input needs.
 * The ADC pins become input-only: a quasi-bidirectional pin's pull-up would add its current
 * to the 250 ohm shunt (datasheet, I/O port configuration: PxM1 = 1, PxM0 = 0 is input-only).
 * The watchdog flag is kept (written back as read) for hal_init to report the reset cause.
 */
#define P1_OUTPUTS 0x70             /* P1.4 bridge enable (CCP1), P1.5 IN_A, P1.6 IN_B */
#define P3_OUTPUTS 0xF8             /* P3.3 LCD SCLK, P3.4 relay, P3.5 buzzer, P3.6 CS, P3.7 SID */
unsigned char _sdcc_external_startup(void)
{
    P1 &= (unsigned char)~P1_OUTPUTS;
    P3 &= (unsigned char)~0x30;     /* relay and buzzer off; the LCD lines idle as they are */
    P1M1 = ADC_PINS_MASK;           /* P1.0, P1.1 input-only */
    P1M0 = P1_OUTPUTS;              /* push-pull */
    P3M1 = 0;
    P3M0 = P3_OUTPUTS;
    AUXR &= (unsigned char)~0x02;   /* EXTRAM = 0: the 1024 bytes of on-chip XRAM */
    WDT_CONTR = (unsigned char)((WDT_CONTR & 0x80) | 0x34);   /* kick, keep WDT_FLAG */
    return 0;                       /* 0: let the runtime initialise the variables */
}

/* ---- critical sections: interrupts off, then back as they were (they nest) ---------------- */
#define IRQ_OFF(s) do { (s) = EA; EA = 0; } while (0)
#define IRQ_RESTORE(s) do { EA = (s); } while (0)

/* ---- PCA: counter at SYSCLK/12, extended to 32 bits by its overflow count ----------------- */
#define PCA_CH CH
#define PCA_CL CL
#define PCA_CF CF
#define PCA_CF_CLEAR() do { CF = 0; } while (0)
#define PCA_IRQ_STATE uint8_t
#define PCA_IRQ_OFF IRQ_OFF
#define PCA_IRQ_RESTORE IRQ_RESTORE
#include "pca_clock.h"

void stc12_pca_isr(void) __interrupt(7)
{
    uint16_t cap = (uint16_t)CCAP0H << 8 | CCAP0L;
    uint8_t captured = CCF0;
    CCF0 = 0;
    PCA_ISR_WORK(captured, cap);
}

#if FW_HIL
static hal_hil_t __xdata *hil;      /* hal_hil: the inputs from the PC's frames */
#endif

uint32_t hal_pca_now(void)
{
    uint32_t t;
    uint8_t ea;
#if FW_HIL
    if (hil)
        return hil->pca_now;
#endif
    IRQ_OFF(ea);
    t = pca_read();
    IRQ_RESTORE(ea);
    return t;
}

void stc12_int0_isr(void) __interrupt(0)
{
    WHEEL_ISR_WORK();
}

void hal_wheel_min_interval(uint32_t min_ticks) __reentrant
{
    uint8_t ea;
#if FW_HIL
    if (hil) {
        hil->wheel_min = min_ticks;
        return;
    }
#endif
    IRQ_OFF(ea);
    wheel_min = min_ticks;
    IRQ_RESTORE(ea);
}

#if FW_HIL
/* a frame's capture, taken: the next take sees only the next frame's */
static void hil_take(hal_capture_t __xdata *f, __idata hal_capture_t *c)
{
    c->count = f->count;
    c->last = f->last;
    c->rejected = f->rejected;
    f->count = 0;
    f->rejected = 0;
}
#endif

void hal_flow_capture_take(__idata hal_capture_t *c) __reentrant
{
    uint8_t ea;
#if FW_HIL
    if (hil) {
        hil_take(&hil->meter, c);
        return;
    }
#endif
    IRQ_OFF(ea);
    c->count = flow_count;
    c->last = flow_last;
    c->rejected = 0;
    flow_count = 0;
    IRQ_RESTORE(ea);
}

void hal_wheel_capture_take(__idata hal_capture_t *c) __reentrant
{
    uint8_t ea;
#if FW_HIL
    if (hil) {
        hil_take(&hil->wheel, c);
        return;
    }
#endif
    IRQ_OFF(ea);
    c->count = wheel_count;
    c->last = wheel_last;
    c->rejected = wheel_rejected;
    wheel_count = 0;
    wheel_rejected = 0;
    IRQ_RESTORE(ea);
}

/* ---- milliseconds from the PCA counter ---------------------------------------------------- */
/*
 * Timer 0 only wakes the count about once a millisecond; the milliseconds themselves are read
 * off the PCA counter (921.6 ticks each: 921 and 3/5), which the hardware clocks without a
 * stop or a reload. A reload that stops the timer loses the clocks of every instruction
 * between the stop and the start (the compiler's, not a constant), and an IAP erase holds the
 * CPU for longer than a timer period. Only the counter's 16 bits are compared (a signed
 * difference: no overflow count, no 32-bit temporaries in the handler), so a held CPU or a
 * late interrupt up to 35 ms (32768 ticks) is caught up with whole milliseconds here; an
 * erase holds it about 21 ms. The PCA is clocked from SYSCLK, not the CPU: it counts on while
 * IAP holds the CPU (checked at bring-up, docs/bringup.md: the LOG time stamps against the
 * PC's clock across saves).
 */
static volatile uint32_t tick_ms;
static uint16_t tick_next_pca;      /* PCA count (low 16 bits) of the next millisecond */
static uint8_t tick_fifths;         /* fifths of a PCA tick carried */

void stc12_timer0_isr(void) __interrupt(1)
{
    uint16_t t;                     /* one 16-bit value: in registers (two bytes took XRAM) */
    TL0 = (uint8_t)(65536u - 11059u);   /* about a millisecond; its exactness does not matter */
    TH0 = (uint8_t)((65536u - 11059u) >> 8);
    for (;;) {
        do {
            t = (uint16_t)CH << 8;
            t |= CL;
        } while ((uint8_t)(t >> 8) != CH);
        if ((int16_t)(t - tick_next_pca) < 0)
            break;
        tick_ms++;
        tick_next_pca += 921u;
        tick_fifths += 3u;
        if (tick_fifths >= 5u) {
            tick_fifths -= 5u;
            tick_next_pca++;
        }
    }
}

uint32_t hal_ms(void)
{
    uint32_t t;
    uint8_t ea;
    IRQ_OFF(ea);
    t = tick_ms;
    IRQ_RESTORE(ea);
    return t;
}

/* ---- ADC: 10 bits, result high 8 bits in ADC_RES, low 2 in ADC_RESL (ADRJ = 0) ----------- */
#define ADC_POWER 0x80
#define ADC_SPEED_90 0x60
#define ADC_FLAG 0x10
#define ADC_START 0x08

uint16_t hal_adc_read(uint8_t ch) __reentrant
{
    uint8_t n = 0;
#if FW_HIL
    if (hil) {
        /* the frame's sum of four conversions: four reads in a row return its quarters, which
         * add up to it (analog.c reads four a period) */
        static uint8_t k;
        return ch < 2 ? (uint16_t)((hil->adc[ch] + (k++ & 3u)) >> 2) : 0;
    }
#endif
    ADC_CONTR = ADC_POWER | ADC_SPEED_90 | ADC_START | (ch & 7);
    NOP(); NOP(); NOP(); NOP();     /* the flag is valid four clocks after the start */
    /* a conversion takes 90 clocks; a converter that never finishes reads 0, an open
     * 4-20 mA loop, so the sensor fault alarms instead of the loop hanging until the watchdog */
    while (!(ADC_CONTR & ADC_FLAG))
        if (++n == 0)
            return 0;
    ADC_CONTR &= (unsigned char)~ADC_FLAG;
    return (uint16_t)ADC_RES << 2 | (ADC_RESL & 3);
}

/* ---- digital I/O ---------------------------------------------------------------------------- */
uint8_t hal_sections(void)
{
#if FW_HIL
    if (hil)
        return hil->sections;
#endif
    return (uint8_t)~PORT_SECTIONS;
}

uint8_t hal_keypad_row(uint8_t row) __reentrant
{
    uint8_t cols;
    PORT_KEYPAD = (uint8_t)~(1u << (row & 3));  /* columns stay high (inputs) */
    NOP(); NOP(); NOP(); NOP(); NOP(); NOP(); NOP(); NOP(); /* let the lines settle */
    cols = (uint8_t)(~PORT_KEYPAD >> 4) & 0x0F;
    PORT_KEYPAD = 0xFF;
    return cols;
}

void hal_valve_out(int8_t dir, uint8_t duty) __reentrant
{
#if FW_HIL
    if (hil)
        dir = HAL_VALVE_OFF;        /* the PC's plant gets the drive in a frame */
#endif
    if (dir == HAL_VALVE_OFF || duty == 0) {
        PCA_PWM1 = 0x03;            /* EPC1H/L: output stays low */
        CCAP1H = 0xFF;
        PIN_VALVE_A = 0;
        PIN_VALVE_B = 0;
        return;
    }
    /* the PWM output is high while CL >= CCAP1L: duty/256 of the period */
    PCA_PWM1 = 0;
    CCAP1H = (uint8_t)(0u - duty);
    PIN_VALVE_A = dir > 0;
    PIN_VALVE_B = dir < 0;
}

void hal_spray_enable(uint8_t on) __reentrant
{
#if FW_HIL
    if (hil)
        on = 0;
#endif
    PIN_SPRAY = on ? 1 : 0;
}

void hal_buzzer(uint8_t on) __reentrant
{
#if FW_HIL
    if (hil)
        on = 0;
#endif
    PIN_BUZZER = on ? 1 : 0;
}

#if FW_HIL
uint8_t hal_hil_active(void)
{
    return hil != 0;
}

void hal_hil(hal_hil_t *s)
{
    hil = (hal_hil_t __xdata *)s;
    if (s) {                        /* the pins held off while the PC's plant stands in */
        hal_valve_out(HAL_VALVE_OFF, 0);
        PIN_SPRAY = 0;
        PIN_BUZZER = 0;
    }
}
#endif

/* ---- supply: the low-voltage detector's flag (PCON.LVDF) ------------------------------------ */
#define PCON_LVDF 0x20
#define PCON_POF 0x10

/* The flag latches a dip below the threshold since it was last cleared: clear it, give the
 * detector a few microseconds, and read it again. */
uint8_t hal_supply_low(void)
{
    uint8_t i;
    PCON &= (unsigned char)~PCON_LVDF;
    for (i = 0; i < 40; i++)
        NOP();
    return (PCON & PCON_LVDF) ? 1 : 0;
}

/* ---- watchdog: prescaler 32 -> 12 * 32 * 32768 / 11059200 = 1.14 s ------------------------ */
void hal_wdt_kick(void)
{
    WDT_CONTR = 0x34;               /* EN_WDT | CLR_WDT | PS = 4 (writes WDT_FLAG 0) */
}

/* ---- the reset cause, read once before anything clears the flags -------------------------- */
static uint8_t reset_cause;

uint8_t hal_reset_cause(void)
{
    return reset_cause;
}

/* WDT_FLAG: the watchdog overflowed; POF: the supply came up from off; LVDF without POF: the
 * supply fell below the low-voltage threshold since power-on and the chip reset (brown-out);
 * none of them: the reset pin or a software reset. Then all three cleared for the next one. */
static void reset_cause_read(void)
{
    if (WDT_CONTR & 0x80)
        reset_cause = HAL_RESET_WATCHDOG;
    else if (PCON & PCON_POF)
        reset_cause = HAL_RESET_POWER;
    else if (PCON & PCON_LVDF)
        reset_cause = HAL_RESET_BROWNOUT;
    else
        reset_cause = HAL_RESET_OTHER;
    WDT_CONTR = 0x34;
    PCON &= (unsigned char)~(PCON_POF | PCON_LVDF);
}

/* ---- everything at power-up --------------------------------------------------------------- */
void hal_init(void)
{
    reset_cause_read();
    /* outputs: off and push-pull since _sdcc_external_startup; inputs pulled up */
    PIN_VALVE_A = 0;
    PIN_VALVE_B = 0;
    PIN_SPRAY = 0;
    PIN_BUZZER = 0;
    PIN_LCD_CS = 0;
    PIN_LCD_SCLK = 0;
    PORT_KEYPAD = 0xFF;
    PORT_SECTIONS = 0xFF;

    /* timer 0: 16-bit, 1T, wakes the millisecond count from the PCA */
    AUXR |= 0x80;                   /* T0x12 */
    TMOD = (TMOD & 0xF0) | 0x01;
    TL0 = (uint8_t)(65536u - 11059u);
    TH0 = (uint8_t)((65536u - 11059u) >> 8);
    tick_ms = 0;
    tick_next_pca = 921u;           /* the first millisecond ends at 921.6 */
    tick_fifths = 3u;

    /* PCA: SYSCLK/12, overflow interrupt; module 0 captures falling edges; module 1 PWM, its
     * compare registers set (output held low) before the module is switched to PWM */
    CMOD = 0x01;                    /* CPS = 000 (SYSCLK/12), ECF */
    CCON = 0;
    CL = 0;
    CH = 0;
    PCA_PWM1 = 0x03;                /* EPC1H/L: 9-bit compare above any count, output low */
    CCAP1L = 0xFF;
    CCAP1H = 0xFF;
    CCAPM0 = 0x11;                  /* CAPN | ECCF */
    CCAPM1 = 0x42;                  /* ECOM | PWM */
    CR = 1;
    PPCA = 1;                       /* captures first */
    ET0 = 1;
    TR0 = 1;

    /* INT0: falling edge */
    IT0 = 1;
    EX0 = 1;

    /* ADC on P1.0, P1.1 */
    P1ASF = ADC_PINS_MASK;
    ADC_CONTR = ADC_POWER;

    /* UART 1 from the BRT generator (hal_serial.c) */
    hal_uart_framing(HAL_UART_38400_8N1);
    ES = 1;

    EA = 1;
    hal_wdt_kick();
}

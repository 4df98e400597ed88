/* ports.c: the STC12C5A60S2's pins: their safe state from reset, the digital inputs and outputs,
 * and hal_init, which starts every peripheral at power-up. */
#include <stc12.h>
#include "hal.h"
#include "stc12_int.h"
#include "pins.h"

#if FW_HIL
hal_hil_t __xdata *stc12_hil;      /* hal_hil: the inputs from the PC's frames */
#endif

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

/* ---- digital I/O ---------------------------------------------------------------------------- */
uint8_t hal_sections(void)
{
#if FW_HIL
    if (stc12_hil)
        return stc12_hil->sections;
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

void hal_spray_enable(uint8_t on) __reentrant
{
#if FW_HIL
    if (stc12_hil)
        on = 0;
#endif
    PIN_SPRAY = on ? 1 : 0;
}

void hal_buzzer(uint8_t on) __reentrant
{
#if FW_HIL
    if (stc12_hil)
        on = 0;
#endif
    PIN_BUZZER = on ? 1 : 0;
}

#if FW_HIL
uint8_t hal_hil_active(void)
{
    return stc12_hil != 0;
}

void hal_hil(hal_hil_t *s)
{
    stc12_hil = (hal_hil_t __xdata *)s;
    if (s) {                        /* the pins held off while the PC's plant stands in */
        hal_valve_out(HAL_VALVE_OFF, 0);
        PIN_SPRAY = 0;
        PIN_BUZZER = 0;
    }
}
#endif

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

    /* UART 1 from the BRT generator (uart.c) */
    hal_uart_framing(HAL_UART_38400_8N1);
    ES = 1;

    EA = 1;
    hal_wdt_kick();
}

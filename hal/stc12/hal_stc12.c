/* hal_stc12.c: the STC12C5A60S2 backend: tick, PCA capture and PWM, ADC, UART, IAP EEPROM, watchdog. */
#include <stc12.h>
#include "hal.h"
#include "pins.h"
#include "isr.h"


/* ---- start-up: before the C runtime clears and initialises RAM ---------------------------- */
unsigned char _sdcc_external_startup(void)
{
    AUXR &= (unsigned char)~0x02;   /* EXTRAM = 0: the 1024 bytes of on-chip XRAM */
    WDT_CONTR = 0x34;               /* clear and keep the watchdog (if the bootloader set it) */
    return 0;                       /* 0: let the runtime initialise the variables */
}

/* ---- system tick: timer 0 in 1T mode, 11059.2 clocks a millisecond ------------------------ */
static volatile uint32_t tick_ms;
static uint8_t tick_frac;           /* fifths of a clock: every 5th period is one clock longer */

void stc12_timer0_isr(void) __interrupt(1)
{
    uint16_t reload = 65536u - 11059u;
    if (++tick_frac == 5) {
        tick_frac = 0;
        reload--;                   /* 4 x 11059 + 11060 = 5 x 11059.2 */
    }
    TR0 = 0;
    /* add to what the timer already counted since the overflow, so latency does not drift */
    {
        uint16_t t = ((uint16_t)TH0 << 8 | TL0) + reload + 7u;  /* 7: the clocks TR0 was off */
        TL0 = (uint8_t)t;
        TH0 = (uint8_t)(t >> 8);
    }
    TR0 = 1;
    tick_ms++;
}

uint32_t hal_ms(void)
{
    uint32_t t;
    EA = 0;
    t = tick_ms;
    EA = 1;
    return t;
}

/* ---- PCA: counter at SYSCLK/12, extended to 32 bits by its overflow count ----------------- */
static volatile uint16_t pca_hi;    /* overflows of the 16-bit PCA counter */
static volatile uint16_t flow_count;
static volatile uint32_t flow_last;
static volatile uint16_t wheel_count;
static volatile uint32_t wheel_last;

/* 32-bit PCA time of a 16-bit reading taken while the overflow flag read cf. A reading in the
 * lower half of the range with an overflow still pending was taken after that overflow. */
static uint32_t pca_extend(uint16_t lo, uint8_t cf)
{
    uint16_t hi = pca_hi;
    if (cf && lo < 0x8000u)
        hi++;
    return (uint32_t)hi << 16 | lo;
}

void stc12_pca_isr(void) __interrupt(7)
{
    if (CCF0) {
        uint16_t cap = (uint16_t)CCAP0H << 8 | CCAP0L;
        CCF0 = 0;
        flow_last = pca_extend(cap, CF);
        flow_count++;
    }
    if (CF) {
        CF = 0;
        pca_hi++;
    }
}

/* PCA time now; interrupts must be off. */
static uint32_t pca_read(void)
{
    uint8_t h, l;
    do {
        h = CH;
        l = CL;
    } while (h != CH);
    return pca_extend((uint16_t)h << 8 | l, CF);
}

#if FW_HIL
static hal_hil_t __xdata *hil;      /* hal_hil: the inputs from the PC's frames */
#endif

uint32_t hal_pca_now(void)
{
    uint32_t t;
#if FW_HIL
    if (hil)
        return hil->pca_now;
#endif
    EA = 0;
    t = pca_read();
    EA = 1;
    return t;
}

static volatile uint32_t wheel_min;    /* hal_wheel_min_interval */
static volatile uint8_t wheel_rejected;

void stc12_int0_isr(void) __interrupt(0)
{
    uint32_t t = pca_read();
    if (t - wheel_last < wheel_min) {   /* too early to be a pulse: bounce, interference */
        if (wheel_rejected != 255)
            wheel_rejected++;
        return;
    }
    wheel_last = t;
    wheel_count++;
}

void hal_wheel_min_interval(uint32_t min_ticks)
{
#if FW_HIL
    if (hil) {
        hil->wheel_min = min_ticks;
        return;
    }
#endif
    EA = 0;
    wheel_min = min_ticks;
    EA = 1;
}

#if FW_HIL
/* a frame's capture, taken: the next take sees only the next frame's */
static void hil_take(hal_capture_t __xdata *f, hal_capture_t *c)
{
    c->count = f->count;
    c->last = f->last;
    c->rejected = f->rejected;
    f->count = 0;
    f->rejected = 0;
}
#endif

void hal_flow_capture_take(hal_capture_t *c)
{
#if FW_HIL
    if (hil) {
        hil_take(&hil->meter, c);
        return;
    }
#endif
    EA = 0;
    c->count = flow_count;
    c->last = flow_last;
    c->rejected = 0;
    flow_count = 0;
    EA = 1;
}

void hal_wheel_capture_take(hal_capture_t *c)
{
#if FW_HIL
    if (hil) {
        hil_take(&hil->wheel, c);
        return;
    }
#endif
    EA = 0;
    c->count = wheel_count;
    c->last = wheel_last;
    c->rejected = wheel_rejected;
    wheel_count = 0;
    wheel_rejected = 0;
    EA = 1;
}

/* ---- ADC: 10 bits, result high 8 bits in ADC_RES, low 2 in ADC_RESL (ADRJ = 0) ----------- */
#define ADC_POWER 0x80
#define ADC_SPEED_90 0x60
#define ADC_FLAG 0x10
#define ADC_START 0x08

uint16_t hal_adc_read(uint8_t ch)
{
#if FW_HIL
    if (hil)
        return ch < 2 ? hil->adc[ch] & 0x3FF : 0;
#endif
    ADC_CONTR = ADC_POWER | ADC_SPEED_90 | ADC_START | (ch & 7);
    NOP(); NOP(); NOP(); NOP();     /* the flag is valid four clocks after the start */
    while (!(ADC_CONTR & ADC_FLAG))
        ;
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

uint8_t hal_keypad_row(uint8_t row)
{
    uint8_t cols;
    PORT_KEYPAD = (uint8_t)~(1u << (row & 3));  /* columns stay high (inputs) */
    NOP(); NOP(); NOP(); NOP(); NOP(); NOP(); NOP(); NOP(); /* let the lines settle */
    cols = (uint8_t)(~PORT_KEYPAD >> 4) & 0x0F;
    PORT_KEYPAD = 0xFF;
    return cols;
}

void hal_valve_out(int8_t dir, uint8_t duty)
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

void hal_spray_enable(uint8_t on)
{
#if FW_HIL
    if (hil)
        on = 0;
#endif
    PIN_SPRAY = on ? 1 : 0;
}

void hal_buzzer(uint8_t on)
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

/* ---- UART 1 from the BRT generator in 1T mode: 11059200 / 32 / 9 = 38400 baud ------------- */
#define UART_TXQ 16     /* powers of two: the index wraps with a mask, not a divide */
#define UART_RXQ 16
static volatile uint8_t txq[UART_TXQ];   /* short queues: serial.c refills as they drain */
static volatile uint8_t tx_head, tx_tail, tx_busy;
static volatile uint8_t rxq[UART_RXQ];
static volatile uint8_t rx_head, rx_tail;

void stc12_uart_isr(void) __interrupt(4)
{
    if (RI) {
        uint8_t n = (uint8_t)((rx_head + 1) & (UART_RXQ - 1));
        RI = 0;
        if (n != rx_tail) {         /* a full queue drops the byte; the frame check catches it */
            rxq[rx_head] = SBUF;
            rx_head = n;
        }
    }
    if (TI) {
        TI = 0;
        if (tx_tail != tx_head) {
            SBUF = txq[tx_tail];
            tx_tail = (uint8_t)((tx_tail + 1) & (UART_TXQ - 1));
        } else {
            tx_busy = 0;
        }
    }
}

uint8_t hal_uart_put(uint8_t b)
{
    uint8_t n = (uint8_t)((tx_head + 1) & (UART_TXQ - 1));
    if (n == tx_tail)
        return 0;
    ES = 0;
    if (!tx_busy) {
        tx_busy = 1;
        SBUF = b;
    } else {
        txq[tx_head] = b;
        tx_head = n;
    }
    ES = 1;
    return 1;
}

int16_t hal_uart_get(void)
{
    int16_t b;
    if (rx_tail == rx_head)
        return -1;
    b = rxq[rx_tail];
    rx_tail = (uint8_t)((rx_tail + 1) & (UART_RXQ - 1));
    return b;
}

/* ---- IAP EEPROM: 1 KB at IAP addresses 0x0000-0x03FF, two 512-byte sectors ------------------ */
#define IAP_EN_WT 0x83              /* IAPEN, wait time for SYSCLK < 12 MHz */
#define IAP_READ 1
#define IAP_PROGRAM 2
#define IAP_ERASE 3

static void iap_cmd(uint8_t cmd, uint16_t addr)
{
    IAP_CONTR = IAP_EN_WT;
    IAP_CMD = cmd;
    IAP_ADDRL = (uint8_t)addr;
    IAP_ADDRH = (uint8_t)(addr >> 8);
    EA = 0;                         /* the trigger pair must not be split */
    IAP_TRIG = 0x5A;
    IAP_TRIG = 0xA5;
    NOP();
    EA = 1;
    IAP_CONTR = 0;                  /* leave IAP disabled and pointing outside the EEPROM */
    IAP_CMD = 0;
    IAP_TRIG = 0;
    IAP_ADDRH = 0x80;
    IAP_ADDRL = 0;
}

uint8_t hal_eeprom_read(uint16_t addr)
{
    if (addr >= HAL_EEPROM_SIZE)
        return 0xFF;
    iap_cmd(IAP_READ, addr);
    return IAP_DATA;
}

void hal_eeprom_erase(uint16_t addr)
{
    if (addr >= HAL_EEPROM_SIZE)
        return;
    iap_cmd(IAP_ERASE, addr & (uint16_t)~(HAL_EEPROM_SECTOR - 1));
}

uint8_t hal_eeprom_write(uint16_t addr, uint8_t b)
{
    if (addr >= HAL_EEPROM_SIZE)
        return 0;
    IAP_DATA = b;
    iap_cmd(IAP_PROGRAM, addr);
    return hal_eeprom_read(addr) == b;
}

/* ---- LCD12864, ST7920 serial mode: sync byte, then the high and low nibbles ---------------- */
static void lcd_shift(uint8_t b)
{
    uint8_t i;
    for (i = 0; i < 8; i++) {
        PIN_LCD_SID = (b & 0x80) ? 1 : 0;
        PIN_LCD_SCLK = 1;
        PIN_LCD_SCLK = 0;
        b <<= 1;
    }
}

static void delay_us(uint16_t us)   /* at least us microseconds at 11.0592 MHz in 1T mode */
{
    while (us--) {
        NOP(); NOP(); NOP(); NOP(); NOP(); NOP(); NOP(); NOP();
    }
}

void hal_lcd_write(uint8_t rs, uint8_t b)
{
    PIN_LCD_CS = 1;
    lcd_shift(rs ? 0xFA : 0xF8);
    lcd_shift(b & 0xF0);
    lcd_shift((uint8_t)(b << 4));
    PIN_LCD_CS = 0;
    /* ST7920 needs 72 us per command, 1.6 ms for clear (0x01) and home (0x02/0x03) */
    delay_us((!rs && b < 0x04) ? 1600 : 80);
}

/* ---- watchdog: prescaler 32 -> 12 * 32 * 32768 / 11059200 = 1.14 s ------------------------ */
void hal_wdt_kick(void)
{
    WDT_CONTR = 0x34;               /* EN_WDT | CLR_WDT | PS = 4 */
}

/* ---- everything at power-up --------------------------------------------------------------- */
void hal_init(void)
{
    /* ports: all quasi-bidirectional (reset state); valve, spray and buzzer off */
    PIN_VALVE_A = 0;
    PIN_VALVE_B = 0;
    PIN_SPRAY = 0;
    PIN_BUZZER = 0;
    PIN_LCD_CS = 0;
    PIN_LCD_SCLK = 0;
    PORT_KEYPAD = 0xFF;
    PORT_SECTIONS = 0xFF;

    /* timer 0: 16-bit, 1T, 1 ms */
    AUXR |= 0x80;                   /* T0x12 */
    TMOD = (TMOD & 0xF0) | 0x01;
    TL0 = (uint8_t)(65536u - 11059u);
    TH0 = (uint8_t)((65536u - 11059u) >> 8);
    ET0 = 1;
    TR0 = 1;

    /* PCA: SYSCLK/12, overflow interrupt; module 0 captures falling edges; module 1 PWM */
    CMOD = 0x01;                    /* CPS = 000 (SYSCLK/12), ECF */
    CCON = 0;
    CL = 0;
    CH = 0;
    CCAPM0 = 0x11;                  /* CAPN | ECCF */
    CCAPM1 = 0x42;                  /* ECOM | PWM */
    PCA_PWM1 = 0x03;
    CCAP1L = 0xFF;
    CCAP1H = 0xFF;
    CR = 1;
    PPCA = 1;                       /* captures first */

    /* INT0: falling edge */
    IT0 = 1;
    EX0 = 1;

    /* ADC on P1.0, P1.1 */
    P1ASF = ADC_PINS_MASK;
    ADC_CONTR = ADC_POWER;

    /* UART 1: mode 1, BRT in 1T mode, 38400 baud */
    SCON = 0x50;
    BRT = (uint8_t)(256u - HAL_SYSCLK_HZ / 32u / HAL_UART_BAUD);
    AUXR |= 0x15;                   /* BRTR | BRTx12 | S1BRS */
    ES = 1;

    EA = 1;
    hal_wdt_kick();
}

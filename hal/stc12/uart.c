/* uart.c: UART 1: its framings (38400 8N1, a Raven console's 9600 or 1200 8N2) and its queues. */
#pragma stackauto           /* locals on the stack, not each its own XRAM (docs/MEMORY.md) */
#include <stc12.h>
#include "hal.h"
#include "stc12_int.h"
#include "isr.h"

/* ---- UART 1 from the BRT generator (framings: hal_uart_framing) ----------------------------- */
/* powers of two: the index wraps with a mask, not a divide. The transmit queue holds what a
 * pass hands over while the UART sends: 8 bytes are 2 ms at 38400 baud, 9 ms at 9600; serial.c
 * refills it every pass, and no line is time-critical beyond its order. */
#define UART_TXQ 8
/* The receive queue holds what arrives while the main loop does not read it: at 38400 baud a
 * byte every 0.26 ms (3840 a second). app_poll runs serial_poll in every pass but the control
 * step's, so the longest wait is about two passes (a redraw's, whose serial_poll ran before the
 * console, then a step's): in 1T time (make chip measures them in the model), times 3840/s,
 * plus the slot the ring keeps free, to a power of two.
 * docs/PIL.md gives the passes from the pil_bench run and the size they ask for; a longer burst
 * is a gap the reader is told of (HAL_UART_LOST, ERR LOST to the PC). */
#define UART_RXQ HAL_UART_RXQ
static volatile uint8_t txq[UART_TXQ];   /* short queues: serial.c refills as they drain */
static volatile uint8_t tx_head, tx_tail, tx_busy;
static volatile uint8_t rxq[UART_RXQ];
static volatile uint8_t rx_head, rx_tail;
/* A byte was lost: nothing more is queued until the queue has been read empty, where
 * hal_uart_get reports HAL_UART_LOST, so the reader knows exactly where the gap is. */
volatile __bit stc12_rx_lost;

/* the received byte in SBUF into the queue, or the loss marked (interrupts off) */
#define RX_TAKE() do {                                                      \
        uint8_t n_ = (uint8_t)((rx_head + 1) & (UART_RXQ - 1));             \
        RI = 0;                                                             \
        if (!stc12_rx_lost && n_ != rx_tail) {                                    \
            rxq[rx_head] = SBUF;                                            \
            rx_head = n_;                                                   \
        } else {                                                            \
            stc12_rx_lost = 1;                                                    \
        }                                                                   \
    } while (0)

void stc12_uart_isr(void) __interrupt(4)
{
    if (RI)
        RX_TAKE();
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

/*
 * The framings, from the STC12C5A60S2 datasheet's "Serial Port (UART)" chapter (modes of SCON's
 * SM0/SM1; the baud rate of modes 1 and 3 from the independent baud rate generator: AUXR's
 * BRTR starts it, S1BRS gives it to UART 1, BRTx12 runs it at SYSclk instead of SYSclk/12, and
 * with SMOD 0 the rate is its clock / 32 / (256 - BRT)):
 *   38400 8N1: mode 1 (10 bits a byte), BRT in 1T: 11059200 / 32 / 9 = 38400
 *   9600 8N2:  mode 3 (11 bits: the 9th is TB8, held at 1, a second stop bit; a received
 *              byte's 9th bit goes to RB8, unread), BRT in 1T: 11059200 / 32 / 36 = 9600
 *   1200 8N2:  mode 3, BRT in 12T (1T would need a reload below 0): 921600 / 32 / 24 = 1200
 * SCON: SM0 0x80, SM1 0x40, REN 0x10, TB8 0x08. AUXR: BRTR 0x10, BRTx12 0x04, S1BRS 0x01.
 */
static const __code uint8_t uart_scon[3] = {0x50, 0xD8, 0xD8};
static const __code uint8_t uart_brt[3] = {
    (uint8_t)(256u - HAL_SYSCLK_HZ / 32u / 38400u),
    (uint8_t)(256u - HAL_SYSCLK_HZ / 32u / 9600u),
    (uint8_t)(256u - HAL_SYSCLK_HZ / 12u / 32u / 1200u),
};

uint8_t hal_uart_framing(uint8_t f)
{
    if (tx_busy || f > HAL_UART_1200_8N2)
        return 0;                   /* the last byte is still going out (or no such framing) */
    AUXR &= (uint8_t)~0x15;         /* the generator stopped while it is set */
    SCON = uart_scon[f];
    BRT = uart_brt[f];
    AUXR |= f == HAL_UART_1200_8N2 ? 0x11 : 0x15;
    return 1;
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
    if (rx_tail == rx_head) {
        if (stc12_rx_lost) {
            stc12_rx_lost = 0;
            return HAL_UART_LOST;
        }
        return -1;
    }
    b = rxq[rx_tail];
    rx_tail = (uint8_t)((rx_tail + 1) & (UART_RXQ - 1));
    return b;
}

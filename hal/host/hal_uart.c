/* hal_uart.c: the host backend's serial line, bit by bit: the PC's frames into the chip's receiver at the chip's framing, the chip's frames out (hal_host.h). */
#include <string.h>
#include "hal_host.h"

/* One byte on the wire: its start bit's time, its bit time, its bits (start, 8 data, stops). */
typedef struct {
    uint64_t t0;
    uint64_t bit_ns;
    uint8_t bits, b;
} frame_t;

/* One direction of the line: the frames sent, and the receiver's place */
typedef struct {
    frame_t f[HAL_HOST_UART_Q];
    uint32_t head, tail;
    uint64_t end_ns;                /* the end of the newest frame sent */
    uint64_t ready_ns;              /* the receiver looks for a start bit from here */
} wire_t;

static wire_t to_chip, to_pc;
static uint8_t uart_tx[HAL_HOST_UART_Q];        /* the bytes sent, for hal_host_uart_tx_pop */
static uint32_t tx_head, tx_tail;
static uint8_t rxq[HAL_HOST_UART_RXQ];  /* the chip's receive queue (hal_host.h: smaller than the chip's) */
static uint32_t rx_head, rx_tail;
static uint8_t rx_lost;
static uint64_t hold_from_ns, hold_until_ns;    /* the last IAP erase held the CPU */
static uint8_t framing;             /* the chip's, HAL_UART_* */
static int pc_framing = -1;         /* the PC's, or -1: the chip's */

static const uint32_t baud[4] = {38400u, 9600u, 1200u, 9600u};
static const uint8_t frame_bits[4] = {10u, 11u, 11u, 10u};

static uint64_t bit_ns(uint8_t f)
{
    return (1000000000u + baud[f] / 2u) / baud[f];
}

uint64_t hal_host_uart_frame_ns(uint8_t f)
{
    return bit_ns(f) * frame_bits[f];
}

uint8_t hal_host_uart_framing(void)
{
    return framing;
}

void hal_host_uart_reset(void)
{
    memset(&to_chip, 0, sizeof to_chip);
    memset(&to_pc, 0, sizeof to_pc);
    tx_head = tx_tail = rx_head = rx_tail = 0;
    rx_lost = 0;
    hold_from_ns = hold_until_ns = 0;
    framing = HAL_UART_38400_8N1;
}

void hal_host_uart_init(void)
{
    framing = HAL_UART_38400_8N1;
}

void hal_host_uart_pc_framing(int f)
{
    pc_framing = f;
}

uint8_t hal_uart_framing(uint8_t f)
{
    if (f > HAL_UART_1200_8N2 || to_pc.end_ns > hal_host_io.time_ns)
        return 0;                   /* a byte still going out */
    framing = f;
    return 1;
}

/* a frame onto a wire: after the one before, or now (the oldest forgotten when the wire is
 * full: nobody listened) */
static void wire_send(wire_t *w, uint8_t b, uint8_t f)
{
    uint32_t n = (w->head + 1) % HAL_HOST_UART_Q;
    frame_t *fr = &w->f[w->head];
    if (n == w->tail)
        w->tail = (w->tail + 1) % HAL_HOST_UART_Q;
    fr->t0 = w->end_ns > hal_host_io.time_ns ? w->end_ns : hal_host_io.time_ns;
    fr->bit_ns = bit_ns(f);
    fr->bits = frame_bits[f];
    fr->b = b;
    w->end_ns = fr->t0 + fr->bit_ns * fr->bits;
    w->head = n;
}

/* the line's level (1 idle) at time t */
static int level(const wire_t *w, uint64_t t)
{
    for (uint32_t i = w->tail; i != w->head; i = (i + 1) % HAL_HOST_UART_Q) {
        const frame_t *fr = &w->f[i];
        if (t < fr->t0)
            return 1;
        uint64_t k = (t - fr->t0) / fr->bit_ns;
        if (k < fr->bits)
            return k == 0 ? 0 : k <= 8 ? (fr->b >> (k - 1)) & 1 : 1;
    }
    return 1;
}

/* the first falling edge at or after t (UINT64_MAX: none sent yet) */
static uint64_t falling_edge(const wire_t *w, uint64_t t)
{
    for (uint32_t i = w->tail; i != w->head; i = (i + 1) % HAL_HOST_UART_Q) {
        const frame_t *fr = &w->f[i];
        int prev = 0;               /* the start bit */
        if (fr->t0 >= t)
            return fr->t0;          /* every frame follows idle or stop bits */
        for (uint8_t k = 1; k <= 8; k++) {
            int bit = (fr->b >> (k - 1)) & 1;
            if (prev && !bit && fr->t0 + k * fr->bit_ns >= t)
                return fr->t0 + k * fr->bit_ns;
            prev = bit;
        }
    }
    return UINT64_MAX;
}

/* The receiver at framing f: the next byte whose frame has ended by now into *b; returns the
 * time its frame ended, or 0 when none has. The receiver looks for the next start bit from
 * the middle of the frame's last data bit on (the 9th bit of mode 3 and the stop bit are not
 * waited for: a PC's back-to-back 8N1 frames are read by a chip set to 8N2). Frames wholly
 * behind the receiver are dropped. */
static uint64_t wire_receive(wire_t *w, uint8_t f, uint8_t *b)
{
    uint64_t now = hal_host_io.time_ns, T = bit_ns(f);
    for (;;) {
        uint64_t te = falling_edge(w, w->ready_ns), done;
        if (te == UINT64_MAX || te + T * frame_bits[f] > now)
            return 0;
        if (level(w, te + T / 2)) {     /* a false start: a glitch, not a start bit */
            w->ready_ns = te + T / 2;
            continue;
        }
        *b = 0;
        for (uint8_t k = 1; k <= 8; k++)
            *b |= (uint8_t)(level(w, te + k * T + T / 2) << (k - 1));
        done = te + T * frame_bits[f];
        w->ready_ns = te + 9 * T + T / 2;
        while (w->tail != w->head && w->f[w->tail].t0 + w->f[w->tail].bit_ns * w->f[w->tail].bits <= w->ready_ns)
            w->tail = (w->tail + 1) % HAL_HOST_UART_Q;
        return done;
    }
}

uint8_t hal_uart_put(uint8_t b)
{
    uint32_t n = (tx_head + 1) % HAL_HOST_UART_Q;
    if (pc_framing >= 0) {          /* the PC listens on the wire (hal_host_uart_pc_get) */
        wire_send(&to_pc, b, framing);
        return 1;
    }
    if (n == tx_tail)
        return 0;
    uart_tx[tx_head] = b;
    tx_head = n;
    to_pc.end_ns = (to_pc.end_ns > hal_host_io.time_ns ? to_pc.end_ns : hal_host_io.time_ns)
                   + hal_host_uart_frame_ns(framing);   /* only its time, for hal_uart_framing */
    return 1;
}

/* a byte into the chip's queue, or the loss marked (as hal/stc12/uart.c's RX_TAKE) */
static void rx_take(uint8_t b)
{
    uint32_t n = (rx_head + 1) % HAL_HOST_UART_RXQ;
    if (!rx_lost && n != rx_tail) {
        rxq[rx_head] = b;
        rx_head = n;
    } else {
        rx_lost = 1;
    }
}

/* The bytes that have arrived by now, in order. Those arriving while an erase held the CPU
 * are a gap (SBUF keeps one, drops the rest; the chip cannot tell how many came, so it drops
 * that one too and marks the loss), as hal/stc12/iap.c's iap_cmd does. */
static void uart_deliver(void)
{
    uint8_t b;
    uint64_t t;
    while ((t = wire_receive(&to_chip, framing, &b)) != 0) {
        if (t >= hold_from_ns && t < hold_until_ns) {
            rx_lost = 1;
            continue;
        }
        rx_take(b);
    }
}

void hal_host_uart_hold(uint64_t from_ns, uint64_t until_ns)
{
    uart_deliver();                 /* what came before the hold */
    hold_from_ns = from_ns;
    hold_until_ns = until_ns;
}

int16_t hal_uart_get(void)
{
    int16_t b;
    uart_deliver();
    if (rx_tail == rx_head) {
        if (rx_lost) {
            rx_lost = 0;
            return HAL_UART_LOST;
        }
        return -1;
    }
    b = rxq[rx_tail];
    rx_tail = (rx_tail + 1) % HAL_HOST_UART_RXQ;
    return b;
}

int hal_host_uart_tx_pop(void)
{
    int b;
    if (tx_tail == tx_head)
        return -1;
    b = uart_tx[tx_tail];
    tx_tail = (tx_tail + 1) % HAL_HOST_UART_Q;
    return b;
}

int hal_host_uart_pc_get(void)
{
    uint8_t b;
    if (pc_framing < 0 || !wire_receive(&to_pc, (uint8_t)pc_framing, &b))
        return -1;
    return b;
}

uint32_t hal_host_uart_rx_waiting(void)
{
    uart_deliver();                 /* what has arrived by now (time stands still in a pass) */
    return (rx_head - rx_tail + HAL_HOST_UART_RXQ) % HAL_HOST_UART_RXQ + rx_lost;
}

void hal_host_uart_rx_push(uint8_t b)
{
    wire_send(&to_chip, b, pc_framing >= 0 ? (uint8_t)pc_framing : framing);
}

/* hilboard_main.c: the host build standing in for a flashed board on a pseudo-terminal, for hardware in the loop without hardware. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "args.h"
#include "hal_host.h"
#include "hil.h"
#include "app.h"
#include "pty.h"

/*
 * The firmware (app_init, app_poll) on the host HAL, its serial link on a pseudo-terminal
 * (sim --pty's): what a board does on its RS232 port, this does there. The board's clock runs
 * a millisecond at a time (the main loop polled each, as on the chip) while commands come in,
 * and in HIL mode with the PC's: a sensor frame carries the PC's PCA time; it goes on the
 * host HAL's wire (38400 baud) so that its last byte arrives within the millisecond it stands
 * for, and the board steps at the instant the simulator's firmware would (its clock then
 * runs ahead of the PC's by the set-up's time, which only moves hal_ms).
 */

static uint64_t t_ms;

/* a sensor frame's time on the wire, whole milliseconds (10 bits a byte) */
#define WIRE_MS ((HIL_IN_BYTES * 10u * 1000u + HAL_UART_BAUD - 1u) / HAL_UART_BAUD)

static void poll_at(uint64_t ms)
{
    while (t_ms < ms) {
        t_ms++;
        hal_host_set_time_ns(t_ms * 1000000ull);
        app_poll();
    }
}

static void flush_tx(int fd)
{
    uint8_t buf[512];
    size_t k = 0;
    int b;
    while ((b = hal_host_uart_tx_pop()) >= 0) {
        buf[k++] = (uint8_t)b;
        if (k == sizeof buf) {
            pty_write(fd, buf, k);
            k = 0;
        }
    }
    if (k)
        pty_write(fd, buf, k);
}

static void usage(FILE *f)
{
    fputs("usage: hilboard [--wait S]\n"
          "  the firmware on the host, its serial link on a new pseudo-terminal (the name on stderr):\n"
          "  build/host/bin/hil --port <it> runs a scenario against it (make hil-host); --wait S: how\n"
          "  long the PC may take to open it (60 s)\n", f);
}

int main(int argc, char **argv)
{
    char name[256];
    double wait_s = 60;
    int fd, i;
    uint8_t buf[256];
    hil_rx_t peek;                  /* finds the frames in the bytes to learn their time */
    uint32_t pca_prev = 0;
    uint64_t t_prev = 0;

    const arg_opt_t opts[] = {{"--wait", ARG_NUM, &wait_s, 0.001, 1e6, NULL}};
    i = args_parse("hilboard", argc, argv, opts, 1, NULL, usage);
    if (i != ARGS_OK)
        return i == ARGS_HELP ? 0 : 2;
    fd = pty_open(name, sizeof name);
    if (fd < 0) {
        fprintf(stderr, "hilboard: %s\n", name);
        return 1;
    }
    hal_host_reset();
    hal_init();
    app_init();
    hil_rx_init(&peek, HIL_IN_START);
    fprintf(stderr, "hilboard: serial link on %s (waiting %.0f s for the PC to open it)\n", name, wait_s);
    if (pty_wait_peer(fd, wait_s) < 0) {
        fprintf(stderr, "hilboard: nobody opened %s in %.0f s\n", name, wait_s);
        return 1;
    }
    for (;;) {
        int got = link_read(fd, buf, sizeof buf, 1.0), k;
        if (got < 0 || pty_peer_gone(fd))
            break;
        for (k = 0; k < got; k++) {
            if (!hil_active()) {
                /* a command: on the wire at 38400 baud, read as the main loop polls */
                hal_host_uart_rx_push(buf[k]);
                if (buf[k] == '\n' || k + 1 == got)
                    poll_at(t_ms + 6);
                if (hil_active()) {         /* OK HIL went out: the frames' clock starts here */
                    pca_prev = 0;
                    t_prev = t_ms;
                }
            } else if (hil_rx_byte(&peek, buf[k])) {
                /* a whole frame for the instant it stands for: put it on the wire the whole
                 * milliseconds its bytes take before (29 bytes: 7.6 ms, so 8), so that its
                 * last byte arrives within that millisecond */
                uint32_t pca = (uint32_t)peek.buf[2] | (uint32_t)peek.buf[3] << 8 | (uint32_t)peek.buf[4] << 16
                               | (uint32_t)peek.buf[5] << 24;
                uint64_t t = t_prev + ((uint64_t)(uint32_t)(pca - pca_prev) * 1000u + HAL_PCA_HZ / 2) / HAL_PCA_HZ;
                int i;
                pca_prev = pca;
                t_prev = t;
                poll_at(t > t_ms + WIRE_MS ? t - WIRE_MS : t_ms);
                for (i = 0; i < HIL_IN_BYTES; i++)
                    hal_host_uart_rx_push(peek.buf[i]);
                poll_at(t);
            }
        }
        flush_tx(fd);
    }
    close(fd);
    return 0;
}

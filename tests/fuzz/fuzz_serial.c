/* fuzz_serial.c: the serial command parser (firmware/link/) through the main loop on any bytes: one
 * checked reply per line, every line out well formed, no setting out of range. */
#include <string.h>
#include "fuzz.h"
#include "hal_host.h"
#include "params.h"
#include "app.h"
#include "serial.h"
#include "hil.h"
#include "link_crc.h"

static uint64_t t_ms;
static char out[SERIAL_TX_MAX + 8];
static size_t out_n;
static unsigned replies;
static int hil;                     /* OK HIL came: from there on the link carries frames */
static unsigned lost;               /* ERR LOST replies: lines' ends may have gone with the bytes */

/* One line the firmware sent, checked: "<body>*HH\r\n", HH the CRC-8 of the body. */
static void take_line(void)
{
    unsigned cs = 0;
    size_t i;
    FUZZ_CHECK(out_n >= 6 && out[out_n - 2] == '\r' && out[out_n - 5] == '*', "line '%.*s'", (int)out_n, out);
    for (i = 0; i + 5 < out_n; i++)
        FUZZ_CHECK(out[i] >= 0x20 && out[i] <= 0x7E, "byte 0x%02x in '%.*s'", (uint8_t)out[i], (int)out_n, out);
    FUZZ_CHECK(sscanf(out + out_n - 4, "%2X", &cs) == 1 && cs == link_crc8(out, out_n - 5), "checksum of '%.*s'",
               (int)out_n, out);
    if (!strncmp(out, "OK HIL*", 7))
        hil = 1;
    if (!strncmp(out, "ERR LOST*", 9))
        lost++;
    if (!strncmp(out, "OK ", 3) || !strncmp(out, "ERR ", 4))
        replies++;
    else
        FUZZ_CHECK(!strncmp(out, "LOG ", 4) || !strncmp(out, "ALM ", 4) || !strncmp(out, "CLR ", 4)
                   || !strncmp(out, "BOOT ", 5) || !strncmp(out, "EE ", 3),
                   "unknown line '%.*s'", (int)out_n, out);
    out_n = 0;
}

static void drain(void)
{
    int b;
    while ((b = hal_host_uart_tx_pop()) >= 0) {
        if (hil) {
            /* frames: HIL_OUT_BYTES each, start byte first (their content: fuzz_hil) */
            FUZZ_CHECK(out_n > 0 || b == HIL_OUT_START, "byte 0x%02x between frames", b);
            if (++out_n == HIL_OUT_BYTES)
                out_n = 0;
            continue;
        }
        FUZZ_CHECK(out_n < SERIAL_TX_MAX, "line longer than SERIAL_TX_MAX");
        out[out_n++] = (char)b;
        if (b == '\n')
            take_line();
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    unsigned lines = 0, i, polls;
    size_t k;
    int in_line = 0;
    if (size > 2048)
        return 0;
    hal_host_reset();
    hal_init();
    hal_host_io.adc[HAL_ADC_PRESSURE] = 205;    /* 4 mA: no pressure */
    hal_host_io.adc[HAL_ADC_LEVEL] = 1023 - 100; /* tank nearly full */
    hal_host_io.sections = 0x3F;
    t_ms = 0;
    out_n = 0;
    replies = 0;
    hil = 0;
    lost = 0;
    app_init();
    for (k = 0; k < size; k++) {
        if (data[k] == '\r' || data[k] == '\n') {
            lines += in_line;
            in_line = 0;
        } else {
            in_line = 1;
        }
    }
    /* the bytes at the wire's pace (3 a millisecond), a poll every millisecond, as on the chip;
     * a line is answered within a poll or two, but one whose bytes were lost (the receive queue
     * overflowed) and whose end went with them is answered ERR LOST only when it has stalled
     * for 3 s (serial.h): the harness waits that long when a reply is missing and no ERR LOST
     * has come (after one, lines run together have fewer replies than lines) */
    polls = (unsigned)size * 2u + 100u + (SERIAL_STALL_S + 1u) * 1000u;
    for (i = 0, k = 0; i < polls && (hil ? i < (unsigned)size * 2u + 100u : k < size || (replies < lines && !lost));
         i++) {
        unsigned j;
        for (j = 0; j < 3 && k < size; j++)
            hal_host_uart_rx_push(data[k++]);
        t_ms++;
        hal_host_set_time_ns(t_ms * 1000000ull);
        app_poll();
        drain();
    }
    /* one reply a line; in HIL mode lines are not read (hil counts its frames' steps). A gap in
     * the bytes (an overflow, an EEPROM erase) is told ERR LOST at the next line end: lines whose
     * ends were in it share it, and one that held only line ends has it alone; the other
     * replies answer one line each */
    FUZZ_CHECK(hil ? replies <= lines : lost ? replies - lost <= lines : replies == lines,
               "%u lines in, %u replies (%u ERR LOST)", lines, replies, lost);
    FUZZ_CHECK(hil == hal_hil_active(), "OK HIL %d, HIL mode %d", hil, hal_hil_active());
    for (i = 0; i < P_COUNT; i++)
        FUZZ_CHECK(param_in_range((uint8_t)i, param_v[i]), "param %u = %u", i, param_v[i]);
    return 0;
}

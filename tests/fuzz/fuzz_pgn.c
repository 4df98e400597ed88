/* fuzz_pgn.c: the serial link with Remote = AgOpenGPS through the main loop on any bytes: every line out checked, every frame out one of the replies with its check, no more frames taken or dropped than frames begun, no setting out of range, a field computer's rate within the window. */
#include <string.h>
#include "fuzz.h"
#include "hal_host.h"
#include "params.h"
#include "app.h"
#include "serial.h"
#include "target.h"
#include "pgn.h"
#include "link_crc.h"

static uint64_t t_ms;
static uint8_t out[SERIAL_TX_MAX + 8];
static size_t out_n;

/* What the firmware sent, checked as it comes: a reply frame (237 with AgOpenGPS's check, 32400
 * and 32401 with RateControl's) or a line "<body>*HH\r\n" of printable bytes, HH its CRC-8. */
static void take(uint8_t b)
{
    unsigned sum = 0, cs = 0;
    size_t i;
    out[out_n++] = b;
    if (out[0] == 0x80 || out[0] == 0x90 || out[0] == 0x91) {
        size_t n = out[0] == 0x80 ? 14 : 15;
        FUZZ_CHECK(out_n < 2 || out[1] == (out[0] == 0x80 ? 0x81 : 0x7E), "frame header %02X %02X", out[0], out[1]);
        if (out_n < n)
            return;
        for (i = out[0] == 0x80 ? 2 : 0; i + 1 < n; i++)
            sum += out[i];
        FUZZ_CHECK(out[n - 1] == (uint8_t)sum, "reply %02X's check", out[0]);
        FUZZ_CHECK(out[0] != 0x80 || (out[3] == 237 && out[4] == 8), "AgOpenGPS reply pgn %u len %u", out[3], out[4]);
        out_n = 0;
        return;
    }
    FUZZ_CHECK(out_n < SERIAL_TX_MAX, "line longer than SERIAL_TX_MAX");
    if (b != '\n')
        return;
    FUZZ_CHECK(out_n >= 6 && out[out_n - 2] == '\r' && out[out_n - 5] == '*', "line '%.*s'", (int)out_n, out);
    for (i = 0; i + 5 < out_n; i++)
        FUZZ_CHECK(out[i] >= 0x20 && out[i] <= 0x7E, "byte 0x%02x in '%.*s'", out[i], (int)out_n, out);
    FUZZ_CHECK(sscanf((char *)out + out_n - 4, "%2X", &cs) == 1 && cs == link_crc8((char *)out, out_n - 5),
               "checksum of '%.*s'", (int)out_n, out);
    out_n = 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    unsigned starts = 0, i, w;
    size_t k;
    int b;
    if (size > 2048)
        return 0;
    hal_host_reset();
    hal_init();
    hal_host_io.adc[HAL_ADC_PRESSURE] = 205;    /* 4 mA: no pressure */
    hal_host_io.adc[HAL_ADC_LEVEL] = 1023 - 100; /* tank nearly full */
    hal_host_io.sections = 0x3F;
    t_ms = 0;
    out_n = 0;
    app_init();
    FUZZ_CHECK(param_put(P_REMOTE, REMOTE_PGN), "Remote = AgOpenGPS");
    /* the first byte chooses the speed source, the sections' and the given speed (so that a
     * RateControl rate meets a speed and a width) */
    if (size) {
        param_put(P_SPEED_SRC, (uint16_t)(data[0] % 3u));
        param_put(P_AOG_SECT, (uint16_t)((data[0] >> 2) & 1u));
        param_put(P_GIVEN_SPEED, (uint16_t)((data[0] >> 3) & 1u ? 80u : 0u));
    }
    for (k = 0; k < size; k++)
        starts += data[k] == 0x80 || (data[k] >= 0xF4 && data[k] <= 0xF6);
    /* the bytes at the wire's pace (3 a millisecond), a poll every millisecond, then 4 s more */
    for (i = 0, k = 0; k < size || i < (unsigned)size / 3u + 4000u; i++) {
        unsigned j;
        for (j = 0; j < 3 && k < size; j++)
            hal_host_uart_rx_push(data[k++]);
        t_ms++;
        hal_host_set_time_ns(t_ms * 1000000ull);
        app_poll();
        while ((b = hal_host_uart_tx_pop()) >= 0)
            take((uint8_t)b);
    }
    FUZZ_CHECK((unsigned)pgn_rx.taken + pgn_rx.bad <= starts, "%u taken, %u dropped, %u start bytes", pgn_rx.taken,
               pgn_rx.bad, starts);
    for (i = 0; i < P_COUNT; i++)
        FUZZ_CHECK(param_in_range((uint8_t)i, param_v[i]), "param %u = %u", i, param_v[i]);
    w = param_v[P_REMOTE_WIN];
    FUZZ_CHECK(!target_rate_remote()
                   || (target_rate_x10() >= 100u && (uint32_t)target_rate_x10() * 100u >= (uint32_t)param_v[P_RATE] * 10u * (100u - (w > 100u ? 100u : w))
                       && (uint32_t)target_rate_x10() * 100u <= (uint32_t)param_v[P_RATE] * 10u * (100u + w)),
               "a remote rate %u outside the window of %u L/ha +- %u %%", target_rate_x10(), param_v[P_RATE], w);
    return 0;
}

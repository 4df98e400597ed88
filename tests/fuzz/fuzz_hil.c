/* fuzz_hil.c: the hardware-in-the-loop frame receiver (firmware/link/hil.c) on any byte stream: only frames
 * whose CRC holds come out, they decode and encode back to the same bytes, and a good frame after
 * the noise is always found. */
#include <string.h>
#include "fuzz.h"
#include "hil.h"

static void check_stream(const uint8_t *data, size_t size, uint8_t start)
{
    hil_rx_t rx;
    uint8_t f[HIL_IN_BYTES], good[HIL_IN_BYTES];
    size_t k;
    unsigned frames = 0, tail = 0;
    uint16_t crc;
    hil_rx_init(&rx, start);
    for (k = 0; k < size; k++) {
        if (hil_rx_byte(&rx, data[k])) {
            frames++;
            FUZZ_CHECK(rx.buf[0] == start, "frame without its start byte");
            crc = hil_crc(rx.buf, (uint8_t)(rx.size - 2));
            FUZZ_CHECK(rx.buf[rx.size - 2] == (uint8_t)(crc >> 8) && rx.buf[rx.size - 1] == (uint8_t)crc,
                       "frame out with a bad CRC");
            if (start == HIL_IN_START) {
                hil_in_t in;
                hil_in_decode(rx.buf, &in);
                hil_in_encode(&in, f);
                /* the ADC fields carry 10 bits: the rest is dropped on decoding */
                FUZZ_CHECK(memcmp(f, rx.buf, 18) == 0 && f[22] == rx.buf[22], "sensor frame changed by decode/encode");
                FUZZ_CHECK(in.adc_pressure < 1024 && in.adc_level < 1024, "ADC above 10 bits");
            } else {
                hil_out_t out;
                hil_out_decode(rx.buf, &out);
                hil_out_encode(&out, f);
                FUZZ_CHECK(out.valve_dir >= -1 && out.valve_dir <= 1, "valve direction %d", out.valve_dir);
                /* the direction and relay bytes keep only their defined values and bits */
                FUZZ_CHECK(f[3] == rx.buf[3] && f[4] == (rx.buf[4] & 3) && memcmp(f + 5, rx.buf + 5, 12) == 0,
                           "output frame changed by decode/encode");
            }
        }
        FUZZ_CHECK(rx.n < rx.size, "receiver holds %u bytes", rx.n);
    }
    /* after any noise, at most one frame's worth of good frames is needed to find them again */
    memset(good, 0, sizeof good);
    if (start == HIL_IN_START) {
        hil_in_t in;
        memset(&in, 0, sizeof in);
        in.seq = 7;
        in.adc_pressure = 300;
        hil_in_encode(&in, good);
    } else {
        hil_out_t out;
        memset(&out, 0, sizeof out);
        out.seq = 7;
        hil_out_encode(&out, good);
    }
    for (k = 0; k < 3u * rx.size; k++)
        tail += hil_rx_byte(&rx, good[k % rx.size]);
    FUZZ_CHECK(tail >= 2, "receiver did not find good frames after the noise (%u)", tail);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > 4096)
        return 0;
    check_stream(data, size, HIL_IN_START);
    check_stream(data, size, HIL_OUT_START);
    return 0;
}

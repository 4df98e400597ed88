/* fuzz_hil.c: the hardware-in-the-loop frame receiver (firmware/link/hil.c) on any byte stream: only frames
 * whose CRC holds come out, they decode and encode back to the same bytes, and a good frame after
 * the noise is always found. */
#include <string.h>
#include "fuzz.h"
#include "hil.h"
#include "hal_host.h"
#include "params.h"

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
                hal_hil_t h;
                memset(&in, 0, sizeof in);
                in.seq = hil_in_decode(rx.buf, &h);
                in.pca_now = h.pca_now;
                in.wheel_count = h.wheel.count;
                in.wheel_last = h.wheel.last;
                in.wheel_rejected = h.wheel.rejected;
                in.meter_count = h.meter.count;
                in.meter_last = h.meter.last;
                in.adc_pressure = h.adc[HAL_ADC_PRESSURE];
                in.adc_level = h.adc[HAL_ADC_LEVEL];
                in.sections = h.sections;
                in.set_id = rx.buf[24];         /* (hil_byte sets it; the bytes go through as they are) */
                in.set_value = (uint16_t)(rx.buf[25] | rx.buf[26] << 8);
                hil_in_encode(&in, f);
                /* the ADC fields carry sums of 4 ten-bit conversions: 12 bits, at most 4092 */
                for (int a = 19; a <= 21; a += 2) {
                    unsigned raw = (rx.buf[a] | rx.buf[a + 1] << 8) & 0xFFFu;
                    FUZZ_CHECK((unsigned)(f[a] | f[a + 1] << 8) == (raw > 4092u ? 4092u : raw),
                               "ADC field %d: %u from %u", a, (unsigned)(f[a] | f[a + 1] << 8), raw);
                }
                FUZZ_CHECK(memcmp(f, rx.buf, 19) == 0 && memcmp(f + 23, rx.buf + 23, 4) == 0,
                           "sensor frame changed by decode/encode");
                FUZZ_CHECK(h.adc[0] <= 4092 && h.adc[1] <= 4092, "ADC sum above 4 x 1023");
            } else {
                hil_out_t out;
                hil_out_decode(rx.buf, &out);
                hil_out_encode(&out, f);
                FUZZ_CHECK(out.valve_dir >= -1 && out.valve_dir <= 1, "valve direction %d", out.valve_dir);
                /* the direction and relay bytes keep only their defined values and bits */
                FUZZ_CHECK(memcmp(f + 3, rx.buf + 3, 2) == 0 && f[5] == (rx.buf[5] & 3)
                           && memcmp(f + 6, rx.buf + 6, 17) == 0, "output frame changed by decode/encode");
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

/* The controller's mode on the same bytes: every frame taken is what the HAL reads, the lost
 * count never runs backwards, a frame's step leaves no capture to be taken twice, and whatever
 * setting a frame carries, every value stays in its range and keeps the cross-checks. */
static void check_mode(const uint8_t *data, size_t size)
{
    hal_capture_t c;
    uint16_t lost = 0;
    size_t k;
    hil_out_t o;
    uint8_t f[HIL_OUT_BYTES];
    hal_host_reset();
    params_defaults();
    hil_begin();
    FUZZ_CHECK(hil_active() && hal_hil_active(), "HIL mode not on after hil_begin");
    for (k = 0; k < size; k++) {
        if (!hil_byte(data[k]))
            continue;
        FUZZ_CHECK(hal_adc_read(HAL_ADC_PRESSURE) < 1024 && hal_adc_read(HAL_ADC_LEVEL) < 1024, "ADC");
        hal_flow_capture_take(&c);
        hal_flow_capture_take(&c);
        FUZZ_CHECK(c.count == 0, "a frame's meter edges taken twice");
        memset(&o, 0, sizeof o);
        hil_answer(&o, f);
        FUZZ_CHECK(o.lost >= lost, "lost count ran backwards");
        lost = o.lost;
        FUZZ_CHECK(o.set_verdict == HIL_NO_SETTING || o.set_verdict <= PARAM_X_METER, "verdict %u", o.set_verdict);
        for (uint8_t i = 0; i < P_COUNT; i++)
            FUZZ_CHECK(param_in_range(i, param_v[i]), "parameter %u at %u, out of its range", i, param_v[i]);
        FUZZ_CHECK(params_cross() == PARAM_OK, "a frame's setting broke cross-check %u", params_cross());
    }
    hal_hil(0);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > 4096)
        return 0;
    check_stream(data, size, HIL_IN_START);
    check_stream(data, size, HIL_OUT_START);
    check_mode(data, size);
    return 0;
}

/* hil.c: hardware-in-the-loop frames: CRC, a byte receiver that finds frames again after a damaged one, encode and decode (see hil.h). */
#include "hil.h"

uint16_t hil_crc(const uint8_t *p, uint8_t n) __reentrant
{
    uint16_t crc = 0xFFFFu;
    uint8_t i;
    while (n--) {
        crc ^= (uint16_t)*p++ << 8;
        for (i = 0; i < 8; i++)
            crc = (crc & 0x8000u) ? (uint16_t)((crc << 1) ^ 0x1021u) : (uint16_t)(crc << 1);
    }
    return crc;
}

void hil_rx_init(hil_rx_t *rx, uint8_t start) __reentrant
{
    rx->n = 0;
    rx->start = start;
    rx->size = start == HIL_IN_START ? HIL_IN_BYTES : HIL_OUT_BYTES;
    rx->synced = 0;
    rx->damaged = 0;
}

/* 1 when buf holds a whole frame whose CRC holds */
static uint8_t frame_ok(const hil_rx_t *rx) __reentrant
{
    uint16_t crc = hil_crc(rx->buf, (uint8_t)(rx->size - 2u));
    return rx->buf[rx->size - 2u] == (uint8_t)(crc >> 8) && rx->buf[rx->size - 1u] == (uint8_t)crc;
}

uint8_t hil_rx_byte(hil_rx_t *rx, uint8_t b) __reentrant
{
    uint8_t i, k;
    if (rx->n == 0 && b != rx->start)
        return 0;                   /* between frames: wait for a start */
    rx->buf[rx->n++] = b;
    while (rx->n == rx->size) {
        if (frame_ok(rx)) {
            rx->n = 0;
            rx->synced = 1;
            return 1;
        }
        if (rx->synced && rx->damaged < 0xFFFFu)
            rx->damaged++;
        /* drop the false start; the next start byte in what came after begins a frame */
        for (i = 1; i < rx->n && rx->buf[i] != rx->start; i++)
            ;
        for (k = 0; i < rx->n; i++, k++)
            rx->buf[k] = rx->buf[i];
        rx->n = k;
    }
    return 0;
}

static uint16_t get16(const uint8_t *p) __reentrant
{
    return (uint16_t)(p[0] | (uint16_t)p[1] << 8);
}

static uint32_t get32(const uint8_t *p) __reentrant
{
    return (uint32_t)get16(p) | (uint32_t)get16(p + 2) << 16;
}

static void put16(uint8_t *p, uint16_t v) __reentrant
{
    p[0] = (uint8_t)v;
    p[1] = (uint8_t)(v >> 8);
}

void hil_put_crc(uint8_t *f, uint8_t size) __reentrant
{
    uint16_t crc = hil_crc(f, (uint8_t)(size - 2u));
    f[size - 2u] = (uint8_t)(crc >> 8);
    f[size - 1u] = (uint8_t)crc;
}

void hil_in_decode(const uint8_t *f, hil_in_t *in) __reentrant
{
    in->seq = f[1];
    in->pca_now = get32(f + 2);
    in->wheel_count = get16(f + 6);
    in->wheel_last = get32(f + 8);
    in->meter_count = get16(f + 12);
    in->meter_last = get32(f + 14);
    in->adc_pressure = get16(f + 18) & 0x3FFu;
    in->adc_level = get16(f + 20) & 0x3FFu;
    in->sections = f[22];
}

void hil_out_encode(const hil_out_t *out, uint8_t *f) __reentrant
{
    f[0] = HIL_OUT_START;
    f[1] = out->seq;
    f[2] = (uint8_t)out->valve_dir;
    f[3] = out->valve_duty;
    f[4] = out->relays;
    put16(f + 5, out->alarms);
    put16(f + 7, out->lost);
    put16(f + 9, out->speed_kmh_x100);
    put16(f + 11, (uint16_t)out->target_lpm_x100);
    put16(f + 13, (uint16_t)out->flow_lpm_x100);
    put16(f + 15, out->pressure_kpa);
    hil_put_crc(f, HIL_OUT_BYTES);
}

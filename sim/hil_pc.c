/* hil_pc.c: the PC's half of the hardware-in-the-loop frames (firmware/link/hil.h): sensor frames out, output frames in. */
#include "hil.h"

static uint16_t get16(const uint8_t *p)
{
    return (uint16_t)(p[0] | (uint16_t)p[1] << 8);
}

static void put16(uint8_t *p, uint16_t v)
{
    p[0] = (uint8_t)v;
    p[1] = (uint8_t)(v >> 8);
}

static void put32(uint8_t *p, uint32_t v)
{
    put16(p, (uint16_t)v);
    put16(p + 2, (uint16_t)(v >> 16));
}

void hil_in_encode(const hil_in_t *in, uint8_t *f)
{
    f[0] = HIL_IN_START;
    f[1] = in->seq;
    put32(f + 2, in->pca_now);
    put16(f + 6, in->wheel_count);
    put32(f + 8, in->wheel_last);
    f[12] = in->wheel_rejected;
    put16(f + 13, in->meter_count);
    put32(f + 15, in->meter_last);
    put16(f + 19, in->adc_pressure);
    put16(f + 21, in->adc_level);
    f[23] = in->sections;
    f[24] = in->set_id;
    put16(f + 25, in->set_value);
    hil_put_crc(f, HIL_IN_BYTES);
}

void hil_out_decode(const uint8_t *f, hil_out_t *out)
{
    out->seq = f[1];
    out->valve_dir = (int8_t)(f[2] == 1 ? 1 : f[2] == 0xFF ? -1 : 0);
    out->valve_duty = f[3];
    out->valve_delay_ms = f[4];
    out->relays = f[5] & 3u;
    out->alarms = get16(f + 6);
    out->lost = get16(f + 8);
    out->wheel_min = (uint32_t)get16(f + 10) | (uint32_t)get16(f + 12) << 16;
    out->speed_kmh_x100 = get16(f + 14);
    out->target_lpm_x100 = (int16_t)get16(f + 16);
    out->flow_lpm_x100 = (int16_t)get16(f + 18);
    out->pressure_kpa = get16(f + 20);
    out->set_verdict = f[22];
}


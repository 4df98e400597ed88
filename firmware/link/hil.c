/* hil.c: hardware-in-the-loop frames: CRC, a byte receiver that finds frames again after a damaged one, encode and decode (see hil.h). */
#include "hil.h"
#include "params.h"

#if FW_HIL

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

/* an ADC field: the sum of 4 ten-bit conversions, at most 4 x 1023 */
static uint16_t adc_sum(const uint8_t *p) __reentrant
{
    uint16_t v = get16(p) & 0xFFFu;
    return v > 4092u ? 4092u : v;
}

uint8_t hil_in_decode(const uint8_t *f, hal_hil_t *in) __reentrant
{
    in->pca_now = get32(f + 2);
    in->wheel.count = get16(f + 6);
    in->wheel.last = get32(f + 8);
    in->wheel.rejected = f[12];
    in->meter.count = get16(f + 13);
    in->meter.last = get32(f + 15);
    in->meter.rejected = 0;
    in->adc[HAL_ADC_PRESSURE] = adc_sum(f + 19);
    in->adc[HAL_ADC_LEVEL] = adc_sum(f + 21);
    in->sections = f[23];
    return f[1];
}

void hil_out_encode(const hil_out_t *out, uint8_t *f) __reentrant
{
    f[0] = HIL_OUT_START;
    f[1] = out->seq;
    f[2] = (uint8_t)out->valve_dir;
    f[3] = out->valve_duty;
    f[4] = out->valve_delay_ms;
    f[5] = out->relays;
    put16(f + 6, out->alarms);
    put16(f + 8, out->lost);
    put16(f + 10, (uint16_t)out->wheel_min);
    put16(f + 12, (uint16_t)(out->wheel_min >> 16));
    put16(f + 14, out->speed_kmh_x100);
    put16(f + 16, (uint16_t)out->target_lpm_x100);
    put16(f + 18, (uint16_t)out->flow_lpm_x100);
    put16(f + 20, out->pressure_kpa);
    f[22] = out->set_verdict;
    hil_put_crc(f, HIL_OUT_BYTES);
}

/* ---- the controller's mode ------------------------------------------------------------------- */
static struct {
    hil_rx_t rx;
    hal_hil_t in;                   /* what the HAL reads while the mode is on */
    uint16_t lost;                  /* sensor frames lost or damaged: skipped sequence numbers */
    uint16_t wheel_total, meter_total;  /* the running totals of the last frame taken */
    uint8_t rejected_total;
    uint8_t on;                     /* HIL_OFF, HIL_WAIT (no frame yet), HIL_RUN */
    uint8_t first;                  /* the frame just taken is the mode's first */
    uint8_t seq;                    /* the sequence number of the last frame taken */
    uint8_t due;                    /* a frame is in, its step not yet answered */
    uint8_t verdict;                /* on the last frame's setting (hil_out_t.set_verdict) */
} hm;

#define HIL_OFF 0
#define HIL_WAIT 1
#define HIL_RUN 2

void hil_init(void)
{
    hm.on = HIL_OFF;
    hal_hil(0);
}

void hil_begin(void)
{
    hil_rx_init(&hm.rx, HIL_IN_START);
    hm.lost = 0;
    hm.first = 0;
    hm.due = 0;
    hm.verdict = HIL_NO_SETTING;
    hm.on = HIL_WAIT;
    hm.in.wheel.count = hm.in.meter.count = 0;
    hm.wheel_total = hm.meter_total = 0;
    hm.rejected_total = 0;
    hal_hil(&hm.in);                /* the pins off now; the inputs are the frames' from here */
}

uint8_t hil_active(void)
{
    return hm.on != HIL_OFF;
}

uint8_t hil_first(void)
{
    return hm.first;
}

uint8_t hil_byte(uint8_t b)
{
    uint8_t seq, gap;
    uint16_t total;
    if (!hil_rx_byte(&hm.rx, b))
        return 0;
    seq = hil_in_decode(hm.rx.buf, &hm.in);
    /* the edges since the last frame taken, lost frames' included (an untaken rest too) */
    b = hm.in.wheel.rejected;
    hm.in.wheel.rejected = (uint8_t)(b - hm.rejected_total);
    hm.rejected_total = b;
    total = hm.in.wheel.count;
    hm.in.wheel.count = (uint16_t)(total - hm.wheel_total);
    hm.wheel_total = total;
    total = hm.in.meter.count;
    hm.in.meter.count = (uint16_t)(total - hm.meter_total);
    hm.meter_total = total;
    hm.first = hm.on == HIL_WAIT;
    gap = (uint8_t)(seq - hm.seq - 1u);             /* frames that never came, or came damaged */
    if (!hm.first && gap) {
        total = (uint16_t)(hm.lost + gap);
        hm.lost = total < gap ? 0xFFFFu : total;    /* (wrapped: it stops at 65535) */
    }
    hm.seq = seq;
    hm.on = HIL_RUN;
    /* the frame's setting, before its step (as the keypad or SET would set it) */
    hm.verdict = hm.rx.buf[24] == HIL_NO_SETTING ? HIL_NO_SETTING : param_try(hm.rx.buf[24], get16(hm.rx.buf + 25));
    return 1;
}

uint8_t hil_due(void)
{
    return hm.due;
}

void hil_poll(void)
{
    int16_t b;
    /* one frame at a time: its step runs before the next is read */
    while (!hm.due && (b = hal_uart_get()) >= 0)
        hm.due = hil_byte((uint8_t)b);
}

void hil_answer(hil_out_t *o, uint8_t *f) __reentrant
{
    hm.due = 0;
    o->seq = hm.seq;
    o->lost = hm.lost;
    o->wheel_min = hm.in.wheel_min;
    o->set_verdict = hm.verdict;
    hil_out_encode(o, f);
}

#endif

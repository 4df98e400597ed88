/* tt_ops.c: each routine the controllers compute with (mul.h's FX_SABOTAGE list) on a few edge and random vectors, briefly; s51 and host must print the same, and each routine built wrong must break that. */
#include "fixed.h"
#include "mul.h"
#include "umath.h"
#include "tt.h"

#define N_VEC 40
#define DOT_N 6

static __xdata int16_t dw_[DOT_N];
static __idata int16_t dx_[DOT_N];
static __xdata int8_t ddw_[DOT_N];

static void line(char tag, uint32_t a, uint32_t b, uint32_t r)
{
    tt_putc(tag);
    tt_putc(' ');
    tt_hex32(a);
    tt_putc(' ');
    tt_hex32(b);
    tt_putc(' ');
    tt_hex32(r);
    tt_putc('\n');
}

static void ops16(int16_t a, int16_t b)
{
    line('m', (uint16_t)a, (uint16_t)b, (uint32_t)MUL(a, b));
    line('u', (uint16_t)a, (uint16_t)b, UMUL(a, b));
    line('r', (uint16_t)a, (uint16_t)b, (uint32_t)MUL_R15(a, b));
    line('R', (uint16_t)a, (uint16_t)b, (uint32_t)MUL_R12(a, b));
    mul_acc = (int32_t)b * 256;
    MAC(a, b);
    line('c', (uint16_t)a, (uint16_t)b, (uint32_t)mul_acc);
    line('s', (uint16_t)a, (uint16_t)b, (uint32_t)ACC_SHR15());
    line('S', (uint16_t)a, (uint16_t)b, (uint32_t)ACC_SHR12());
    line('z', (uint16_t)a, 0, (uint16_t)fx_sat16((int32_t)a * 3));
    line('Z', (uint16_t)a, 0, (uint16_t)fx_sat16((int32_t)a / 2));
    line('t', (uint16_t)a, 0, (uint16_t)fx_tanh(a));
    line('t', (uint16_t)(a >> 4), 0, (uint16_t)fx_tanh((int16_t)(a >> 4)));
}

static void ops32(uint32_t a, uint16_t n, uint32_t d)
{
    line('h', a, n, um_mul32x16_shr16(a, n));
    line('d', a, ((uint32_t)n << 16) | (d >> 16), um_muldiv(a, n, d));
    if (d)
        line('q', a, ((uint32_t)n << 16) | (d >> 16), um_scaled_div(a >> 8, n, d));
}

/* one dot product and one learning row (the bp_pid network's), within UPD's contract */
static void rows(void)
{
    uint8_t j;
    int16_t eg = (int16_t)(tt_rand16() >> 1), v;
    for (j = 0; j < DOT_N; j++) {
        dx_[j] = (int16_t)tt_rand16();
        v = (int16_t)tt_rand16();
        dw_[j] = v > 16384 ? 16384 : v < -16384 ? -16384 : v;
        ddw_[j] = (int8_t)tt_rand16();
    }
    mul_acc = 0;
    DOT(dw_, dx_, DOT_N);
    line('D', (uint16_t)dw_[0], (uint16_t)dx_[0], (uint32_t)mul_acc);
    UPD(dw_, ddw_, dx_, eg, 16384, DOT_N, 1);
    for (j = 0; j < DOT_N; j++)
        line('U', j, (uint16_t)ddw_[j], (uint16_t)dw_[j]);
}

int main(void)
{
    uint8_t k;
    static const __code int16_t edges[] = {0, 1, -1, 255, -256, 16384, -16384, 32767, -32768};
    tt_begin();
    for (k = 0; k < sizeof edges / sizeof edges[0]; k++)
        ops16(edges[k], edges[sizeof edges / sizeof edges[0] - 1 - k]);
    for (k = 0; k < N_VEC; k++) {
        int16_t a = (int16_t)tt_rand16();   /* one statement each: argument order is unspecified */
        int16_t b = (int16_t)tt_rand16();
        uint32_t x = (uint32_t)tt_rand16() << (k & 15);
        uint16_t n = tt_rand16();
        uint32_t d = ((uint32_t)tt_rand16() << 8) | (k + 1u);
        ops16(a, b);
        ops32(x | (uint16_t)a, n, d);
        if ((k & 3) == 0)
            rows();
    }
    tt_end();
    return 0;
}

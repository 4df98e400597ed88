/* tt_fixed.c: every fixed-point routine on edge and random vectors; s51 and host must print the same. */
#include "fixed.h"
#include "mul.h"
#include "fmt.h"
#include "tt.h"

static const __code int16_t edges[] = {
    0, 1, -1, 2, -2, 127, -128, 255, -256, 4095, -4096, 4096, -4097, 16384, -16384,
    24575, 24576, -24576, -24577, 32766, -32767, 32767, -32768
};
#define N_EDGES (sizeof edges / sizeof edges[0])
#define N_RANDOM 300

static void line(char tag, int16_t a, int16_t b, uint32_t r)
{
    tt_putc(tag);
    tt_putc(' ');
    tt_hex16((uint16_t)a);
    tt_putc(' ');
    tt_hex16((uint16_t)b);
    tt_putc(' ');
    tt_hex32(r);
    tt_putc('\n');
}

static void all_ops(int16_t a, int16_t b)
{
    line('a', a, b, (uint16_t)fx_add_sat(a, b));
    line('s', a, b, (uint16_t)fx_sub_sat(a, b));
    line('m', a, b, (uint32_t)fx_mul32(a, b));
    line('u', a, b, UMUL(a, b));
    line('r', a, b, (uint32_t)MUL_R15(a, b));
    line('R', a, b, (uint32_t)MUL_R12(a, b));
    mul_acc = (int32_t)((uint32_t)(uint16_t)a << 16 | (uint16_t)b);    /* every 32-bit pattern */
    line('h', a, b, (uint32_t)ACC_SHR15());
    line('H', a, b, (uint32_t)ACC_SHR12());
    line('q', a, b, (uint16_t)q15_mul(a, b));
    line('w', a, b, (uint16_t)q12_mul(a, b));
    line('x', a, b, (uint16_t)fx_mul_shift(a, b, (uint8_t)(b & 15)));
    line('t', a, 0, (uint16_t)fx_tanh(a));
    line('g', a, 0, (uint16_t)fx_sigmoid(a));
    line('z', a, 0, (uint16_t)fx_sat16((int32_t)a * 3));
    line('Z', a, b, (uint16_t)fx_sat16((((int32_t)b * 32768L) >> (b & 15)) + a));
}

/* UPD (mul.h), one learning row, on random rows within its contract: bounds, momentum and the
 * change's clamp all reached; the row's weights and changes printed */
#define UPD_N 8
static __xdata int16_t uw[UPD_N];
static __idata int16_t ux[UPD_N];   /* x in the internal RAM, as bp_step's locals */
static __xdata int8_t udw[UPD_N];

static void upd_rows(uint16_t rows)
{
    uint8_t j, n, sh;
    int16_t eg, lim, v;
    while (rows--) {
        n = (uint8_t)(1 + (tt_rand16() & 7u));
        sh = (tt_rand16() & 1u) ? 1 : 4;
        lim = (tt_rand16() & 3u) ? 16384 : (int16_t)(tt_rand16() & 0x7FFFu);
        eg = (int16_t)tt_rand16();
        if (sh == 4)
            eg >>= 4;               /* (eg * x) >> 12 within int16 */
        for (j = 0; j < n; j++) {
            ux[j] = (int16_t)tt_rand16();
            if (sh == 1 && ux[j] == -32768 && eg == -32768)
                ux[j] = 0;
            v = (int16_t)tt_rand16();
            if (tt_rand16() & 1u)
                v >>= 3;
            uw[j] = v > lim ? lim : v < -lim ? -lim : v;
            udw[j] = (int8_t)tt_rand16();
        }
        UPD(uw, udw, ux, eg, lim, n, sh);
        tt_putc('u');
        for (j = 0; j < n; j++) {
            tt_putc(' ');
            tt_hex16((uint16_t)uw[j]);
            tt_hex8((uint8_t)udw[j]);
        }
        tt_putc('\n');
    }
}

/* x / y of 32-bit unsigned values: SDCC's __divulong (hal/mcs51/divulong.c on the target)
 * against the host's divide, on edges and on random pairs of every pair of magnitudes */
static void div_line(uint32_t x, uint32_t y)
{
    tt_putc('d');
    tt_putc(' ');
    tt_hex32(x);
    tt_putc(' ');
    tt_hex32(y);
    tt_putc(' ');
    tt_hex32(x / y);
    tt_putc(' ');
    tt_hex32(x - x / y * y);
    tt_putc('\n');
}

static uint32_t rand32(void)
{
    uint32_t hi = tt_rand16();
    return hi << 16 | tt_rand16();
}

static void div_lines(void)
{
    static const __code uint32_t e[] = {
        0, 1, 2, 3, 7, 10, 100, 255, 256, 65535, 65536, 1000000, 0x7FFFFFFFUL, 0x80000000UL,
        0xFFFFFFFEUL, 0xFFFFFFFFUL
    };
    uint8_t i, j;
    uint32_t x, y;
    for (i = 0; i < sizeof e / sizeof e[0]; i++)
        for (j = 1; j < sizeof e / sizeof e[0]; j++)
            div_line(e[i], e[j]);
    for (i = 0; i < 32; i++)
        for (j = 0; j < 32; j++) {
            x = rand32() >> i;
            y = rand32() >> j;
            div_line(x, y ? y : 1);
        }
}

static void fmt_line(uint32_t v, uint8_t decimals, uint8_t trim)
{
    __idata char s[FMT_MAX];        /* fmt_u32 writes to the internal RAM (fmt.h) */
    uint8_t i, n = fmt_u32(s, v, decimals, trim);
    tt_putc('f');
    tt_putc(' ');
    tt_hex32(v);
    tt_putc(' ');
    for (i = 0; i < n; i++)
        tt_putc(s[i]);
    tt_putc('\n');
}

int main(void)
{
    uint8_t i, j;
    uint16_t k;
    volatile int16_t va = 12345, vb = -23456, vx = 5000;
    volatile uint32_t vd = 0xFFFFFFFFUL;
    volatile int32_t sink32;
    volatile int16_t sink16;
    uint32_t c;

    tt_begin();
    for (i = 0; i < N_EDGES; i++)
        for (j = 0; j < N_EDGES; j++)
            all_ops(edges[i], edges[j]);
    for (k = 0; k < N_RANDOM; k++) {
        int16_t a = (int16_t)tt_rand16();   /* one statement each: argument order is unspecified */
        int16_t b = (int16_t)tt_rand16();
        all_ops(a, b);
    }
    for (k = 0; k < 200; k++) {             /* the number formatter */
        uint32_t hi = tt_rand16();
        uint32_t v = (hi << 16 | tt_rand16()) >> (k & 31);
        fmt_line(v, (uint8_t)(k & 3), (uint8_t)(k & 4));
    }

    upd_rows(400);
    div_lines();

    /* the cost of the building blocks, in machine cycles (stopwatch overhead included) */
    tt_cycles_start();
    c = tt_cycles_stop();
    tt_bench("stopwatch", c);
    tt_cycles_start();
    sink32 = fx_mul32(va, vb);
    tt_bench("fx_mul32", tt_cycles_stop());
    tt_cycles_start();
    sink32 = (int32_t)va * vb;
    tt_bench("mul16x16_32_inline", tt_cycles_stop());
    tt_cycles_start();
    sink16 = fx_tanh(vx);
    tt_bench("fx_tanh", tt_cycles_stop());
    tt_cycles_start();
    sink16 = fx_sigmoid(vx);
    tt_bench("fx_sigmoid", tt_cycles_stop());
    tt_cycles_start();
    sink16 = q15_mul(va, vb);
    tt_bench("q15_mul", tt_cycles_stop());
    tt_cycles_start();
    UPD(uw, udw, ux, 100, 16384, 5, 1);
    tt_bench("upd_row_of_5", tt_cycles_stop());
    tt_cycles_start();
    sink32 = (int32_t)(vd / 3u);
    tt_bench("divulong", tt_cycles_stop());
    (void)sink32;
    (void)sink16;
    tt_end();
    return 0;
}

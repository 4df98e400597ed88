/* tt_measure.c: the application's divide-free arithmetic and the rate target (eq. 1, Table 1) in s51 and on the host. */
#include "params.h"
#include "target.h"
#include "umath.h"
#include "tt.h"

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

static uint32_t rand32(void)
{
    uint32_t hi = tt_rand16();      /* separate statements: argument order differs */
    uint32_t lo = tt_rand16();
    return hi << 16 | lo;
}

int main(void)
{
    uint16_t k, v;
    uint32_t a, d, c;
    uint16_t n;
    static const __code uint16_t rates[] = {1000, 1250, 1500, 100, 10000};     /* Rate 1, 0.1 L/ha */
    static const __code uint8_t switches[] = {0x3F, 0x0F, 0x01, 0x00, 0x3E};
    uint8_t r, s;

    tt_begin();
    /* umath: random operands, and the edges 0, 1 and the saturation */
    line('m', 0, 1, um_muldiv(0, 1, 1));
    line('m', 1, 0, um_muldiv(1, 1, 0));
    line('m', 0xFFFFFFFFUL, 0xFFFF, um_muldiv(0xFFFFFFFFUL, 0xFFFF, 1));
    for (k = 0; k < 400; k++) {
        /* one draw a statement: operand order is unspecified in C, and SDCC and gcc differ */
        a = rand32();
        a >>= tt_rand16() & 15;
        n = tt_rand16();
        d = rand32();
        d >>= tt_rand16() & 31;
        line('m', a, ((uint32_t)n << 16) | (d >> 16), um_muldiv(a, n, d));
        line('h', a, n, um_mul32x16_shr16(a, n));
        line('r', a, 0, um_sqrt32(a));
    }
    line('r', 0xFFFFFFFFUL, 0, um_sqrt32(0xFFFFFFFFUL));

    /* eq. (1) with Table 1 over doses, section switches and speeds 0 .. 15 km/h */
    params_defaults();
    target_init();
    for (r = 0; r < sizeof rates / sizeof rates[0]; r++) {
        param_set(P_RATE, rates[r]);
        for (s = 0; s < sizeof switches; s++) {
            target_update(switches[s]);
            for (v = 0; v <= 1500; v += 25)
                line('q', ((uint32_t)rates[r] << 8) | switches[s], v, (uint16_t)target_flow_x100(v));
            line('o', switches[s], target_width_cm(), target_open_nozzles());
        }
    }

    tt_cycles_start();
    c = um_muldiv(123456789UL, 40000u, 98765UL);
    tt_bench("um_muldiv", tt_cycles_stop());
    tt_cycles_start();
    c = um_sqrt32(123456789UL);
    tt_bench("um_sqrt32", tt_cycles_stop());
    tt_cycles_start();
    c = (uint16_t)target_flow_x100(700);
    tt_bench("target_flow_x100", tt_cycles_stop());
    (void)c;
    tt_end();
    return 0;
}

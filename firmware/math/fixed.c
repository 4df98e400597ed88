/* fixed.c: saturating fixed-point arithmetic and table-driven tanh; same bits on SDCC and gcc. */
#include "fixed.h"

#if !defined(__SDCC)
/* the reference of the 8051's assembly (hal/mcs51/sat16.c); the target tests compare the two bit for bit */
int16_t fx_sat16(int32_t x)
{
    if (x > 32767L)
        return 32767;
    if (x < -32768L)
        return -32768;
    return (int16_t)x;
}

#endif

q15_t fx_tanh(q12_t x) __reentrant
{
    uint16_t ax;            /* |x| in Q12 */
    uint16_t i;             /* table interval, 1/64 wide */
    int16_t y;              /* Q15 */
    int16_t d;              /* Q15 rise over the interval: 0 .. 512 since tanh' <= 1 */
    uint8_t f;              /* the fraction of the interval, 1/64 */

    ax = x < 0 ? (uint16_t)(-(int32_t)x) : (uint16_t)x;   /* -(-32768) = 32768 fits uint16 */
    if (ax >= (uint16_t)((FX_TANH_N - 1) * 64)) {
        y = 32767;
    } else {
        i = ax >> 6;
        if (i < FX_TANH_J) {
            y = fx_tanh_tab[i];
            d = fx_tanh_tab[i + 1] - y;
        } else {            /* within 255 of 32767: a byte a point */
            const FX_CODE uint8_t *t = &fx_tanh_tail[i - FX_TANH_J];
            y = 32767 - t[0];
            d = (uint8_t)(t[0] - t[1]);
        }
        /* d * frac <= 512 * 63 = 32256, d >= 0 (tanh rises): two 8 x 8 products (MUL AB) */
        f = (uint8_t)(ax & 63u);
        y += (int16_t)(((uint16_t)((uint8_t)d * f) + ((uint16_t)((uint8_t)((uint16_t)d >> 8) * f) << 8) + 32u) >> 6);
    }
#if defined(__SDCC) && FX_SABOTAGE == 11
    y |= 1;                 /* wrong bits on purpose (mul.h) */
#endif
    return x < 0 ? (q15_t)-y : (q15_t)y;
}

/* mul.c: the dot product and the learning row in C for the host (the 8051's assembly: hal/mcs51/mul.c). */
#include "mul.h"

#if !defined(__SDCC)
int32_t mul_acc;

void acc_start(uint8_t hi)
{
    mul_acc = (int32_t)hi << 8;
}

void mac_c(int16_t a, int16_t b)
{
    mul_acc += (int32_t)a * b;
}

void dot_c(const int16_t *w, const int16_t *x, uint8_t n)
{
    while (n--)
        mul_acc += (int32_t)*w++ * *x++;
}

void upd_c(int16_t *w, int8_t *dw, const int16_t *x, int16_t eg, int16_t lim, uint8_t n, uint8_t s)
{
    while (n--) {
        /* bits 16-s .. 31-s of the rounded product, as the 8051 takes them */
        int32_t p = (int32_t)eg * *x++ + (int32_t)(0x8000L >> s);
        int16_t d = (int16_t)(uint16_t)((uint32_t)p >> (16 - s));
        int32_t sum, dd;
        d = (int16_t)(d + (*dw >> 4) - (*dw >> 6) + (*dw >> 8));
        sum = (int32_t)*w + d;
        sum = sum > lim ? lim : sum < -lim ? -lim : sum;
        dd = sum - *w;
        *dw++ = (int8_t)(dd > 127 ? 127 : dd < -127 ? -127 : dd);
        *w++ = (int16_t)sum;
    }
}
#endif

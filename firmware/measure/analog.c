/* analog.c: 4-20 mA pressure and level inputs: scaling by the corrected eq. (5) and (4), open/short faults. */
#include "hal.h"
#include "params.h"
#include "umath.h"
#include "analog.h"
#include "mul.h"

#define C40_4MA 8184u               /* 4 mA in sums of four conversions x10: 204.6 * 40 */
#define C40_SPAN 32736u             /* 16 mA: (1023 - 204.6) * 40 */

typedef struct {
    uint16_t value;                 /* kPa or L */
    uint8_t bad;                    /* consecutive faulty periods */
    uint8_t good;                   /* consecutive good periods */
    uint8_t ok;                     /* debounced state */
    uint8_t raw_fault;              /* ANALOG_FAULT_* of the last reading */
} chan_t;

static struct {
    chan_t p, l;
    uint32_t kp;                    /* Q16: kPa per (sum*10 - 4 mA) */
    uint32_t kl;                    /* Q16: L per (sum*10 - 4 mA) */
    uint32_t level_f;               /* filtered level, Q4 litres */
    uint8_t level_init;
    uint8_t gen;
} an;

static void analog_derive(void) __reentrant
{
    /* value = c40 * full / 32736; full <= 10000 so full * 65536 fits, divided once here */
    an.kp = ((uint32_t)param_v[P_PSENS_MAX] * 65536UL + C40_SPAN / 2u) / C40_SPAN;
    an.kl = ((uint32_t)param_v[P_TANK_L] * 65536UL + C40_SPAN / 2u) / C40_SPAN;
    an.gen = param_generation;
}

void analog_init(void)
{
    an.p.value = an.l.value = 0;
    an.p.bad = an.p.good = an.l.bad = an.l.good = 0;
    an.p.ok = an.l.ok = 1;
    an.p.raw_fault = an.l.raw_fault = 0;
    an.level_f = 0;
    an.level_init = 0;
    analog_derive();
}

/* sum of four conversions of ch; *sat set when one of them is at full scale */
static uint16_t read4(uint8_t ch, __idata uint8_t *sat) __reentrant
{
    uint16_t s = 0, x;
    uint8_t i;
    *sat = 0;
    for (i = 0; i < 4; i++) {
        x = hal_adc_read(ch);
        if (x >= ANALOG_SAT_COUNTS)
            *sat = 1;
        s += x;
    }
    return s;
}

/* (sum * 10 - 4 mA) * k >> 16, 0 below 4 mA */
static uint16_t scale(uint16_t sum4, uint32_t k) __reentrant
{
    uint32_t c40 = UMUL(sum4, 10u);
    uint32_t v;
    if (c40 <= C40_4MA)
        return 0;
    v = um_mul32x16_shr16(k, (uint16_t)(c40 - C40_4MA));
    return v > 0xFFFFu ? 0xFFFFu : (uint16_t)v;
}

uint16_t analog_kpa_of_sum(uint16_t sum4) __reentrant
{
    if (an.gen != param_generation)
        analog_derive();
    return scale(sum4, an.kp);
}

/* debounce a channel's fault state; returns 1 when this reading is usable */
static uint8_t judge(chan_t __xdata *c, uint8_t fault) __reentrant
{
    c->raw_fault = fault;
    if (fault) {
        c->good = 0;
        if (c->bad < 255)
            c->bad++;
        if (c->bad >= ANALOG_FAULT_PERIODS)
            c->ok = 0;
        return 0;
    }
    c->bad = 0;
    if (c->good < 255)
        c->good++;
    if (!c->ok && c->good >= ANALOG_OK_PERIODS)
        c->ok = 1;
    return c->ok;
}

void analog_step(void) __reentrant
{
    uint16_t s;
    uint8_t sat;
    uint16_t l;

    if (an.gen != param_generation)
        analog_derive();

    s = read4(HAL_ADC_PRESSURE, (__idata uint8_t *)&sat);   /* sat: on this function's stack */
    if (judge(&an.p, s < ANALOG_OPEN_SUM ? ANALOG_FAULT_OPEN : sat ? ANALOG_FAULT_SHORT : 0))
        an.p.value = scale(s, an.kp);

    s = read4(HAL_ADC_LEVEL, (__idata uint8_t *)&sat);
    if (judge(&an.l, s < ANALOG_OPEN_SUM ? ANALOG_FAULT_OPEN : 0)) {
        l = scale(s, an.kl);
        /* the tank's surface moves with the machine: first order, 0.4 s */
        if (!an.level_init) {
            an.level_f = (uint32_t)l << 4;
            an.level_init = 1;
        } else {
            an.level_f = an.level_f - (an.level_f >> 2) + ((uint32_t)l << 2);
        }
        an.l.value = (uint16_t)((an.level_f + 8u) >> 4);
    }
}

uint16_t analog_pressure_kpa(void)
{
    return an.p.value;
}

uint16_t analog_tank_l(void)
{
    return an.l.value;
}

uint8_t analog_pressure_ok(void)
{
    return an.p.ok;
}

uint8_t analog_level_ok(void)
{
    return an.l.ok;
}

#if FW_PROBES
uint8_t analog_pressure_fault(void)
{
    return an.p.raw_fault;
}

uint8_t analog_level_fault(void)
{
    return an.l.raw_fault;
}
#endif

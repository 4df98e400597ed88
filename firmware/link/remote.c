/* remote.c: Raven's remote-computer strings on the serial link: rate change, calibration and data requests (remote.h). */
#include "hal.h"
#include "params.h"
#include "app.h"
#include "target.h"
#include "totals.h"
#include "umath.h"
#include "linebuf.h"
#include "remote.h"

/* the lines queued, sent lowest bit first */
#define RV_AR 0x01
#define RV_C1 0x02
#define RV_C2 0x04
#define RV_C3 0x08
#define RV_D1 0x10
#define RV_D2 0x20
#define RV_D3 0x40
static uint8_t rv_due;

/* ---- parsing ------------------------------------------------------------------------------ */
static uint8_t starts(const char *s, const char *w) __reentrant
{
    while (*w)
        if (*s++ != *w++)
            return 0;
    return 1;
}

const char *remote_command(const char *line) __reentrant
{
    uint32_t v = 0;
    uint8_t n = 0;
    if (!param_v[P_REMOTE])
        return "REMOTE";
    if (!starts(line, "$R,"))
        return "CMD";
    line += 3;
    if (starts(line, "RC,")) {
        for (line += 3; *line >= '0' && *line <= '9'; line++) {
            v = v * 10u + (uint8_t)(*line - '0');
            if (++n > 5)
                return "NUM";
        }
        if (n == 0 || (*line && *line != ','))
            return "NUM";
        if (*line)
            return "ARG";           /* one product: no rate 2 or 3 */
        if (v > 65535UL)
            return "NUM";
        if (!target_remote_rate((uint16_t)v))
            return "WINDOW";
        rv_due |= RV_AR;
        return 0;
    }
    if ((starts(line, "CR") || starts(line, "DR")) && line[2] == 0) {
        rv_due |= line[0] == 'C' ? RV_C1 | RV_C2 | RV_C3 : RV_D1 | RV_D2 | RV_D3;
        return 0;
    }
    if (starts(line, "CR") || starts(line, "DR"))
        return "ARG";
    return "CMD";
}

void remote_tick(void)
{
    if (param_v[P_REMOTE])
        rv_due |= RV_AR;
}

/* ---- composing ------------------------------------------------------------------------------ */
/* ',' and v / 10^drop */
static void put_d(uint32_t v, uint8_t drop) __reentrant
{
    serial_put_c(',');
    serial_put_u32_div(v, drop);
}
#define put_n(v) put_d((v), 0)

/* the actual rate, L/ha x10: flow x 600000 / (speed x width), 0 when not spraying */
static uint16_t actual_x10(void) __reentrant
{
    uint32_t d = (uint32_t)app_status.speed_kmh_x100 * target_width_cm(), r;
    if (!app_status.spraying || app_status.flow_lpm_x100 <= 0 || d == 0)
        return 0;
    r = um_muldiv((uint32_t)app_status.flow_lpm_x100 * 10u, 60000u, d);
    return r > 65535UL ? 65535u : (uint16_t)r;
}

uint8_t remote_next(void) __reentrant
{
    uint8_t bit, s, sw = 0x80;
    const totals_t *t = totals_get();
    uint16_t w;

    if (!rv_due)
        return 0;
    for (bit = 1; !(rv_due & bit); bit <<= 1)
        ;
    rv_due &= (uint8_t)~bit;
    serial_put_s(RAVEN_ID);
    switch (bit) {
    case RV_AR:
        serial_put_s("AR");
        put_n(actual_x10());
        break;
    case RV_C1:                     /* booms 1-7 on, bit 7 set; auto: rate 1 */
        serial_put_s("C1");
        for (s = 0; s < 7u && s < (uint8_t)param_v[P_SECTIONS]; s++)
            if (hal_sections() & (1u << s))
                sw |= (uint8_t)(1u << s);
        put_n(sw);
        put_n(app_status.manual ? 0x80u : 0x88u);
        for (s = 0; s < 6u; s++) {
            w = (uint16_t)target_section_nozzles(s) * param_v[P_SPACING];
            put_n(w > 9999u ? 9999u : w);      /* boom widths, cm */
        }
        put_n(param_v[P_WHEEL]);                /* 0.1 mm a pulse */
        break;
    case RV_C2:
        serial_put_s("C2");
        put_n(param_v[P_METER_K]);              /* 0.1 pulse a litre */
        put_n(0);
        break;
    case RV_C3:
        serial_put_s("C3");
        put_n(param_v[P_RAVEN_CAL]);
        put_n(target_rate_x10());
        put_n(0);
        break;
    case RV_D1:                     /* areas, 0.1 ha: lifetime, job */
        serial_put_s("D1");
        put_d(t->life_m2, 3);
        put_d(t->job_dm2, 5);
        break;
    case RV_D2:                     /* volumes, L */
        serial_put_s("D2");
        put_d(t->life_ml, 3);
        put_d(t->job_ml, 3);
        break;
    default:                        /* tank L, distance since power-up m */
        serial_put_s("D3");
        put_n(app_status.tank_l);
        put_n(um_muldiv(app_wheel_pulses(), param_v[P_WHEEL], 10000UL));
        break;
    }
    return 1;
}

/* remote.c: Raven's remote-computer strings on the serial link: rate change, calibration and data requests (remote.h). */
#include "hal.h"
#include "params.h"
#include "ops.h"
#include "target.h"
#include "totals.h"
#include "umath.h"
#include "linebuf.h"
#include "remote.h"
#include "mul.h"

/* the lines queued, sent lowest bit first */
#define RV_AR 0x01
#define RV_C1 0x02
#define RV_C2 0x04
#define RV_C3 0x08
#define RV_D1 0x10
#define RV_D2 0x20
#define RV_D3 0x40
static uint8_t rv_due;

const __code char link_e_cmd[] = "CMD", link_e_arg[] = "ARG", link_e_num[] = "NUM";

/* ---- parsing ------------------------------------------------------------------------------ */
const __code char *remote_command(const __xdata char *line) __reentrant
{
    uint16_t v = 0;
    uint8_t n = 0, c;
    if (param_v[P_REMOTE] != REMOTE_RAVEN)
        return "REMOTE";
    if (line[1] != 'R' || line[2] != ',')      /* line[0] is '$' (serial.c) */
        return link_e_cmd;
    c = (uint8_t)line[3];
    if ((c == 'C' || c == 'D') && line[4] == 'R') {
        if (line[5])
            return link_e_arg;
        rv_due |= c == 'C' ? RV_C1 | RV_C2 | RV_C3 : RV_D1 | RV_D2 | RV_D3;
        return 0;
    }
    if (c != 'R' || line[4] != 'C' || line[5] != ',')
        return link_e_cmd;
    for (line += 6; (c = (uint8_t)(*line - '0')) <= 9u; line++, n++) {
        if (v > 6553u || (v == 6553u && c > 5u))
            return link_e_num;      /* beyond 65535 */
        v = v * 10u + c;
    }
    if (*line == ',')
        return n ? link_e_arg : link_e_num;     /* one product: no rate 2 or 3 */
    if (n == 0 || *line)
        return link_e_num;
    if (!target_remote_rate(v))
        return "WINDOW";
    rv_due |= RV_AR;
    return 0;
}

void remote_tick(void)
{
    if (param_v[P_REMOTE] == REMOTE_RAVEN)
        rv_due |= RV_AR;
}

/* ---- composing ------------------------------------------------------------------------------ */
/* Each line: its two letters and its values: V_PARAM | a parameter's id, V_TOTAL | a field of
 * totals_t (0 job_dm2, 1 job_ml, 2 life_m2, 3 life_ml), or one of the others */
#define V_PARAM 0x80
#define V_TOTAL 0x40
enum { V_END, V_AR, V_SW1, V_SW2, V_RATE, V_TANK, V_DIST, V_ZERO, V_B1 };
static const __code uint8_t rv_lines[7][11] = {
    {'A', 'R', V_AR},
    {'C', '1', V_SW1, V_SW2, V_B1, V_B1 + 1, V_B1 + 2, V_B1 + 3, V_B1 + 4, V_B1 + 5, V_PARAM | P_WHEEL},
    {'C', '2', V_PARAM | P_METER_K, V_ZERO},
    {'C', '3', V_PARAM | P_RAVEN_CAL, V_RATE, V_ZERO},
    {'D', '1', V_TOTAL | 2, V_TOTAL | 0},   /* areas 0.1 ha: lifetime m^2 / 1000, job dm^2 / 100000 */
    {'D', '2', V_TOTAL | 3, V_TOTAL | 1},   /* volumes L: ml / 1000 */
    {'D', '3', V_TANK, V_DIST},             /* tank L, distance since power-up m */
};

/* the actual rate, L/ha x10: flow x 6000 / (speed x width / 100), 0 when not spraying */
static uint32_t actual_x10(void) __reentrant
{
    uint16_t w = target_width_cm();
    uint32_t d = UMUL(app_status.speed_kmh_x100, w) / 100u;
    if (!app_status.spraying || app_status.flow_lpm_x100 <= 0 || d == 0)
        return 0;
    return UMUL(app_status.flow_lpm_x100, 6000u) / d;     /* flow > 0 */
}

static uint32_t value(uint8_t k) __reentrant
{
    uint16_t w;
    if (k & V_PARAM)
        return param_v[k & 0x7Fu];
    if (k & V_TOTAL)
        return (&totals.job_dm2)[k & 3u];
    switch (k) {
    case V_AR:
        return actual_x10();
    case V_SW1:                     /* sections 1-7 on, bit 7 set */
        return 0x80u | (hal_sections() & 0x7Fu & ((1u << param_v[P_SECTIONS]) - 1u));
    case V_SW2:                     /* auto: rate 1 */
        return app_status.manual ? 0x80u : 0x88u;
    case V_RATE:
        return target_rate_x10();
    case V_TANK:
        return app_status.tank_l;
    case V_DIST:
        return um_muldiv(ops_wheel_pulses(), param_v[P_WHEEL], 10000UL);
    case V_ZERO:
        return 0;
    default:                        /* boom widths, cm */
        w = (uint16_t)target_section_nozzles(k - V_B1) * param_v[P_SPACING];
        return w > 9999u ? 9999u : w;
    }
}

uint8_t remote_next(void) __reentrant
{
    uint8_t line, i, k;

    if (!rv_due)
        return 0;
    for (line = 0, k = 1; !(rv_due & k); line++)
        k <<= 1;
    rv_due &= (uint8_t)~k;
    serial_put_s(RAVEN_ID);
    serial_put_c(rv_lines[line][0]);
    serial_put_c(rv_lines[line][1]);
    for (i = 2; i < 11u && (k = rv_lines[line][i]) != V_END; i++) {
        serial_put_c(',');
        serial_put_u32_div(value(k), (k & V_TOTAL) && !(k & V_PARAM) ? (k == V_TOTAL ? 5u : 3u) : 0u);
    }
    return 1;
}

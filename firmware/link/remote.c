/* remote.c: the serial link as a Raven console's: rate change, calibration and data requests, the data logger's lines (remote.h). */
#include "hal.h"
#include "params.h"
#include "ops.h"
#include "target.h"
#include "totals.h"
#include "umath.h"
#include "linebuf.h"
#include "remote.h"
#include "mul.h"
#include "linecheck.h"

/* the lines queued, sent lowest bit first: so a trigger's AR, D1, D2, D3, TD and a switch
 * change's D1, D2, D3, TD, C1, C2, C3 go in the manuals' order */
#define RV_AR 0x01
#define RV_D 0x1E                   /* D1, D2, D3, TD */
#define RV_C 0xE0                   /* C1, C2, C3 */
static struct {
    uint8_t due;
    uint8_t gen;                    /* param_generation at the last look (remote_tick) */
    uint8_t sw;                     /* the switch bytes' changing bits then (switches()) */
    uint8_t periods;                /* trigger periods since power-up then, modulo 256 */
} rv;
static __bit rv_primed;             /* the marks above hold (Remote on since the last look) */

const __code char link_e_cmd[] = "CMD", link_e_arg[] = "ARG", link_e_num[] = "NUM";

/* ---- parsing ------------------------------------------------------------------------------ */
uint8_t remote_command(const __xdata char *line) __reentrant
{
    uint16_t v = 0, other;
    uint8_t i, given = 0, c;
    if (line[1] != 'R' || line[2] != ',')      /* line[0] is '$' (serial.c) */
        return 0;
    c = (uint8_t)line[3];
    if ((c == 'C' || c == 'D') && line[4] == 'R' && !line[5]) {
        rv.due |= c == 'C' ? RV_C : RV_D;
        return 1;
    }
    if (c != 'R' || line[4] != 'C' || line[5] != ',')
        return 0;
    /* rate 1, then the other products' (read, not used): an empty field changes nothing */
    for (line += 6, i = 0;; line++, i++) {
        if (*line != ',' && *line) {
            if (!(line = line_number(line, (__idata uint16_t *)(i ? &other : &v), ',')))
                return 0;           /* neither empty nor a number */
            given |= i == 0;
        }
        if (!*line)
            break;
    }
    if (!given)
        return 1;
    if (!target_remote_rate(v))
        return 0;
    if (param_v[P_LOG_EVERY])
        rv.due |= RV_C;             /* rate 1's cal changed */
    return 1;
}

/* ---- the lines and their values ----------------------------------------------------------- */
/* Each line: its two letters and its fields: V_PARAM | a parameter's id, V_TOTAL | a field of
 * totals_t (0 job_dm2, 1 job_ml, 2 life_m2, 3 life_ml), or one of the others */
#define V_PARAM 0x80
#define V_TOTAL 0x40
enum { V_END, V_AR, V_SW1, V_SW2, V_RATE, V_TANK, V_DIST, V_ZERO, V_TD, V_B1 };
#define RV_FIELDS 9
static const __code uint8_t rv_lines[8][2 + RV_FIELDS] = {
    {'A', 'R', V_AR},
    {'D', '1', V_TOTAL | 2, V_TOTAL | 0},
    {'D', '2', V_TOTAL | 3, V_TOTAL | 1},
    {'D', '3', V_TANK, V_DIST},
    {'T', 'D', V_TD},
    {'C', '1', V_SW1, V_SW2, V_B1, V_B1 + 1, V_B1 + 2, V_B1 + 3, V_B1 + 4, V_B1 + 5, V_PARAM | P_WHEEL},
    {'C', '2', V_PARAM | P_METER_K, V_ZERO},
    {'C', '3', V_PARAM | P_RAVEN_CAL, V_RATE, V_ZERO},
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

/* the distance since power-up, m */
static uint32_t metres(void) __reentrant
{
    return um_muldiv(ops_wheel_pulses(), param_v[P_WHEEL], 10000UL);
}

static uint32_t value(uint8_t k) __reentrant
{
    if (k & V_PARAM)
        return param_v[k & 0x7Fu];
    if (k & V_TOTAL)
        return (&totals.job_dm2)[k & 3u];
    switch (k) {
    case V_AR:
        return actual_x10();
    case V_SW1:                     /* booms 1-6 on (bit 0 = boom 1), bit 7 set */
        return 0x80u | (hal_sections() & 0x3Fu & ((1u << param_v[P_SECTIONS]) - 1u));
    case V_SW2:                     /* bit 7 set; in auto the rate in use: rate 1 (REMOTE_SW2_*) */
        return app_status.manual ? 0x80u : 0x80u | REMOTE_SW2_RATE1;
    case V_RATE:
        return target_rate_x10();
    case V_TANK:
        return app_status.tank_l;
    case V_DIST:
        return metres();
    case V_B1: case V_B1 + 1: case V_B1 + 2: case V_B1 + 3: case V_B1 + 4: case V_B1 + 5:
        return UMUL(target_section_nozzles(k - V_B1), param_v[P_SPACING]);     /* cm */
    default:                        /* V_ZERO, V_TD */
        return 0;
    }
}

/* How a field is written: its value's decimals, and the decimals sent (rates, areas and the
 * cal numbers with one, as the Hiniker 8605's emulation of a Raven 450 documents) */
static void put_field(uint8_t k) __reentrant
{
    uint8_t dec = 0, keep = 0;
    if (k == V_TD) {                /* no clock and no field reference (docs/REMOTE.md) */
        serial_put_s("00:00,00/00/00,0");
        return;
    }
    if (k == V_AR || k == V_RATE || k == (V_PARAM | P_WHEEL) || k == (V_PARAM | P_METER_K))
        dec = keep = 1;
    else if (k == (V_TOTAL | 2))    /* lifetime m^2 as ha */
        dec = 4, keep = 1;
    else if (k == (V_TOTAL | 0))    /* job dm^2 as ha */
        dec = 6, keep = 1;
    else if (k & V_TOTAL)           /* ml as whole litres */
        dec = 3;
    serial_put_num(value(k), dec, keep);
}

/* ---- the data logger ------------------------------------------------------------------------ */
/* The console's pushes, looked for once a second (Log every not 0: the data logger on): every
 * Log every metres or seconds since power-up (Log unit) AR, D1, D2, D3, TD; after a setting
 * changed C1, C2, C3; after a switch byte changed D1, D2, D3, TD, C1, C2, C3. The first look
 * after Remote comes on only takes the marks. */
void remote_tick(void) __reentrant
{
    uint8_t sw, n;
    uint16_t every = param_v[P_LOG_EVERY];
    if (!param_v[P_REMOTE])
        rv.due = 0;                 /* nothing owed to a Raven console any more */
    if (!param_v[P_REMOTE] || !every) {
        rv_primed = 0;
        return;
    }
    /* the bits of the switch bytes that change: booms 1-6, rates 1 and 2 */
    sw = (uint8_t)((value(V_SW1) & 0x3Fu) | (value(V_SW2) & 0x18u) << 3);
    n = (uint8_t)((param_v[P_LOG_UNIT] ? hal_ms() / 1000u : metres()) / every);   /* trigger periods */
    if (rv_primed) {
        if (sw != rv.sw)
            rv.due |= RV_D | RV_C;
        else if (rv.gen != param_generation)
            rv.due |= RV_C;
        if (n != rv.periods)
            rv.due |= RV_AR | RV_D;
    }
    rv.sw = sw;
    rv.gen = param_generation;
    rv.periods = n;
    rv_primed = 1;
}

/* ---- composing ------------------------------------------------------------------------------ */
uint8_t remote_next(void) __reentrant
{
    uint8_t line, i, k;

    if (!rv.due)
        return 0;
    for (line = 0, k = 1; !(rv.due & k); line++)
        k <<= 1;
    rv.due &= (uint8_t)~k;
    serial_put_s(RAVEN_ID);
    serial_put_c(rv_lines[line][0]);
    serial_put_c(rv_lines[line][1]);
    for (i = 2; i < 2 + RV_FIELDS && (k = rv_lines[line][i]) != V_END; i++) {
        serial_put_c(',');
        put_field(k);
    }
    return 1;
}

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
#include "units.h"

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
    if (!target_remote_rate(unit_in(P_RATE, v)))    /* in the console's units (gal/acre x10 ..) */
        return 0;
    if (param_v[P_LOG_EVERY])
        rv.due |= RV_C;             /* rate 1's cal changed */
    return 1;
}

/* ---- the lines and their values ----------------------------------------------------------- */
/* Each line: its two letters and its fields, each a source (S_*, its value: value()) and how it
 * is written in metric units (F_*: the divisor, rv_div, and the decimals sent) */
enum { S_END, S_AR, S_SW1, S_SW2, S_RATE, S_TANK, S_DIST, S_ZERO, S_TD, S_WHEEL, S_METER, S_VALVE,
       S_JOB_A, S_JOB_V, S_LIFE_A, S_LIFE_V, S_B1 };      /* S_JOB_A..S_LIFE_V: totals_t's order */
#define F_WHOLE 0x00
#define F_TENTH 0x20                /* x10 values with their decimal point: 150.0 */
#define F_HA_M2 0x40                /* m^2 as ha, one decimal (truncated) */
#define F_L_ML 0x60                 /* ml as whole litres */
static const __code uint16_t rv_div[4] = {1u, 1u, 1000u, 1000u};
#define RV_FIELDS 9
static const __code uint8_t rv_lines[8][2 + RV_FIELDS] = {
    {'A', 'R', F_TENTH | S_AR},
    {'D', '1', F_HA_M2 | S_LIFE_A, F_HA_M2 | S_JOB_A},
    {'D', '2', F_L_ML | S_LIFE_V, F_L_ML | S_JOB_V},
    {'D', '3', S_TANK, S_DIST},
    {'T', 'D', S_TD},
    {'C', '1', S_SW1, S_SW2, S_B1, S_B1 + 1, S_B1 + 2, S_B1 + 3, S_B1 + 4, S_B1 + 5, F_TENTH | S_WHEEL},
    {'C', '2', F_TENTH | S_METER, S_ZERO},
    {'C', '3', S_VALVE, F_TENTH | S_RATE, S_ZERO},
};

/* Each source's unit class in US and turf units (units.h): the calibration numbers too in the
 * console's own units, as a Raven console's */
static const __code uint8_t rv_class[S_B1 + 6] = {
    CU_NONE, CU_RATE, CU_NONE, CU_NONE, CU_RATE, CU_VOL, CU_FEET, CU_NONE, CU_NONE, CU_INCH100,
    CU_PER_GAL, CU_NONE, CU_AREA, CU_ML, CU_AREA, CU_ML,
    CU_INCH, CU_INCH, CU_INCH, CU_INCH, CU_INCH, CU_INCH,       /* the booms */
};

/* the actual rate, L/ha x10: flow x 6000 / (speed x width / 100), 0 when not spraying */
static uint32_t actual_x10(void) __reentrant
{
    uint16_t w = target_width_cm();
    uint32_t d = UMUL(app_status.in.speed_kmh_x100, w) / 100u;
    if (!app_status.spraying || app_status.in.flow_lpm_x100 <= 0 || d == 0)
        return 0;
    return UMUL(app_status.in.flow_lpm_x100, 6000u) / d;     /* flow > 0 */
}

/* the distance since power-up, m */
static uint32_t metres(void) __reentrant
{
    return um_muldiv(ops_wheel_pulses(), param_v[P_WHEEL], 10000UL);
}

static uint32_t value(uint8_t k) __reentrant
{
    switch (k) {
    case S_AR:
        return actual_x10();
    case S_SW1:                     /* booms 1-6 on (bit 0 = boom 1), bit 7 set */
        return 0x80u | (hal_sections() & 0x3Fu & ((1u << param_v[P_SECTIONS]) - 1u));
    case S_SW2:                     /* bit 7 set; in auto the preset in use, rate 1 or rate 2 (REMOTE_SW2_*) */
        return app_status.manual ? 0x80u : param_v[P_PRESET] ? 0x80u | REMOTE_SW2_RATE2 : 0x80u | REMOTE_SW2_RATE1;
    case S_RATE:
        return target_rate_x10();
    case S_TANK:
        return app_status.tank_l;
    case S_DIST:
        return metres();
    case S_WHEEL:
        return param_v[P_WHEEL];
    case S_METER:
        return param_v[P_METER_K];
    case S_VALVE:
        return param_v[P_RAVEN_CAL];
    case S_ZERO:
    case S_TD:
        return 0;
    case S_JOB_A:                   /* m^2, as the lifetime's */
        return totals_job_m2();
    default:
        if (k < S_B1)               /* the totals */
            return (&totals.job_dm2)[k - S_JOB_A];
        return UMUL(target_section_nozzles(k - S_B1), param_v[P_SPACING]);     /* cm */
    }
}

/* A field as it is written, its decimal point sent as the Hiniker 8605's emulation of a Raven
 * 450 documents: in metric units rates, areas and the cal numbers with one decimal; in US or
 * turf units each in the console's unit and decimals (units.c) */
static void put_field(uint8_t k) __reentrant
{
    uint8_t f = k >> 5, c;
    const __code unit_t *u;
    k &= 0x1Fu;
    if (k == S_TD)                  /* no clock and no field reference (docs/REMOTE.md) */
        serial_put_s("00:00,00/00/00,0");
    else if ((u = unit_of(c = rv_class[k])) != 0)      /* US or turf: the console's units */
        serial_put_num(unit_q(value(k), c), u->dec);
    else
        serial_put_num(value(k) / rv_div[f], f && f < 3u);
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
    if (!REMOTE_IS_RAVEN(param_v[P_REMOTE]))
        rv.due = 0;                 /* nothing owed to a Raven console any more */
    if (!REMOTE_IS_RAVEN(param_v[P_REMOTE]) || !every) {
        rv_primed = 0;
        return;
    }
    /* the bits of the switch bytes that change: booms 1-6, rates 1 and 2 */
    sw = (uint8_t)((value(S_SW1) & 0x3Fu) | (value(S_SW2) & 0x18u) << 3);
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
    for (i = 2; i < 2 + RV_FIELDS && (k = rv_lines[line][i]) != S_END; i++) {
        serial_put_c(',');
        put_field(k);
    }
    return 1;
}

/* diag.c: the alarm rules (tank, pump, leak, clog, meter, speed, sensors, pressure, off-rate, valve) and their texts. */
#include "params.h"
#include "umath.h"
#include "app.h"
#include "analog.h"
#include "flow.h"
#include "speed.h"
#include "target.h"
#include "valve.h"
#include "diag.h"

static const char * const __code codes[AL_COUNT] = {
    "TANK_LOW", "PUMP_DRY", "LEAK", "CLOG", "METER_LOST", "SPEED_LOST", "PSENS_FAULT",
    "LSENS_FAULT", "OVERPRESSURE", "OFF_RATE", "VALVE_STOP", "METER_NOISE", "WHEEL_NOISE",
    "INTERNAL"
};
/* LCD texts: at most 16 characters */
static const char * const __code texts[AL_COUNT] = {
    "Tank low: stop",
    "Pump dry:PTO off",
    "Leak after meter",
    "Nozzles clogged",
    "Flowmeter lost",
    "Speed sens lost",
    "P sensor fault",
    "Level sens fault",
    "Over-pressure",
    "Rate off target",
    "Valve at stop",
    "Flowmeter noise",
    "Wheel noise",
    "Internal fault"
};

static struct {
    uint32_t knoz;                  /* Q16: L/min x100 per 256 sqrt(kPa): n Q3 / sqrt(300) / 256 */
    uint32_t nq;                    /* n * Q3 (L/min x100 at 3 bar) */
    uint16_t offrate_cnt;
    uint16_t meter_glitches, wheel_glitches;    /* counts seen last period */
    uint16_t alarms;
    uint8_t cnt[AL_COUNT];
    uint8_t meter_noise, wheel_noise;
    uint8_t meter_suspect;                      /* this period: the meter under a quarter of the nozzle model */
    uint8_t nozzles;
    uint8_t gen;
} dg;

void diag_init(void)
{
    uint8_t i;
    for (i = 0; i < AL_COUNT; i++)
        dg.cnt[i] = 0;
    dg.alarms = 0;
    dg.offrate_cnt = 0;
    dg.meter_noise = dg.wheel_noise = 0;
    dg.meter_suspect = 0;
    dg.meter_glitches = flow_glitches();
    dg.wheel_glitches = speed_glitches();
    dg.nozzles = 0;
    dg.gen = (uint8_t)(param_generation - 1u);
    diag_set_nozzles(0);
}

void diag_set_nozzles(uint8_t open_nozzles) __reentrant
{
    if (open_nozzles == dg.nozzles && dg.gen == param_generation)
        return;
    dg.nozzles = open_nozzles;
    dg.gen = param_generation;
    dg.nq = (uint32_t)open_nozzles * param_v[P_NOZZLE_Q3];
    /* 65536 / (256 sqrt(300)) = 14.7802 = 60539 / 4096 */
    dg.knoz = um_mul32x16_shr16(dg.nq << 4, 60539u);
}

int16_t diag_nozzle_flow_x100(uint16_t pressure_kpa, uint8_t open_nozzles) __reentrant
{
    uint32_t dp, q;
    diag_set_nozzles(open_nozzles);
    if (pressure_kpa <= DIAG_P_CHECK_KPA)
        return 0;
    dp = pressure_kpa - DIAG_P_CHECK_KPA;
    if (dp > 65535u)
        dp = 65535u;
    q = um_mul32x16_shr16(dg.knoz, um_sqrt32(dp << 16));    /* sqrt(dp << 16) = 256 sqrt(dp) */
    return q > 32767u ? 32767 : (int16_t)q;
}

uint16_t diag_nozzle_pressure_kpa(int16_t flow_x100, uint8_t open_nozzles) __reentrant
{
    uint32_t r, p;
    diag_set_nozzles(open_nozzles);
    if (dg.nq == 0 || flow_x100 <= 0)
        return flow_x100 > 0 ? 0xFFFFu : 0;
    r = um_muldiv((uint32_t)flow_x100, 4096u, dg.nq);      /* Q12: q / (n Q3) */
    if (r > 65535u)
        return 0xFFFFu;
    r = (r * r) >> 12;                                      /* Q12 */
    p = DIAG_P_CHECK_KPA + ((r * 300u + 2048u) >> 12);
    return p > 65535u ? 0xFFFFu : (uint16_t)p;
}

void diag_internal_fault(void)
{
    dg.alarms |= 1u << AL_INTERNAL;
}

/* One timed rule: `set` for `need` periods raises the alarm, `clr` for DIAG_CLEAR_PERIODS
 * clears it; neither (the rule cannot be judged now) holds the state. */
static void rule(uint8_t bit, uint8_t set, uint8_t clr, uint8_t need) __reentrant
{
    uint16_t m = 1u << bit;
    uint8_t active = (dg.alarms & m) != 0;
    if (!active ? set : clr) {
        if (dg.cnt[bit] < 255)
            dg.cnt[bit]++;
        if (dg.cnt[bit] >= (active ? DIAG_CLEAR_PERIODS : need)) {
            dg.alarms ^= m;
            dg.cnt[bit] = 0;
        }
    } else {
        dg.cnt[bit] = 0;
    }
}

/* leaky score of pulse glitches: +20 a glitch, -1 a period; above 60 the alarm is raised */
static uint8_t noise(uint8_t *score, uint8_t glitch) __reentrant
{
    if (glitch)
        *score = (uint8_t)(*score > 235 ? 255 : *score + 20);
    else if (*score)
        (*score)--;
    return *score;
}

uint16_t diag_step(uint8_t settled, uint8_t p_watch) __reentrant
{
    uint16_t tmin = param_v[P_TANK_MIN];
    uint16_t tank = app_status.tank_l;
    uint16_t p = app_status.pressure_kpa;
    int16_t meter = flow_lpm_x100();
    int16_t target = app_status.target_lpm_x100;
    uint8_t psens = analog_pressure_ok(), lsens = analog_level_ok();
    uint8_t refill = lsens && tank >= tmin + (param_v[P_TANK_L] >> 6) + 1u;
    uint8_t judge, g;
    uint16_t pexp;
    uint32_t p100, x;
    int16_t qp;

    /* tank and pump */
    x = (uint32_t)tank * 100u;
    rule(AL_TANK_LOW, lsens && tank < tmin, refill, DIAG_TANK_PERIODS);
    rule(AL_PUMP_DRY, lsens && x <= param_v[P_TANK_L], refill && x > param_v[P_TANK_L],
         DIAG_TANK_PERIODS);

    /* sensors (debounced by analog.c) */
    rule(AL_PSENS, !psens, psens, 1);
    rule(AL_LSENS, !lsens, lsens, 1);

    /* over-pressure, 5 % hysteresis: while spraying or with the bypass parked open (at power-up
     * the pump may push against a bypass left closed until the parking opens it: the relief
     * valve's job, not a fault) */
    rule(AL_OVERPRESSURE, p_watch && psens && p > param_v[P_P_MAX],
         !psens || (uint32_t)p * 20u < (uint32_t)param_v[P_P_MAX] * 19u, DIAG_OVERP_PERIODS);

    /* flow meter lost: the nozzles pass qp at this pressure, the meter sees under a quarter */
    qp = diag_nozzle_flow_x100(p, dg.nozzles);
    judge = settled && psens;
    dg.meter_suspect = judge && qp >= DIAG_MODEL_MIN_X100 && (int32_t)meter * 4 < qp;
    rule(AL_METER_LOST, dg.meter_suspect,
         meter >= DIAG_MODEL_MIN_X100 / 2 && (int32_t)meter * 2 >= qp, DIAG_METER_PERIODS);

    /* leak and clog: the pressure against the nozzle model's pressure for the metered flow */
    judge = judge && !(dg.alarms & (1u << AL_METER_LOST)) && meter >= DIAG_MODEL_MIN_X100 && dg.nq;
    pexp = diag_nozzle_pressure_kpa(meter, dg.nozzles);
    p100 = (uint32_t)p * 100u;
    x = (uint32_t)pexp * (100u - param_v[P_PDEV]);
    rule(AL_LEAK, judge && p100 < x, judge && p100 >= x, DIAG_PDEV_PERIODS);
    x = (uint32_t)pexp * (100u + param_v[P_PDEV]);
    rule(AL_CLOG, judge && p100 > x, judge && p100 <= x, DIAG_PDEV_PERIODS);

    /* speed sensor lost: pulses stopped for 2 s after working speed (a tractor that slows
     * down keeps making pulses; one that stops dead from working speed inside one pulse
     * distance is the false alarm this rule accepts) */
    g = target_speed_given();
    rule(AL_SPEED_LOST, !g && speed_quiet_periods() >= DIAG_SPEED_PERIODS &&
                            speed_at_last_pulse_x100() >= param_v[P_MINF_SPEED] * 10u,
         g || speed_quiet_periods() < DIAG_SPEED_PERIODS / 2u, 1);

    /* off-rate: |q - q1| > P_OFFRATE % of q1 for P_OFFRATE_S */
    judge = !app_status.manual && settled && target > 0;
    qp = app_status.flow_lpm_x100 - target;
    p100 = (uint32_t)(qp < 0 ? -(int32_t)qp : qp) * 100u;
    x = (uint32_t)param_v[P_OFFRATE] * (uint16_t)target;
    if (!(dg.alarms & (1u << AL_OFFRATE))) {
        if (judge && p100 > x) {
            if (++dg.offrate_cnt >= param_v[P_OFFRATE_S] * 10u) {
                dg.alarms |= 1u << AL_OFFRATE;
                dg.offrate_cnt = 0;
            }
        } else {
            dg.offrate_cnt = 0;
        }
    } else {
        rule(AL_OFFRATE, 0, !judge || p100 <= x, 1);
    }

    /* the valve refused at a stop */
    g = valve_refused();
    rule(AL_VALVE_STOP, g, !g, DIAG_VALVE_PERIODS);

    /* pulse noise */
    g = flow_glitches() != dg.meter_glitches;
    dg.meter_glitches = flow_glitches();
    rule(AL_METER_NOISE, noise(&dg.meter_noise, g) > 60, dg.meter_noise == 0, 1);
    g = speed_glitches() != dg.wheel_glitches;
    dg.wheel_glitches = speed_glitches();
    rule(AL_WHEEL_NOISE, noise(&dg.wheel_noise, g) > 60, dg.wheel_noise == 0, 1);

    return dg.alarms;
}

uint16_t diag_alarms(void)
{
    return dg.alarms;
}

const char *diag_code(uint8_t bit)
{
    return bit < AL_COUNT ? codes[bit] : "";
}

const char *diag_text(uint8_t bit)
{
    return bit < AL_COUNT ? texts[bit] : "";
}

uint8_t diag_meter_suspect(void)
{
    return dg.meter_suspect;
}

/* ctl.c: the four flow controllers behind one interface, dispatched by a switch, states in one union. */
#include "ctl.h"
#include "params.h"

/*
 * Units and the mapping of the paper's incremental PID, eq. (7), onto this valve
 * ------------------------------------------------------------------------------
 * The paper's u(k) is read as the bypass valve position (a fraction of its stroke): the
 * valve is an integrating actuator, so the increment du(k) = kp*(e-e1) + ki*e + kd*(e-2e1+e2)
 * is what the motor must do in one period, and u itself is kept by the valve, not by us.
 *   - the error is normalised by CTL_FLOW_SCALE = 100 L/min per full stroke (about the pump
 *     flow: the open bypass takes it all), so e = 1.0 means 100 L/min;
 *   - one period (APP_PERIOD_MS = 100 ms) at full duty moves the valve 1/T_travel of its
 *     stroke, T_travel = P_VALVE_TRAVEL in 0.1 s = periods, so drive = du * P_VALVE_TRAVEL.
 * With the paper's kp 1.2, ki 0.2, kd 0.8 and the default 4 s valve: 1 L/min of error held for
 * one period asks for 0.2 * 0.01 * 40 = 0.08 duty (the integral time is 0.5 s).
 * Signs: e = target - measured; positive drive = more boom flow (bypass toward closed).
 *
 * The common output stage (all four controllers): the valve does not move below 20 % duty
 * (stiction), so increments smaller than that are accumulated and sent as one 20 % pulse when
 * they add up (pulse accumulation, as floating-valve controllers do): the valve gets the
 * movement the law asked for, later. Requests beyond full duty are cut (anti-windup: the valve
 * is the integrator, the excess is dropped, never stored), and nothing is asked or
 * accumulated against an end stop that valve_limit reports.
 *
 * Control step cost: see `make bench` (tests/target/tt_ctl_*.c).
 */

#define CTL_STICTION Q15(0.2)       /* the valve's break-away duty */
#define CTL_E_MAX 16000             /* errors clamped to +-160 L/min (x100) */

/* ---- state shared by all controllers -------------------------------------------------- */
static uint8_t ctl_id = CTL_BEST;
static uint8_t ctl_first;           /* 1: the next step starts from rest (no P/D kick) */
static uint8_t ctl_gen;             /* param_generation the derived constants belong to */
static int16_t ctl_kf;              /* Q8: drive per unit of du (x100 L/min, Q4) */
static q15_t ctl_carry;             /* Q15: accumulated sub-stiction drive */
static q15_t ctl_last;              /* Q15: last drive sent */
static uint8_t ctl_sat;             /* 1: the last drive was cut (limit or end stop) */
static int16_t ctl_k[3];            /* Q12: kp, ki, kd of the last step */

/* ---- per-controller states, overlaid (only one runs) ---------------------------------- */
typedef struct {
    int16_t e1, e2;                 /* x100 L/min: e(k-1), e(k-2) */
} pid_state_t;

static union {
    pid_state_t pid;
} st;

static const __code char nm_pid[] = "pid";
static const __code char nm_fuzzy[] = "fuzzy_pid";
static const __code char nm_bp[] = "bp_pid";
static const __code char nm_best[] = "ffmap";

const char *ctl_name(uint8_t id)
{
    switch (id) {
    case CTL_PID: return nm_pid;
    case CTL_FUZZY_PID: return nm_fuzzy;
    case CTL_BP_PID: return nm_bp;
    case CTL_BEST: return nm_best;
    default: return "?";
    }
}

/* Constants derived from parameters, recomputed when a parameter changes (outside the law). */
static void ctl_derive(void)
{
    uint32_t t = param_v[P_VALVE_TRAVEL];
    /* drive(Q15) = du(Q12 x100 L/min) * T / (4096 * 100 * 100) * 32768 = du_q4 * T * 0.2048 */
    ctl_kf = (int16_t)((t * 839u + 8u) >> 4);       /* Q8 of T * 0.2048 (839/4096 = 0.20483) */
    ctl_gen = param_generation;
}

static void pid_reset(void)
{
    st.pid.e1 = 0;
    st.pid.e2 = 0;
}

void ctl_reset(q15_t drive_now)
{
    ctl_first = 1;
    ctl_carry = 0;
    ctl_last = drive_now;
    ctl_sat = 0;
    ctl_derive();
    switch (ctl_id) {
    default:
        pid_reset();
        break;
    }
}

uint8_t ctl_select(uint8_t id)
{
    if (id >= CTL_COUNT)
        return 0;
    ctl_id = id;
    ctl_k[0] = ctl_k[1] = ctl_k[2] = 0;
    ctl_reset(0);
    return 1;
}

uint8_t ctl_selected(void)
{
    return ctl_id;
}

int16_t ctl_gain(uint8_t i)
{
    return i < 3 ? ctl_k[i] : 0;
}

static int16_t clamp_e(int16_t e)
{
    if (e > CTL_E_MAX)
        return CTL_E_MAX;
    if (e < -CTL_E_MAX)
        return -CTL_E_MAX;
    return e;
}

/* The output stage: du (Q12 x100 L/min, 32 bit) -> drive, with pulse accumulation and limits. */
static q15_t ctl_out(int32_t du, uint8_t limit)
{
    int16_t s4;                     /* du in Q4 */
    int32_t d;                      /* Q15 drive requested, plus the carry */

    s4 = fx_sat16((du + 128) >> 8);
    d = ((int32_t)s4 * ctl_kf + 128) >> 8;
    d += ctl_carry;
    ctl_sat = 0;
    if (d > 32767) {
        d = 32767;
        ctl_sat = 1;
    } else if (d < -32767) {
        d = -32767;
        ctl_sat = 1;
    }
    if ((d > 0 && (limit & CTL_AT_CLOSED)) || (d < 0 && (limit & CTL_AT_OPEN))) {
        d = 0;
        ctl_sat = 1;
    }
    if (d < CTL_STICTION && d > -CTL_STICTION) {
        ctl_carry = (q15_t)d;
        d = 0;
    } else {
        ctl_carry = 0;
    }
    ctl_last = (q15_t)d;
    return (q15_t)d;
}

/* ---- pid: eq. (7) with the paper's gains --------------------------------------------------- */
#define PID_KP Q12(1.2)
#define PID_KI Q12(0.2)
#define PID_KD Q12(0.8)

static q15_t pid_step(const ctl_in_t *in)
{
    int16_t e;                      /* x100 L/min */
    int32_t du;                     /* Q12 x100 L/min */
    int16_t d2e;                    /* x100 L/min: e - 2 e1 + e2 */

    e = clamp_e(in->target_lpm_x100 - in->flow_lpm_x100);
    if (ctl_first) {
        st.pid.e1 = e;
        st.pid.e2 = e;
        ctl_first = 0;
    }
    d2e = fx_sat16((int32_t)e - 2 * (int32_t)st.pid.e1 + st.pid.e2);
    du = (int32_t)PID_KP * (int16_t)(e - st.pid.e1) + (int32_t)PID_KI * e + (int32_t)PID_KD * d2e;
    st.pid.e2 = st.pid.e1;
    st.pid.e1 = e;
    ctl_k[0] = PID_KP;
    ctl_k[1] = PID_KI;
    ctl_k[2] = PID_KD;
    return ctl_out(du, in->valve_limit);
}

q15_t ctl_step(const ctl_in_t *in)
{
    if (ctl_gen != param_generation || ctl_kf == 0)
        ctl_derive();
    switch (ctl_id) {
    default:
        return pid_step(in);
    }
}

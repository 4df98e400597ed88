/* ctl.c: the one interface of the six flow controllers: select, reset, step, dispatched by a switch. */
#if defined(__SDCC)
#pragma stackauto           /* locals on the stack, not each its own XRAM (docs/MEMORY.md) */
#endif
#include "ctl_int.h"
#include "params.h"
#include "store.h"
#include "speed.h"
#include "umath.h"

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
 * The controllers: pid.c (pid and fuzzy_pid, one law), bp.c (bp_pid), ffmap.c, and two
 * peers to compare with: aog.c (AgOpenGPS Rate Control's valve loop), raven.c (Raven's valve cal); their
 * common output stage: ctl_out.c; their products: mul.h. docs/CONTROLLERS.md has the design.
 */

/* ---- state shared by all controllers -------------------------------------------------- */
static uint8_t ctl_id = CTL_FFMAP;
static uint8_t ctl_gen;             /* param_generation the derived constants belong to */
__data uint8_t ctl_first;
int16_t ctl_kf;
int16_t ctl_travel;
int16_t ctl_stiction = CTL_STICTION_DEF;    /* P_VALVE_BRK in Q15 */
int16_t ctl_drun;
int16_t ctl_run_span = 32767;
int16_t ctl_backlash = CTL_BACKLASH_DEF;     /* P_VALVE_SLACK in Q15 */
__data q15_t ctl_carry;
q15_t ctl_last;
__data uint8_t ctl_sat;
const __xdata ctl_in_t *__data ctl_in;
int16_t ctl_k[3];

/* ---- per-controller states, overlaid (only one runs) ---------------------------------- */
ctl_state_t ctl_st;

static const __code char nm_ffmap[] = "ffmap";
#if FW_PEERS                        /* the field image: ffmap only (params.h) */
static const __code char nm_bp[] = "bp_pid";
static const __code char nm_pid[] = "pid";
static const __code char nm_fuzzy[] = "fuzzy_pid";
static const __code char nm_aog[] = "aog";
static const __code char nm_raven[] = "raven";
#endif

const __code char *ctl_name(uint8_t id)
{
    switch (id) {
    case CTL_FFMAP: return nm_ffmap;
#if FW_PEERS
    case CTL_BP_PID: return nm_bp;
    case CTL_PID: return nm_pid;
    case CTL_FUZZY_PID: return nm_fuzzy;
    case CTL_AOG: return nm_aog;
    case CTL_RAVEN: return nm_raven;
#endif
    default: return "?";
    }
}

#if FW_PROBES
uint8_t ctl_saturated(void)
{
    return ctl_sat;
}

q15_t ctl_carry_now(void)
{
    return ctl_carry;
}
#endif

/* Constants derived from parameters: recomputed when a parameter changes (the one divide is
 * here, not in the control law). */
static void ctl_derive(void)
{
    int16_t s, b, t = ctl_travel;
    ctl_travel = (int16_t)param_v[P_VALVE_TRAVEL];
    if (ctl_travel < 1)
        ctl_travel = 40;
    /* drive(Q15) = du(Q12 x100 L/min) * T / (4096 * 100 * 100) * 32768 = du_q4 * T * 0.2048 */
    ctl_kf = (int16_t)((MUL(ctl_travel, 839) + 8) >> 4);   /* Q8 of T * 0.2048 (839/4096) */
    /* Min duty in % and Backlash in 0.1 % of the stroke, to Q15 (rounded); told new values of
     * these or of Valve time, ffmap drops the break-away, the loop gain and the duty cap it had learnt against
     * the old ones (the operator knows the valve now) */
    s = (int16_t)um_scaled_div(param_v[P_VALVE_BRK], 32768u, 100u);       /* (v 2^15 + 50) / 100 */
    b = (int16_t)um_scaled_div(param_v[P_VALVE_SLACK], 32768u, 1000u);    /* (v 2^15 + 500) / 1000 */
    if ((s != ctl_stiction || b != ctl_backlash || t != ctl_travel) && t && ctl_id == CTL_FFMAP) {
        ffmap_forget();
    }
    ctl_stiction = s;
    ctl_backlash = b;
    ctl_drun = (int16_t)((MUL(ctl_stiction, CTL_RUN_NUM) + 8) >> 4);
    if (ctl_drun > Q15(0.45))
        ctl_drun = Q15(0.45);       /* 1 / (1 - d_run) within Q14 */
    ctl_run_span = (int16_t)(32767 - ctl_drun);
#if FW_PEERS
    if (ctl_id == CTL_AOG)
        ag_derive();
    else if (ctl_id == CTL_RAVEN)
        rv_derive();
#endif
    ctl_gen = param_generation;
}

/* ---- the interface ------------------------------------------------------------------------ */
void ctl_applied(q15_t drive, uint8_t limit)
{
    (void)limit;
    if (ctl_id == CTL_FFMAP && drive != ctl_last)
        ctl_carry = 0;              /* overridden (relief, jog, priming): nothing owed any more */
}

void ctl_reset(q15_t drive_now)
{
    ctl_first = 1;
    ctl_carry = 0;
    ctl_last = drive_now;
    ctl_sat = 0;
    ctl_prepare();                  /* the constants only when stale: a reset (leaving manual
                                       mode, starting to spray) shares the pass with a step */
}

uint8_t ctl_select(uint8_t id)
{
#if FW_PEERS
    if (id >= CTL_COUNT)
        return 0;
#else
    if (id != CTL_FFMAP)
        return 0;                   /* the field image: ffmap only (FW_PEERS) */
#endif
    ctl_id = id;
    speed_set_plain(0);             /* (ffmap sets it from what it learnt, each step) */
    ctl_kf = 0;                     /* the reset below derives this controller's constants */
    ctl_k[0] = ctl_k[1] = ctl_k[2] = 0;
    switch (id) {
#if FW_PEERS
    case CTL_PID:
        ctl_st.pid.e1 = ctl_st.pid.e2 = 0;
        break;
    case CTL_FUZZY_PID:
        ctl_st.fz.e1 = ctl_st.fz.e2 = 0;
        break;
    case CTL_BP_PID:
        bp_init();
        break;
#endif
    case CTL_AOG:
    case CTL_RAVEN:
        break;                      /* their first step starts them from rest (ctl_first) */
    default:
        ffmap_init();
        break;
    }
    ctl_reset(0);
    return 1;
}

uint8_t ctl_selected(void)
{
    return ctl_id;
}

uint8_t ctl_learnt_byte(uint8_t i)
{
    if (ctl_id != CTL_FFMAP)
        return store_learnt(i);
    if (ctl_gen != param_generation)
        ctl_derive();               /* valve parameters told anew: what was learnt goes first */
    return ffmap_learnt_byte(i);
}

#if FW_PROBES
int16_t ctl_gain(uint8_t i)
{
    return i < 3 ? ctl_k[i] : 0;
}
#endif

void ctl_prepare(void)
{
    if (ctl_gen != param_generation || ctl_kf == 0)
        ctl_derive();
}

q15_t ctl_step(const __xdata ctl_in_t *step_in)
{
    ctl_in = step_in;
    if (ctl_gen != param_generation || ctl_kf == 0)
        ctl_derive();
    switch (ctl_id) {
#if FW_PEERS
    case CTL_BP_PID:
        return bp_step();
    case CTL_PID:
        return pid_step();
    case CTL_FUZZY_PID:
        return fz_step();
    case CTL_AOG:
        return ag_step();
    case CTL_RAVEN:
        return rv_step();
#endif
    default:
        return ffmap_step();
    }
}

/* ctl_int.h: the controllers' internal states and constants, for the controllers' files and the tests. */
#ifndef CTL_INT_H
#define CTL_INT_H

#include "ctl.h"
#include "mul.h"

/* ---- common ---------------------------------------------------------------------------- */
#define CTL_FLOW_SCALE_LPM 100      /* L/min of boom flow per full valve stroke (normalisation) */
/* The valve's break-away duty (the smallest drive that moves it) and backlash (stroke lost on a
 * reversal): the parameters Min duty and Backlash, in Q15, derived when a parameter changes.
 * CTL_STICTION_DEF / CTL_BACKLASH_DEF: their defaults. */
extern int16_t ctl_stiction, ctl_backlash;
#define CTL_STICTION ctl_stiction
#define CTL_STICTION_DEF Q15(0.2)
#define CTL_BACKLASH_DEF Q15(0.02)
#define CTL_E_MAX 16000             /* errors clamped to +-160 L/min (x100) */

/* ---- pid: eq. (7), the paper's gains ----------------------------------------------------- */
#define PID_KP Q12(1.2)
#define PID_KI Q12(0.2)
#define PID_KD Q12(0.8)
typedef struct {
    int16_t e1, e2;                 /* x100 L/min: e(k-1), e(k-2) */
} pid_state_t;

/* ---- fuzzy_pid: gains kp0 + QP * dKp(e, ec) ... with dK in [-3, 3] from the rule tables ----- */
#define FZ_E_LEVEL 100              /* x100 L/min of error per fuzzy level (PB = 3 L/min) */
#define FZ_EC_LEVEL 50              /* x100 L/min of error change a period per level */
#define FZ_QP Q12(0.2)              /* gain change per level */
#define FZ_QI Q12(0.05)
#define FZ_QD Q12(0.2)
typedef struct {
    int16_t e1, e2;                 /* x100 L/min */
} fz_state_t;

/* ---- bp_pid: 3(+bias)-5-3 network --------------------------------------------------------- */
#define BP_IN 4
#define BP_HID 5
#define BP_OUT 3
#define BP_ETA Q12(0.2)
#define BP_WMAX Q12(4.0)            /* weight bound (a deviation: keeps tanh out of its flat tails) */
#define BP_SEED 0x2020u             /* initial weights: xorshift16 from this seed */
#define BP_Q_NORM 26844             /* flows to the network: q / 50 L/min, Q12: x100 * 0.8192 (Q15 const) */
#define BP_E_NORM 16777             /* error: e / 5 L/min, Q12: x100 * 8.192 (Q11 const) */
#define BP_E_CLAMP 1500             /* error input clamped to +-15 L/min (x100) */
typedef struct {
    int16_t w[BP_HID][BP_IN];       /* Q12 input -> hidden, column 0 = bias */
    int16_t v[BP_OUT][BP_HID];      /* Q12 hidden -> output */
    int8_t dw[BP_HID][BP_IN];       /* Q12 last change of w (momentum), saturated to +-127 */
    int8_t dv[BP_OUT][BP_HID];      /* Q12 last change of v */
    int16_t k[BP_OUT];              /* Q15 kp, ki, kd */
    int16_t e1, e2;                 /* x100 L/min */
    int16_t n1, n2;                 /* Q12 normalised error e(k-1), e(k-2) */
} bp_state_t;

/* ---- ffmap (the project's own, `ffmap`): a damped incremental PID with a deadband, an output
 * stage that knows the motor's running friction, a break-away, the motion a reversal is worth
 * and a loop gain learnt from the flow (docs/CONTROLLERS.md) ------------------------------------------------------------------ */
#define FFMAP_KP Q12(1.0)              /* gains on the pid normalisation (ctl.c) */
#define FFMAP_KI Q12(1.2)
#define FFMAP_KD Q12(0.8)
#define FFMAP_DB_IN 8                  /* deadband: the valve rests once the filtered error <= target >> 8 */
#define FFMAP_DB_OUT 7                 /* ... and wakes beyond target >> 7, or when the target moves */
#define FFMAP_DB_PAST 10               /* ... past the target the way it last moved, within target >> 10 */
#define FFMAP_MOVE_SHIFT 6             /* the target moves: |dq| > target >> 6 in one period */
#define FFMAP_REST_KI Q12(0.15)        /* resting, a slow integral only, on the filtered error */
#define FFMAP_STALL_N 6                /* smallest pulses one way without the flow moving: a stall
                                     * (fewer counted the backlash's take-up as one) */
#define FFMAP_STALL_MOVE 6             /* ... the flow not moved that way by target >> this */
#define FFMAP_STALL_BIG 4              /* ... a smallest pulse counts this while the error is beyond
                                     * target >> FFMAP_BIG_SHIFT (2 otherwise) */
#define FFMAP_BRK_STEP Q15(0.05)       /* the smallest pulse grows by this at each stall ... */
#define FFMAP_BRK_MAX Q15(0.25)        /* ... up to Min duty + this */
#define FFMAP_BRK_AGE 3000u            /* ... and steps back after 5 min without a stall */
#define FFMAP_LONE_N 5                 /* a lone smallest pulse: this many periods quiet before it and
                                     * after it, when the flow's step is judged ... */
#define FFMAP_LONE_SH 6                /* ... a step beyond target >> this takes the smallest pulse ... */
#define FFMAP_BRK_DN Q15(0.025)        /* ... down by this, to half Min duty (ffmap.c ffmap_stall) */
#define FFMAP_G_MIN 32                 /* the learnt loop gain, Q8: 1/8 .. 2 of what Valve time gives */
#define FFMAP_G_INIT 192               /* ... where a valve nothing was learnt of starts: 3/4, as the
                                     * valve may be faster than told (docs/CONTROLLERS.md) */
#define FFMAP_G_MAX 512
#define FFMAP_TOP_N 3                  /* a start's big-swing cut takes half after this many periods at
                                     * the top duty, not a quarter (ffmap.c ffmap_out) */
#define FFMAP_REV_MIN Q15(0.6)         /* a reversal is sent once the motion owed the other way is this */
#define FFMAP_REV_LOW Q15(0.1)         /* ... learnt down to this by cycles at a steady target (-1/8 each) */
#define FFMAP_ANSWER 3                 /* a reversal's answer: periods until the flow shows it (ffmap_out) */
#define FFMAP_OSC_GAP 16               /* a reversal this soon after the last, |e| <= target: g -1/8 */
#define FFMAP_OSC_GAP_SLOW 32          /* ... this soon on a valve whose stroke takes FFMAP_SLOW_T periods
                                     * or more at its learnt gain, the speed steady */
#define FFMAP_SLOW_T 20
#define FFMAP_SLOW_N 20                /* this long awake with the error one way: +3/32 */
#define FFMAP_BIG_SHIFT 4              /* a half cycle whose error reached target >> this swung big */
#define FFMAP_P_WAIT 5                 /* periods after a (re)start without the proportional term */
#define FFMAP_FF_RSH 2                 /* the speed's feed-forward: a ramp is its change of the target ... */
#define FFMAP_FF_RAMP 40               /* ... filtered over about 2^FFMAP_FF_RSH periods beyond this (x100) */
#define FFMAP_STEADY() ((uint16_t)(ctl_st.fm.ramp + FFMAP_FF_RAMP) <= 2 * FFMAP_FF_RAMP)  /* the speed steady */
#define FFMAP_FF_ESH 7                 /* ... the error beyond target >> this: ff_gain lags or leads */
#define FFMAP_FF_MAX 2000              /* the largest ff_gain */
#define FFMAP_FF_RUN_SH 3              /* ff_gain's step: 2, and 2 more every 2^this periods taught one way in a row */
#define FFMAP_FF_LEAD 32               /* ff_gain under this: the flow follows the speed by itself (a pump
                                     * on the wheels learns at most 20, one on a fixed PTO 56-404
                                     * after its first ramps): the speed without its lead (speed.h) */
#define FFMAP_FF_OFF_SH 3              /* ... and, the wheel unlearnt, only a ramp 2^this past the band teaches it */
#define FFMAP_LEAD 3                   /* after a start-up closing: the integral on the flow this many
                                     * periods ahead while it comes toward the target ... */
#define FFMAP_LEAD_DRIVE Q15(0.5)      /* ... and the valve runs beyond this duty */
#define FFMAP_CAP_N 3                  /* the duty cap (ffmap.c ffmap_cap): after this many periods at it,
                                     * a period ... */
#define FFMAP_CAP_SH 2                 /* ... that moved the flow by more than target >> this: -1/4 */
#define FFMAP_CAP_MIN 13               /* ... not below 13/256 of full duty */
#define FFMAP_P_REF 200u              /* kPa: above this the loop gain is cut by sqrt(FFMAP_P_REF / P) */
#define FFMAP_P_HI_F 191u              /* ... and beyond 360 kPa (that root under 191/256), where the
                                     * bypass holds the flow hardest, cycles cut it in a start too */
#define FFMAP_P_T_F 181u               /* the target's pressure P (target / flow)^2 over 400 kPa:
                                     * target FFMAP_P_T_F > flow x that root (256 sqrt(200 / 400)) */
#define FFMAP_P_T_DUTY Q15(0.10)       /* ... a closing there at most the smallest pulse + this, on
                                     * a valve whose gain was learnt under FFMAP_G_INIT (ffmap_out); at
                                     * 1/4 and 0.15 a 0.15 s motor's coast still took a 1.9 s
                                     * valve's line over P max */
#define FFMAP_WARM 100                 /* little gain learning in the first 10 s of a (re)start: the pump
                                     * spins up, the line primes, the flow overshoots from the parked
                                     * valve (ffmap_gain_adapt says what is learnt there) */
typedef struct {
    int16_t e1, e2;                 /* x100 L/min: e(k-1), e(k-2) */
    int16_t err_filt;               /* x100 the error filtered over 4 periods (the deadband's) */
    int16_t target_last;            /* x100 L/min: the last period's target */
    uint8_t rest;                   /* 1: inside the deadband, the valve rests */
    int8_t dir;                     /* +1 / -1: the direction of the last pulse */
    uint8_t stall_n;                /* smallest pulses one way in a row */
    int16_t stall_flow;             /* x100 L/min: the flow when the first of them was sent */
    /* what is learnt of the valve, together (the EEPROM keeps these STORE_LEARN_CTL bytes): */
    int16_t gain;                   /* Q8: the loop gain learnt for this valve (256 = as told) */
    int16_t brk_extra;              /* Q15 added to Min duty after stalls (under 0: lone pulses' steps) */
    int16_t rev_min;                /* Q15: the motion owed the other way that makes a reversal */
    int16_t ff_gain;                /* Q15 drive per x100 L/min the speed moves the target (ffmap_ff, even) */
    uint16_t brk_age;               /* periods since the last stall */
    uint8_t rev_age;                /* periods since the last reversal (saturates) */
    uint8_t moved;                  /* 1: the target moved since the last reversal */
    uint8_t slow_n;                 /* periods awake with the error one way and no reversal */
    uint8_t warm;                   /* periods since the loop (re)started, up to FFMAP_WARM */
    int16_t err_peak;               /* x100 the largest abs error since the last reversal */
    uint8_t big;                    /* 1: the half cycle before the last reversal swung big */
    uint8_t err_big;                /* 1: this period's abs error beyond target >> FFMAP_BIG_SHIFT */
    uint16_t speed_last;            /* x100 km/h: the last period's speed */
    int16_t ramp;                   /* x100 L/min: the speed's change of the target, filtered */
    int32_t ff_drive;               /* Q15 this period's feed-forward drive */
    uint8_t lead;                   /* 1: this (re)start found the meter at a quarter of the target */
    uint8_t cap;                    /* the duty cap: (cap << 7) | 127, Q15 (255: full duty) */
    uint8_t cap_run;                /* periods in a row the valve was driven at the cap one way */
    uint8_t cap_run_before;         /* ... before this period */
    int16_t flow_last;              /* x100 L/min the last period's flow */
    int16_t gain_start;             /* Q8: the loop gain when the loop (re)started */
    uint8_t hold;                   /* periods left without P and D after the sections changed */
    uint8_t ff_run;                 /* periods in a row ff_gain was taught the same way (ffmap_ff_lag), to 120 */
    uint8_t quiet;                  /* periods in a row without a pulse, to 255 */
    uint8_t lone_n;                 /* periods until a lone smallest pulse's step is judged (0: none) */
    int16_t lone_flow;              /* x100 L/min: the flow when it was sent */
} ffmap_state_t;

/* ---- aog: SK21's RateControl module's valve PID (aog.c), the user's settings P_AOG_* --------- */
#define AG_DB_Q15 492               /* dead band: |e| <= 1.5 % of the target (Q15 of the target) */
#define AG_MAXI_Q15 2141            /* the integral's change a period: 25 PWM counts a 150 ms run, x 2/3 */
#define AG_ZERO_Q15 13              /* a change under 0.1 PWM count sends nothing */
typedef struct {
    int16_t integ;                  /* Q15 duty: the integral, within +-(max - min) */
    int16_t ref;                    /* x100 L/min: the highest target since the loop started */
    /* derived from the settings when a parameter changes (ctl.c ctl_derive), in ag_derive's order: */
    int16_t kp;                     /* Q11: Kp / 100, beyond the brake point */
    int16_t ki;                     /* Q11: Ki / 100 x 2/3 (a 100 ms period of a 150 ms loop) */
    int16_t min;                    /* Q15 duty: min PWM */
    int16_t max;                    /* Q15 duty: max PWM (at least min PWM) */
    int16_t brake;                  /* Q15 of the reference: the brake point */
    int16_t kps;                    /* Q11: Kp / 100 x slow adjust, inside it */
    uint8_t pos;                    /* 1: the error was last beyond the dead band above the target */
} ag_state_t;

/* ---- raven: the SCS consoles' four-digit valve calibration (raven.c), P_RAVEN_CAL ------------ */
#define RV_PULSE_Q15 3277           /* a backlash digit: 10 ms of full drive in a 100 ms period */
typedef struct {
    int8_t dir;                     /* +1 / -1: the direction of the last correction, 0 none yet */
    uint8_t fast;                   /* 1: a fast valve (a three-digit cal: backlash digit 0) */
    int16_t speed;                  /* Q15 duty of a correction beyond the brake point */
    int16_t brake;                  /* Q15 of the target: the brake point */
    int16_t band;                   /* Q15 of the target: the dead band */
    int16_t pulse;                  /* Q15 duty added to the first correction after a reversal */
} rv_state_t;

/* One controller runs at a time; the field image carries ffmap alone (FW_PEERS, hal/compiler.h),
 * so its union holds ffmap's state only (bp_pid's is more than twice the size) */
typedef union {
    ffmap_state_t fm;
#if FW_PEERS
    pid_state_t pid;
    fz_state_t fz;
    bp_state_t bp;
    ag_state_t ag;
    rv_state_t rv;
#endif
} ctl_state_t;

/* The live state (read by the tests; only the controllers' files write it). */
extern ctl_state_t ctl_st;
#if !defined(__SDCC)
/* bp_pid's inputs and hidden outputs live on bp_step's stack; the host build keeps the last
 * step's hidden outputs here for the tests (Q15) */
extern int16_t bp_o_seen[BP_HID];
#endif
/* 1 when the last drive was cut: drive limit or end stop (learning is frozen then). */
uint8_t ctl_saturated(void);
/* Q15 sub-stiction drive accumulated by the output stage of pid / fuzzy_pid / bp_pid. */
q15_t ctl_carry_now(void);
/* The fuzzy rule tables (rows e NB..PB, columns ec NB..PB, values -3..3). */
extern const __code int8_t fz_tab[3][7][7];

/* ---- shared by the controllers' files (ctl.c, ctl_out.c, pid.c, bp.c, ffmap.c, aog.c, raven.c) - */
/* CTL_SHARED: locals and compiler temporaries of the non-network controllers go on the stack
 * (__reentrant), so the controllers share those bytes (only one runs) instead of each holding
 * its own in the scarce internal RAM and XRAM. */
#define CTL_SHARED __reentrant
/* CTL_STEP: a named step of a control step, inlined where it is used: no call, and no copy of
 * its own in the flash (a C99 inline definition; the host keeps a static one) */
#if defined(__SDCC)
#define CTL_STEP inline
#else
#define CTL_STEP static inline
#endif

/* the inputs of the step in progress: ctl_step's argument (direct RAM: read at every input) */
extern const __xdata ctl_in_t *__data ctl_in;
/* ffmap: the last reversal sent was under 1.5 times the smallest one (rev_min) and at most one pulse
 * followed it the same way: what the half cycle swung is the valve's resolution, not the loop
 * gain (ffmap.c ffmap_out); ffmap_rl1: a pulse followed it */
extern __bit ffmap_rlim, ffmap_rl1;
/* ffmap: the target last moved up (ffmap_deadband: past it, the valve rests only nearer) */
extern __bit ffmap_up;
extern __data uint8_t ctl_first;    /* 1: the next step starts from rest (no P/D kick) */
extern int16_t ctl_kf;              /* Q8: drive per unit of du (x100 L/min, Q4) */
extern int16_t ctl_travel;          /* P_VALVE_TRAVEL: periods for a full stroke at full duty */
/* The motor's running friction: moving, it runs at (duty - d_run) / (1 - d_run) of full speed.
 * d_run is taken as CTL_RUN_NUM/16 of Min duty (the break-away duty). */
#define CTL_RUN_NUM 10
extern int16_t ctl_drun;            /* Q15: d_run (at most 0.45) */
extern int16_t ctl_run_span;        /* Q15: 1 - d_run */
extern __data q15_t ctl_carry;      /* Q15: accumulated sub-stiction drive (direct RAM: every step) */
extern q15_t ctl_last;              /* Q15: last drive sent */
extern __data uint8_t ctl_sat;      /* 1: the last drive was cut (limit or end stop) */
extern int16_t ctl_k[3];            /* Q12: kp, ki, kd of the last step */

/* The output stage (ctl_out.c). */
int16_t ctl_clamp_e(int16_t e);
int16_t ctl_clamp16(int16_t x, int16_t lo, int16_t hi) CTL_SHARED;
/* frac (Q15) of this step's target, x100 L/min, floored (the peers' dead bands and brake
 * points; ctl_peer.c) */
int16_t ctl_of_target(int16_t frac) CTL_SHARED;
/* The second difference x - 2 x1 + x2 of the incremental law's D term, saturated to int16. */
int16_t ctl_d2(int16_t x, int16_t x1, int16_t x2) CTL_SHARED;
/* du (Q12, x100 L/min of flow-equivalent) -> Q15 drive, 32 bit, not yet limited. */
int32_t ctl_du_to_drive(int32_t du);
/* pid, fuzzy_pid and bp_pid: pulse accumulation below stiction, drive limit and end stops. */
q15_t ctl_out(int32_t d, uint8_t limit) CTL_SHARED;
/* A drive (int32, Q15) cut to full duty either way; ctl_sat says whether it was. */
#define CTL_CLIP(d)                                                                          \
    do {                                                                                     \
        ctl_sat = 0;                                                                         \
        if ((d) > 32767) {                                                                   \
            (d) = 32767;                                                                     \
            ctl_sat = 1;                                                                     \
        } else if ((d) < -32767) {                                                           \
            (d) = -32767;                                                                    \
            ctl_sat = 1;                                                                     \
        }                                                                                    \
    } while (0)
/* ... and nothing against an end stop: closing (d > 0) when `limit` has a bit of `closed`,
 * opening when it has CTL_AT_OPEN (anti-windup: what the valve cannot do is dropped). */
#define CTL_STOP(d, limit, closed)                                                           \
    do {                                                                                     \
        if (((d) > 0 && ((limit) & (closed))) || ((d) < 0 && ((limit) & CTL_AT_OPEN))) {     \
            (d) = 0;                                                                         \
            ctl_sat = 1;                                                                     \
        }                                                                                    \
    } while (0)

/* The controllers (pid.c, bp.c, ffmap.c): start from scratch, one step. */
q15_t pid_step(void) CTL_SHARED;
q15_t fz_step(void) CTL_SHARED;
void bp_init(void);
q15_t bp_step(void) CTL_SHARED;
void ffmap_init(void);
q15_t ffmap_step(void) CTL_SHARED;
/* ffmap's learnt figures: forgotten (the valve told anew: a new valve's starting point), and
 * byte i of their EEPROM image (store.h STORE_LEARN_CTL bytes; ffmap_init reads it back). */
void ffmap_forget(void);
uint8_t ffmap_learnt_byte(uint8_t i) __reentrant;
q15_t ag_step(void) CTL_SHARED;
void ag_derive(void) CTL_SHARED;
q15_t rv_step(void) CTL_SHARED;
void rv_derive(void) CTL_SHARED;

#endif

/* ctl_int.h: the controllers' internal states and constants, for the controllers' files and the tests. */
#ifndef CTL_INT_H
#define CTL_INT_H

#include "ctl.h"
#include "mul.h"

/* ---- common ---------------------------------------------------------------------------- */
#define CTL_FLOW_SCALE_LPM 100      /* L/min of boom flow per full valve stroke (normalisation) */
/* The valve's break-away duty (the smallest drive that moves it) and backlash (stroke lost on a
 * reversal, which ffmap takes up before counting): the parameters Min duty and Backlash, in Q15,
 * derived when a parameter changes. CTL_STICTION_DEF / FM_BACKLASH_DEF: their defaults. */
extern int16_t ctl_stiction, ctl_backlash;
#define CTL_STICTION ctl_stiction
#define CTL_STICTION_DEF Q15(0.2)
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
    int16_t x[BP_IN];               /* Q12 this period's inputs */
    int16_t o[BP_HID];              /* Q15 this period's hidden outputs */
    int16_t k[BP_OUT];              /* Q15 kp, ki, kd */
    int16_t de[BP_OUT];             /* scratch: the law's e - e1, e, e - 2e1 + e2 (x100) */
    int16_t dn[BP_OUT];             /* scratch: the same of the normalised error (Q12) */
    int16_t dl[BP_OUT];             /* Q12 output deltas of this period */
    int16_t e1, e2;                 /* x100 L/min */
    int16_t n1, n2;                 /* Q12 normalised error e(k-1), e(k-2) */
} bp_state_t;

/* ---- ffmap (the project's own, `best`): position servo + learned flow->position map ------ */
#define FM_NODES 17                 /* map nodes every FM_BIN of target flow: 0 .. 81.9 L/min */
#define FM_BIN_SHIFT 9              /* node spacing 512 x100 = 5.12 L/min */
#define FM_BACKLASH ctl_backlash     /* stroke lost on a reversal (taken up before counting) */
#define FM_BACKLASH_DEF Q15(0.02)
/* Where the end stops put the estimate (Q15 of the stroke, 1 = closed): the closed stop below
 * the int16 top, so an early "closed" report leaves room to go on closing when the valve's
 * stop logic lets it retry (at 32767 the reference could not pass the estimate and the loop
 * stopped short of its target for good) */
#define FM_AT_CLOSED 28672
#define FM_AT_OPEN (FM_AT_CLOSED - 32768)
/* Gain schedule (tools/gen_fmgain.py writes the tables): g = FM_GS_K (1/Q_v + (1 - Pc/P)/Q_b),
 * 80 L/min a stroke over the stroke's effect on the boom flow, clamped */
extern const FX_CODE int16_t fm_inv_cv[17];     /* 4096 / Cv(o), o = k/16 */
extern const FX_CODE int16_t fm_inv_sqp[26];    /* 4096 / sqrt(P), P = 64 k kPa */
extern const FX_CODE int16_t fm_pc_p[26];       /* 32767 (1 - Pc/P) */
extern const FX_CODE int16_t fm_inv_q[33];      /* 65536 / Q, Q = 2.56 k L/min */
#define FM_GS_K 94                  /* Q10: 80 / ln(30) * 256 / 65536 = 0.0919 */
#define FM_GS_MIN 179               /* Q8: 0.7 */
#define FM_GS_MAX 410               /* Q8: 1.6 */
#define FM_DEF_SLOPE 1678           /* Q15 stroke per node spacing: 5.12 / 100 L/min */
/* x100 L/min a Q15 stroke moves at the default slope (Q15): 512 * 32768 / FM_DEF_SLOPE */
#define FM_COVER 9998
#define FM_WARM 200                 /* periods (20 s) after a (re)start before the map learns: the
                                     * pump may still spin up (coupled PTO) and the line prime */
#define FM_KP Q12(0.6)              /* feedback gains on the pid normalisation */
#define FM_KI Q12(0.5)
#define FM_LEAD Q15(0.5)            /* p_ref stays within this of p_hat (anti-windup) */
#define FM_REV_MIN Q15(0.004)       /* smallest move worth a reversal */
#define FM_REV_MIN_REST Q15(0.001)  /* ... inside the band (the slow integral alone moves p_ref) */
#define FM_CALM 5                   /* periods of calm before the map learns */
#define FM_IGATE Q15(0.02)          /* integral only while |p_ref - p_hat| is under this */
#define FM_DB_IN 8                  /* deadband: the feedback rests once |e| <= target >> FM_DB_IN (0.4 %) */
#define FM_DB_OUT 7                 /* ... and re-engages beyond target >> FM_DB_OUT (0.8 %) */
#define FM_REST_KI Q12(0.25)        /* integral only, at half the gain, inside the band */
#define FM_REST_E0 10               /* ... and none while |e| <= target >> FM_REST_E0 (0.1 %) */
#define FM_FF_UNLEARNED 208         /* Q8: the share of the feed-forward where the map is not learned (13/16) */
#define FM_HOLD 3                   /* periods the integral waits after a feed-forward move */
#define FM_LR_SHIFT 2               /* map learning rate 1/4 a calm period */
#define FM_DU_F 13422L              /* du_q4 to Q15 stroke: 0.2048 * 65536, times the gain (Q8) */
typedef struct {
    int16_t node[FM_NODES];         /* Q15 stroke: closure (1 = bypass closed) for each flow, less off */
    int16_t off;                    /* Q15: the frame of the nodes (an end stop's calibration moves it) */
    uint8_t seen[3];                /* bit n: node n learned from the loop */
    int16_t p_hat;                  /* Q15 closure: the drive the valve got (ctl_applied), integrated */
    int16_t p_ref;                  /* Q15 closure the servo drives to */
    int16_t takeup;                 /* Q15 backlash still to take up (sign = direction) */
    int16_t y1;                     /* x100 last measured flow */
    int16_t t1;                     /* x100 last target */
    int8_t dir;                     /* +1 / -1 direction of the last motion */
    uint8_t calm;                   /* periods the target has been steady and the error small */
    uint8_t warm;                   /* periods since the loop (re)started, up to FM_WARM (no learning before) */
    uint8_t rest;                   /* 1: the flow is within the deadband, feedback off (hysteresis) */
    uint8_t pend;                   /* 1: the last drive is not yet accounted in p_hat (see ctl_applied) */
    uint8_t hold;                   /* periods the integral still waits after a big feed-forward move */
    uint8_t cal;                    /* 1: an end stop has set the estimate's frame */
    int8_t stopd;                   /* +1 / -1: at the closed / open stop a report set (until a move away) */
    int16_t gain;                   /* Q8: the gain schedule's factor of the last step (256 = 1) */
    /* a valve stiffer than Min duty: the smallest pulses are counted but do not move it */
    uint8_t stall_n;                /* smallest pulses one way since the target last moved */
    int16_t stall_y;                /* x100 flow when the first of them was decided */
    uint16_t stall_v;               /* x100 km/h: the speed then (a coupled PTO's pump follows it) */
    int16_t stall_mv;               /* Q15 stroke they were counted as */
    int16_t brk;                    /* Q15 duty added to Min duty after a stall was found */
    uint16_t brk_age;               /* periods since the last stall or hunt (brk and tk_cut step back after FM_BRK_AGE) */
    /* a valve with less backlash than Backlash: each reversal overshoots by the difference */
    int8_t rev;                     /* periods since the last reversal, signed as the error was then (0: none near) */
    uint8_t hunt;                   /* reversals in a row, each within FM_HUNT_GAP of the last and against its error */
    int16_t tk_cut;                 /* Q15 taken off Backlash after FM_HUNT_N of them */
    /* the step in progress (its named steps share these instead of passing them on the stack;
     * here they cost no XRAM: bp_pid's state, which shares the union, is larger) */
    struct {
        int16_t e;                  /* x100 L/min: target - flow, clamped */
        int16_t y;                  /* x100 L/min: the measured flow */
        int16_t q;                  /* x100 L/min: the target */
        int16_t dq;                 /* x100 L/min: the target's change since the last step */
        int16_t aq;                 /* |dq| */
        int32_t ff;                 /* Q15 stroke: the feed-forward of this step */
        int32_t du;                 /* Q12 x100 L/min: the feedback's increment */
    } w;
} fm_state_t;
#define FM_STALL_N 5                /* smallest pulses without a flow change that mean a stall */
#define FM_BRK_STEP Q15(0.1)        /* the smallest pulse grows by this at each stall found ... */
#define FM_BRK_MAX Q15(0.4)         /* ... up to Min duty + this */
#define FM_BRK_AGE 6000u            /* ... and steps back after 10 min without one (a stall read where
                                     * the valve did move must not coarsen the pulses for good) */
/* periods: reversals this close, each against the last one's error ... (2 + T_travel / 20: 4 for
 * the default 4 s valve; a slow valve's limit cycle is slower: at 8 s a reversal every 5 periods) */
#define FM_HUNT_GAP(travel) (2 + (travel) / 20)
#define FM_HUNT_N 4                 /* ... FM_HUNT_N in a row: the take-up is too large */
#define FM_TK_STEP Q15(0.0025)      /* it shrinks by this each time, ... */
#define FM_TK_MIN Q15(0.005)        /* ... down to this, and grows back after FM_BRK_AGE quiet periods */

/* ---- aog: AgOpenGPS Rate Control's valve loop (aog.c), the user's settings P_AOG_* ----------- */
#define AG_DB_Q15 1311              /* dead band: |e| <= 4 % of the target (Q15 of the target) */
#define AG_BRAKE_Q15 6554           /* brake point: 20 % of the target */
typedef struct {
    int32_t integ;                  /* Q23 (Q15 duty << 8): the integral, within +-max PWM */
    int16_t y1;                     /* x100 L/min: the last measured flow (the derivative's) */
    /* derived from the settings when a parameter changes (ctl.c ctl_derive): */
    int16_t kp;                     /* Q7: Q15 duty per x100 L/min of error */
    int16_t ki;                     /* the integral's Q23 per x100 L/min of error a 100 ms period */
    int16_t kd;                     /* Q8: Q15 duty per x100 L/min of flow change a 100 ms period */
    int16_t min;                    /* Q15 duty: min PWM */
    int16_t max;                    /* Q15 duty: max PWM (at least min PWM) */
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

typedef union {
    pid_state_t pid;
    fz_state_t fz;
    bp_state_t bp;
    fm_state_t fm;
    ag_state_t ag;
    rv_state_t rv;
} ctl_state_t;

/* The live state (read by the tests; only the controllers' files write it). */
extern ctl_state_t ctl_st;
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

extern const __xdata ctl_in_t *ctl_in;  /* the inputs of the step in progress */
extern uint8_t ctl_first;           /* 1: the next step starts from rest (no P/D kick) */
extern int16_t ctl_kf;              /* Q8: drive per unit of du (x100 L/min, Q4) */
extern int16_t ctl_travel;          /* P_VALVE_TRAVEL: periods for a full stroke at full duty */
extern int16_t ctl_inv_travel;      /* Q15: 1 / ctl_travel */
extern int16_t ctl_stiction_half;   /* Q15: half of Min duty (no divide in a step: SDCC calls one) */
extern int8_t ctl_hunt_gap;         /* FM_HUNT_GAP for P_VALVE_TRAVEL */
extern q15_t ctl_carry;             /* Q15: accumulated sub-stiction drive */
extern q15_t ctl_last;              /* Q15: last drive sent */
extern uint8_t ctl_sat;             /* 1: the last drive was cut (limit or end stop) */
extern int16_t ctl_k[3];            /* Q12: kp, ki, kd of the last step */

/* The output stage (ctl_out.c). */
int16_t ctl_clamp_e(int16_t e);
int16_t ctl_clamp16(int16_t x, int16_t lo, int16_t hi) CTL_SHARED;
/* frac (Q15) of this step's target, x100 L/min, floored (the peers' dead bands and brake points) */
int16_t ctl_of_target(int16_t frac) CTL_SHARED;
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
void fm_init(void);
q15_t fm_step(void) CTL_SHARED;
q15_t ag_step(void) CTL_SHARED;
void ag_derive(void) CTL_SHARED;
q15_t rv_step(void) CTL_SHARED;
void rv_derive(void) CTL_SHARED;
/* ffmap: the stops the valve reports, the drive it got (ctl_applied). */
void fm_stops(uint8_t limit) CTL_SHARED;
void fm_account(q15_t d) CTL_SHARED;

#endif

/* ctl_twin.h: double-precision twins of the controllers' arithmetic (tests/helper_ctl_twin.c). */
#ifndef CTL_TWIN_H
#define CTL_TWIN_H

#include "ctl_int.h"
#include "params.h"

/* eq. (7) increment in valve stroke for errors in L/min and gains as plain numbers. */
double ctltw_pid_du_stroke(double e, double e1, double e2, double kp, double ki, double kd);
/* The drive (fraction of full duty) that moves the valve du_stroke in one period of a valve
 * with a full stroke in travel_periods periods. */
double ctltw_drive(double du_stroke, double travel_periods);
/* fuzzy_pid's gains for an error and error change in L/min: kp, ki, kd. */
void ctltw_fuzzy_gains(double e_lpm, double ec_lpm, double k[3]);
/* bp_pid's forward pass: weights as plain numbers, inputs target/flow in L/min; hidden and outputs. */
void ctltw_bp_forward(const double w[5][4], const double v[3][5], double target_lpm, double flow_lpm,
                      double o[5], double k[3]);
/* bp_pid's learning step as the paper has it (eta 0.2, momentum 0.05, E = n^2 / 2 through the
 * incremental law, sgn(dy/du) = +1): the output rows v, then the hidden rows w with the output
 * weights just updated, each weight held within +-wmax. dw0, dv0: the last changes (momentum);
 * x: the inputs (bias first), o: the hidden outputs, k: the gains of the forward pass; n, n1, n2:
 * the normalised error e(k), e(k-1), e(k-2). */
void ctltw_bp_learn(double w[5][4], double v[3][5], const double dw0[5][4], const double dv0[3][5],
                    const double x[4], const double o[5], const double k[3], double n, double n1, double n2,
                    double wmax);

/* ---- ffmap: one step of the damped PID with its deadband and motor-aware output ------
 * Flows in L/min, drives as fractions of full duty, plain double arithmetic, no rounding. */

/* ffmap's constants as plain numbers, from the firmware's own (ctl_int.h): nothing retyped. */
#define CTLTW_FFMAP_KP (FFMAP_KP / 4096.0)
#define CTLTW_FFMAP_KI (FFMAP_KI / 4096.0)
#define CTLTW_FFMAP_KD (FFMAP_KD / 4096.0)
#define CTLTW_FFMAP_REST_KI (FFMAP_REST_KI / 4096.0)
#define CTLTW_FFMAP_DB_IN (1 << FFMAP_DB_IN)      /* rest once the filtered error <= target / 256 */
#define CTLTW_FFMAP_DB_OUT (1 << FFMAP_DB_OUT)    /* wake beyond target / 128 */
#define CTLTW_FFMAP_DB_PAST (1 << FFMAP_DB_PAST)  /* past the target the way it moved: rest within target / 1024 */
#define CTLTW_FFMAP_MOVE (1 << FFMAP_MOVE_SHIFT)  /* the target moves: |dq| > target / 64 */
#define CTLTW_STICTION (param_v[P_VALVE_BRK] / 100.0)       /* ctl.c ctl_stiction: Min duty, % */
#define CTLTW_RUN (CTLTW_STICTION * CTL_RUN_NUM / 16.0 > 0.45 ? 0.45 : CTLTW_STICTION * CTL_RUN_NUM / 16.0)
#define CTLTW_E_MAX (CTL_E_MAX / 100.0) /* errors clamped to +-160 L/min */

/* The state a step starts from, as plain numbers (loaded from the firmware's: the twin is
 * compared one step at a time). */
typedef struct {
    double e1, e2, err_filt, target_last;  /* L/min */
    int rest, dir, stall_n, warm, rev_age, slow_n, brk_age, moved;
    int up;                         /* the target last moved up (ffmap.c ffmap_up) */
    double rev_min;                 /* motion owed the other way that makes a reversal */
    double stall_flow;              /* L/min: the flow when the stall count started */
    double err_peak;                /* L/min: the largest abs error since the last reversal */
    int big;                        /* the half cycle before the last reversal swung big */
    int rlim, rl1;                  /* the last reversal was under 1.5 rmin, with at most one pulse
                                     * after it; a pulse followed it (ffmap.c ffmap_rlim, ffmap_rl1) */
    double brk_extra;               /* duty added to Min duty */
    double ramp;                    /* L/min: the speed's change of the target, filtered (as loaded) */
    double gain;                    /* loop gain (1 = as told) */
    double gain_start;              /* the loop gain when the loop (re)started */
    double carry;                   /* motion owed, share of full speed for a period */
    double last;                    /* the last drive, fraction of full duty */
    int lead;                       /* the (re)start found the meter reading a quarter of the target */
    int cap, cap_run;               /* the duty cap (/256 of full duty, 255 none), periods at it */
    double flow_last;               /* L/min: the last period's flow */
    int hold;                       /* periods left without P and D after the nozzles changed */
    int quiet;                      /* periods in a row without a pulse (to 255) */
    int lone_n;                     /* periods until a lone smallest pulse's step is judged */
    double lone_flow;               /* L/min: the flow when it was sent */
    int first;
} ctltw_ffmap_t;
typedef struct {
    double target, flow;            /* L/min */
    double travel;                  /* periods of a full stroke (Valve time) */
    int limit;                      /* CTL_AT_* | CTL_NO_CLOSE */
    double pressure;                /* kPa */
    int noz_q;                      /* the gain's factor for the nozzles open, quarters (target_noz_q) */
    int noz_new;                    /* 1: the nozzles open changed this period (target_noz_new) */
} ctltw_ffmap_in_t;
typedef struct {
    double drive;                   /* fraction of full duty, + toward closed */
    int rest;                       /* the deadband's state after the step */
    int near;                       /* 1: a decision (band, pulse, gain) within rounding of its
                                     * threshold: the firmware may have taken the other side */
} ctltw_ffmap_out_t;
void ctltw_ffmap_load(ctltw_ffmap_t *tw, const ffmap_state_t *fm, int first, q15_t carry);
/* One step of ffmap (ffmap_step of ffmap.c) on the twin's state. */
ctltw_ffmap_out_t ctltw_ffmap_step(ctltw_ffmap_t *m, const ctltw_ffmap_in_t *in);

/* ---- the peers: aog (AgOpenGPS Rate Control, valve mode) and raven (Raven's valve cal) ----------
 * Each returns the drive (fraction of full duty, + = more boom flow) its description asks for,
 * before the output stage (ctl_out.c); 0 within the dead band. Flows in L/min. */
typedef struct {
    double kp, ki;                  /* the user's settings as the RateControl app sets them (x 100) */
    double brake, slow;             /* the brake point (fraction of the reference), slow adjust (fraction) */
    double min_pwm, max_pwm;        /* PWM counts of 255 */
    double integ;                   /* PWM counts */
    double ref;                     /* L/min: the highest target since the start */
    int pos;                        /* the error last beyond the dead band above the target */
    int first;
} ctltw_ag_t;
double ctltw_ag_step(ctltw_ag_t *a, double target, double actual);
typedef struct {
    int cal;                        /* the four digits */
    int dir;                        /* +1 / -1 last correction, 0 none */
} ctltw_rv_t;
/* reversed: set to 1 when this correction changed direction (the output stage drops its carry) */
double ctltw_rv_step(ctltw_rv_t *r, double target, double actual, int *reversed);

#endif

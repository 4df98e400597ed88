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

/* ---- ffmap (`best`): one step of the position servo with its learned map ----------------------
 * Closures (node, p_hat, p_ref, takeup) as fractions of the stroke (0 open .. 1 bypass closed),
 * flows in L/min, speeds in km/h; plain double arithmetic, no rounding and no Q formats. */

/* ffmap's constants as plain numbers, from the firmware's own (ctl_int.h): nothing retyped. */
#define CTLTW_FM_KP (FM_KP / 4096.0)
#define CTLTW_FM_KI (FM_KI / 4096.0)
#define CTLTW_FM_LEAD (FM_LEAD / 32768.0)
#define CTLTW_FM_REV_MIN (FM_REV_MIN / 32768.0)
#define CTLTW_FM_REV_MIN_REST (FM_REV_MIN_REST / 32768.0)   /* inside the band */
#define CTLTW_FM_CALM FM_CALM
#define CTLTW_FM_IGATE (FM_IGATE / 32768.0)
#define CTLTW_FM_DB_IN (1 << FM_DB_IN)      /* rest once |e| <= target / 256 */
#define CTLTW_FM_DB_OUT (1 << FM_DB_OUT)    /* wake beyond target / 128 */
#define CTLTW_FM_REST_KI (FM_REST_KI / 4096.0)
#define CTLTW_FM_REST_E0 (1 << FM_REST_E0)  /* no slow integral while |e| <= target / 1024 */
#define CTLTW_FM_HOLD FM_HOLD               /* periods the integral waits after a big feed-forward */
#define CTLTW_FM_FF_UNLEARNED (FM_FF_UNLEARNED / 256.0)  /* the feed-forward's share where the map is not learned */
#define CTLTW_FM_LR (1.0 / (1 << FM_LR_SHIFT))   /* learning rate 1/4 */
#define CTLTW_FM_BIN ((1 << FM_BIN_SHIFT) / 100.0)     /* node spacing, L/min (5.12) */
#define CTLTW_FM_BACKLASH (param_v[P_VALVE_SLACK] / 1000.0)  /* ctl.c ctl_backlash: Backlash, 0.1 % */
#define CTLTW_FM_COVER (FM_COVER / 100.0)  /* ctl_int.h FM_COVER: L/min a stroke moves on the default
                                         * slope (FM_DEF_SLOPE), 99.98 */
#define CTLTW_STICTION (param_v[P_VALVE_BRK] / 100.0)       /* ctl.c ctl_stiction: Min duty, % */
#define CTLTW_E_MAX (CTL_E_MAX / 100.0) /* errors clamped to +-160 L/min */
/* fm_step holds the PI increment in an int16 of 1/16 x100 L/min (fx_sat16 of du_q4): at most
 * 32767/16 x100 L/min of flow-equivalent, 0.2048 stroke a period. Part of the algorithm as
 * built (it cuts increments beyond about 20 L/min-equivalent), so the twin has it too. */
#define CTLTW_FM_DU_MAX (32767.0 / 16.0 / 100.0 / CTL_FLOW_SCALE_LPM)
/* fm_step's increment to stroke: du_q4 times 13422 (0.2048 * 65536) times the gain (Q8) over
 * 2^24, the factor rounded to an integer first. The twin's increment is du * g; this is what
 * the firmware's factor is made of (ffmap.c fm_step), for the interval of its rounding. */
#define CTLTW_FM_DU_F ((double)FM_DU_F)  /* ffmap.c fm_reference: (FM_DU_F * gain + 128) >> 8 */
#define CTLTW_FM_DU_F_EXACT (0.2048 * 65536.0)  /* 13421.77: the factor of an exact 0.2048 */

/* The gain schedule (ffmap.c fm_gain): g = K (1/Q_v + (1 - Pc/P)/Q_b), clamped, 1 until an end stop
 * has set the frame. The sum comes from the firmware's tables (ctl_int.h, tools/gen_fmgain.py),
 * read as data and interpolated in double: 1/Q_v = fm_inv_cv(o) fm_inv_sqp(P) / 2^24, (1 - Pc/P)/Q_b
 * = fm_pc_p(P) fm_inv_q(y) / 2^31, as the firmware scales them (its s is this sum in Q16 of
 * 1/(L/min), cut at 8191); o = 1 - (p_hat - FM_AT_OPEN) the opening, P cut at 1599 kPa, y at
 * 0 .. 81.91 L/min. K and the clamps as plain numbers (test_ctl.c checks their Q10 / Q8). */
#define CTLTW_FM_GS_K (80.0 / 3.4011973816621555)   /* ctl_int.h FM_GS_K: 80 L/min / ln(30) = 23.52 L/min
                                         * (its Q10 of K 256 / 65536: 94) */
#define CTLTW_FM_GS_MIN 0.7             /* ctl_int.h FM_GS_MIN Q8(0.7) */
#define CTLTW_FM_GS_MAX 1.6             /* ctl_int.h FM_GS_MAX Q8(1.6) */
#define CTLTW_FM_GS_SCUT (8191.0 / 65536.0)    /* fm_gain's cut of the sum (an int16 for MUL), 1/(L/min) */

/* The closures are kept in the estimate's frame, which is no longer cut to the stroke: p_hat
 * and p_ref may leave 0 .. 1 between end-stop calibrations. As int16 of Q15 in the firmware they
 * (and the map's frame off, its nodes, a node difference, a lookup, an error learned) saturate
 * at -1 and at 32767/32768 (CTLTW_FM_TOP). The stops calibrate the estimate to FM_AT_CLOSED
 * (0.875) and FM_AT_OPEN (-0.125): the frame has room above the closed end, so an early
 * "closed" report does not leave the reference stuck at the int16 top. */
#define CTLTW_FM_TOP (32767.0 / 32768.0)
/* where the end stops calibrate the estimate (ctl_int.h FM_AT_CLOSED / FM_AT_OPEN) */
#define CTLTW_FM_CLOSED (FM_AT_CLOSED / 32768.0)
#define CTLTW_FM_OPEN (FM_AT_OPEN / 32768.0)
typedef struct {
    double node[FM_NODES];          /* closure for the target flow of each node (FM_BIN apart), less off */
    double off;                     /* the frame of the nodes: map = off + interpolated nodes */
    unsigned long seen;             /* bit n: node n learned */
    double p_hat, p_ref, takeup;    /* stroke */
    double y1, t1;                  /* L/min: last measured flow, last target */
    int dir;                        /* +1 / -1 / 0: direction of the last motion */
    int calm, warm, rest, hold, cal;
    int stopd;                      /* +1 / -1: at the stop a report set (drives into it do not move) */
    int stall_n;                    /* smallest pulses one way since the target moved (a stall after FM_STALL_N) */
    double stall_y, stall_v;        /* L/min, km/h: the flow and speed the run started from */
    double stall_mv;                /* stroke the run's pulses were counted as */
    double brk;                     /* duty added to Min duty after a stall (LSB-exact) */
    int brk_age;                    /* periods since the last stall or hunt */
    int rev;                        /* periods since the last reversal, signed as the error then (0: none near) */
    int hunt;                       /* close reversals in a row, each against the last one's error */
    double tk_cut;                  /* stroke taken off Backlash after FM_HUNT_N of them (LSB-exact) */
    int pend;                       /* 1: the last drive is not yet accounted in p_hat */
    double last;                    /* the drive the controller sent last (ctl.c ctl_last), duty */
    int first;                      /* 1: the loop (re)starts with this step (ctl_reset before it) */
    double gain;                    /* the gain schedule's factor of the last step (1 = unscaled) */
} ctltw_fm_t;

typedef struct {
    double target, flow;            /* L/min */
    double speed, minf_speed;       /* km/h: ground speed and P_MINF_SPEED */
    int limit;                      /* CTL_AT_* and CTL_NO_CLOSE */
    double travel;                  /* periods for a full stroke at full duty (P_VALVE_TRAVEL) */
    double pressure;                /* kPa: the boom's pressure (the gain schedule's input) */
} ctltw_fm_in_t;

/* Decisions the fixed-point rounding can tip. The twin follows, step by step, the interval in
 * which the firmware's value minus its own can lie (the map's interpolation, the feed-forward's
 * flow and the PI increment rounded, the gains in Q12, the gain schedule in Q8 from rounded table
 * lookups, full duty at 32767, the backlash at
 * 655/32768, 1/T_travel at round(32768/T), the moves a drive makes rounded to an LSB; *_lo ..
 * *_hi below) and flags a step where a closure or a drive it compares with a
 * threshold may lie on the other side of the firmware's threshold (the Q15 constant) within that
 * interval. Flows and speeds need none: the firmware's are exact (x100 integers) and the twin
 * keeps their ties (ctltw_gt in the .c); nor do the drives accounted (the firmware's, exact). */
#define CTLTW_B_IGATE 0x01u         /* |p_ref + feed-forward - p_hat| against FM_IGATE */
#define CTLTW_B_REV 0x02u           /* a reversal's |need| against FM_REV_MIN (FM_REV_MIN_REST in the band) */
#define CTLTW_B_STICTION 0x04u      /* |drive| against half the break-away duty (0 or 0.2) */
#define CTLTW_B_SAT 0x08u           /* |drive| against full duty while the calm counter hangs on
                                     * the saturation flag: only the calm counter and the map may differ */
#define CTLTW_B_HOLD 0x10u          /* |feed-forward| against one period at full duty (1 / T_travel) */
#define CTLTW_B_ZERO 0x20u          /* need's sign with backlash pending (a step without direction
                                     * takes none up) */
#define CTLTW_B_STALL 0x40u         /* whether a pulse is a smallest one (take-up left, in the rounding) */
#define CTLTW_B_SERVO (CTLTW_B_IGATE | CTLTW_B_REV | CTLTW_B_STICTION | CTLTW_B_HOLD | CTLTW_B_ZERO | CTLTW_B_STALL)
#define CTLTW_B_KINDS 7
/* The branches the step took (coverage for the tests). */
#define CTLTW_P_REST 0x001u         /* inside the deadband: the slow integral only */
#define CTLTW_P_INTEGRAL 0x002u     /* outside it, servo near its goal: P and I */
#define CTLTW_P_HELD 0x004u         /* outside it, servo travelling: P only */
#define CTLTW_P_REVERSAL 0x008u     /* a reversal with its backlash take-up */
#define CTLTW_P_HYST 0x010u         /* a reversal too small to make (FM_REV_MIN, in the band FM_REV_MIN_REST) */
#define CTLTW_P_ROUNDED 0x020u      /* a drive under the break-away duty rounded to 0 or 0.2 */
#define CTLTW_P_SAT 0x040u          /* drive cut (full duty, end stop or over-pressure) */
#define CTLTW_P_ENDSTOP 0x080u      /* an end stop reported */
#define CTLTW_P_LEARN 0x100u        /* the map learned: the two nodes around the target */
#define CTLTW_P_ANCHOR 0x200u       /* ... its first point: the frame (off) moved */
#define CTLTW_P_CALIB 0x400u        /* an end stop moved the estimate, p_ref and the map's frame */
#define CTLTW_P_LEADCUT 0x800u      /* p_ref held within FM_LEAD of p_hat */
#define CTLTW_P_DUCUT 0x1000u       /* the PI increment cut at CTLTW_FM_DU_MAX */
#define CTLTW_P_TAKEUP 0x2000u      /* backlash still pending in the servo's drive */
#define CTLTW_P_HOLDSET 0x4000u     /* a feed-forward over a period's full-duty move: the integral waits */
#define CTLTW_P_HOLDING 0x8000u     /* servo near its goal, integral waiting (hold) */
#define CTLTW_P_GATED 0x10000u      /* feed-forward dropped: against the target's change or the flow */
#define CTLTW_P_COVER 0x20000u      /* P adds part of the target's change (0 < k < dq or dq < k < 0) */
#define CTLTW_P_PEND 0x40000u       /* the last drive accounted at the step's start (no ctl_applied) */
#define CTLTW_P_MOVED 0x80000u      /* a drive accounted moved the estimate */
#define CTLTW_P_STILL 0x100000u     /* a drive accounted under the break-away duty: no move */
#define CTLTW_P_NOCLOSE 0x200000u   /* over-pressure (CTL_NO_CLOSE alone) held p_ref or cut a closing drive */
#define CTLTW_P_FRAME 0x400000u     /* p_hat or p_ref outside 0 .. 1 (the frame beyond the stroke) */
#define CTLTW_P_GAIN 0x800000u      /* the gain schedule inside its clamps (frame set) */
#define CTLTW_P_GAIN_MIN 0x1000000u /* ... clamped at CTLTW_FM_GS_MIN */
#define CTLTW_P_GAIN_MAX 0x2000000u /* ... clamped at CTLTW_FM_GS_MAX */
#define CTLTW_P_INTOSTOP 0x4000000u /* a drive into the stop a report set: no move */
#define CTLTW_P_UNLEARNED 0x8000000u /* feed-forward cut to 13/16: the map around a target not learned */
#define CTLTW_P_RESTZERO 0x10000000u /* inside the band, |e| <= target / 1024: no integral either */
#define CTLTW_P_STALL 0x20000000u   /* a stall found: the smallest pulses taken back, the smallest pulse grows */
#define CTLTW_P_HUNT 0x40000000u    /* hunting found: the take-up shrinks */
typedef struct {
    double drive;                   /* fraction of full duty, + toward closed (ctltw_fm_applied: the drive given) */
    int sat;                        /* what ctl_saturated() reports after the step */
    int sat_edge;                   /* the firmware's drive may lie across full duty: sat may differ */
    double ref_lo, ref_hi;          /* stroke: what the firmware's p_ref minus the twin's can be */
    double hat_lo, hat_hi;          /* ... p_hat's */
    double take_lo, take_hi;        /* ... takeup's */
    double off_lo, off_hi;          /* ... off's (off_iv 1: checked; 0 after a saturated lookup learned) */
    int off_iv;
    double drive_lo, drive_hi;      /* duty: the same for the drive (a flagged branch aside) */
    double gain;                    /* the gain schedule (1 = unscaled; ctl_st.fm.gain / 256) */
    double gain_lo, gain_hi;        /* the firmware's gain (Q8 / 256) minus the twin's: p_hat's interval
                                     * through the opening, each lookup rounded (+-0.5 of a table's
                                     * unit), the products' and the result's shifts (+-0.5), FM_GS_K
                                     * in Q10 and the clamps in Q8 */
    double gain_tab;                /* Q8 LSB: the lookups' rounding alone through the sum, K s_i (0.5
                                     * (a + b) / 256 + 0.5 (c + d) / 32768), for the test's tolerance */
    double du;                      /* stroke: the PI increment before the gain (after its cut) */
    unsigned border;                /* CTLTW_B_* */
    unsigned path;                  /* CTLTW_P_* */
} ctltw_fm_out_t;

/* The twin's state from the firmware's (Q15 closures, x100 L/min flows) and ctl.c's ctl_last
 * (last: what ctl_step returned last, or the drive ctl_reset was given); first as above. */
void ctltw_fm_load(ctltw_fm_t *tw, const fm_state_t *fm, int first, q15_t last);
/* One step of ffmap (fm_step of ffmap.c) on the twin's state. */
ctltw_fm_out_t ctltw_fm_step(ctltw_fm_t *m, const ctltw_fm_in_t *in);
/* ctl_applied(drive, limit): the valve got drive (duty) this period and sits at the stops in
 * limit (CTL_AT_*): calibration there, then the motion accounted. */
ctltw_fm_out_t ctltw_fm_applied(ctltw_fm_t *m, double drive, int limit, double travel);

/* ---- the peers: aog (AgOpenGPS Rate Control, valve mode) and raven (Raven's valve cal) ----------
 * Each returns the drive (fraction of full duty, + = more boom flow) its description asks for,
 * before the output stage (ctl_out.c); 0 within the dead band. Flows in L/min. */
typedef struct {
    double kp, ki, kd;              /* the user's settings: PWM counts a L/min (ki, kd a 50 ms loop) */
    double min_pwm, max_pwm;        /* PWM counts of 255 */
    double integ;                   /* PWM counts */
    double y1;                      /* L/min: the last actual flow */
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

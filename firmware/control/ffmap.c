/* ffmap.c: best, the project's own controller: a position servo on an estimate of the valve, a learned map. */
#include "ctl_int.h"
#include "params.h"

/* the state: at a fixed address (no pointer to load) */
#define M (&ctl_st.fm)

/*
 * A position servo on an estimate of the valve's closure, which nothing measures: p_hat is the
 * drive the valve really got (ctl_applied), integrated: motion = duty / T_travel a period, the
 * backlash taken up first, nothing below the break-away duty (the parameters Valve time,
 * Backlash and Min duty). Real end stops calibrate the estimate (FM_AT_CLOSED, FM_AT_OPEN, with
 * room above "closed"); over-pressure refuses closing but is not a stop. The reference closure
 * p_ref moves by a feed-forward from a learned map (flow -> closure) when the target changes and
 * by an incremental PI feedback scaled by a gain schedule; a deadband with hysteresis rests the
 * feedback near the target. Two checks adapt to a valve other than the parameters say: a stall
 * check (the smallest pulses do not move it: they grow) and a hunting check (reversals overshoot:
 * the take-up shrinks). docs/CONTROLLERS.md has the design and the figures that chose it.
 */
void fm_init(void)
{
    uint8_t i;
    for (i = 0; i < FM_NODES; i++)
        M->node[i] = (int16_t)(i * FM_DEF_SLOPE);
    M->seen[0] = M->seen[1] = M->seen[2] = 0;
    M->p_hat = Q15(0.5);
    M->p_ref = Q15(0.5);
    M->takeup = 0;
    M->dir = 0;
    M->calm = 0;
    M->warm = 0;
    M->rest = 0;
    M->pend = 0;
    M->hold = 0;
    M->off = 0;
    M->cal = 0;
    M->stopd = 0;
    M->gain = 256;
    M->stall_n = 0;
    M->stall_mv = 0;
    M->brk = 0;
    M->brk_age = 0;
    M->rev = 0;
    M->hunt = 0;
    M->tk_cut = 0;
}

/* map(q): closure for a target flow, Q15 stroke. */
static int16_t fm_map(int16_t q) CTL_SHARED
{
    uint8_t i;
    uint16_t f;
    int16_t a;
    if (q < 0)
        q = 0;
    if (q >= (FM_NODES - 1) << FM_BIN_SHIFT)
        return fx_add_sat(M->off, M->node[FM_NODES - 1]);
    i = (uint8_t)(q >> FM_BIN_SHIFT);
    f = (uint16_t)q & ((1u << FM_BIN_SHIFT) - 1u);  /* 0..511 */
    a = M->node[i];
    /* nodes more than a stroke apart (the estimate's frame is +-1 stroke) would wrap as int16 */
    return fx_sat16((int32_t)M->off + a
                    + ((MUL(fx_sat16((int32_t)M->node[i + 1] - a), (int16_t)f) + 256) >> FM_BIN_SHIFT));
}

static const __code uint8_t fm_bit[8] = {1, 2, 4, 8, 16, 32, 64, 128};

/* 1 when both nodes around flow q were learned from the loop. */
static uint8_t fm_learned(int16_t q) CTL_SHARED
{
    uint8_t i;
    if (q < 0 || q >= (FM_NODES - 1) << FM_BIN_SHIFT)
        return 0;
    i = (uint8_t)(q >> FM_BIN_SHIFT);
    return (M->seen[i >> 3] & fm_bit[i & 7]) && (M->seen[(i + 1) >> 3] & fm_bit[(i + 1) & 7]);
}

static void fm_learn(int16_t q) CTL_SHARED
{
    uint8_t i, near;
    int16_t f, err, d0, d1;
    if (q < 0 || q >= (FM_NODES - 1) << FM_BIN_SHIFT)
        return;
    i = (uint8_t)(q >> FM_BIN_SHIFT);
    f = (int16_t)((uint16_t)q & ((1u << FM_BIN_SHIFT) - 1u));
    near = f < (1 << (FM_BIN_SHIFT - 1)) ? i : (uint8_t)(i + 1);
    err = fx_sub_sat(M->p_hat, fm_map(q));
    if (!(M->seen[0] | M->seen[1] | M->seen[2])) {
        M->off = fx_add_sat(M->off, err);   /* the first point learned anchors the whole default curve */
    } else {
        /* the two nodes around q move toward the estimate, each by its share (rate 1/4) */
        d0 = (int16_t)((MUL(err, (int16_t)((1 << FM_BIN_SHIFT) - f)) + (1L << (FM_BIN_SHIFT + FM_LR_SHIFT - 1)))
                       >> (FM_BIN_SHIFT + FM_LR_SHIFT));
        d1 = (int16_t)((MUL(err, f) + (1L << (FM_BIN_SHIFT + FM_LR_SHIFT - 1))) >> (FM_BIN_SHIFT + FM_LR_SHIFT));
        M->node[i] = fx_add_sat(M->node[i], d0);
        M->node[i + 1] = fx_add_sat(M->node[i + 1], d1);
    }
    M->seen[near >> 3] |= fm_bit[near & 7];
}

/* An end stop tells where the valve is: the estimate jumps there, and the reference and the
 * map (learned in the estimate's frame) move with it, so nothing learned is lost. */
static void fm_calibrate(int16_t at) CTL_SHARED
{
    int16_t sh = fx_sub_sat(at, M->p_hat);
    if (!sh)
        return;
    M->p_hat = at;
    M->p_ref = fx_add_sat(M->p_ref, sh);
    M->off = fx_add_sat(M->off, sh);    /* the map's nodes are kept relative to M->off */
}

/* A real end stop (CTL_AT_* in limit) sets the estimate there: the closure is known from then on
 * (the gain schedule needs it). Over-pressure (CTL_NO_CLOSE) is not a stop. */
void fm_stops(uint8_t limit) CTL_SHARED
{
    if (limit & (CTL_AT_CLOSED | CTL_AT_OPEN)) {
        fm_calibrate((limit & CTL_AT_CLOSED) ? FM_AT_CLOSED : FM_AT_OPEN);
        M->cal = 1;
        M->stopd = (limit & CTL_AT_CLOSED) ? 1 : -1;
    }
}

/* The valve got drive d for one period: move the estimate (the backlash is taken up first).
 * Below the break-away duty the valve does not move. */
void fm_account(q15_t d) CTL_SHARED
{
    int16_t mv, c;
    int8_t s;
    if (d < CTL_STICTION && d > -CTL_STICTION)
        return;
    if (d == Q15_MIN)
        d = -Q15_MAX;               /* -32768 has no int16 magnitude */
    s = d > 0 ? 1 : -1;
    /* driven into the stop a report has put it at (the valve module's retry): it cannot go
     * further, and the frame must not move along with each retry (docs/CONTROLLERS.md) */
    if (s == M->stopd)
        return;
    M->stopd = 0;
    if (s != M->dir) {
        M->takeup = FM_BACKLASH - M->tk_cut;
        M->dir = s;
    }
    mv = (int16_t)((MUL((int16_t)(d > 0 ? d : -d), ctl_inv_travel) + 16384) >> 15);   /* Q15 stroke */
    c = mv < M->takeup ? mv : M->takeup;
    M->takeup -= c;
    mv -= c;
    M->p_hat = fx_add_sat(M->p_hat, s > 0 ? mv : (int16_t)-mv);
    /* small pulses one way, up to Min duty + brk + Min duty (fm_step looks for a stall; it keeps
     * the flow and the speed the run started from) */
    if (c == 0 && mv > 0 && (d > 0 ? d : -d) <= 2 * (int32_t)ctl_stiction + M->brk) {
        if (M->stall_n < 255)
            M->stall_n++;
        M->stall_mv = fx_add_sat(M->stall_mv, mv);
    } else {
        M->stall_n = 0;
        M->stall_mv = 0;
    }
    /* driven past a stop that nobody reported: the estimate was that much ahead of the valve
     * (a stop believed early, a valve that stuck, or a frame not yet set by a stop): the valve is
     * at most at the stop, the frame moves. This also keeps the estimate and the reference off
     * the int16 ends, where the servo would see no move left to make (a valve stuck for 30 s
     * before any stop was found ran the estimate to -32768, and the loop stalled there) */
    if (M->p_hat > FM_AT_CLOSED)
        fm_calibrate(FM_AT_CLOSED);
    else if (M->p_hat < FM_AT_OPEN)
        fm_calibrate(FM_AT_OPEN);
}

/* Table t between node i and i + 1 at the fraction f (Q15 of the node spacing), linear. With the
 * spacing 1 << SH and x's low bits r, f = r << (15 - SH) gives exactly (d r + 2^(SH-1)) >> SH. */
static int16_t fm_tab(const FX_CODE int16_t *t, uint8_t i, int16_t f) CTL_SHARED
{
    int16_t a = t[i];
    return (int16_t)(a + ((MUL((int16_t)(t[i + 1] - a), f) + 16384L) >> 15));
}

/* The gain schedule, Q8 (256 = 1): 80 L/min a stroke over how much boom flow a stroke of the
 * bypass moves here. With an equal-percentage valve that sensitivity is ln(R) hm(Q_v, Q_b P/(P -
 * Pc)): large with a fixed PTO (the bypass carries most of the pump), about a third of that with
 * a coupled PTO at low speed (the valve nearly shut), where the schedule raises the feedback.
 * The reciprocals come from tables, no divide; below the first pressure node (64 kPa, just
 * above the check valves) the table's straight line from the capped 0 kPa node would
 * overestimate 1/sqrt(P) and underestimate 1 - Pc/P, so the pressure is taken as 64 kPa there.
 * Only once an end stop has set the estimate's frame (the closure must be known). */
/* q: the target flow (x100 L/min), the boom's in steady state; a dead meter would read 0 */
static int16_t fm_gain(int16_t q, uint16_t p_kpa) CTL_SHARED
{
    int32_t c = (int32_t)M->p_hat - FM_AT_OPEN;  /* closure, Q15 */
    int32_t s;
    int16_t a, b;
    uint16_t o;
    if (!M->cal)
        return 256;
    o = (uint16_t)(32767 - (c < 0 ? 0 : c > 32767 ? 32767 : c));   /* opening, Q15 */
    if (p_kpa > 1599)
        p_kpa = 1599;
    if (p_kpa < 64)
        p_kpa = 64;
    if (q < 0)
        q = 0;
    if (q > 8191)
        q = 8191;
    /* 1/Q_v = 1/Cv(o) 1/sqrt(P), Q16 of 1/(L/min); (1 - Pc/P)/Q_b, Q16 */
    /* (the table lookups multiply too: on the 8051 MUL's operands are shared, so one at a time) */
    a = fm_tab(fm_inv_cv, (uint8_t)(o >> 11), (int16_t)((o & 2047u) << 4));
    b = fm_tab(fm_inv_sqp, (uint8_t)(p_kpa >> 6), (int16_t)((p_kpa & 63u) << 9));
    s = (MUL(a, b) + 128) >> 8;
    a = fm_tab(fm_pc_p, (uint8_t)(p_kpa >> 6), (int16_t)((p_kpa & 63u) << 9));
    b = fm_tab(fm_inv_q, (uint8_t)((uint16_t)q >> 8), (int16_t)(((uint16_t)q & 255u) << 7));
    s += (MUL(a, b) + 16384) >> 15;
    if (s > 8191)
        s = 8191;
    s = (MUL((int16_t)s, FM_GS_K) + 512) >> 10;
    return (int16_t)(s < FM_GS_MIN ? FM_GS_MIN : s > FM_GS_MAX ? FM_GS_MAX : s);
}

/* ---- the control step, in named steps (each inlined into fm_step) ------------------------- */
/* The step's values (M->w): e = target - flow (clamped), y the flow, q the target, dq the
 * target's change since the last step, aq |dq|, ff the feed-forward, du the feedback. */
#define W (&ctl_st.fm.w)

/* A drive nobody reported is taken as applied; a restart begins from rest; end stops calibrate
 * the estimate (over-pressure, CTL_NO_CLOSE, is not a stop). */
CTL_STEP void fm_begin(void) CTL_SHARED
{
    if (M->pend) {
        M->pend = 0;
        fm_account(ctl_last);       /* nobody said what the valve got: what we asked */
    }
    if (ctl_first) {
        M->y1 = W->y;
        M->t1 = W->q;
        M->p_ref = M->p_hat;
        M->calm = 0;
        M->warm = 0;
        M->rest = 0;
        M->hold = 0;
        ctl_first = 0;
    }
    fm_stops(ctl_in->valve_limit);
}

/* Adaptation to the valve. A stall: FM_STALL_N smallest pulses one way, the target and the
 * speed steady (a coupled PTO's pump follows the speed), the flow not moved by the deadband
 * while the error still asks for more that way: the valve is stiffer than Min duty says. The
 * estimate takes the pulses back and the smallest pulse grows (brk). brk and the hunting
 * check's tk_cut step back after FM_BRK_AGE quiet periods; the last reversal ages. */
CTL_STEP void fm_adapt_valve(void) CTL_SHARED
{
    int16_t c;
    int32_t k;
    if (M->stall_n >= FM_STALL_N) {
        c = (int16_t)(W->y - M->stall_y);
        k = (int32_t)ctl_in->speed_kmh_x100 - M->stall_v;
        if ((c < 0 ? -c : c) <= (W->q >> FM_DB_IN) && (M->dir > 0 ? W->e > 0 : W->e < 0)
            && ((k < 0 ? -k : k) << 6) <= (int32_t)ctl_in->speed_kmh_x100) {
            c = M->dir > 0 ? M->stall_mv : (int16_t)-M->stall_mv;
            M->p_hat = fx_sub_sat(M->p_hat, c);
            M->p_ref = fx_sub_sat(M->p_ref, c);     /* not a full-duty burst to make them up */
            if (M->brk < FM_BRK_MAX)
                M->brk += FM_BRK_STEP;
            M->brk_age = 0;
        }
        M->stall_n = 0;
        M->stall_mv = 0;
    }
    if ((M->brk > 0 || M->tk_cut > 0) && ++M->brk_age >= FM_BRK_AGE) {
        if (M->brk > 0)
            M->brk -= FM_BRK_STEP;
        if (M->tk_cut > 0)
            M->tk_cut -= FM_TK_STEP;
        M->brk_age = 0;
    }
    /* the last reversal ages; too old, the run of close reversals is over */
    if (M->rev != 0) {
        M->rev += M->rev > 0 ? 1 : -1;
        if (M->rev > ctl_hunt_gap || M->rev < -ctl_hunt_gap) {
            M->rev = 0;
            M->hunt = 0;
        }
    }
}

/* Feed-forward: map(target now) - map(target before), Q15 stroke. Only the way the target went
 * (a map folded by a coupled PTO's low-speed points would open the bypass on a rising target),
 * and only while the flow is not already past the target that way (a coupled PTO's pump follows
 * the throttle before the tractor does); FM_FF_UNLEARNED of it where the map around either
 * target is not learned (interpolated from nodes learned at other flows it overestimates the
 * move; the feedback finishes it). A move bigger than one period at full duty holds the integral
 * for FM_HOLD periods (the meter shows it late; the integral would count the error the move is
 * still removing, and overshoot). */
CTL_STEP void fm_feedforward(void) CTL_SHARED
{
    int16_t q = W->q, e = W->e, dq = W->dq;
    int32_t d = (int32_t)fm_map(q) - fm_map(M->t1);
    int16_t band = q >> FM_DB_IN;
    if ((dq > 0 && d < 0) || (dq < 0 && d > 0) || (d > 0 && e < -band) || (d < 0 && e > band))
        d = 0;
    if (d != 0 && (!fm_learned(q) || !fm_learned(M->t1)))
        d = (MUL(fx_sat16(d), FM_FF_UNLEARNED) + 128) >> 8;
    if (d > ctl_inv_travel || d < -ctl_inv_travel)
        M->hold = FM_HOLD;
    else if (M->hold)
        M->hold--;
    W->ff = d;
}

/* Deadband with hysteresis: within target >> FM_DB_IN the feedback rests and the servo stops
 * where it is (no limit cycle of backlash take-ups and break-away pulses); it re-engages beyond
 * target >> FM_DB_OUT or when the target moves (|dq| > q/64, as for learning). */
CTL_STEP void fm_deadband(void) CTL_SHARED
{
    int16_t q = W->q;
    int16_t c = W->e < 0 ? (int16_t)-W->e : W->e;
    if (((int32_t)W->aq << 6) > q) {
        M->rest = 0;                /* the target moves: the loop follows it */
        M->stall_n = 0;             /* ... and the flow with it: no stall to tell, */
        M->stall_mv = 0;
        M->hunt = 0;                /* nor a hunt */
    }
    else if (M->rest) {
        if (c > (q >> FM_DB_OUT))
            M->rest = 0;
    } else if (c <= (q >> FM_DB_IN) && q > 0) {
        M->rest = 1;
        M->p_ref = M->p_hat;        /* entering the band stops the servo where it is */
    }
}

/* Feedback, du in Q12 x100 L/min. Inside the band a slow integral only (FM_REST_KI, none
 * within target >> FM_REST_E0). Outside it an incremental PI: P on the measurement plus the part
 * of the target's change the feed-forward does not cover (FM_COVER: flow per stroke of the
 * default slope), so a step is not kicked twice where the map follows the plant; the integral
 * held while the servo still travels (it would wind up) and while M->hold lasts. */
CTL_STEP void fm_feedback(void) CTL_SHARED
{
    int16_t e = W->e, dq = W->dq;
    int32_t du, k;
    int16_t c, need;
    if (M->rest) {
        c = (int16_t)(W->q >> FM_REST_E0);
        c = e > c ? (int16_t)(e - c) : e < -c ? (int16_t)(e + c) : 0;
        du = MUL(FM_REST_KI, c);
    } else {
        k = dq - ((MUL(fx_sat16(W->ff), FM_COVER) + 16384) >> 15);
        if (dq >= 0)
            k = k < 0 ? 0 : k > dq ? dq : k;
        else
            k = k > 0 ? 0 : k < dq ? dq : k;
        du = MUL(FM_KP, fx_sat16((int32_t)M->y1 - W->y + k));
        need = fx_sat16(W->ff + M->p_ref - M->p_hat);
        if (need < FM_IGATE && need > -FM_IGATE && !M->hold)
            du += MUL(FM_KI, e);
    }
    W->du = du;
}

/* The reference p_ref moves by the feed-forward and the feedback (du_q4 * 0.2048 = Q15 stroke,
 * times the gain schedule), within FM_LEAD of the estimate, and not into a stop. */
CTL_STEP void fm_reference(void) CTL_SHARED
{
    int32_t d;
    M->gain = fm_gain(W->q, ctl_in->pressure_kpa);
    d = W->ff + ((MUL(fx_sat16((W->du + 128) >> 8), (int16_t)((FM_DU_F * M->gain + 128) >> 8)) + 32768L) >> 16);
    d += M->p_ref;
    if (d > (int32_t)M->p_hat + FM_LEAD)
        d = (int32_t)M->p_hat + FM_LEAD;
    if (d < (int32_t)M->p_hat - FM_LEAD)
        d = (int32_t)M->p_hat - FM_LEAD;
    M->p_ref = fx_sat16(d);         /* the estimate's frame: +-1 stroke around where it started */
    if (((ctl_in->valve_limit & CTL_CLOSE_BLOCKED) && M->p_ref > M->p_hat)
        || ((ctl_in->valve_limit & CTL_AT_OPEN) && M->p_ref < M->p_hat))
        M->p_ref = M->p_hat;
}

/* The servo: drive the move still needed, plus the backlash to take up on a reversal; a
 * reversal must be worth it (FM_REV_MIN, FM_REV_MIN_REST in the band). Hunting: FM_HUNT_N
 * reversals in a row, each within FM_HUNT_GAP(T) periods of the last and against the error the
 * last one was made for, shrink the take-up (tk_cut). Nothing or at least the smallest pulse
 * (Min duty + brk; under half of Min duty nothing); limits and stops as the output stage. */
CTL_STEP q15_t fm_servo(void) CTL_SHARED
{
    int16_t need, c, e = W->e;
    int8_t s;
    int32_t d, k;
    need = fx_sub_sat(M->p_ref, M->p_hat);
    s = need > 0 ? 1 : need < 0 ? -1 : 0;
    if (s != 0 && s != M->dir && (need < 0 ? -need : need) < (M->rest ? FM_REV_MIN_REST : FM_REV_MIN))
        s = 0, need = 0;
    if (s != 0 && s != M->dir) {
        if (M->rev != 0 && (M->rev > 0 ? e < 0 : e > 0) && ++M->hunt >= FM_HUNT_N) {
            M->hunt = 0;
            if (M->tk_cut <= FM_BACKLASH - FM_TK_MIN - FM_TK_STEP)
                M->tk_cut += FM_TK_STEP;
            M->brk_age = 0;
        }
        M->rev = e > 0 ? 1 : e < 0 ? -1 : 0;
    }
    if (s != 0 && s != M->dir)
        c = FM_BACKLASH - M->tk_cut;
    else if (s == 0)
        c = 0;                      /* nothing to do: no take-up either */
    else
        c = M->takeup;
    d = MUL(need + (s < 0 ? -c : c), ctl_travel);  /* Q15 drive */
    CTL_CLIP(d);
    k = (int32_t)CTL_STICTION + M->brk;   /* the smallest pulse: Min duty, more after a stall */
    if (d < k && d > -k)
        d = (d >= ctl_stiction_half) ? k : (d <= -ctl_stiction_half) ? -k : 0;
    CTL_STOP(d, ctl_in->valve_limit, CTL_CLOSE_BLOCKED);
    return (q15_t)d;
}

/* The map learns where the loop is calm (target steady, error under 1/16 of it, no limit, at or
 * above the minimum-flow speed) for FM_CALM periods, and not for FM_WARM periods after a
 * (re)start (the pump may still spin up, the line prime). */
CTL_STEP void fm_adapt_map(void) CTL_SHARED
{
    int16_t q = W->q, e = W->e;
    if (((int32_t)W->aq << 6) <= q && ((int32_t)(e < 0 ? -e : e) << 4) <= q && q > 0 && !ctl_sat && !ctl_in->valve_limit
        && ctl_in->speed_kmh_x100 >= (uint16_t)(param_v[P_MINF_SPEED] * 10u)) {
        if (M->calm < 255)
            M->calm++;
    } else {
        M->calm = 0;
    }
    if (M->warm < FM_WARM)
        M->warm++;
    else if (M->calm >= FM_CALM)
        fm_learn(q);
}

q15_t fm_step(void) CTL_SHARED
{
    q15_t d;
    W->e = ctl_clamp_e(ctl_in->target_lpm_x100 - ctl_in->flow_lpm_x100);
    W->y = ctl_in->flow_lpm_x100;
    W->q = ctl_in->target_lpm_x100;
    fm_begin();
    fm_adapt_valve();
    W->dq = (int16_t)(W->q - M->t1);
    W->aq = W->dq < 0 ? (int16_t)-W->dq : W->dq;
    fm_feedforward();
    fm_deadband();
    fm_feedback();
    fm_reference();
    d = fm_servo();
    M->pend = 1;                    /* accounted by ctl_applied() (or the next step) */
    fm_adapt_map();
    M->y1 = W->y;
    M->t1 = W->q;
    if (M->stall_n == 0) {
        M->stall_y = W->y;          /* where a run of smallest pulses starts from */
        M->stall_v = ctl_in->speed_kmh_x100;
    }
    ctl_k[0] = FM_KP;
    ctl_k[1] = FM_KI;
    ctl_k[2] = 0;
    ctl_last = d;
    return d;
}

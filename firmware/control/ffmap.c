/* ffmap.c: ffmap, the project's own controller: a damped PID with a deadband and a learnt speed feed-forward, an output stage that knows the valve's motor. */
#include "ctl_int.h"
#include "target.h"
#include "speed.h"

static __bit ffmap_warm;             /* warm reached FFMAP_WARM: the (re)start is over (the step asks it six times) */
__bit ffmap_rlim, ffmap_rl1;                  /* the last reversal near the smallest (ctl_int.h) */
static void ffmap_cap_up(void);

/* The incremental PID of eq. (7) on the common normalisation (ctl.c): the valve is asked for a
 * motion, drive = du * T_travel. The output stage makes the valve do it: running friction, break-
 * away (ffmap_stall, stepped back at a cycle of its resolution: ffmap_reversal), reversals worth
 * the backlash and, on a fast valve, their answer awaited (ffmap_out), a duty cap for a valve far
 * faster than told (ffmap_cap), a gentle closing near P max; the loop gain is learnt from how the
 * flow answers (ffmap_gain_adapt, ffmap_reversal) and cut at high pressure (ffmap_gain_at_p); a
 * deadband rests the valve near the target (ffmap_deadband); a feed-forward of the speed is learnt
 * from the lag a speed change leaves (ffmap_ff). docs/CONTROLLERS.md gives each rule, its constants
 * and why; tests/control/test_ffmap*.c and test_ctl.c pin them. */
/* The loop gain learnt from how the flow answers: reversals within FFMAP_OSC_GAP periods of each
 * other (an overshoot, a limit cycle: the valve is faster than told; FFMAP_OSC_GAP_SLOW at a steady
 * speed on a valve whose stroke takes FFMAP_SLOW_T periods at the learnt gain: its cycle through
 * the slack is longer) lower it by 1/8 after the first FFMAP_WARM periods of a (re)start, or in
 * them over FFMAP_P_HI_F's pressure (ffmap_gain_at_p: the bypass holds the flow hardest) or at a
 * steady target (not moved since the last reversal: a stiff valve's stick-slip cycle at the
 * starting gain); FFMAP_SLOW_N periods awake with the error one way (slower than told; a quarter as
 * many with the error beyond target >> FFMAP_BIG_SHIFT) raise it by 3/32; not with the drive at its
 * top and the gain at or over FFMAP_G_INIT: no gain moves the valve faster there (a slow valve's
 * slack, taken up at full duty after each reversal, would raise it until it cycles at full duty
 * both ways). Nothing is raised against a stop or a refusal the error pushes toward, nor in the
 * first FFMAP_WARM periods of a (re)start while the gain is where the start found it (the line's
 * filling is not the valve's slowness); a start's swings may cut it there and it comes back at
 * once, unless the duty cap holds a valve that swung the flow (ffmap_cap): there the cut is the
 * cure. */
CTL_STEP void ffmap_gain_adapt(int16_t e) CTL_SHARED
{
    if (!ffmap_warm && ++ctl_st.fm.warm >= FFMAP_WARM)
        ffmap_warm = 1;
    if (ctl_st.fm.rest || (e > 0) != (ctl_st.fm.e1 > 0)
        || (!ffmap_warm && (ctl_st.fm.gain >= ctl_st.fm.gain_start || ctl_st.fm.cap != 255))
        || (ctl_in->valve_limit & (e > 0 ? CTL_CLOSE_BLOCKED : CTL_AT_OPEN))) {
        ctl_st.fm.slow_n = 0;
    } else if ((!ctl_st.fm.cap_run || ctl_st.fm.gain < FFMAP_G_INIT)
               && (ctl_st.fm.slow_n += ctl_st.fm.err_big ? 4 : 1) >= FFMAP_SLOW_N) {
        ctl_st.fm.slow_n = 0;
        if (ctl_st.fm.gain < FFMAP_G_MAX)
            ctl_st.fm.gain += (ctl_st.fm.gain >> 4) + (ctl_st.fm.gain >> 5);
        ffmap_cap_up();
    }
    if (ctl_st.fm.rev_age < 255)
        ctl_st.fm.rev_age++;
}

/* The speed's feed-forward. With the pump at a fixed PTO speed the bypass must move as the ground
 * speed does, and a loop on the error alone lags through every change of speed; with the pump on
 * the wheels the boom's flow follows the speed by itself. Which of the two this sprayer is, and how
 * far its valve moves the flow, is learnt from the error a speed change leaves: ff_gain, the drive
 * per x100 L/min the speed moves the target a period, rises by 2 each period the flow lags a ramp
 * of the target (its change filtered over about 2^FFMAP_FF_RSH periods beyond FFMAP_FF_RAMP) by
 * more than target >> FFMAP_FF_ESH, and falls by 2 each period it leads; from FFMAP_FF_LEAD on, by
 * 2 more every 2^FFMAP_FF_RUN_SH periods taught the same way in a row (ff_run: a slow valve on a
 * fixed PTO needs hundreds; near its value the lags and leads alternate and the step stays 2);
 * nothing in the first FFMAP_WARM periods, at rest or against a stop, nor in the FFMAP_ANSWER
 * periods after a reversal (the loop's own swing). While ff_gain is under FFMAP_FF_LEAD and the
 * wheel unlearnt (speed_learnt), only a ramp over target >> 4 counts: the wheel steps the target by
 * a few percent a pulse, which the flow never follows. Only a change of the target that the speed
 * made counts, the speed moving the same way (not the minimum-flow rule, not a section, not the
 * rate). The drive is ff_gain times that change filtered over about 2^FFMAP_FF_RSH periods: at a
 * steady speed the wheel's pulses move the target up and back by about a percent. */
/* the most used values in the direct RAM (the cheapest addressing; the step never runs inside
 * itself), the others in the controllers' union (XRAM). This period's error: */
static __data int16_t ffmap_e;
static __bit ffmap_hi_p;                   /* the pressure over 360 kPa this period (FFMAP_P_HI_F) */
static __bit ffmap_hi_t;                   /* the target's pressure over 400 kPa (FFMAP_P_T_F) */
static __bit ffmap_ff_lag;                 /* ff_gain was last taught up (the flow lagged) */
/* The step's scratch in the direct RAM: 4 bytes that each phase of the step names for what it
 * holds there (the phases run one after the other and keep nothing in them across the step). */
static __data union {
    struct {
        uint16_t speed;             /* x100 km/h: this period's speed */
        int16_t dq;                 /* x100 L/min: the target's change the speed made */
    } ff;                           /* ffmap_ff, the feed-forward's input */
    struct { uint16_t band, abs_e; } ffl;  /* ffmap_ff's learning, x100 L/min: target >> FFMAP_FF_ESH, |error| */
    uint16_t cap_next;              /* ffmap_cap_up: the cap raised by an eighth, before its limit */
    struct {
        uint16_t lim;               /* x100 L/min: target >> FFMAP_CAP_SH */
        int16_t dq;                 /* x100 L/min: the flow's change the way the valve ran */
    } cap;                          /* ffmap_cap */
    uint16_t top;                   /* ffmap_cap_limit: the top duty, Q15 (the cap, at least the smallest pulse) */
    struct { uint16_t d, k; } rev;  /* ffmap_reversal: Q15 the reversal's duty, the smallest pulse */
    struct { uint16_t root; int16_t bit; } gp;  /* ffmap_gain_at_p: Q8 floor(sqrt(FFMAP_P_REF / P))
                                                 * built bit by bit, the bit being tried */
} ffmap_w;

static void ffmap_ff(void)
{
    speed_set_plain(ctl_st.fm.ff_gain < FFMAP_FF_LEAD);
    ffmap_w.ff.speed = ctl_in->speed_kmh_x100;
    ffmap_w.ff.dq = ctl_in->target_lpm_x100 - ctl_st.fm.target_last;
    if (!ctl_st.fm.speed_last || (ffmap_w.ff.speed > ctl_st.fm.speed_last ? ffmap_w.ff.dq <= 0
                   : ffmap_w.ff.speed == ctl_st.fm.speed_last || ffmap_w.ff.dq >= 0))
        ffmap_w.ff.dq = 0;
    ctl_st.fm.speed_last = ffmap_w.ff.speed;
    ctl_st.fm.ramp += ffmap_w.ff.dq - (ctl_st.fm.ramp >> FFMAP_FF_RSH);
    ctl_st.fm.ff_drive = 0;
    if (ctl_st.fm.rest)
        return;
    ffmap_w.ffl.band = (uint16_t)(ctl_in->target_lpm_x100 >> FFMAP_FF_ESH);
    ffmap_w.ffl.abs_e = ffmap_e < 0 ? -ffmap_e : ffmap_e;
    if (ffmap_warm && !ctl_in->valve_limit && ffmap_w.ffl.abs_e > ffmap_w.ffl.band
        && ctl_st.fm.rev_age >= FFMAP_ANSWER
        && (uint16_t)(ctl_st.fm.ramp < 0 ? -ctl_st.fm.ramp : ctl_st.fm.ramp)
               > (speed_plain && !speed_learnt ? ffmap_w.ffl.band << FFMAP_FF_OFF_SH : FFMAP_FF_RAMP)) {
        if (((ctl_st.fm.ramp ^ ffmap_e) >= 0) != ffmap_ff_lag) {
            ffmap_ff_lag = !ffmap_ff_lag;   /* the same sign: the flow lags */
            ctl_st.fm.ff_run = 0;          /* the run starts anew: taught the other way */
        }
        ctl_st.fm.ff_run += ctl_st.fm.ff_run < 120;
        if (ffmap_ff_lag) {         /* (never under 0: 2 under FFMAP_FF_LEAD, at most 32 over) */
            if (ctl_st.fm.ff_gain < FFMAP_FF_MAX)
                ctl_st.fm.ff_gain += ctl_st.fm.ff_gain < FFMAP_FF_LEAD
                                     ? 2 : 2 + ((ctl_st.fm.ff_run >> FFMAP_FF_RUN_SH) << 1);
        } else if (ctl_st.fm.ff_gain) {
            ctl_st.fm.ff_gain -= ctl_st.fm.ff_gain < FFMAP_FF_LEAD
                                 ? 2 : 2 + ((ctl_st.fm.ff_run >> FFMAP_FF_RUN_SH) << 1);
        }
    }
    /* nothing while the flow is past the target the way it would push, by a big error (ff_gain is
     * learnt slowly); no closing while the line is over 360 kPa (ffmap_hi_p, the last period's)
     * and the error filtered over 4 periods (the wheel's jitter) is over the band the other way:
     * near P max the closing would hold back the loop's opening. */
    if ((ctl_st.fm.err_big || (ffmap_hi_p && ctl_st.fm.err_filt < -(int16_t)ffmap_w.ffl.band))
        && (ctl_st.fm.ramp ^ ffmap_e) < 0)
        return;
    ctl_st.fm.ff_drive = MUL(ctl_st.fm.ramp >> FFMAP_FF_RSH, ctl_st.fm.ff_gain);
}

/* The duty cap: how fast the valve may run, learnt from how fast the flow answers it. A valve much
 * faster than told, on a pump and bypass far bigger than the boom needs, moves the flow by more in
 * one period at full duty than the loop sees in time (the meter's lag, the motor's coast and the
 * backlash carry it past the target): at full duty a smaller gain changes nothing, a lower top
 * speed does. After FFMAP_CAP_N periods in a row at the cap one way, a
 * period whose flow moved that way by more than target >> FFMAP_CAP_SH takes a quarter off the cap
 * (down to FFMAP_CAP_MIN), one that moved by less than half of that gives an eighth back, as does
 * the gain's raise (the valve is slower than the cap lets it be). Never under the smallest pulse;
 * in RAM only (a valve this fast shows itself in its first swing). */
static void ffmap_cap_up(void)
{
    ffmap_w.cap_next = ctl_st.fm.cap + (ctl_st.fm.cap >> 3) + 1;
    ctl_st.fm.cap = ffmap_w.cap_next > 255 ? 255 : (uint8_t)ffmap_w.cap_next;
}

/* each period before the output stage: the flow's change, judged after FFMAP_CAP_N at the cap */
static void ffmap_cap(void)
{
    ffmap_w.cap.dq = ctl_in->flow_lpm_x100 - ctl_st.fm.flow_last;
    ctl_st.fm.flow_last = ctl_in->flow_lpm_x100;
    ctl_st.fm.cap_run_before = ctl_st.fm.cap_run;
    ctl_st.fm.cap_run = 0;
    if (ctl_st.fm.cap_run_before < FFMAP_CAP_N)
        return;
    if (ctl_st.fm.dir < 0)
        ffmap_w.cap.dq = -ffmap_w.cap.dq;
    ffmap_w.cap.lim = ctl_in->target_lpm_x100 >> FFMAP_CAP_SH;
    if (ffmap_w.cap.dq > (int16_t)ffmap_w.cap.lim) {
        if (ctl_st.fm.cap > FFMAP_CAP_MIN)
            ctl_st.fm.cap -= ctl_st.fm.cap >> 2;
    } else if (ffmap_w.cap.dq < (int16_t)(ffmap_w.cap.lim >> 1)) {
        ffmap_cap_up();
    }
    if (ctl_st.fm.cap_run_before == 255)
        ctl_st.fm.cap_run_before--;
}

/* The duty d at most the cap, which is at least the smallest pulse; a duty within 1/256 of full
 * duty under the cap counts as at the cap (cap_run_before 255: a reversal). */
static uint16_t ffmap_cap_limit(uint16_t d, uint16_t smallest) CTL_SHARED
{
    ffmap_w.top = smallest;
    if ((uint8_t)(ffmap_w.top >> 7) < ctl_st.fm.cap)
        ffmap_w.top = ((uint16_t)ctl_st.fm.cap << 7) | 0x7F;
    if (d >= (ffmap_w.top & 0xFF80u)) {
        if (d > ffmap_w.top)
            d = ffmap_w.top;
        ctl_st.fm.cap_run = ctl_st.fm.cap_run_before + 1;
    }
    return d;
}

/* Deadband with hysteresis on the filtered error; the target moving wakes the loop. Past the
 * target the way it last moved (ffmap_up) the valve rests only within target >> FFMAP_DB_PAST: a rest
 * there is the change's overshoot (0.3 % of the level, 2 % of a small change). */
__bit ffmap_up;
CTL_STEP void ffmap_deadband(int16_t e, int16_t q) CTL_SHARED
{
    int16_t c, dq = (int16_t)(q - ctl_st.fm.target_last);
    uint8_t c2;
    ctl_st.fm.err_filt = (int16_t)(ctl_st.fm.err_filt + ((e - ctl_st.fm.err_filt + 2) >> 2));
    c = ctl_st.fm.err_filt < 0 ? (int16_t)-ctl_st.fm.err_filt : ctl_st.fm.err_filt;
    c2 = (uint16_t)(dq < 0 ? -dq : dq) > (uint16_t)(q >> FFMAP_MOVE_SHIFT);  /* |dq| 2^6 > q (q >= 0) */
    ctl_st.fm.moved |= c2;
    if (c2)
        ffmap_up = dq > 0;
    if (c2 || (ctl_st.fm.rest && c > (q >> FFMAP_DB_OUT))) {
        if (ctl_st.fm.rest && (ctl_carry > 0) != (e > 0))
            ctl_carry = 0;          /* waking: what the slow integral owed the other way is stale */
        ctl_st.fm.rest = 0;
    } else if (!ctl_st.fm.rest
               && c <= (q >> ((ctl_st.fm.err_filt < 0) == ffmap_up ? FFMAP_DB_PAST : FFMAP_DB_IN)) && q > 0) {
        ctl_st.fm.rest = 1;
        ctl_carry = 0;              /* entering the band: nothing owed */
        ctl_st.fm.stall_n = 0;
    }
}

/* A stall: FFMAP_STALL_N smallest pulses one way (or twice as many up to twice the smallest) and
 * the flow has not moved that way by target >> FFMAP_STALL_MOVE (whatever the target did
 * meanwhile; the meter's lag after a motion is less), the error still asking for that way: the
 * smallest pulse grows (from under Min duty, back to it), or, within 2 FFMAP_STALL_N periods of a
 * reversal, rev_min by 1/8 up to FFMAP_REV_MIN (the pulses went into a slack bigger than told).
 * brk_extra steps back after FFMAP_BRK_AGE periods without one. A lone smallest pulse (ffmap_out)
 * that stepped the flow its way by more than target >> FFMAP_LONE_SH, the speed steady: the valve
 * moves on less (a fast valve's break-away under Min duty, each pulse a swing past the band); the
 * smallest pulse and the running friction step down by FFMAP_BRK_DN, to half Min duty. */
CTL_STEP void ffmap_stall(int16_t e, int16_t q) CTL_SHARED
{
    int32_t k;
    if (ctl_st.fm.stall_n >= 2 * FFMAP_STALL_N) {
        k = (int32_t)ctl_in->flow_lpm_x100 - ctl_st.fm.stall_flow;
        if (ctl_st.fm.dir <= 0)
            k = -k;
        if (k <= (q >> FFMAP_STALL_MOVE) && (ctl_st.fm.dir > 0 ? e > 0 : e < 0)) {
            if (ctl_st.fm.rev_age < 2 * FFMAP_STALL_N && ctl_st.fm.rev_min < FFMAP_REV_MIN)
                ctl_st.fm.rev_min += ctl_st.fm.rev_min >> 3;    /* the reversal's slack not taken up */
            else if (ctl_st.fm.brk_extra < 0)
                ctl_st.fm.brk_extra = 0;
            else if (ctl_st.fm.brk_extra <= FFMAP_BRK_MAX - FFMAP_BRK_STEP)
                ctl_st.fm.brk_extra += FFMAP_BRK_STEP;
            ctl_st.fm.brk_age = 0;
        }
        ctl_st.fm.stall_n = 0;
    }
    if (ctl_st.fm.lone_n && !--ctl_st.fm.lone_n) {
        k = ((int32_t)ctl_in->flow_lpm_x100 - ctl_st.fm.lone_flow) * ctl_st.fm.dir;
        if (k > (q >> FFMAP_LONE_SH) && ctl_st.fm.brk_extra <= 0 && ffmap_warm && FFMAP_STEADY()
            && ctl_st.fm.brk_extra - FFMAP_BRK_DN >= -(CTL_STICTION >> 1))
            ctl_st.fm.brk_extra -= FFMAP_BRK_DN;
    }
    if (ctl_st.fm.brk_extra > 0 && ++ctl_st.fm.brk_age >= FFMAP_BRK_AGE) {
        ctl_st.fm.brk_extra -= FFMAP_BRK_STEP;
        ctl_st.fm.brk_age = 0;
    }
}

/* A reversal sent (ffmap_w.rev: its duty and the smallest pulse; c: periods at the top duty before
 * it; lim: 1 under 1.5 rev_min): the gain's rules (the file's header; gap: a half cycle's bound)
 * and the smallest pulse's and reversal's own; the half cycle's counters start anew. One soon after
 * the last at a steady target, its pulse near the smallest (the valve's resolution, not the gain),
 * takes FFMAP_BRK_STEP off what stalls added to the smallest pulse (a stall on a headland is no
 * break-away). Big swings with the gain at its floor and the reversal near rev_min lower rev_min in
 * a start and with the target moving too (the wheel's jitter): a fast valve told slow. */
CTL_STEP void ffmap_reversal(uint8_t c, uint8_t lim) CTL_SHARED
{
    uint8_t gap = FFMAP_STEADY() && UMUL(ctl_travel, ctl_st.fm.gain) >= ((uint32_t)FFMAP_SLOW_T << 8)
                  ? FFMAP_OSC_GAP_SLOW : FFMAP_OSC_GAP;
    __bit fl = 0;                   /* smaller reversals, at a steady target */
    __bit fb = 0;                   /* ... or after big swings, the gain at its floor */
    /* two half cycles in a row that swung big, soon after each other; the last at the top */
    c = (uint8_t)((c >= FFMAP_TOP_N) << 1)
        | (ctl_st.fm.err_peak > (ctl_in->target_lpm_x100 >> FFMAP_BIG_SHIFT));
    if ((c & 1) && ctl_st.fm.big && ctl_st.fm.rev_age <= gap) {
        if (ctl_st.fm.gain > (ffmap_rlim ? FFMAP_G_INIT / 2 : FFMAP_G_MIN))
            ctl_st.fm.gain -= !ffmap_warm && c == 3 ? ctl_st.fm.gain >> 1 : ctl_st.fm.gain >> 2;
        else
            fl = fb = ffmap_rlim;
    } else if (ctl_st.fm.rev_age <= gap && (ffmap_warm || ffmap_hi_p || !ctl_st.fm.moved)
        && ffmap_w.rev.d > 2 * ffmap_w.rev.k && (ffmap_e < 0 ? -ffmap_e : ffmap_e) <= ctl_in->target_lpm_x100) {
        /* (a pulse near the smallest: the valve's resolution, not the gain) */
        if (ctl_st.fm.gain > FFMAP_G_MIN)
            ctl_st.fm.gain -= ctl_st.fm.gain >> 3;
        fl = 1;
    } else if (ctl_st.fm.rev_age <= gap && ffmap_warm && !ctl_st.fm.moved && ctl_st.fm.brk_extra > 0) {
        ctl_st.fm.brk_extra -= FFMAP_BRK_STEP;   /* a cycle of pulses near the smallest: it is too big */
    }
    if (fl && (fb || (!ctl_st.fm.moved && ffmap_warm)) && ctl_st.fm.rev_min > FFMAP_REV_LOW)
        ctl_st.fm.rev_min -= ctl_st.fm.rev_min >> 3;    /* a cycle at a steady target: smaller reversals */
    ffmap_rlim = lim;
    ctl_st.fm.big = c & 1;
    ctl_st.fm.err_peak = 0;
    ctl_st.fm.rev_age = 0;
    ctl_st.fm.moved = 0;
    ctl_st.fm.slow_n = 0;
    ffmap_rl1 = 0;
}

/* The output stage: the motion owed plus this period's (Q15 share of full speed for a period),
 * limits and stops; below the smallest pulse it stays owed; a pulse is sent at the duty that makes
 * the motion against the running friction. At a reversal, the gain's rules (the file's header). The
 * smallest pulses count two toward a stall (FFMAP_STALL_BIG while the error is big: a valve stiffer
 * than told), those up to twice the smallest one (a gain learnt that low) one. A reversal's answer:
 * on a valve learnt under half as fast as a new one starts, its smallest pulse not raised by stalls
 * (a stiff valve needs the pulses that follow), the FFMAP_ANSWER - 1 periods after a reversal at a
 * steady target (no move since, no ramp of the speed) send nothing more that way, the motion
 * dropped: the flow shows the reversal only then, and on a fast valve the pulses sent meanwhile
 * carry it past the target. */
CTL_STEP q15_t ffmap_out(int32_t m) CTL_SHARED
{
    uint16_t d, k;                  /* (duties up to 2 x 0.7 of full: 16 bits unsigned) */
    int8_t s;
    uint8_t c;
    __bit lim;
    m += ctl_carry;
    CTL_CLIP(m);
    CTL_STOP(m, ctl_in->valve_limit, CTL_CLOSE_BLOCKED);
    s = m > 0 ? 1 : m < 0 ? -1 : 0;
    if (s == 0) {
        ctl_carry = 0;
        return 0;
    }
    d = (uint16_t)(m > 0 ? m : -m);    /* (clipped to 15 bits) */
    if (s == ctl_st.fm.dir && !ctl_st.fm.moved && ctl_st.fm.rev_age < FFMAP_ANSWER
        && ctl_st.fm.gain < FFMAP_G_INIT / 2 && ctl_st.fm.brk_extra <= 0 && FFMAP_STEADY()) {
        ctl_carry = 0;              /* the reversal's answer awaited (above) */
        return 0;
    }
    if (s != ctl_st.fm.dir && ctl_st.fm.dir != 0 && d < (uint16_t)ctl_st.fm.rev_min) {
        ctl_carry = (q15_t)m;       /* a reversal waits until it is worth more than the slack */
        return 0;
    }
    lim = d - (uint16_t)ctl_st.fm.rev_min < ((uint16_t)ctl_st.fm.rev_min >> 1);    /* (a reversal: d >= rev_min) */
    d = (uint16_t)ctl_drun + (uint16_t)MUL_R15((int16_t)d, ctl_run_span);
    if (ctl_st.fm.brk_extra < 0)        /* under Min duty: the running friction 10/16 of it down */
        d = (uint16_t)((int16_t)d + (ctl_st.fm.brk_extra >> 1) + (ctl_st.fm.brk_extra >> 3));
    k = (uint16_t)CTL_STICTION + (uint16_t)ctl_st.fm.brk_extra;
    if (d < k) {
        ctl_carry = (q15_t)m;       /* owed until it is worth a pulse */
        return 0;
    }
    ctl_carry = 0;
    if (d > 32767)
        d = 32767;
    c = ctl_st.fm.cap_run_before;                    /* periods in a row at the top duty before this one */
    if (s != ctl_st.fm.dir)
        ctl_st.fm.cap_run_before = 255;
    d = ffmap_cap_limit(d, k);
    if (s != ctl_st.fm.dir && ctl_st.fm.dir != 0) {
        ffmap_w.rev.d = d;
        ffmap_w.rev.k = k;
        ffmap_reversal(c, lim);
    } else {
        ffmap_rlim &= !ffmap_rl1;         /* a second pulse after the reversal: the swing is the loop's */
        ffmap_rl1 = 1;
    }
    ctl_st.fm.lone_n = 0;                            /* a lone smallest pulse (ffmap_stall) */
    if (s == ctl_st.fm.dir && d <= k + (k >> 3) && ctl_st.fm.quiet >= FFMAP_LONE_N && !ctl_st.fm.hold) {
        ctl_st.fm.lone_n = FFMAP_LONE_N;
        ctl_st.fm.lone_flow = ctl_in->flow_lpm_x100;
    }
    if (d <= 2 * k && s == ctl_st.fm.dir) {    /* toward a stall */
        if (ctl_st.fm.stall_n == 0)
            ctl_st.fm.stall_flow = ctl_in->flow_lpm_x100;
        if (ctl_st.fm.stall_n < 250)
            ctl_st.fm.stall_n += d <= k + (k >> 3) ? (ctl_st.fm.err_big ? FFMAP_STALL_BIG : 2) : 1;
    } else {
        ctl_st.fm.stall_n = 0;
    }
    ctl_st.fm.dir = s;
    if (s < 0)
        return -(q15_t)d;
    /* a slower closing coasts less (ffmap_gain_at_p); the rules above judged the loop's demand */
    if (ffmap_hi_t && d > k + FFMAP_P_T_DUTY)
        d = k + FFMAP_P_T_DUTY;
    return (q15_t)d;
}

/* The loop gain at this pressure. The bypass's hold on the boom's flow grows with the boom's share
 * of the pump's flow: with q the boom's flow and Q the pump's, dq/dx goes as q^2 / Q, and q^2 as
 * the pressure P at the nozzles. With the pump at a fixed PTO speed that is P itself; with the pump
 * on the wheels (Q with the speed, as q) sqrt(P). Above FFMAP_P_REF the learnt gain is cut by
 * sqrt(FFMAP_P_REF / P), the lesser of the two: near P max a gain learnt lower down swings the flow
 * and takes the line over P max. (A failed sensor holds its last reading: the cut it had, a slower
 * loop, never a faster one.) With o of the boom's n nozzles open the gain is (n / o + 1) / 2 times
 * the whole boom's, at most 4 (target.c target_noz_q, in quarters). At a given pressure the boom's
 * flow q is o / n of the whole boom's, and through the bypass's equal-percentage opening dq/dx goes
 * as q (Q - q) / Q: with the pump at two to three times the whole boom's flow that is (n / o + 1) /
 * 2 times less within about a fifth (6 of 36 nozzles: 3.3-4.2 against 3.5). What is learnt stays
 * the whole boom's. */
static int16_t ffmap_gain_at_p(void) CTL_SHARED
{
    ffmap_hi_p = 0;
    ffmap_hi_t = 0;
    ffmap_w.gp.root = 256;
    if (ctl_in->pressure_kpa > FFMAP_P_REF) {
        /* f = floor(sqrt(FFMAP_P_REF 2^16 / P)), Q8, bit by bit and without a divide: the largest f
         * with f^2 P <= FFMAP_P_REF 2^16 (below 256, as P > FFMAP_P_REF) */
        ffmap_w.gp.root = 0;
        for (ffmap_w.gp.bit = 0x80; ffmap_w.gp.bit; ffmap_w.gp.bit >>= 1) {
            ffmap_w.gp.root |= ffmap_w.gp.bit;
            if (UMUL((uint16_t)UMUL(ffmap_w.gp.root, ffmap_w.gp.root), ctl_in->pressure_kpa)
                > ((uint32_t)FFMAP_P_REF << 16))
                ffmap_w.gp.root ^= ffmap_w.gp.bit;
        }
        ffmap_hi_p = (uint8_t)ffmap_w.gp.root < FFMAP_P_HI_F;
        /* Closing toward a target that needs over 400 kPa, on a valve learnt faster than a new one
         * starts, ffmap_out gives at most the smallest pulse + FFMAP_P_T_DUTY: a motor that runs on
         * after its drive stops carries the flow past the target by what its speed was, and near
         * P max a sixth over the target is over P max. The target's pressure P (q / f)^2 over
         * 400 kPa: q sqrt(P) > f sqrt(400), with sqrt(P) = 256 sqrt(FFMAP_P_REF) / f_root. */
        if (ctl_st.fm.gain < FFMAP_G_INIT
            && UMUL(ctl_st.fm.flow_last, ffmap_w.gp.root) < UMUL(ctl_in->target_lpm_x100, FFMAP_P_T_F))
            ffmap_hi_t = 1;                    /* (flow_last: ffmap_cap took this period's flow) */
    }
    /* (the product first: on the 8051 MUL and UMUL share their operands' bytes, and a product
     * in MUL's second operand would overwrite its first) */
    return (int16_t)(MUL((uint16_t)UMUL(ffmap_w.gp.root, target_noz_q) >> 2, ctl_st.fm.gain) >> 8);
}

/* The hold. When the number of nozzles open changes (target.c target_noz_take), the target steps
 * at once and the boom's flow steps by itself a period or two later, as the nozzles open or shut
 * and the meter follows. The proportional and derivative terms would read the flow's own step
 * as the valve's answer, and the reversal rules would take that turn for a swing and cut the
 * learnt gain at every switch. For FFMAP_P_WAIT periods the step sees no change of the error (the
 * integral alone acts), as after a start. */
q15_t ffmap_step(void) CTL_SHARED
{
    int16_t q = ctl_in->target_lpm_x100;
    int16_t d2e;
    int32_t du, d32;
    q15_t d;

    ffmap_e = ctl_clamp_e(q - ctl_in->flow_lpm_x100);
    if (ctl_first) {
        ctl_st.fm.e1 = ctl_st.fm.e2 = ctl_st.fm.err_filt = ffmap_e;
        ctl_st.fm.target_last = q;
        ctl_st.fm.rest = 0;
        ctl_st.fm.stall_n = 0;
        ctl_st.fm.warm = 0;
        ffmap_warm = 0;
        ctl_st.fm.err_peak = 0;
        ctl_st.fm.big = 0;
        ctl_st.fm.speed_last = ctl_in->speed_kmh_x100;
        ctl_st.fm.ramp = 0;
        ctl_st.fm.lead = ffmap_e <= q - (q >> 2);
        ctl_st.fm.cap_run = 0;
        ctl_st.fm.gain_start = ctl_st.fm.gain;
        ctl_st.fm.hold = 0;
        (void)target_noz_take();        /* a change before the start needs no hold */
        ctl_first = 0;
    }
    if (target_noz_take())              /* the hold (above) */
        ctl_st.fm.hold = FFMAP_P_WAIT;
    if (ctl_st.fm.hold) {
        ctl_st.fm.hold--;
        ctl_st.fm.e1 = ctl_st.fm.e2 = ffmap_e;
    }
    ctl_st.fm.quiet = ctl_last ? 0 : ctl_st.fm.quiet + (ctl_st.fm.quiet < 255);
    ffmap_deadband(ffmap_e, q);
    ffmap_stall(ffmap_e, q);
    d2e = ffmap_e < 0 ? -ffmap_e : ffmap_e;
    if (d2e > ctl_st.fm.err_peak)
        ctl_st.fm.err_peak = d2e;
    ctl_st.fm.err_big = d2e > (q >> FFMAP_BIG_SHIFT);    /* a big error this period */
    ffmap_ff();
    if (ctl_st.fm.rest) {
        du = MUL(FFMAP_REST_KI, ctl_st.fm.err_filt);   /* a slow integral on the filtered error: no steady bias */
    } else {
        d2e = fx_sat16((int32_t)ffmap_e - 2 * (int32_t)ctl_st.fm.e1 + ctl_st.fm.e2);
        /* (not while the line fills after the boom opens: the flow's rise is not the valve's) */
        du = ctl_st.fm.warm < FFMAP_P_WAIT ? 0 : MUL(FFMAP_KP, fx_sat16((int32_t)ffmap_e - ctl_st.fm.e1));
        du += MUL(FFMAP_KI, ffmap_e);
        du += MUL(FFMAP_KD, d2e);
        if (ctl_st.fm.lead && !ffmap_warm && (ctl_last > FFMAP_LEAD_DRIVE || ctl_last < -FFMAP_LEAD_DRIVE)) {
            /* the flow's change this period (the error is clamped far beyond any target) */
            d2e = fx_sat16((int32_t)(q - ffmap_e) - (ctl_st.fm.target_last - ctl_st.fm.e1));
            if ((d2e > 0) == (ffmap_e > 0))
                du -= MUL(FFMAP_KI, fx_sat16((int32_t)FFMAP_LEAD * d2e));
        }
    }
    ffmap_gain_adapt(ffmap_e);
    ffmap_cap();
    d32 = ctl_du_to_drive(du);
    /* (the gain is at most 2 x 4 of as told: 2^11 in Q8, so d32 times it fits 32 bits) */
    if (d32 > 1048575L)
        d32 = 1048575L;
    else if (d32 < -1048575L)
        d32 = -1048575L;
    d = ffmap_out(((d32 * ffmap_gain_at_p()) >> 8) + ctl_st.fm.ff_drive);
    ctl_st.fm.e2 = ctl_st.fm.e1;
    ctl_st.fm.e1 = ffmap_e;
    ctl_st.fm.target_last = q;
#if FW_PROBES
    /* the gains for the probes (ctl_gain: the simulator, PIL, the s51 tests); the field image
     * reads ctl_k only in pid's and bp_pid's own steps */
    ctl_k[0] = FFMAP_KP;
    ctl_k[1] = FFMAP_KI;
    ctl_k[2] = FFMAP_KD;
#endif
    ctl_last = d;
    return d;
}

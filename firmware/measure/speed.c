/* speed.c: ground speed from wheel pulse periods, decaying as 1/t when pulses stop. */
#include "hal.h"
#include "params.h"
#include "umath.h"
#include "speed.h"
#include "mul.h"

static struct {
    uint32_t k;             /* km/h x100 * PCA ticks a pulse: P_WHEEL * 33177.6 */
    uint32_t last_pca;      /* PCA time of the newest edge */
    uint32_t pulses;
    uint32_t t0;            /* PCA time of element 0's last edge seen as a period's newest */
    uint32_t t_rev;         /* the last turn's time (element 0 to element 0), 0: none */
    int32_t d_rev;          /* how much it changed from the turn before */
    uint16_t v_x100;
    uint16_t v_pulse_x100;  /* speed at the last pulse */
    uint16_t v_meas;        /* the last span's own speed (before speed_ahead), 0: none */
    uint16_t quiet;         /* periods since the last pulse */
    uint16_t glitches;
    uint8_t since;          /* periods since the estimate was last measured (slew allowance) */
    uint16_t v_base;        /* the estimate before the current run of rises (speed_judge_rise) */
    uint8_t base_age;       /* periods since v_base was taken */
    uint8_t rises;          /* measured periods in a row that rose as no tractor can from v_base */
    uint8_t jumped;         /* 1: a rise a tractor cannot make (SPEED_JUMP_PERIODS), until standstill */
    uint8_t gen;
    uint8_t n;              /* elements a turn (P_WHEEL_PPR) */
    uint8_t idx;            /* element of the newest edge */
    uint8_t t0_stamp;       /* low byte of `pulses` at t0 */
    uint8_t learnt;         /* offsets learnt in this turn of learning */
    uint8_t drift;          /* bit 0: an edge left its learnt place in this turn; bits 1-6: steady
                             * turns in a row that had one, times 2; SPEED_FIRST_TURN */
    uint8_t turns;          /* turns learnt at this gain */
    uint8_t shift;          /* the gain: 1 / 2^shift */
    int16_t off[SPEED_TEETH_MAX];   /* each element's position against element 0's, 1/4096 of a spacing */
} sp;

/* flags in the bit-addressable RAM (XRAM is within bytes of its floor): a previous edge to
 * time a span from; element 0's last edge is timed (t0); the last turn as long as the one
 * before (learning allowed) */
static __bit have_edge, t0_ok, steady;

/* the newest span, measured by speed_step (speed_learn checks it) */
static uint32_t sl_dt;
static __bit learn_due;             /* speed_learn_now: the newest span's (wk.edges) learning waits */
static uint8_t learn_old;           /* ... and its first element */

/* The step's working values in the direct RAM (the cheapest addressing; the step never nests) */
static __data struct {
    hal_capture_t edges;    /* the period's wheel edges */
    uint32_t v_x100;        /* the newest span's speed, km/h x100: measured, led, slewed */
    uint16_t ceil_x100;     /* the tracker's speed may not pass it (speed_track_out): where no edge
                             * came, the speed at which the next would have come; 0x7FFF: one came */
} wk;

/* Until the offsets are learnt: a tracker of the wheel's position (speed_track): the spacing
 * errors put white noise on the edges' positions, which a filter on the position averages (a
 * span's speed carries two elements' errors; a window of spans lags by half its length). */
static struct {
    uint16_t v;     /* the pulse rate at the newest edge, 1/4096 pulse per 512 PCA/256 ticks */
    int16_t e;      /* the estimate's position there less the pulses counted, 1/4096 pulse */
    int16_t a;      /* the rate's change, v's units per PCA/256 tick x8192 */
    uint8_t n;      /* edges tracked */
} tk;

/* the learnt offsets back to nothing (the turn's timing is kept) */
static void speed_restart_offsets(void) __reentrant
{
    uint8_t i;
    for (i = 0; i < SPEED_TEETH_MAX; i++)
        sp.off[i] = 0;
    sp.learnt = 0;
    sp.turns = 0;
    sp.shift = 0;
    sp.drift = 0;
}

static void speed_forget_offsets(void) __reentrant
{
    speed_restart_offsets();
    t0_ok = 0;
    sp.t_rev = 0;
    steady = 0;             /* no learning before a turn is timed again */
}

static void speed_derive(void) __reentrant
{
    uint32_t w = param_v[P_WHEEL];
    /* v[km/h x100] = w[0.1 mm] * 1e-4 m * 3.6 * 100 * 921600 / dt[ticks] = w * 33177.6 / dt */
    sp.k = (UMUL(w, 3u) + 2u) / 5u;                     /* w < 65536 */
    sp.k += UMUL(w, 33177u);
    if (sp.n != (uint8_t)param_v[P_WHEEL_PPR]) {
        sp.n = (uint8_t)param_v[P_WHEEL_PPR];
        sp.idx = 0;
        speed_forget_offsets();
        learn_due = 0;      /* (what it would learn, the forgetting undoes) */
    }
    sp.gen = param_generation;
}

void speed_prepare(void)
{
    if (sp.gen != param_generation)
        speed_derive();
}

void speed_init(void)
{
    uint8_t i;
    for (i = 0; i < sizeof sp; i++)     /* all as at power-up (what speed_derive sets, it sets) */
        ((__xdata uint8_t *)&sp)[i] = 0;
    sp.quiet = 0xFFFF;                  /* no pulse yet */
    tk.n = 0;
    have_edge = 0;
    speed_derive();                     /* (n 0: Pulses/turn taken anew, the offsets forgotten) */
}

/* Element 0's edges time the turns (t_rev; d_rev its change). At a steady speed (the turn's
 * time within 1/2^SPEED_STEADY_SH), a span of `count` pulses (sl_dt) should be (count + off[new]
 * - off[old]) t_rev / n: the difference moves the new element's offset (element 0's: the old's). */
/* where an edge `count` pulses after another one sits against it, from the span dt between
 * them, in 1/4096 of a spacing past the even place: dt n 4096 / T - count 4096 */
static int32_t spans(uint32_t dt, uint8_t count) __reentrant
{
    return (int32_t)(um_muldiv(dt, (uint16_t)sp.n * 2048u, sp.t_rev) << 1) - ((int32_t)count << 12);
}

/* The learning speed_step left (the newest span, wk.edges, from element learn_old), read by the
 * next step alone: in a pass of its own (app.c), else first thing in the next step; a new
 * Pulses/turn drops it (the offsets forgotten). */
void speed_learn_now(void) __reentrant
{
    uint8_t m, neg, c;
    int32_t err;
    int16_t e;
    if (!learn_due)
        return;
    learn_due = 0;
    m = (uint8_t)((uint8_t)sp.pulses - sp.t0_stamp);
    if (sp.idx == 0) {
        if (t0_ok && m == sp.n) {
            /* the change needs two turns in a row; until then it reads as too fast to learn */
            sp.d_rev = sp.t_rev ? (int32_t)(sp.last_pca - sp.t0 - sp.t_rev) : 0x7FFFFFFFL;
            sp.t_rev = sp.last_pca - sp.t0;
        } else {
            sp.t_rev = 0;
        }
        sp.t0 = sp.last_pca;
        sp.t0_stamp = (uint8_t)sp.pulses;
        t0_ok = 1;
        m = 0;
        err = sp.d_rev < 0 ? -sp.d_rev : sp.d_rev;
        steady = sp.t_rev && err <= (int32_t)(sp.t_rev >> SPEED_STEADY_SH);
        /* Learning starts again when the first turn's offsets (taken whole) were learnt while
         * the speed changed, or when edges leave their places through SPEED_BAD_TURNS steady
         * turns in a row: the offsets are wrong (an element bent, a change the turn hid). */
        c = sp.drift;
        sp.drift = 0;
        if (!steady) {
            if (sp.shift == 0 || (c & SPEED_FIRST_TURN))
                speed_restart_offsets();
        } else if (c & 1) {
            c = (uint8_t)((c & 0x7Eu) + 2u);
            if (c >= 2 * SPEED_BAD_TURNS)
                speed_restart_offsets();
            else
                sp.drift = c;
        }
    }
    if (!steady || m > sp.n)
        return;
    /* later turns: an edge away from where its learnt offset puts it against element 0's (which
     * opened this turn) says the speed changed since the turn was timed: nothing is learnt */
    err = spans(sp.last_pca - sp.t0, m) - sp.off[sp.idx];
    if (sp.shift && (uint32_t)err + SPEED_LEARN_DRIFT > 2u * SPEED_LEARN_DRIFT) {     /* |err| over it */
        sp.drift |= 1;
        return;
    }
    /* where the new edge sits against the old one */
    err = spans(sl_dt, (uint8_t)wk.edges.count) - ((int32_t)sp.off[sp.idx] - sp.off[learn_old]);
    if ((uint32_t)err + SPEED_SPAN_MAX > 2u * SPEED_SPAN_MAX)     /* |err| over it */
        return;                 /* a missed or an extra pulse, not the wheel */
    /* the first turn takes what it sees, then a mean growing to about 16 turns: halved for
     * every doubling of the turns learnt (on the magnitude: shifts, no divide) */
    e = (int16_t)err;
    neg = e < 0;
    if (neg)
        e = -e;
    if (sp.shift)
        e = ((e >> (sp.shift - 1)) + 1) >> 1;  /* rounded: truncated, a residue under 2^shift stays */
    if (neg)
        e = -e;
    if (++sp.learnt >= sp.n) {
        sp.learnt = 0;
        if (sp.shift < 4 && ++sp.turns >= (uint8_t)(1u << sp.shift)) {
            if (sp.shift++ == 0)
                sp.drift |= SPEED_FIRST_TURN;   /* judged at element 0's edge, which ends it */
            sp.turns = 0;
        }
    }
    if (sp.idx != 0)
        sp.off[sp.idx] += e;
    else
        sp.off[learn_old] -= e;
}

/* 1: the offsets are learnt and judged (a first turn's are judged at the edge that ends it,
 * after this step's speed: until then they may hold a speed change, not the wheel); speed.h */
__bit speed_learnt;
static __bit tk_slipped;    /* 1: the tracker's last edge was a whole pulse off its place */

/* x / 4096, rounded */
static uint32_t r12(uint32_t x) __reentrant
{
    return (x + 2048u) >> 12;
}

/* the rate's change over t (PCA/256 ticks) at the tracker's acceleration */
static int16_t speed_tk_dv(uint16_t t) __reentrant
{
    return (int16_t)(MUL(tk.a, t) >> 13);
}

/* a rate clipped to the tracker's range */
static uint16_t speed_tk_clip(int32_t rate) __reentrant
{
    return rate < 0 ? 0 : rate > (int32_t)SPEED_TK_V_MAX ? SPEED_TK_V_MAX : (uint16_t)rate;
}

/* The tracker's gains by tk.n: first the expanding-memory quadratic filter's, g 3 (3n^2 + 3n +
 * 2) / N, h 18 (2n + 1) / N, k 30 / N, N = (n + 1)(n + 2)(n + 3), n = 2 .. 6; then the steady
 * ones (speed.h). g and h x256, k x16384. */
static __code const int16_t tk_gain[SPEED_TK_FILL_N][3] = {
    {256, 384, 8192}, {243, 269, 4096}, {227, 197, 2341}, {210, 151, 1463}, {195, 119, 975},
    {SPEED_TK_ALPHA, SPEED_TK_BETA, SPEED_TK_GAMMA},
};

static int16_t speed_tk_gain(uint8_t k) __reentrant
{
    return tk_gain[tk.n - 1][k];
}

/* x within 16 bits */
static int16_t speed_tk_16(int32_t x) __reentrant
{
    return x > 32767 ? 32767 : x < -32767 ? -32767 : (int16_t)x;
}

/* The tracker from this edge, `span` PCA/256 ticks after the last: its rate, no acceleration. */
static void speed_tk_start(uint16_t span) __reentrant
{
    tk.v = speed_tk_clip((int32_t)(((uint32_t)wk.edges.count << 21) / span));
    tk.a = tk.e = 0;
    tk.n = 1;
    tk_slipped = 0;
}

/* An edge: wk.edges.count pulses over sl_dt. The tracker's alpha-beta-gamma step on the position
 * (speed.h SPEED_TK_*); after a span over SPEED_TK_T_MAX (a crawl, a stop) it starts again from
 * rest at this edge. */
static void speed_track(void) __reentrant
{
    uint16_t span;          /* the newest span, PCA/256 ticks */
    int16_t dv, resid, part, inv, rate;
    if (sl_dt >= ((uint32_t)SPEED_TK_T_MAX << 8) || sl_dt < 0x10080ul) {
        tk.n = 0;               /* (0x10080: span over 256, inv within 16 bits) */
        return;
    }
    span = (uint16_t)((sl_dt + 128u) >> 8);
    if (tk.n == 0) {
        speed_tk_start(span);
        return;
    }
    /* the edge's position less the one predicted from the last edge, (v + dv / 2) t, within 16
     * bits (1/4096 pulse) */
    dv = speed_tk_dv(span);
    resid = speed_tk_16(((int32_t)wk.edges.count << 12) - tk.e
                        - (int32_t)(UMUL(speed_tk_clip((int32_t)tk.v + (dv >> 1)), span) >> 9));
    /* on the steady gains an edge over half a spacing from its place is a pulse missed or extra
     * (bounce the HAL let through): only what is left of a whole pulse counts; two in a row are
     * the rate off by a whole pulse a span, and the tracker starts again from this span */
    if (tk.n == SPEED_TK_FILL_N) {
        part = (int16_t)((uint16_t)resid << 4) >> 4;
        if (part != resid && tk_slipped) {
            speed_tk_start(span);
            return;
        }
        tk_slipped = part != resid;
        resid = part;
    }
    inv = (int16_t)(0x800000ul / span);         /* 2^23 / span */
    tk.e = (int16_t)-(MUL(resid, 256 - speed_tk_gain(0)) >> 8);
    /* the residual as a rate over the span (resid 2^9 / t), then the rate and the acceleration */
    rate = (int16_t)(MUL(resid, inv) >> 14);
    tk.v = speed_tk_clip((int32_t)tk.v + dv + (MUL(rate, speed_tk_gain(1)) >> 8));
    tk.a = speed_tk_16((int32_t)tk.a + (MUL((int16_t)(MUL(rate, inv) >> 14), speed_tk_gain(2)) >> 9));
    if (tk.n < SPEED_TK_FILL_N)
        tk.n++;
}

/* A span's speed is its middle's. Once the offsets are learnt, a quarter of the change from the
 * span before is added (most of the lag out; all of it runs ahead at a level-off), at most
 * 1/2^SPEED_AHEAD_MAX; not while speed_plain (a pump on the wheels follows the speed itself). */
static void speed_ahead(void) __reentrant
{
    uint16_t meas = (uint16_t)wk.v_x100, lead;
    if (speed_learnt && sp.v_meas && !speed_plain) {
        lead = (meas > sp.v_meas ? meas - sp.v_meas : sp.v_meas - meas) >> 2;
        if (lead > (meas >> SPEED_AHEAD_MAX))
            lead = meas >> SPEED_AHEAD_MAX;
        wk.v_x100 = meas > sp.v_meas ? meas + lead : meas - lead;
    }
    sp.v_meas = meas;
}

/* The wheel's plausibility (speed.h SPEED_JUMP_PERIODS): this span's speed against the estimate
 * before a run of rises (v_base, measured base_age periods ago): a quarter over it, and over the
 * rise SPEED_SLEW_X100 a period allows since. */
static void speed_judge_rise(void) __reentrant
{
    if (sp.v_base && wk.v_x100 >= sp.v_base + (sp.v_base >> 2)
        && wk.v_x100 > sp.v_base + UMUL(SPEED_SLEW_X100, sp.base_age)) {
        if (++sp.rises >= SPEED_JUMP_PERIODS)
            sp.jumped = 1;
    } else {
        sp.rises = 0;
    }
}

/* The span's speed judged (speed_judge_rise), then taken as the estimate with its rise limited
 * to SPEED_SLEW_X100 for each period since the last measurement; out of a run of rises, the next
 * base. */
static void speed_slew(void) __reentrant
{
    uint32_t lim = (uint32_t)sp.v_x100 + UMUL(SPEED_SLEW_X100, sp.since);
    speed_judge_rise();
    if (wk.v_x100 > lim)
        wk.v_x100 = lim;
    sp.v_x100 = (uint16_t)wk.v_x100;
    sp.since = 0;
    if (!sp.rises) {
        sp.v_base = sp.v_x100;
        sp.base_age = 0;
    }
}

/* A period more since the estimate was measured (the slew's allowance) and since v_base. */
static void speed_age(void) __reentrant
{
    if (sp.since < 255)
        sp.since++;
    if (sp.base_age < 255)
        sp.base_age++;
}

/* Each period after the edges: offsets unlearnt, the tracker's speed, carried on from the newest
 * edge at the acceleration, under wk.ceil_x100. The acceleration decays. */
static void speed_track_out(void) __reentrant
{
    int32_t since;          /* (an edge the HAL stamped after this period's `now`: just under 0) */
    uint16_t t, v;
    if (tk.n == SPEED_TK_FILL_N)
        tk.a -= tk.a >> SPEED_TK_DECAY;     /* (the first edges' fit takes it as constant) */
    if (!speed_learnt && have_edge && tk.n >= SPEED_TK_OUT_N && tk.v < SPEED_TK_V_MAX) {
        since = (int32_t)(hal_pca_now() - sp.last_pca);
        t = since >= ((int32_t)SPEED_TK_T_MAX << 8) ? SPEED_TK_T_MAX : (uint16_t)(since >> 8);
        v = (uint16_t)(UMUL(speed_tk_clip((int32_t)tk.v + speed_tk_dv(t)), (uint16_t)(sp.k >> 14)) >> 15);     /* k rate / 2^29 */
        sp.v_x100 = v < wk.ceil_x100 ? v : wk.ceil_x100;
    }
}

/* The HAL's bounce filter: no pulse sooner than a quarter of the period at 1.5 times the speed,
 * the last span's where faster than the estimate (slewed: from rest it would refuse the wheel's
 * own pulses); at standstill 60 km/h (the last span may be a crawl's, long before). */
static void speed_bounce_filter(void) __reentrant
{
    uint16_t v = sp.v_x100 && sp.v_meas > sp.v_x100 ? sp.v_meas : sp.v_x100;
    hal_wheel_min_interval(um_muldiv(sp.k, 1, v ? UMUL(v, 6u) : SPEED_MAX_X100 * 4ul));
}

uint16_t speed_step(void) __reentrant
{
    speed_learn_now();
    if (sp.gen != param_generation)
        speed_derive();
    hal_wheel_capture_take(&wk.edges);
    speed_learnt = sp.shift && !(sp.drift & SPEED_FIRST_TURN);
    sp.glitches += wk.edges.rejected;
    speed_age();
    if (wk.edges.count) {
        uint8_t old = sp.idx, nw;
        uint16_t w = sp.idx + wk.edges.count;
        while (w >= sp.n)
            w -= sp.n;              /* (idx + count) mod n without a divide */
        nw = (uint8_t)w;
        sp.pulses += wk.edges.count;
        sp.quiet = 0;
        wk.ceil_x100 = 0x7FFF;
        if (have_edge) {
            sl_dt = wk.edges.last - sp.last_pca;
            if (wk.edges.count < 15u) {
                /* the distance the span covers, in 1/4096 of a pulse spacing: each element's
                 * learnt offset takes the wheel's spacing error out of the period */
                wk.v_x100 = r12(um_muldiv(sp.k, (uint16_t)(((uint16_t)wk.edges.count << 12) + sp.off[nw] - sp.off[old]), sl_dt));
                if (sp.n > 1) {
                    learn_due = 1;      /* speed_learn_now */
                    learn_old = old;
                }
            } else {
                wk.v_x100 = um_muldiv(sp.k, wk.edges.count, sl_dt);
            }
            if (!sl_dt || wk.v_x100 > SPEED_MAX_X100) {
                sp.glitches++;
            } else {
                sp.idx = nw;
                speed_ahead();
                speed_slew();
                if (sp.n > 1)
                    speed_track();
            }
        } else {
            tk.n = 0;               /* the tracker starts again from this edge */
        }
        sp.idx = nw;
        sp.last_pca = wk.edges.last;
        have_edge = 1;
        sp.v_pulse_x100 = sp.v_x100;
    } else {
        if (sp.quiet < 0xFFFF)
            sp.quiet++;
        if (have_edge) {
            /* the next element is (1 + its offset - this one's) spacings away, once the
             * offsets are learnt (a turn's being learnt may hold a speed change) */
            uint8_t nx = sp.idx + 1u == sp.n ? 0 : sp.idx + 1u;
            uint16_t w = speed_learnt ? (uint16_t)(4096 + sp.off[nx] - sp.off[sp.idx]) : SPEED_TK_NEXT;
            uint32_t next = r12(um_muldiv(sp.k, w, hal_pca_now() - sp.last_pca));
            wk.ceil_x100 = next > 0x7FFFu ? 0x7FFF : (uint16_t)next;
            if (wk.ceil_x100 < sp.v_x100)
                sp.v_x100 = wk.ceil_x100;
            if (sp.quiet >= SPEED_STALE_PERIODS) {
                have_edge = 0;   /* before the 32-bit PCA time can wrap */
                sp.v_meas = 0;      /* ... and no span before the next one */
                if (sp.v_pulse_x100 >= SPEED_LOST_X100)
                    speed_forget_offsets();     /* pulses stopped at speed: which element is next is lost */
            }
        } else {
            sp.v_x100 = 0;
        }
    }
    speed_track_out();
    if (sp.v_x100 < SPEED_ZERO_X100) {
        sp.v_x100 = 0;
        sp.jumped = 0;              /* a stop ends the suspicion: the wheel starts again from rest */
    }
    speed_bounce_filter();
    return sp.v_x100;
}

#if FW_PROBES
uint16_t speed_kmh_x100(void)
{
    return sp.v_x100;
}
#endif

uint32_t speed_pulses(void)
{
    return sp.pulses;
}

uint16_t speed_glitches(void)
{
    return sp.glitches;
}

uint16_t speed_quiet_periods(void)
{
    return sp.quiet;
}

uint8_t speed_jumped(void)
{
    return sp.jumped;
}

uint16_t speed_at_last_pulse_x100(void)
{
    return sp.v_pulse_x100;
}

/* tt_ctl.c: every controller (the peers aog and raven with non-default settings too) on recorded input sequences and a long closed-loop learning run with an integer toy plant; s51 and host must print the same bits; cycles per control step, within the budget. */
#include "ctl_int.h"
#include "params.h"
#include "target.h"
#include "tt.h"

/* A deterministic integer plant: closure p (Q15) moved by the drive at 1/40 stroke a period
 * above its break-away (20 % duty, or pl_brk), boom flow = the pump's share through the closure,
 * a one-period lag, meter noise of +-0.3 L/min, end stops reported as valve_limit. */
static int16_t pl_p, pl_q;
static uint16_t pl_pump;            /* x100 L/min through a closed bypass */
static q15_t pl_brk = Q15(0.2);

static void plant(q15_t drive, ctl_in_t *in)
{
    int32_t p = pl_p;
    int16_t qss, noise;
    if (drive >= pl_brk || drive <= -pl_brk)
        p += ((int32_t)drive * 819 + 16384) >> 15;
    if (p > 32767)
        p = 32767;
    if (p < 0)
        p = 0;
    pl_p = (int16_t)p;
    qss = (int16_t)(((int32_t)pl_p * pl_pump) >> 15);
    pl_q += (int16_t)((qss - pl_q) >> 1);
    noise = (int16_t)(tt_rand16() & 63u) - 32;
    in->flow_lpm_x100 = pl_q + noise;
    in->valve_limit = pl_p == 32767 ? CTL_AT_CLOSED : pl_p == 0 ? CTL_AT_OPEN : 0;
}

static uint32_t cyc_max, cyc_sum;

/* the step's inputs, passed to ctl_step (in XRAM on the chip, ctl.h) */
static __xdata ctl_in_t step_in;
#if defined(__SDCC)
__bit speed_learnt;             /* speed.h's, which ffmap reads: 0, a wheel not learnt (no wheel module here) */
#endif

static q15_t timed_step(const __xdata ctl_in_t *in)
{
    q15_t d;
    uint32_t c;
    tt_cycles_start();
    d = ctl_step(in);
    ctl_applied(d, in->valve_limit);    /* as app.c does each period: the valve got what was asked */
    c = tt_cycles_stop();
    if (c > cyc_max)
        cyc_max = c;
    cyc_sum += c;
    return d;
}

/* One line a step: drive, the three gains. */
static void out_line(q15_t d)
{
    tt_hex16((uint16_t)d);
    tt_putc(' ');
    tt_hex16((uint16_t)ctl_gain(0));
    tt_hex16((uint16_t)ctl_gain(1));
    tt_hex16((uint16_t)ctl_gain(2));
    tt_putc('\n');
}

/* A checksum of the active controller's state words (no padding bytes: the hosts' layouts differ). */
static uint16_t state_sum(uint8_t id)
{
    const int16_t *w;
    uint16_t s = 0, i, n;
    switch (id) {
    case CTL_PID: w = &ctl_st.pid.e1; n = 2; break;
    case CTL_FUZZY_PID: w = &ctl_st.fz.e1; n = 2; break;
    case CTL_BP_PID: w = &ctl_st.bp.w[0][0]; n = BP_IN * BP_HID; break;
    case CTL_AOG: w = &ctl_st.ag.integ; n = 8; break;              /* integral, reference and the derived settings */
    case CTL_RAVEN: w = &ctl_st.rv.speed; n = 4; break;
    default: w = &ctl_st.fm.e1; n = 4; break;
    }
    for (i = 0; i < n; i++)
        s = (uint16_t)((s << 1) | (s >> 15)) ^ (uint16_t)w[i];
    if (id == CTL_BP_PID) {
        for (i = 0; i < BP_OUT * BP_HID; i++) {
            s = (uint16_t)((s << 1) | (s >> 15)) ^ (uint16_t)(&ctl_st.bp.v[0][0])[i];
            s ^= (uint8_t)(&ctl_st.bp.dv[0][0])[i];
        }
        for (i = 0; i < BP_IN * BP_HID; i++)
            s = (uint16_t)((s << 1) | (s >> 15)) ^ (uint8_t)(&ctl_st.bp.dw[0][0])[i];
    }
    if (id == CTL_AOG)
        s ^= ctl_st.ag.pos;
    if (id == CTL_RAVEN)
        s ^= (uint16_t)(uint8_t)ctl_st.rv.dir;
    if (id == CTL_FFMAP)
        s ^= (uint16_t)ctl_st.fm.brk_extra ^ (uint16_t)ctl_st.fm.gain ^ (uint16_t)ctl_st.fm.stall_flow ^ (uint16_t)ctl_carry_now()
             ^ ((uint16_t)ctl_st.fm.rest << 8) ^ (uint16_t)(uint8_t)ctl_st.fm.dir;
    return s;
}

static const __code char *const bench_names[CTL_COUNT] = {
    "ctl_step_pid_max", "ctl_step_fuzzy_pid_max", "ctl_step_bp_pid_max", "ctl_step_ffmap_max",
    "ctl_step_aog_max", "ctl_step_raven_max"};

/* n periods closed loop on the toy plant, a new target every 5 s, the pump at `pump_late` from
 * the middle on; a line every 100 periods. */
static void long_run(uint8_t id, uint16_t n, uint16_t pump_late)
{
    __xdata ctl_in_t *in = &step_in;
    uint16_t k, r;
    q15_t d;
    for (k = 0; k < n; k++) {
        if (k % 50 == 0) {
            r = tt_rand16();
            in->target_lpm_x100 = (int16_t)(1800 + (r & 2047u));
        }
        if (k == n / 2)
            pl_pump = pump_late;    /* the plant changes under the controller */
        d = timed_step(in);
        plant(d, in);
        if (k % 100 == 99) {
            tt_hex16((uint16_t)k);
            tt_putc(' ');
            tt_hex16((uint16_t)pl_p);
            tt_putc(' ');
            tt_hex16((uint16_t)in->flow_lpm_x100);
            tt_putc(' ');
            tt_hex16(state_sum(id));
            tt_putc(' ');
            out_line(d);
        }
    }
}

/* One controller: a recorded open-loop input sequence, then a long closed loop on the toy plant. */
static void run_ctl(uint8_t id, const char *bench)
{
    uint16_t k, n_long;
    __xdata ctl_in_t *in = &step_in;
    q15_t d;
    uint16_t r;

    tt_puts(ctl_name(id));
    tt_putc('\n');
    /* recorded input sequence: random targets, flows, limits (open loop) */
    ctl_select(id);
    for (k = 0; k < 120; k++) {
        r = tt_rand16();
        in->target_lpm_x100 = (int16_t)(1500 + (r & 4095u));
        r = tt_rand16();
        in->flow_lpm_x100 = (int16_t)(in->target_lpm_x100 + (int16_t)(r & 1023u) - 512);
        in->speed_kmh_x100 = 700;
        in->pressure_kpa = 300;
        r = tt_rand16();
        in->valve_limit = (r & 0x700u) == 0 ? (uint8_t)((r & 1u) + 1u) : 0;
        target_noz_q = (uint8_t)(4u + k % 13u);     /* sections shut: ffmap's gain factor 1-4 */
        if (k % 13u == 0 || k % 13u == 7)
            target_noz_new = 1;                     /* ... switched: ffmap's hold */
        d = ctl_step(in);
        out_line(d);
    }
    target_noz_q = 4;
    /* long closed-loop run on the toy plant: target steps every 5 s, learning on */
    ctl_select(id);
    pl_p = 0;                   /* from the open stop (as after parking) */
    pl_q = 0;
    pl_pump = 6000;
    in->flow_lpm_x100 = 0;
    in->valve_limit = CTL_AT_OPEN;
    in->target_lpm_x100 = 3000;
    in->speed_kmh_x100 = 700;
    in->pressure_kpa = 300;
    cyc_max = 0;
    cyc_sum = 0;
    n_long = id == CTL_BP_PID ? 3000 : 1000;
    long_run(id, n_long, 5000);
    if (id == CTL_FFMAP) {
        /* a valve that breaks away at half its Min duty on a pump whose flow each smallest pulse
         * steps by ~3 %: ffmap takes the smallest pulse down (ffmap_stall) */
        pl_brk = Q15(0.1);
        pl_pump = 20000;
        long_run(id, 2000, 20000);
        pl_brk = Q15(0.2);
        tt_hex16((uint16_t)ctl_st.fm.brk_extra);
        tt_putc('\n');
    }
    if (bench)
        tt_bench(bench, cyc_max);
}

int main(void)
{
    uint8_t id;

    tt_begin();
    params_defaults();
    for (id = 0; id < CTL_COUNT; id++) {
        run_ctl(id, bench_names[id]);
        if (cyc_max > CTL_STEP_BUDGET_CYCLES) {     /* s51 only: the host's stopwatch reads 0 */
            tt_puts("over the step budget: ");
            tt_puts(ctl_name(id));
            tt_putc('\n');
        }
    }
    /* the peers with their other settings: aog's larger gains, a narrow brake point and slow
     * adjust, a min PWM under Min duty (the output stage's pulses); raven's fast valve (743) and
     * a standard one's widest brake point and backlash (9999 ... 9991) */
    param_set(P_AOG_KP, 250);
    param_set(P_AOG_KI, 300);
    param_set(P_AOG_BRAKE, 100);
    param_set(P_AOG_SLOW, 30);
    param_set(P_AOG_MIN, 40);
    param_set(P_AOG_MAX, 200);
    run_ctl(CTL_AOG, 0);
    param_set(P_RAVEN_CAL, 743);
    run_ctl(CTL_RAVEN, 0);
    param_set(P_RAVEN_CAL, 9991);
    run_ctl(CTL_RAVEN, 0);
    tt_end();
    return 0;
}

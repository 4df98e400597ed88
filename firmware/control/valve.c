/* valve.c: H-bridge direction and PWM for the bypass valve, dead time on reversal, end-stop estimate. */
#include "hal.h"
#include "params.h"
#include "ctl.h"
#include "valve.h"
#include "umath.h"
#include "mul.h"

static struct {
    int32_t oneway;                 /* Q15 strokes driven one way since the last reversal */
    uint16_t over;                  /* Q15 strokes driven past the estimated end (a period adds
                                     * under 32768 to at most VALVE_OVER_Q15: 16 bits) */
    uint16_t pos;                   /* Q15, 0 closed; VALVE_POS_UNKNOWN */
    q15_t applied;                  /* drive of the current period */
    q15_t rate;                     /* Q15 stroke per period and unit of duty above drun: full speed
                                     * (0.1 s / travel) over (1 - drun) */
    q15_t drun;                     /* Q15 the motor's running duty (as ctl.c: 10/16 of Min duty) */
    uint16_t off_ms;                /* low 16 bits of hal_ms() when the bridge went off */
    int8_t out_dir;                 /* what the bridge does now */
    int8_t last_dir;                /* the last direction it drove */
    int8_t want_dir;
    uint8_t want_duty;
    uint8_t limit;                  /* CTL_AT_* */
    uint8_t blocked;                /* periods a stop has been believed */
    int8_t mv_dir;                  /* direction of the last moving drive: + closes */
    uint8_t gen;
} va;

static void valve_derive(void) __reentrant
{
    /* one period at full duty moves APP_PERIOD (100 ms) / (P_VALVE_TRAVEL x 100 ms) strokes */
    /* a turning motor runs at (duty - d_run) / (1 - d_run) of full speed (ctl_int.h) */
    va.drun = (q15_t)um_scaled_div(param_v[P_VALVE_BRK], 20480u, 100u);   /* 10/16 of Min duty, Q15, rounded */
    if (va.drun > Q15(0.45))
        va.drun = Q15(0.45);
    va.rate = (q15_t)((((uint32_t)1 << 30) / param_v[P_VALVE_TRAVEL]) / (uint16_t)(32768 - va.drun));
    va.gen = param_generation;
}

void valve_prepare(void)
{
    if (va.gen != param_generation)
        valve_derive();
}

static void bridge(int8_t dir, uint8_t duty, uint16_t now) __reentrant
{
    if (dir == HAL_VALVE_OFF || duty == 0) {
        if (va.out_dir != HAL_VALVE_OFF)
            va.off_ms = now;
        va.out_dir = HAL_VALVE_OFF;
        hal_valve_out(HAL_VALVE_OFF, 0);
        return;
    }
    va.out_dir = dir;
    va.last_dir = dir;
    hal_valve_out(dir, duty);
}

/* Drive the bridge toward what was asked, honouring the dead time. */
static void apply(uint16_t now) __reentrant
{
    if (va.want_dir == HAL_VALVE_OFF || va.want_duty == 0) {
        bridge(HAL_VALVE_OFF, 0, now);
    } else if (va.want_dir == va.out_dir) {
        bridge(va.want_dir, va.want_duty, now);
    } else if (va.out_dir != HAL_VALVE_OFF) {
        bridge(HAL_VALVE_OFF, 0, now);      /* reversal: off first */
    } else if (va.last_dir == HAL_VALVE_OFF || va.want_dir == va.last_dir ||
               (uint16_t)(now - va.off_ms) >= VALVE_DEAD_MS) {
        bridge(va.want_dir, va.want_duty, now);
    }
}

/* valve_init's cleared state is the bridge off */
typedef char valve_off_is_zero[(HAL_VALVE_OFF == 0) ? 1 : -1];

void valve_init(void)
{
    uint8_t i;
    for (i = 0; i < sizeof va; i++)     /* all as at power-up: the bridge off, no drive, no stop
                                         * found (what valve_derive sets, it sets) */
        ((__xdata uint8_t *)&va)[i] = 0;
    va.pos = VALVE_POS_UNKNOWN;
    hal_valve_out(HAL_VALVE_OFF, 0);
    valve_derive();
}

/* Integrate the last period's drive into the position estimate and the stop detection. */
static void integrate(void) __reentrant
{
    q15_t d = va.applied;
    int16_t step;                           /* (d - drun) rate / 2^15 <= 32766 */
    uint16_t t;
    int8_t dir;

    if (d == 0)
        return;
    dir = d > 0 ? 1 : -1;                   /* + closes */
    if (d < 0)
        d = (q15_t)(d == Q15_MIN ? Q15_MAX : -d);
    if (d < VALVE_MOVE_Q15)
        return;                             /* stiction: it does not move */
    step = d > va.drun ? (int16_t)MUL_R15(d - va.drun, va.rate) : 0;    /* (.. * rate + 2^14) >> 15 */
    if (dir != va.mv_dir) {                 /* moving the other way: off the other stop */
        va.mv_dir = dir;
        va.oneway = 0;
        va.over = 0;
        va.limit &= (uint8_t)~(dir > 0 ? CTL_AT_OPEN : CTL_AT_CLOSED);
    }
    va.oneway += step;
    if (va.pos != VALVE_POS_UNKNOWN) {
        /* the new position (step >= 0: rate > 0 for every Valve time); past an end, the rest
         * counts as driven over it. In 16 bits: pos and step are at most 32767 */
        t = va.pos;
        if (dir > 0) {
            if ((uint16_t)step >= t) {
                va.over += (uint16_t)step - t;
                t = 0;
            } else {
                t -= (uint16_t)step;
            }
        } else {
            t += (uint16_t)step;
            if (t >= 32767u) {
                va.over += t - 32767u;
                t = 32767u;
            }
        }
        va.pos = t;
    }
    if (va.oneway >= VALVE_ONEWAY_Q15 || va.over >= VALVE_OVER_Q15) {
        va.limit |= dir > 0 ? CTL_AT_CLOSED : CTL_AT_OPEN;
        va.pos = dir > 0 ? 0 : 32767;
        va.oneway = VALVE_ONEWAY_Q15;
        va.over = VALVE_OVER_Q15;
    }
}

void valve_set(q15_t drive) __reentrant
{
    uint8_t bit;
    uint16_t mag;

    if (va.gen != param_generation)
        valve_derive();
    integrate();

    /* a stop found stays believed for VALVE_RETRY_PERIODS, then the controller (which is told
     * valve_limit() and asks nothing against it) may try VALVE_RETRY_Q15 more */
    if (va.limit) {
        if (++va.blocked >= VALVE_RETRY_PERIODS) {
            va.blocked = 0;
            va.limit = 0;
            va.oneway = VALVE_ONEWAY_Q15 - VALVE_RETRY_Q15;
            va.over = VALVE_OVER_Q15 - VALVE_RETRY_Q15;
        }
    } else {
        va.blocked = 0;
    }
    if (drive != 0) {
        bit = drive > 0 ? CTL_AT_CLOSED : CTL_AT_OPEN;
        if (va.limit & bit)
            drive = 0;
    }
    va.applied = drive;
    if (drive == 0) {
        va.want_dir = HAL_VALVE_OFF;
        va.want_duty = 0;
    } else {
        mag = drive > 0 ? (uint16_t)drive : drive == Q15_MIN ? 32767u : (uint16_t)-drive;
        va.want_dir = drive > 0 ? HAL_VALVE_CLOSE : HAL_VALVE_OPEN;
        va.want_duty = (uint8_t)(mag >> 7);
        if (va.want_duty == 0)
            va.want_duty = 1;
    }
    apply((uint16_t)hal_ms());
}

void valve_poll(uint32_t now_ms) __reentrant
{
    if (va.out_dir != va.want_dir)
        apply((uint16_t)now_ms);
}

uint8_t valve_limit(void)
{
    return va.limit;
}

q15_t valve_applied(void)
{
    return va.applied;
}

uint16_t valve_position(void)
{
    return va.pos;
}

uint8_t valve_opened_by(uint16_t q15)
{
    return va.mv_dir < 0 && va.oneway >= q15;
}

#if FW_HIL
uint8_t valve_pending(int8_t *dir, uint8_t *duty) __reentrant
{
    uint16_t since;
    *dir = va.want_dir;
    *duty = va.want_duty;
    if (va.want_dir == va.out_dir || va.want_dir == HAL_VALVE_OFF || va.want_duty == 0
        || va.last_dir == HAL_VALVE_OFF || va.want_dir == va.last_dir)
        return 0;
    since = (uint16_t)((uint16_t)hal_ms() - va.off_ms);
    return since >= VALVE_DEAD_MS ? 0 : (uint8_t)(VALVE_DEAD_MS - since);
}
#endif

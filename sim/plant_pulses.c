/* plant_pulses.c: the sprayer model's toothed pulse trains (meter blades, wheel elements): their spacing errors and the edges a tick gives, bounce included. */
#include "plant.h"
#include "plant_int.h"

/* The teeth's offsets from a random stream of their own (seed and a tag), so that changing the
 * jitter changes no other draw; the mean is removed (not rescaled) and each offset clipped so
 * the pulses keep their order. The first pulse comes after a random part of a spacing. */
void plant_teeth_init(plant_teeth_t *t, int n, double jitter_pct, uint64_t seed, uint64_t tag, double first)
{
    rng_t r;
    double mean = 0.0;
    int i;
    if (n < 1)
        n = 1;
    if (n > PLANT_MAX_TEETH)
        n = PLANT_MAX_TEETH;
    t->n = n;
    rng_seed(&r, seed ^ (tag * 0x9e3779b97f4a7c15ull));
    for (i = 0; i < n; i++) {
        t->e[i] = jitter_pct / 100.0 * rng_normal(&r);
        mean += t->e[i];
    }
    mean /= n;
    for (i = 0; i < n; i++) {
        double e = t->e[i] - mean;
        t->e[i] = e > PLANT_JITTER_MAX ? PLANT_JITTER_MAX : e < -PLANT_JITTER_MAX ? -PLANT_JITTER_MAX : e;
    }
    t->idx = 0;
    t->next = 1 % n;
    t->thr = 1.0 + t->e[t->next];
    t->pos = first;
}

/* Emit the edges of a toothed pulse train that advances n pulses over the tick: pulse j + 1
 * comes when the position since pulse j reaches 1 + e[(j + 1) % teeth]; a bounce adds an extra
 * edge PLANT_BOUNCE_NS after a real one with probability bounce_pct. */
static uint64_t emit(plant_t *pl, plant_teeth_t *t, double n, uint64_t t0, uint32_t dt_ns,
                     plant_edge_fn fn, double bounce_pct)
{
    double start = t->pos, end = t->pos + n;
    uint64_t count = 0;
    for (;;) {
        double thr = t->thr;
        uint64_t te;
        if (end < thr)
            break;
        te = t0 + (uint64_t)((thr - start) / n * dt_ns + 0.5);
        if (te > t0 + dt_ns)
            te = t0 + dt_ns;
        if (te <= t0)
            te = t0 + 1;
        count++;
        if (fn)
            fn(te);
        if (bounce_pct > 0.0 && rng_uniform(&pl->rng) * 100.0 < bounce_pct) {
            uint64_t tb = te + PLANT_BOUNCE_NS;
            if (tb > t0 + dt_ns)
                tb = t0 + dt_ns;
            count++;
            if (fn)
                fn(tb);
        }
        t->idx++;
        if (++t->next == t->n)
            t->next = 0;
        t->thr = 1.0 + t->e[t->next];
        start -= 1.0;
        end -= 1.0;
    }
    t->pos = end;
    return count;
}

/* The train advances n pulses: most ticks no pulse is due and only the position moves. */
uint64_t plant_train_advance(plant_t *pl, plant_teeth_t *t, double n, uint64_t t0, uint32_t dt_ns,
                             plant_edge_fn fn, double bounce_pct)
{
    if (t->pos + n < t->thr) {
        t->pos += n;
        return 0;
    }
    return emit(pl, t, n, t0, dt_ns, fn, bounce_pct);
}

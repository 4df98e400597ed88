/* plant_int.h: what plant.c shares with its parts, plant_pulses.c and plant_valve.c (not for the simulator's users: plant.h). */
#ifndef PLANT_INT_H
#define PLANT_INT_H

#include "plant.h"

/* exp(-dt / tau) of the last arguments (the tick and the constants rarely change) */
double plant_decay_of(plant_decay_t *c, double dt, double tau);

/* A train's n teeth and their offsets (jitter_pct of a spacing, from a stream of their own: seed
 * and tag), the first pulse after `first` of a spacing. */
void plant_teeth_init(plant_teeth_t *t, int n, double jitter_pct, uint64_t seed, uint64_t tag, double first);
/* The train advances n pulses over the tick from t0: the edges it gives to fn (bounce_pct of them
 * doubled), their count. */
uint64_t plant_train_advance(plant_t *pl, plant_teeth_t *t, double n, uint64_t t0, uint32_t dt_ns,
                             plant_edge_fn fn, double bounce_pct);

#endif

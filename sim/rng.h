/* rng.h: the simulator's own random numbers (xoshiro128**), so a seed gives the same run on every machine. */
#ifndef SIM_RNG_H
#define SIM_RNG_H

#include <stdint.h>

typedef struct {
    uint32_t s[4];
    int has_spare;                  /* Box-Muller makes two normals at a time */
    double spare;
} rng_t;

/* Seed the generator (any 64-bit seed; splitmix64 spreads it over the state). */
void rng_seed(rng_t *r, uint64_t seed);
/* Next 32 random bits. */
uint32_t rng_u32(rng_t *r);
/* Uniform in [0, 1). */
double rng_uniform(rng_t *r);
/* Standard normal (mean 0, standard deviation 1). */
double rng_normal(rng_t *r);

#endif

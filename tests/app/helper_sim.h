/* helper_sim.h: a simulated sprayer from a scenario's text, for the tests that run the firmware against the plant. */
#ifndef HELPER_SIM_H
#define HELPER_SIM_H

#include "sim.h"

/* Parses `text` (errors name `name`, and fail the test) into the helper's one scenario and
 * starts `sim` on it; `*live` says whether `sim` runs, and a running one is freed first (the
 * scenario a simulation reads must outlive it: it lives here until the next call). */
void helper_sim_load(sim_t *sim, int *live, const char *text, const char *name);
/* Frees `sim` if `*live` says it runs (a test's teardown). */
void helper_sim_end(sim_t *sim, int *live);

#endif

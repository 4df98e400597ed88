/* helper_ffmap.h: ffmap as a new controller on a simulated sprayer, for the ffmap tests. */
#ifndef HELPER_FFMAP_H
#define HELPER_FFMAP_H
#include "sim.h"

/* ffmap as a new controller from the default settings (nothing learnt): a seed's run of its own */
void ffmap_anew(void);
/* a simulated sprayer from a scenario's text (its scenario outlives the run: helper_sim.c) */
void ffmap_sim_from(sim_t *sim, const char *text);
/* a whole run: its metrics; returns the alarms it raised */
int ffmap_run(const char *text, metrics_result_t *r);

#endif

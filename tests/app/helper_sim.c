/* helper_sim.c: a simulated sprayer from a scenario's text (helper_sim.h). */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include "helper_sim.h"

void helper_sim_end(sim_t *sim, int *live)
{
    if (*live)
        sim_free(sim);
    *live = 0;
}

void helper_sim_load(sim_t *sim, int *live, const char *text, const char *name)
{
    static scenario_t scn;
    char err[256];
    helper_sim_end(sim, live);
    if (scenario_parse(&scn, text, name, err, sizeof err) != 0)
        fail_msg("%s: scenario: %s", name, err);
    sim_init(sim, &scn);
    *live = 1;
}

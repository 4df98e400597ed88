/* helper_ffmap.c: ffmap as a new controller on a simulated sprayer, for the ffmap tests. */
#include "ctl.h"
#include "params.h"
#include "helper_ffmap.h"
#include "../app/helper_sim.h"

void ffmap_anew(void)
{
    params_defaults();
    ctl_select(CTL_FFMAP);
    ctl_reset(0);
}

void ffmap_sim_from(sim_t *sim, const char *text)
{
    int live = 0;
    helper_sim_load(sim, &live, text, "test_ffmap");
}

int ffmap_run(const char *text, metrics_result_t *r)
{
    sim_t sim;
    int alarms;
    ffmap_sim_from(&sim, text);
    while (!sim_done(&sim))
        sim_step(&sim);
    sim_finish(&sim, r);
    alarms = sim.metrics.n_alarms;
    sim_free(&sim);
    return alarms;
}

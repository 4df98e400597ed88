/* summary.h: a run's figures for a person to read, printed before the metrics' JSON line. */
#ifndef SIM_SUMMARY_H
#define SIM_SUMMARY_H

#include <stdio.h>
#include "sim.h"

/* The scenario, controller and seed, a table of the dose, step and zone figures (the rows
 * tools/demo_report.py sets beside the paper's), then the start, the valve's wear, the pressure,
 * the volume and the alarms; "n/a" where a figure is undefined. Every figure is one of the JSON's. */
void sim_summary(const sim_t *sim, const metrics_result_t *r, FILE *f);

#endif

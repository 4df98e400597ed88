/* ctl_twin.h: double-precision twins of the controllers' arithmetic (tests/helper_ctl_twin.c). */
#ifndef CTL_TWIN_H
#define CTL_TWIN_H

/* eq. (7) increment in valve stroke for errors in L/min and gains as plain numbers. */
double ctltw_pid_du_stroke(double e, double e1, double e2, double kp, double ki, double kd);
/* The drive (fraction of full duty) that moves the valve du_stroke in one period of a valve
 * with a full stroke in travel_periods periods. */
double ctltw_drive(double du_stroke, double travel_periods);
/* fuzzy_pid's gains for an error and error change in L/min: kp, ki, kd. */
void ctltw_fuzzy_gains(double e_lpm, double ec_lpm, double k[3]);
/* bp_pid's forward pass: weights as plain numbers, inputs target/flow in L/min; hidden and outputs. */
void ctltw_bp_forward(const double w[5][4], const double v[3][5], double target_lpm, double flow_lpm,
                      double o[5], double k[3]);
/* bp_pid's output-layer change for one step: dv = eta * delta_l * o_j (momentum excluded). */
void ctltw_bp_dv(const double k[3], const double o[5], double n, double n1, double n2, double dv[3][5]);

#endif

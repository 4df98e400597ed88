/* helper_ctl_twin.c: double-precision twins of the controllers, the references of tests/test_ctl.c. */
#include <math.h>
#include "ctl_twin.h"
#include "ctl_int.h"

double ctltw_pid_du_stroke(double e, double e1, double e2, double kp, double ki, double kd)
{
    return (kp * (e - e1) + ki * e + kd * (e - 2 * e1 + e2)) / CTL_FLOW_SCALE_LPM;
}

double ctltw_drive(double du_stroke, double travel_periods)
{
    return du_stroke * travel_periods;
}

static double ctltw_clamp(double x, double lo, double hi)
{
    return x < lo ? lo : x > hi ? hi : x;
}

/* bilinear blend of a rule table at level coordinates le, lc in [0, 6] */
static double ctltw_blend(int t, double le, double lc)
{
    int i = (int)floor(le), j = (int)floor(lc);
    double fe, fc;
    if (i > 5)
        i = 5;
    if (j > 5)
        j = 5;
    fe = le - i;
    fc = lc - j;
    return fz_tab[t][i][j] * (1 - fe) * (1 - fc) + fz_tab[t][i][j + 1] * (1 - fe) * fc
           + fz_tab[t][i + 1][j] * fe * (1 - fc) + fz_tab[t][i + 1][j + 1] * fe * fc;
}

void ctltw_fuzzy_gains(double e_lpm, double ec_lpm, double k[3])
{
    static const double k0[3] = {1.2, 0.2, 0.8}, q[3] = {0.2, 0.05, 0.2};
    double le = ctltw_clamp(e_lpm / (FZ_E_LEVEL / 100.0), -3, 3) + 3;
    double lc = ctltw_clamp(ec_lpm / (FZ_EC_LEVEL / 100.0), -3, 3) + 3;
    for (int t = 0; t < 3; t++) {
        k[t] = k0[t] + q[t] * ctltw_blend(t, le, lc);
        if (k[t] < 0)
            k[t] = 0;
    }
}

void ctltw_bp_forward(const double w[5][4], const double v[3][5], double target_lpm, double flow_lpm,
                      double o[5], double k[3])
{
    double e = ctltw_clamp(target_lpm - flow_lpm, -15, 15);
    double x[4] = {1.0, ctltw_clamp(target_lpm, 0, 160) / 50.0, ctltw_clamp(flow_lpm, 0, 160) / 50.0, e / 5.0};
    for (int i = 0; i < 5; i++) {
        double a = 0;
        for (int j = 0; j < 4; j++)
            a += w[i][j] * x[j];
        o[i] = tanh(a);
    }
    for (int l = 0; l < 3; l++) {
        double a = 0;
        for (int j = 0; j < 5; j++)
            a += v[l][j] * o[j];
        k[l] = (1 + tanh(a)) / 2;
    }
}

void ctltw_bp_dv(const double k[3], const double o[5], double n, double n1, double n2, double dv[3][5])
{
    double dn[3] = {n - n1, n, n - 2 * n1 + n2};
    for (int l = 0; l < 3; l++) {
        double delta = n * dn[l] * 2 * k[l] * (1 - k[l]);
        for (int j = 0; j < 5; j++)
            dv[l][j] = 0.2 * delta * o[j];
    }
}

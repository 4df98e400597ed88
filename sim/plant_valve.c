/* plant_valve.c: the sprayer model's bypass valve: the DC gear motor with break-away and running friction, its time constant, the backlash and the end stops. */
#include <math.h>
#include "plant.h"
#include "plant_int.h"

double plant_valve_speed(const plant_t *pl, double drive)
{
    double run = pl->p.valve_running_duty, a = fabs(drive);
    double w = a > run ? (a - run) / (1.0 - run) / pl->p.valve_travel_s : 0.0;
    return drive < 0.0 ? -w : w;
}

/* The DC gear motor (docs/SCENARIOS.md): from rest it starts only at abs(d) >= d_break; moving, a drive
 * that pushes its way with abs(d) >= d_run pulls its speed towards (abs(d) - d_run)/(1 - d_run)/T
 * with the time constant tau_m, anything else brakes it towards 0 with tau_m; below 1 % of full
 * speed, or at an end stop, it is at rest. Speed and position are integrated exactly over the
 * tick (first order, constant drive). The valve follows the motor across the backlash gap and
 * stops hard at both ends; a reversal is a motion that starts the other way than the last one. */
void plant_valve_step(plant_t *pl, double drive, double dt)
{
    const plant_params_t *p = &pl->p;
    double half = 0.5 * p->valve_backlash, w_aim, decay, dx, th0 = pl->theta, w0;
    int dir = drive > 0.0 ? 1 : drive < 0.0 ? -1 : 0;
    pl->drive = drive;
    if (pl->valve_stuck) {
        pl->omega = 0.0;
        pl->moving = 0;
        return;
    }
    if (!pl->moving) {
        if (dir == 0 || fabs(drive) < p->valve_stiction_duty)
            return;
        pl->moving = 1;
        pl->omega = 0.0;
        if (pl->motion_dir != 0 && dir != pl->motion_dir)
            pl->valve_reversals++;
        pl->motion_dir = dir;
    }
    /* moving: pushed its own way hard enough, or braked */
    if (dir == pl->motion_dir && fabs(drive) >= p->valve_running_duty)
        w_aim = plant_valve_speed(pl, drive);
    else
        w_aim = 0.0;
    decay = plant_decay_of(&pl->motor_decay, dt, p->valve_motor_tau_s);
    w0 = pl->omega;
    dx = w_aim * dt + (pl->omega - w_aim) * p->valve_motor_tau_s * (1.0 - decay);
    pl->omega = w_aim + (pl->omega - w_aim) * decay;
    if (pl->motion_dir > 0 ? dx < 0.0 : dx > 0.0)
        dx = 0.0;                   /* braking never turns it round */
    pl->motor += dx;
    if (pl->motor > pl->theta + half)
        pl->theta = pl->motor - half;
    else if (pl->motor < pl->theta - half)
        pl->theta = pl->motor + half;
    if (pl->motor >= 1.0 + half) {
        pl->theta = 1.0;
        pl->motor = 1.0 + half;     /* the motor stalls against the stop */
        if (pl->motion_dir > 0)
            pl->moving = 0;
    } else if (pl->motor <= -half) {
        pl->theta = 0.0;
        pl->motor = -half;
        if (pl->motion_dir < 0)
            pl->moving = 0;
    }
    if (fabs(pl->omega) < fabs(w0) && fabs(pl->omega) < PLANT_REST_FRAC / p->valve_travel_s)
        pl->moving = 0;             /* slowing down, and below 1 % of full speed */
    if (!pl->moving)
        pl->omega = 0.0;
    pl->valve_travel += fabs(pl->theta - th0);
}

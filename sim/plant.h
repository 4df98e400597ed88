/* plant.h: the sprayer behind the host HAL: tractor, PTO pump, relief and bypass valves, boom, tank and sensors (docs/SCENARIOS.md). */
#ifndef SIM_PLANT_H
#define SIM_PLANT_H

#include <stdint.h>
#include "rng.h"

/*
 * Every physical key of a scenario's [plant] section: X(key, default, min, max, integer).
 * The key carries its unit. Defaults, ranges and reasons are in docs/SCENARIOS.md.
 */
#define PLANT_KEYS(X)                                                                     \
    X(pump_lpm_at_540,           120,   0,     2000,   0)                                 \
    X(pump_slip_per_bar,         0.01,  0,     0.15,   0)                                 \
    X(pump_pulsation_pct,        4,     0,     50,     0)                                 \
    X(pto_coupled,               1,     0,     1,      1)                                 \
    X(pto_rpm,                   540,   0,     1500,   0)                                 \
    X(v_rated_kmh,               11,    1,     60,     0)                                 \
    X(relief_bar,                5.0,   0.5,   50,     0)                                 \
    X(relief_lpm_per_bar,        200,   1,     10000,  0)                                 \
    X(valve_cv_open,             120,   0,     2000,   0)                                 \
    X(valve_rangeability,        30,    1.5,   1000,   0)                                 \
    X(valve_travel_s,            4,     0.1,   600,    0)                                 \
    X(valve_stiction_duty,       0.2,   0,     0.99,   0)                                 \
    X(valve_backlash,            0.02,  0,     0.5,    0)                                 \
    X(valve_running_duty,        0.12,  0,     0.99,   0)                                 \
    X(valve_motor_tau_s,         0.05,  0.001, 5,      0)                                 \
    X(valve_start_pos,           0,     0,     1,      0)                                 \
    X(line_compliance_l_per_bar, 0.03,  0.001, 10,     0)                                 \
    X(line_loss_bar_at_50lpm,    0.025, 0,     5,      0)  /* k_line = this/50^2 */ \
    X(nozzle_lpm_at_3bar,        1.18,  0.05,  20,     0)                                 \
    X(check_valve_bar,           0.3,   0,     5,      0)                                 \
    X(nozzle_wear_pct,           0,     -50,   200,    0)                                 \
    X(tank_l,                    1000,  1,     100000, 0)                                 \
    X(tank_height_m,             1.2,   0.1,   10,     0)                                 \
    X(tank_start_l,              1000,  0,     100000, 0)                                 \
    X(meter_k_ppl,               380,   1,     10000,  0)                                 \
    X(meter_lag_s,               0.03,  0,     5,      0)                                 \
    X(meter_blades,              6,     1,     64,     1)                                 \
    X(meter_blade_jitter_pct,    1.5,   0,     20,     0)                                 \
    X(wheel_elements,            12,    1,     1000,   1)                                 \
    X(wheel_radius_m,            0.75,  0.05,  5,      0)                                 \
    X(wheel_slip_pct,            0,     -50,   50,     0)                                 \
    X(wheel_spacing_jitter_pct,  2,     0,     20,     0)                                 \
    X(speed_bounce_pct,          0,     0,     100,    0)                                 \
    X(pressure_noise_lsb,        1,     0,     100,    0)                                 \
    X(level_noise_lsb,           1,     0,     100,    0)  /* the level's ADC noise */ \
    X(tractor_lag_s,             1,     0.01,  60,     0)                                 \
    X(tractor_accel_max,         0.5,   0.01,  20,     0)

#define PLANT_KEY_FIELD(key, def, lo, hi, isint) double key;
typedef struct {
    PLANT_KEYS(PLANT_KEY_FIELD)
    /* the boom, from the operator's [config] (the plant has what the console is told) */
    int nozzles;                    /* nozzles on the boom */
    double spacing_m;               /* nozzle spacing */
} plant_params_t;
#undef PLANT_KEY_FIELD

/* Fixed properties of the model that are not scenario keys. */
#define PLANT_PSENS_BAR 16.0        /* pressure sensor: 4-20 mA over 0-16 bar */
#define PLANT_ADC_PER_MA 51.15      /* 250 ohm into a 10-bit ADC at 5 V: 1023 * 0.25 / 5 counts a mA */
#define PLANT_LEAK_REF_BAR 3.0      /* a leak of X L/min is an orifice that passes X L/min at 3 bar */
#define PLANT_DRY_L 2.0             /* the pump loses its suction over the last 2 L in the tank */
#define PLANT_BOUNCE_NS 500000u     /* a bounce pulse follows its real one after 0.5 ms */
#define PLANT_MAX_TEETH 1024        /* largest wheel_elements (meter_blades is at most 64) */
#define PLANT_JITTER_MAX 0.4        /* spacing offsets are clipped to +-0.4 of a spacing, so pulses keep their order */
#define PLANT_REST_FRAC 0.01        /* the valve motor is at rest below 1 % of its full speed */
#define PLANT_SERIES_RAD 0.5        /* the pulsation's turn a tick up to which its series holds */
#define PLANT_MA_MIN 3.8            /* a transmitter's output saturates at 3.8 mA below its range ... */
#define PLANT_MA_MAX 21.0           /* ... and at 21 mA above it */

/* A pulse train from a toothed rotor (meter blades, wheel elements): tooth i's pulse comes at
 * position k + e[i] (in pulses), e drawn once per run, mean removed, so the pattern repeats every
 * revolution and sums to zero over it. */
typedef struct {
    double pos;                     /* position since pulse `idx`, in pulses (may be < 0) */
    uint64_t idx;                   /* pulses emitted so far (the tooth of pulse j is j % n) */
    int n;                          /* teeth a revolution */
    int next;                       /* the tooth of the next pulse: (idx + 1) % n */
    double thr;                     /* where the next pulse comes: 1 + e[next] */
    double e[PLANT_MAX_TEETH];      /* each tooth's offset, in pulse spacings */
} plant_teeth_t;

/* What the firmware drives (through the host HAL). */
typedef struct {
    double drive;                   /* valve motor: signed duty in [-1, 1], + opens the bypass */
    int spray_on;                   /* master boom valve */
} plant_in_t;

typedef void (*plant_edge_fn)(uint64_t t_ns);

/* exp(-dt / tau) for the last dt and tau it was asked for (plant.c computes it again on a change). */
typedef struct {
    double dt, tau, k;
} plant_decay_t;

/* The constants of a tick that plant_step would otherwise divide out each time: computed again
 * when the tick's length or one of the parameters they come from changes (tests set parameters
 * after plant_init). */
typedef struct {
    uint32_t dt_ns;                 /* the key: the tick and the parameters below */
    double slip_pct, v_rated_kmh, pump_lpm, compliance, tank_l, lag_s, m_per_pulse;
    double dt;                      /* s */
    double g, inv_g;                /* the line's compliance over the tick, L/min/bar, and 1/g */
    double pto_per_mps;             /* PTO rpm per m/s of ground speed per rated rpm (coupled) */
    double turn_per_rpm;            /* the pulsation's turn a tick per PTO rpm, rad */
    double pump_per_rpm;            /* pump flow per PTO rpm, L/min */
    double dt_min;                  /* the tick in minutes */
    double level_ma_per_l;          /* the level loop's mA per litre in the tank */
    double inv_lag;                 /* 1 / tractor_lag_s */
    double wheel_per_mps;           /* wheel pulses a tick per m/s of ground speed */
} plant_tick_t;

typedef struct {
    plant_params_t p;
    /* derived constants (plant_init) */
    double kn;                      /* nozzle coefficient L/min/sqrt(bar), wear included */
    double k_line;                  /* bar/(L/min)^2 */
    double m_per_pulse;             /* true distance a wheel pulse: 2 pi r / N */
    /* time */
    uint64_t t_ns;
    /* tractor */
    double v_cmd_kmh;               /* driver's command (the sim sets it from [drive]) */
    double v_mps;                   /* true ground speed */
    double dist_m;                  /* true distance travelled */
    /* pump and PTO */
    double pto_rpm;                 /* rated (coupled) or fixed (uncoupled) PTO speed */
    double pto_now_rpm;             /* PTO speed this tick */
    double pulse_phase;             /* pulsation phase, rad (at plant_init; then the rotor below) */
    double pulse_c, pulse_s;        /* cos and sin of the pulsation phase, turned each tick */
    double pulse_a, pulse_ca, pulse_sa;  /* the last tick's turn, its cos and sin */
    /* valve */
    double theta;                   /* bypass valve position 0 closed .. 1 open */
    double motor;                   /* motor side of the backlash, in stroke units */
    double omega;                   /* motor speed, strokes/s (+ opens); 0 at rest */
    int moving;                     /* 1 while the motor turns (friction: running, not static) */
    int motion_dir;                 /* direction of the last motion: +1 opening, -1 closing, 0 none yet */
    uint64_t valve_reversals;       /* changes of the motor's direction of motion */
    double valve_travel;            /* strokes the valve travelled */
    double cv;                      /* Cv(theta), L/min/sqrt(bar) */
    double cv_theta;                /* the theta cv was computed for */
    double drive;                   /* drive applied this tick (after the HAL) */
    /* line */
    double p_bar;                   /* line pressure at the boom */
    double p_last;                  /* the one before (Newton's first guess follows the trend) */
    double root_p, root_s, root_sc, root_d;  /* p_bar, about sqrt(p_bar) and sqrt(p_bar - check),
                                            and 1 / the slope of the line's equation there: kept
                                            from the last tick for the next one's first Newton step */
    double q_pump, q_relief, q_bypass, q_boom, q_leak;   /* L/min over the last tick */
    double q_meter;                 /* through the flow meter: boom + leak */
    int spray_on;
    int boom_m;                     /* flowing nozzles boom_a was computed for (-1: none yet) */
    double boom_kn, boom_kline, boom_a;
    /* boom */
    int open_nozzles;               /* nozzles in the open sections */
    int clogged;                    /* nozzles that pass nothing (of the open ones) */
    double leak_lpm;                /* leak after the meter, L/min at 3 bar */
    double tank_v;                  /* litres in the tank */
    /* sensors */
    double q_rotor;                 /* turbine rotor's flow (lagged), L/min */
    plant_decay_t motor_decay, rotor_decay;   /* the valve motor's and the rotor's lag a tick */
    plant_tick_t tick;              /* constants of the tick (plant.c) */
    plant_teeth_t meter_teeth, wheel_teeth;   /* blade and element spacing, pulse positions */
    uint64_t flow_pulses, wheel_pulses;  /* pulses sent so far */
    double ma_pressure, ma_level;        /* the 4-20 mA loops this tick */
    uint16_t adc_pressure, adc_level;    /* 10-bit counts of the last conversion (plant_adc_sample) */
    double bounce_pct;
    /* faults */
    int meter_fail, speed_fail, psens_open, valve_stuck;
    double psens_offset_bar;        /* the pressure transmitter reads this much high (its zero off) */
    double psens_drift_bar_per_min; /* ... and the offset grows this much a minute */
    double level_offset_l;          /* the level transmitter reads this much high */
    double wheel_mult;              /* wheel sensor edges a real one (1; 2 doubled, 0.5 every other lost) */
    /* where the edges go (NULL: only counted) */
    plant_edge_fn flow_edge, wheel_edge;
    rng_t rng;
} plant_t;

/* The defaults of docs/SCENARIOS.md (36 nozzles at 50 cm). */
void plant_params_default(plant_params_t *p);
/* Start a plant at rest at time 0: tank at tank_start_l, valve at valve_start_pos, all nozzles
 * open, line pressure 0; the seed drives the sensor noise, the pulsation phase and bounce. */
void plant_init(plant_t *pl, const plant_params_t *p, uint64_t seed);
/* Advance the plant by dt_ns: tractor, valve, pressure (implicit step), tank, then the sensors;
 * edges inside the tick go to the edge functions with their exact times in (t, t + dt]. */
void plant_step(plant_t *pl, const plant_in_t *in, uint32_t dt_ns);

/* One ADC conversion of channel ch (0 pressure, 1 level) now, with its own noise draw: the
 * noise is drawn when the firmware converts, not every tick. Also stores it in adc_*. */
uint16_t plant_adc_sample(plant_t *pl, int ch);
/* The counts a conversion without noise would give now (no draw, nothing stored). */
uint16_t plant_adc_ideal(const plant_t *pl, int ch);

/* The sensors' pulse trains alone (plant_step calls them with the line flow and the ground
 * speed of the tick): the turbine rotor follows q with its lag and pulses at K(q) q; the
 * wheel pulses every 2 pi r / N of its (slipping) travel, bounce adds extra pulses. */
void plant_meter_step(plant_t *pl, double q_lpm, uint64_t t0_ns, uint32_t dt_ns);
void plant_wheel_step(plant_t *pl, double v_mps, uint64_t t0_ns, uint32_t dt_ns);

/* Pieces of the model, for tests and the trace (no side effects). */
/* The valve motor alone over dt seconds with drive d (what step_valve does each tick). */
void plant_valve_step(plant_t *pl, double drive, double dt);
/* The speed the motor tends to under drive d while moving with it: (|d| - d_run)/(1 - d_run)/T. */
double plant_valve_speed(const plant_t *pl, double drive);
double plant_cv(const plant_t *pl, double theta);            /* bypass valve, L/min/sqrt(bar) */
double plant_boom_flow(const plant_t *pl, double p_bar);     /* nozzles' total at boom pressure */
double plant_meter_k(const plant_t *pl, double q_lpm);       /* the meter's true pulses a litre at q */
double plant_pump_flow(const plant_t *pl, double p_bar);     /* without pulsation, this tick's PTO */
double plant_speed_kmh(const plant_t *pl);                   /* true ground speed */
/* The bypass position that holds the boom at q_boom L/min at this tick's PTO speed, steady
 * state, mean pump flow (the ideal controller's valve); 0 or 1 where the valve cannot. */
double plant_bypass_needed(const plant_t *pl, double q_boom);

#endif

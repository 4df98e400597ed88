/* scenario.h: the scenario file of docs/SCENARIOS.md ([run] [config] [plant] [drive] [events]), read strictly. */
#ifndef SIM_SCENARIO_H
#define SIM_SCENARIO_H

#include <stddef.h>
#include <stdint.h>
#include "plant.h"
#include "params.h"

#define SCN_MAX_DRIVE 4096
#define SCN_MAX_EVENTS 1024
#define SCN_MAX_BYTES (1u << 20)     /* a scenario file larger than 1 MB is refused */

/* Events of the [events] section: `time_s name [value]`. */
#define SCN_EVENTS(X)                                                           \
    X(EV_SECTIONS_OPEN,      "sections_open",           1)  /* N nozzles open */  \
    X(EV_RATE,               "rate_l_ha",               1)  /* param_set(P_RATE), Rate 1 */ \
    X(EV_GIVEN_SPEED,        "given_speed_kmh",         1)  /* param_set(P_GIVEN_SPEED), 0: wheel */ \
    X(EV_PTO_RPM,            "pto_rpm",                 1)                         \
    X(EV_METER_FAIL,         "meter_fail",              0)                         \
    X(EV_METER_RESTORE,      "meter_restore",           0)                         \
    X(EV_SPEED_FAIL,         "speed_sensor_fail",       0)                         \
    X(EV_SPEED_RESTORE,      "speed_sensor_restore",    0)                         \
    X(EV_PSENS_OPEN,         "pressure_sensor_open",    0)                         \
    X(EV_PSENS_RESTORE,      "pressure_sensor_restore", 0)                         \
    X(EV_VALVE_STUCK,        "valve_stuck",             0)                         \
    X(EV_VALVE_FREE,         "valve_free",              0)                         \
    X(EV_BOUNCE,             "speed_bounce_pct",        1)                         \
    X(EV_LEAK,               "leak_lpm",                1)  /* after the meter, at 3 bar */ \
    X(EV_CLOG,               "clog_nozzles",            1)                         \
    X(EV_TANK,               "tank_l",                  1)  /* refill to X litres */ \
    X(EV_METER_K,            "meter_k_ppl",             1)  /* the meter's true K from now on */ \
    X(EV_P_OFFSET,           "pressure_offset_bar",     1)  /* the pressure sensor reads X bar high */ \
    X(EV_P_DRIFT,            "pressure_drift_bar_per_min", 1)  /* ... its offset grows X bar a minute */ \
    X(EV_LEVEL_OFFSET,       "level_offset_l",          1)  /* the level sensor reads X L high */ \
    X(EV_WHEEL_MULT,         "wheel_pulse_mult",        1)  /* the wheel sensor gives X edges a real one */ \
    X(EV_POWER_CUT,          "power_cut",               1)  /* X s without power, then a boot */ \
    X(EV_AOG_HZ,             "aog_hz",                  1)  /* AgOpenGPS's 254 and 239 at X Hz (0: stop) */ \
    X(EV_AOG_SECTIONS,       "aog_sections",            1)  /* ... their sections: N nozzles' worth */ \
    X(EV_RC_RATE,            "rc_rate_l_ha",            1)  /* RateControl's 32500 for X L/ha (0: stop) */ \
    X(EV_KEY,                "key",                     2)  /* a keypad key held (text: the key) */ \
    X(EV_SERIAL,             "serial",                  2)  /* a line into the UART (text: the line) */ \
    X(EV_PRESET,             "rate_preset",             1)  /* the preset in use: 1 or 2 */ \
    X(EV_NUDGE,              "rate_nudge",              1)  /* +1 / -1: a Rate step up / down; 0: back to the preset */

#define SCN_EV_ENUM(id, name, arg) id,
enum { SCN_EVENTS(SCN_EV_ENUM) EV_COUNT };
#undef SCN_EV_ENUM

typedef struct {
    double t_s;
    double kmh;                     /* commanded speed */
} scn_drive_t;

#define SCN_TEXT_MAX 72             /* a key or serial event's text, its end included (sim_input_t) */

typedef struct {
    double t_s;
    int kind;                       /* EV_* */
    double value;                   /* 0 when the event takes none */
    int line;                       /* where it stands in the file */
    char text[SCN_TEXT_MAX];        /* key and serial events: the key, the line ("" for the others) */
} scn_event_t;

typedef struct {
    char name[256];                 /* file name, for messages */
    /* [run] */
    double duration_s;              /* default 300 */
    uint64_t seed;                  /* default 7 */
    /* [config]: the firmware parameters the operator set, in params.h units, all valid */
    uint16_t param[P_COUNT];        /* starts at the firmware's defaults */
    /* [plant] (nozzles and spacing follow [config]) */
    plant_params_t plant;
    /* [drive]: time-ordered, linear between rows, two rows at one time make a step */
    int n_drive;
    scn_drive_t drive[SCN_MAX_DRIVE];
    /* [events]: time-ordered */
    int n_events;
    scn_event_t events[SCN_MAX_EVENTS];
} scenario_t;

/* Read a scenario file. 0 on success; -1 with "file:line: key 'k': what is wrong" in err (and
 * the scenario must not be run) on any error: unknown section or key, a key given twice, a
 * bad or missing number, a value out of range, values the firmware's cross-checks refuse
 * together (the line of the latest named), time going backwards, an unknown event, no drive
 * rows (an empty file too; without a line when there is no [drive]). Bytes that do not
 * print are written \xHH in err. */
int scenario_load(scenario_t *s, const char *path, char *err, size_t errlen);
/* The same from text in memory; name stands for the file in messages. */
int scenario_parse(scenario_t *s, const char *text, const char *name, char *err, size_t errlen);
/* src into dst (n bytes with the terminator, cut at a whole character) with every byte outside
 * printable ASCII written as \xHH: the messages name what a file holds, which may be binary. */
void scenario_printable(char *dst, size_t n, const char *src);
/* A scenario of defaults only, no drive (what the reader starts from). */
void scenario_default(scenario_t *s, const char *name);
/* Controller by name: ctl_name(id) of any id, or an old name of the alias table in scenario_rows.c. -1 when unknown. */
/* The i-th old name the alias table accepts and the id it stands for; NULL past the table's end. */
const char *scenario_controller_alias(size_t i, int *id);
int scenario_controller_id(const char *name);
/* Change the controller after loading (the program's --controller); -1 and err when unknown. */
int scenario_set_controller(scenario_t *s, const char *name, char *err, size_t errlen);
/* The run cut at t_s seconds when that ends it sooner (the program's --duration): the events
 * after t_s dropped. -1 and why in err when t_s is not a duration (0, 1000000] s. */
int scenario_cut(scenario_t *s, double t_s, char *err, size_t errlen);
/* The driver's commanded speed at time t (km/h). */
double scenario_drive_kmh(const scenario_t *s, double t_s);
/* 0 when an event's value is valid for this scenario; -1 and why in msg otherwise. */
int scenario_event_check(const scenario_t *s, int kind, double value, char *msg, size_t n);
/* The name of an event kind. */
const char *scenario_event_name(int kind);
/* 1 when the event takes a value (`rate_l_ha 125`), 0 when it stands alone (`meter_fail`), 2
 * when it takes the rest of its row as text (`key #`, `serial SET 0 100*EA`: '#' included). */
int scenario_event_takes_value(int kind);
/* 0 when a key or serial event's text is valid (a key of 0-9 A-D * #; a line of 1..SCN_TEXT_MAX-1
 * printable characters); -1 and why in msg otherwise. */
int scenario_event_text_check(int kind, const char *text, char *msg, size_t n);
/* Nozzles a section holds (param NOZZLES / SECTIONS; the reader checks it divides). */
int scenario_nozzles_per_section(const scenario_t *s);

#endif

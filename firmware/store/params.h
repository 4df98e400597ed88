/* params.h: every setting of the controller in one table: range-checked, with defaults, names and units. */
#ifndef PARAMS_H
#define PARAMS_H

#include "compiler.h"

/*
 * One row per parameter: id, short name (LCD and serial), unit, decimals shown, min, max,
 * default. Values are uint16 in the unit times 10^decimals. The console's menus, the serial
 * link, the EEPROM store and the scenario reader all go through this table; nothing else
 * holds a setting.
 */
/* Control: the field image carries ffmap (3) only; the research image (FW_PEERS) all six of
 * ctl.h, the paper's bp_pid among them */
#define P_CTL_MIN (FW_PEERS ? 0 : 3)
#define P_CTL_MAX (FW_PEERS ? 5 : 3)
#define PARAM_TABLE(X)                                                              \
    X(P_RATE,        "Rate 1",     "L/ha",  1,   100, 10000, 1500)  /* eq. (1) C: the first preset */ \
    X(P_NOZZLES,     "Nozzles",    "",      0,     1,    96,   36)  /* eq. (1) m */      \
    X(P_SPACING,     "Spacing",    "cm",    0,    10,   200,   50)  /* eq. (1) d */      \
    X(P_SECTIONS,    "Sections",   "",      0,     1,     8,    6)  /* nozzles split evenly */ \
    X(P_WHEEL,       "Wheel cal",  "mm/p",  1,   100, 30000, 3927)  /* distance a pulse */ \
    X(P_METER_K,     "Meter K",    "p/L",   1,   100, 60000, 3800)  /* flow meter pulses a litre */ \
    X(P_MINF_SPEED,  "MinQ speed", "km/h",  1,     0,   100,   40)  /* Table 1 rule below this */ \
    X(P_GIVEN_SPEED, "Given spd",  "km/h",  1,     0,   300,    0)  /* 0: wheel sensor */ \
    X(P_CONTROLLER,  "Control",    "",      0, P_CTL_MIN, P_CTL_MAX, 3)  /* ctl.h CTL_* */ \
    X(P_MODE,        "Mode",       "",      0,     0,     1,    0)  /* 0 auto, 1 manual */ \
    X(P_TANK_L,      "Tank size",  "L",     0,    10, 10000, 1000)                      \
    X(P_TANK_MIN,    "Tank min",   "L",     0,     0,  2000,   30)  /* below: stop spraying */ \
    X(P_TANK_H,      "Tank hgt",   "mm",    0,   100,  5000, 1200)  /* level sensor span */ \
    X(P_PSENS_MAX,   "P sensor",   "kPa",   0,   100, 10000, 1600)  /* pressure at 20 mA */ \
    X(P_P_MAX,       "P max",      "kPa",   0,    50,  2000,  480)  /* over-pressure alarm */ \
    X(P_P_MIN,       "P start",    "kPa",   0,     0,   500,  100)  /* start-up: check valves open */ \
    X(P_OFFRATE,     "Off-rate",   "%",     0,     1,    50,   10)  /* alarm above this error */ \
    X(P_OFFRATE_S,   "Off-rate t", "s",     0,     1,    60,    5)  /* ... for this long */ \
    X(P_PDEV,        "P dev",      "%",     0,     5,    90,   30)  /* leak / clog: pressure off the nozzle model */ \
    X(P_NOZZLE_Q3,   "Nozzle Q3",  "L/min", 2,    10,  2000,  118)  /* one nozzle at 3 bar */ \
    X(P_VALVE_TRAVEL,"Valve time", "s",     1,     5,   600,   40)  /* full stroke of the valve */ \
    X(P_VALVE_BRK,   "Min duty",   "%",     0,     5,    90,   20)  /* the valve's break-away duty, or a little above */ \
    X(P_VALVE_SLACK, "Backlash",   "%",     1,     0,   100,   20)  /* the valve's backlash, % of the stroke, or a little under */ \
    X(P_WHEEL_PPR,   "Wheel p/rev","",      0,     1,    16,   12)  /* wheel pulses a turn: their spacing error is learnt */ \
    X(P_AOG_KP,      "AOG Kp",     "",      0,     0,  1500,   45)  /* aog: as the app sets it (the module's Kp x 100) */ \
    X(P_AOG_KI,      "AOG Ki",     "",      0,     0,  2000,   70)  /* aog: as the app sets it (the module's Ki x 100) */ \
    X(P_AOG_BRAKE,   "AOG brake",  "%",     1,     0,   500,  350)  /* aog: the brake point, % of the target */ \
    X(P_AOG_MIN,     "AOG minPWM", "",      0,     0,   255,    5)  /* aog: the smallest drive, PWM counts */ \
    X(P_AOG_MAX,     "AOG maxPWM", "",      0,     1,   255,  255)  /* aog: the largest drive, PWM counts */ \
    X(P_RAVEN_CAL,   "Valve cal",  "",      0,    11,  9999, 2123)  /* raven: backlash, speed, brake point, dead band digits */ \
    X(P_REMOTE,      "Remote",     "",      0,     0, P_REMOTE_MAX, 0)  /* 0 off; Raven at 1 9600, 2 1200 baud (remote.h); 3 AgOpenGPS frames (pgn.h) */ \
    X(P_REMOTE_WIN,  "Remote win", "%",     0,     1,   100,   50)  /* a remote rate within this of the preset */ \
    X(P_LOG_EVERY,   "Log every",  "",      0,     0,  9999,    1)  /* Raven's data logger trigger, in Log unit; 0 off */ \
    X(P_LOG_UNIT,    "Log unit",   "",      0,     0,     1,    1)  /* 0 metres, 1 seconds */ \
    X(P_AOG_SLOW,    "AOG slow",   "%",     0,     1,   100,   60)  /* aog: the gain inside the brake point, % */ \
    X(P_RATE2,       "Rate 2",     "L/ha",  1,   100, 10000, 2000)  /* the second preset */ \
    X(P_PRESET,      "Preset",     "",      0,     0,     1,    0)  /* 0 Rate 1, 1 Rate 2 in use */ \
    X(P_RATE_STEP,   "Rate step",  "%",     0,     1,    50,    5)  /* a nudge of the rate in use */ \
    X(P_UNITS,       "Units",      "",      0,     0,     2,    0)  /* 0 metric, 1 US, 2 turf (ops/units.c) */ \
    X(P_SPEED_SRC,   "Speed src",  "",      0,     0,     2,    0)  /* 0 wheel, 1 GPS (PGN 254), 2 both cross-checked */ \
    X(P_SPEED_DIFF,  "Speed diff", "%",     0,     2,    50,    5)  /* both: wheel off GPS by this: WHEEL_NOISE */ \
    X(P_AOG_SECT,    "AOG sect",   "",      0,     0,     1,    0)  /* 1: sections also from the frames */ \
    X(P_AOG_REPLY,   "AOG reply",  "",      0,     0,     1,    1)  /* 1: PGN 237 answers each 239, as a machine module */ \
    X(P_FRAMES_LOST, "Frames lost","s",     1,     3,   100,   26)  /* frames in use stopped this long: boom shut */ \
    X(P_RC_ID,       "RC module",  "",      0,     0,    15,    0)  /* RateControl module id */
/* The frame settings are in every image's table (a record loads in any image); an image
 * without the frames (FW_PGN 0) only stores them, and its Remote stops at Raven */
#define REMOTE_RAVEN_9600 1         /* P_REMOTE: Raven's strings at 9600 baud (remote.h) */
#define REMOTE_RAVEN_1200 2         /* ... at 1200 baud */
#define REMOTE_PGN 3                /* P_REMOTE: AgOpenGPS and RateControl frames (pgn.h) */
/* Remote's top value; whether it is a Raven console's link; the UART's framing for it (hal.h
 * HAL_UART_*: a Raven's is Remote's value, the frames ride our own link's) */
#if FW_PGN
#define P_REMOTE_MAX REMOTE_PGN
#define REMOTE_IS_RAVEN(r) ((r) && (r) != REMOTE_PGN)
#define REMOTE_FRAMING(r) ((uint8_t)((r) == REMOTE_PGN ? HAL_UART_38400_8N1 : (r)))
#else
#define P_REMOTE_MAX REMOTE_RAVEN_1200
#define REMOTE_IS_RAVEN(r) ((r) != 0)
#define REMOTE_FRAMING(r) ((uint8_t)(r))
#endif
#define SPEED_SRC_WHEEL 0           /* P_SPEED_SRC: the wheel sensor */
#define SPEED_SRC_GPS 1             /* ... PGN 254's speed */
#define SPEED_SRC_BOTH 2            /* ... PGN 254's, the wheel's cross-checked against it */

#define PARAM_ENUM(id, name, unit, dec, lo, hi, def) id,
enum { PARAM_TABLE(PARAM_ENUM) P_COUNT };
#undef PARAM_ENUM

#define PARAMS_VERSION 11           /* bump when the table or the EEPROM record changes (2: lifetime totals,
                                     * 3: Min duty and Backlash appended, 4: Wheel p/rev appended, 5: the peers'
                                     * settings and Remote appended, 6: the learnt figures after the totals,
                                     * 7: ffmap's speed feed-forward among them, 8: the job totals after them,
                                     * 9: Raven's data logger trigger and AOG slow appended, the aog peer's
                                     * settings in the current RateControl's units, AOG brake in AOG Kd's
                                     * place, 10: Dose as Rate 1 in 0.1 L/ha, Rate 2, Preset, Rate step and
                                     * Units appended, 11: the speed source and frame settings appended; a
                                     * copy of version 2 to 10 still loads, the values appended since and
                                     * (before 9) the aog settings at their defaults) */
#define PARAMS_V2_COUNT 21          /* P_COUNT of version 2: the table up to P_VALVE_TRAVEL */
#define PARAMS_V3_COUNT 23          /* P_COUNT of version 3: up to P_VALVE_SLACK */
#define PARAMS_V4_COUNT 24          /* P_COUNT of version 4: up to P_WHEEL_PPR */
#define PARAMS_V8_COUNT 32          /* P_COUNT of versions 5 to 8: up to P_REMOTE_WIN */
#define PARAMS_V9_COUNT 35          /* P_COUNT of version 9: up to P_AOG_SLOW */
#define PARAMS_V10_COUNT 39         /* P_COUNT of version 10: up to P_UNITS */
/* the count of values each known version's record holds, from version 2 (params.c) */
extern const __code uint8_t params_version_count[PARAMS_VERSION - 1u];

typedef struct {
    const __code char *name;
    const __code char *unit;
    uint8_t decimals;
    uint16_t min, max, def;
} param_info_t;

/* The live values, in the table's units. Read them directly: param_v[P_RATE]. */
extern uint16_t param_v[P_COUNT];

/* Every value back to its default. */
void params_defaults(void);

/*
 * Cross-checks between parameters, at the keypad, the serial link and the EEPROM load:
 *   PARAM_X_TANK      Tank min below Tank size (else the boom stops at once, for good)
 *   PARAM_X_PRESSURE  P start below P max (else start-up closes the valve into over-pressure)
 *   PARAM_X_METER     the meter's pulse rate at the largest flow (every nozzle at P max)
 *                     within PARAM_METER_HZ_MAX: each pulse is a PCA interrupt, and a rate
 *                     beyond the budget starves the main loop into a watchdog reset loop
 *   PARAM_X_FLOW      the largest flow (every nozzle at P max) within PARAM_FLOW_MAX_X100:
 *                     the meter's range (flow.h FLOW_MAX_X100) and under the target's
 *                     (327.67 L/min, L/min x100 in 16 bits), so no flow the boom can pass
 *                     is read as a glitch or held at a clipped target
 */
#define PARAM_OK 0
#define PARAM_E_RANGE 1
#define PARAM_X_TANK 2
#define PARAM_X_PRESSURE 3
#define PARAM_X_METER 4
#define PARAM_X_FLOW 5
#define PARAM_METER_HZ_MAX 5000UL
#define PARAM_FLOW_MAX_X100 30000UL
/* The rule param_v as it is breaks; PARAM_OK. */
uint8_t params_cross(void) __reentrant;
/* Set one value if it is in range and keeps every cross-check: PARAM_OK, or why not (nothing changes). */
uint8_t param_try(uint8_t id, uint16_t v) __reentrant;
/* param_try as a yes / no: 1 when set. */
uint8_t param_set(uint8_t id, uint16_t v) __reentrant;
/* Set one value checking its range only (a whole set being loaded: check params_cross after). */
uint8_t param_put(uint8_t id, uint16_t v) __reentrant;
/* At most 16 characters on why a value was refused ("Tank min>=size"); "" for PARAM_OK. */
const __code char *param_why_text(uint8_t why) __reentrant;
/* 1 when v is within the range of parameter id (and, for Valve cal, its dead band digit is 1-9). */
uint8_t param_in_range(uint8_t id, uint16_t v) __reentrant;
/* Value v of parameter id in a record of version ver: param_in_range of param_of_version's, or
 * Remote = AgOpenGPS in an image without the frames (a record from one with them) */
uint8_t param_stored_ok(uint8_t ver, uint8_t id, uint16_t v) __reentrant;
/* Value v of parameter id in a record of version ver, in this version's units: Rate 1 was whole
 * L/ha before version 9 (0, out of every range, for what it cannot have been). */
uint16_t param_of_version(uint8_t ver, uint8_t id, uint16_t v) __reentrant;
/* The table row of a parameter (NULL for a bad id). */
const __code param_info_t *param_info(uint8_t id);
/* Bumped by every change, so readers (controller, target) can tell when to pick values up. */
extern __data uint8_t param_generation;    /* direct RAM: read by every module */

#endif

/* diag.h: the alarms: each with a bit, a code, an LCD text and a serial message, and the rules that raise and clear them. */
#ifndef DIAG_H
#define DIAG_H

#include "compiler.h"
#include "status.h"

/* The alarms, one row each: bit name, serial code, LCD text. The text fits the LCD line after
 * its mark ("!" not yet acknowledged): at most DIAG_TEXT_MAX characters (test_console checks
 * every row). A new alarm is one more row here and its rule in diag.c. */
#define DIAG_TEXT_MAX 15
#define DIAG_ALARMS(X)                                                                          \
    X(AL_TANK_LOW,     "TANK_LOW",     "Tank low: stop")   /* tank below P_TANK_MIN: spraying stops */ \
    X(AL_PUMP_DRY,     "PUMP_DRY",     "PumpDry:PTO off")  /* tank empty (<= 1 % of P_TANK_L): disengage the PTO */ \
    X(AL_LEAK,         "LEAK",         "Leak past meter")  /* pressure low for the measured flow */ \
    X(AL_CLOG,         "CLOG",         "Nozzles clogged")  /* pressure high for the measured flow */ \
    X(AL_METER_LOST,   "METER_LOST",   "Flowmeter lost")   /* no meter pulses while the pressure says flow */ \
    X(AL_SPEED_LOST,   "SPEED_LOST",   "Speed sens lost")  /* wheel pulses stopped at working speed; or the AgOpenGPS frames in use stopped (pgn.h) */ \
    X(AL_PSENS,        "PSENS_FAULT",  "P sensor fault")   /* pressure sensor open or short, or off its zero with the line at rest */ \
    X(AL_LSENS,        "LSENS_FAULT",  "Tank sens fault")  /* level sensor open */ \
    X(AL_OVERPRESSURE, "OVERPRESSURE", "Over-pressure")    /* pressure above P_P_MAX: the valve is opened */ \
    X(AL_OFFRATE,      "OFF_RATE",     "Rate off target")  /* flow off the target by P_OFFRATE % for P_OFFRATE_S */ \
    X(AL_METER_NOISE,  "METER_NOISE",  "Flowmeter noise")  /* meter pulses faster than the meter can make */ \
    X(AL_WHEEL_NOISE,  "WHEEL_NOISE",  "Wheel noise")      /* wheel pulses faster than 60 km/h; or off the GPS's speed (Speed src both) */ \
    X(AL_INTERNAL,     "INTERNAL",     "Internal fault")   /* a parameter out of range in RAM: latched, the watchdog resets */ \
    X(AL_METER_CAL,    "METER_CAL",    "Meter/tank cal.")  /* the metered volume off the tank level's fall: Meter K (or Tank size) is wrong */ \
    X(AL_NOZZLE_WEAR,  "NOZZLE_WEAR",  "Nozzles worn")     /* notice: the held nozzle model passes over 10 % more than the catalog */ \
    X(AL_MIN_FLOW,     "MIN_FLOW",     "MinQ: dose high")  /* warning: the minimum-flow rule holds the dose over Dose by more than 10 % */

/* Alarm bits (app_status.alarms, ops.h: 16 bits, all used). */
#define DIAG_AL_ENUM(bit, code, text) bit,
enum { DIAG_ALARMS(DIAG_AL_ENUM) AL_COUNT };
#undef DIAG_AL_ENUM
/* Bits that show on the LCD and the link but do not sound the buzzer (notices and warnings);
 * OFF_RATE is one in manual mode, where the operator sets the valve (app.c). */
#define DIAG_QUIET_BITS ((1u << AL_NOZZLE_WEAR) | (1u << AL_MIN_FLOW))

/* Persistence and hysteresis, in control periods (100 ms). */
#define DIAG_TANK_PERIODS 10u       /* 1 s below the minimum */
#define DIAG_PDEV_PERIODS 20u       /* leak/clog: 2 s off the nozzle model */
#define DIAG_METER_PERIODS 10u      /* 1 s without meter flow while the pressure says flow */
#define DIAG_SPEED_PERIODS 20u      /* 2 s without a wheel pulse after working speed */
#define DIAG_OVERP_PERIODS 3u       /* 0.3 s above P_P_MAX */
#define DIAG_CLEAR_PERIODS 10u      /* 1 s without the cause clears an alarm */
#define DIAG_MIN_FLOW_PERIODS 30u   /* 3 s under MinQ speed / 1.1 (a start from rest passes it) */
#define DIAG_MANUAL_PERIODS 20u     /* manual mode: 2 s off the rate is OFF_RATE (a warning there) */
#define DIAG_P_CHECK_KPA 30u        /* anti-drip check valves open at 0.3 bar (nozzle model) */
#define DIAG_MODEL_MIN_X100 500     /* leak/clog/meter rules need 5 L/min or more */
#define DIAG_METER_RANGE_X100 750   /* ... learning and the fine band 7.5 L/min (the meter's K within 3 %) */
#define DIAG_WHEEL_GLITCH 8u        /* wheel noise score of a rejected pulse (a good one: -1) */
#define DIAG_METER_QUIET 3u         /* periods without a meter pulse that make the meter suspect */
#define DIAG_PDEV_FAR_KPA 120u      /* ... elsewhere a deviation of P_PDEV % and at least this */
#define DIAG_PDEV_MIN_KPA 50u       /* leak/clog judged where the nozzles need this above their check valves */
#define DIAG_MOVE_SHIFT 7u          /* ... and not while the target moves by more than 1/128 a period */
#define DIAG_WEAR_KP_KPA 242u       /* the model under this kPa at the catalog flow (300 / 1.115^2 = 241.3): worn over 11.5 %, 10 % and the meter's 1 % */
#define DIAG_BAL_PERIODS 10u        /* METER_CAL: the tank balance off (diag_line.h) for 1 s */
/* The nozzle model learnt from the sprayer at a calibration only (no model yet, the tank test,
 * "Nozzles relearn"): DIAG_LEARN_N samples, one every DIAG_LEARN_EVERY clean periods (steady
 * flow within 5 % of its target, no flow alarm): the first half minute of clean spraying after
 * it, then held until the next calibration. A fit needs the flows' squares to spread (N^2 var(x), x in Q8), and by at
 * least 1/2^DIAG_LEARN_REL of their mean's square (a standard deviation of a quarter of it). */
#define DIAG_LEARN_N 64u
#define DIAG_LEARN_EVERY 4u
#define DIAG_LEARN_SPREAD 2700000UL
#define DIAG_LEARN_REL 4u

void diag_init(void);
/* One period: evaluate every rule. The inputs: this period's figures `st` (tank, pressure,
 * target, flow, speed, manual), `settled` (the boom sprays and start-up is over), `p_watch`
 * (the pressure must stay under P max now: spraying, or the bypass parked open), the sensors'
 * ok flags, the pulse modules' quiet counters and glitch counts, the valve's refusals. Returns
 * the active alarm bits. */
uint16_t diag_step(const __xdata app_status_t *st, uint8_t settled, uint8_t p_watch) __reentrant;
/* The nozzle model's constant derived again after a fit (diag_step leaves it to this, in a pass
 * of its own, or to its next use); 1 when it did. */
uint8_t diag_after_fit(void);
uint16_t diag_alarms(void);
/* Forget the held nozzle model (new nozzles, a meter calibration, the menu): learn it again
 * from the next clean spraying, then hold it. */
void diag_nozzle_relearn(void);
uint8_t diag_nozzle_learnt(void);
/* Byte i of the EEPROM's learnt figures (store.h store_learnt_from; diag_init registers it):
 * ffmap's valve, then the nozzle model learnt over the range (check valves, kPa at the rated
 * flow; 0xFF while there is none). diag_init restores the record's model. */
uint8_t diag_learnt_byte(uint8_t i) __reentrant;
/* The flow the nozzles pass at this pressure, q = n Q3 / sqrt(3 bar) * sqrt(P - P_check), L/min x100. */
int16_t diag_nozzle_flow_x100(uint16_t pressure_kpa, uint8_t open_nozzles) __reentrant;
/* The pressure the nozzle model needs for this flow, kPa (0 with no nozzles). */
uint16_t diag_nozzle_pressure_kpa(int16_t flow_x100, uint8_t open_nozzles) __reentrant;
/* Nozzles the model uses (set by the application each period). */
void diag_set_nozzles(uint8_t open_nozzles) __reentrant;
/* Latch the internal fault. */
void diag_internal_fault(void);
const __code char *diag_code(uint8_t bit);
const __code char *diag_text(uint8_t bit);
/* The reset cause (hal_reset_cause): "WATCHDOG" for the serial link's BOOT line, and a line
 * of at most 16 characters for the LCD ("Reset: watchdog"). */
const __code char *diag_reset_code(void);
const __code char *diag_reset_text(void);

/* The meter reads under a quarter of what the nozzles pass at this pressure, this period (the
 * METER_LOST rule before its 1 s of persistence): the control stops trusting the meter at once. */
uint8_t diag_meter_suspect(void);
#endif

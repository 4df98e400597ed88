/* app.h: the application: measurement -> rate target -> controller -> valve, console and alarms. */
#ifndef APP_H
#define APP_H

#include "compiler.h"

/* The control period: every measurement, target and controller step runs once per period.
 * 100 ms: the BP-PID step must fit in 25 % of it on a classic 12-clock 8051 (23040 cycles). */
#define APP_PERIOD_MS 100

/* Alarm bits of app_status.alarms (codes and LCD texts from app_alarm_code/_text). */
#define APP_ALARM_BITS 16

/* What the application measured and decided in its last control step: the console, the
 * serial log and the simulator's trace read it; only the application writes it. */
typedef struct {
    uint16_t speed_kmh_x100;        /* ground speed used for the target (measured or given) */
    int16_t target_lpm_x100;        /* target boom flow, eq. (1) and Table 1 */
    int16_t flow_lpm_x100;          /* measured boom flow */
    uint16_t pressure_kpa;          /* boom line pressure */
    uint16_t tank_l;                /* tank contents from the level sensor */
    uint16_t applied_l_ha_x10;      /* dose applied over the job so far */
    int16_t drive;                  /* Q15 valve drive from the controller (+ = more flow) */
    int16_t gain[3];                /* kp, ki, kd the controller used in its last step, Q12 */
    uint16_t alarms;                /* active alarm bits */
    uint16_t alarms_unacked;        /* alarm bits raised and not yet acknowledged */
    uint8_t spraying;               /* master boom valve open */
    uint8_t manual;                 /* manual mode (operator jogs the valve) */
    uint8_t open_nozzles;           /* nozzles in the switched-on sections */
    uint32_t job_area_m2;           /* totals: area and volume of this job ... */
    uint32_t job_volume_ml;
    uint32_t life_area_m2;          /* ... and of the machine's life */
    uint32_t life_volume_ml;
} app_status_t;

extern app_status_t app_status;

void app_init(void);
/* Call as often as possible: runs whatever is due (control step, keypad, display, serial). */
void app_poll(void);
/* Manual mode or the I/O test: drive the valve for one jog (+1 more boom flow, -1 less). */
void app_jog(int8_t dir);
/* The I/O test: APP_IO_ON hands the outputs to the technician (the boom's control stops,
 * the spray relay and the buzzer follow APP_IO_RELAY and APP_IO_BUZZER, app_jog drives the
 * valve); without APP_IO_ON everything goes back to the application. No parameter changes. */
#define APP_IO_ON 1
#define APP_IO_RELAY 2
#define APP_IO_BUZZER 4
void app_io_test(uint8_t flags);
uint8_t app_io_test_flags(void);
/* Acknowledge the alarms now shown (they stay active while their cause lasts). */
void app_alarm_ack(void);
/* Zero the job totals. */
void app_totals_reset(void);
/* Short code ("TANK_LOW") and LCD text (at most 16 characters) of an alarm bit. */
const char *app_alarm_code(uint8_t bit);
const char *app_alarm_text(uint8_t bit);
/* Running pulse totals since start, for the calibration procedures (100 m, tank method). */
uint32_t app_wheel_pulses(void);
uint32_t app_flow_pulses(void);
/* Control steps that ran a whole period or more late, since start. */
uint16_t app_overruns(void);

#endif

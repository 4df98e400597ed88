/* ops.h: the operations the console and the serial link call down into, and the status they read. */
#ifndef OPS_H
#define OPS_H

#include "compiler.h"
#include "ctl.h"
#include "status.h"

/* Bits of app_status.alarms (diag.h names them; codes and texts from diag_code/_text). */
#define OPS_ALARM_BITS 16

/* The application's figures of its control step, each into its field of app_status. */
void ops_set_speed(uint16_t kmh_x100) __reentrant;         /* in.speed_kmh_x100 */
void ops_set_target(int16_t lpm_x100) __reentrant;         /* in.target_lpm_x100 */
void ops_set_flow(int16_t lpm_x100) __reentrant;           /* in.flow_lpm_x100 */
void ops_set_pressure(uint16_t kpa) __reentrant;           /* in.pressure_kpa */
void ops_set_valve_limit(uint8_t limit) __reentrant;       /* in.valve_limit */
void ops_set_manual(uint8_t manual) __reentrant;
void ops_set_open_nozzles(uint8_t open) __reentrant;
void ops_set_spraying(uint8_t spraying) __reentrant;
void ops_set_boom_wait(uint8_t wait) __reentrant;
/* The tank's contents and the valve's applied drive into the status (each control step). */
void ops_show_step(void);
/* The job's area and dose into the status (once a second: a divide). */
void ops_show_totals(void);
/* The alarms diag_step left into the status: the newly raised ones unacknowledged but the quiet
 * bits (DIAG_QUIET_BITS, and OFF_RATE in manual mode, where the operator sets the valve), which
 * show without the buzzer; the buzzer while any is unacked (the I/O test's switch otherwise). */
void ops_alarms_step(void);

/* A jog asked for (manual mode, the I/O test): the control step drives it, OPS_JOG_PERIODS periods. */
#define OPS_JOG_PERIODS 3u
/* The control step's jog: +1 more boom flow, -1 less, 0 none; each call takes one period of the
 * jog asked for. */
int8_t ops_jog_take(void);
/* A jog not yet driven dropped (the mode changed). */
void ops_jog_cancel(void);

/* The I/O test (console): OPS_IO_ON hands the outputs to the technician: the boom's control
 * stops, the spray relay and the buzzer follow OPS_IO_RELAY and OPS_IO_BUZZER, ops_jog drives
 * the valve; without OPS_IO_ON everything goes back to the application. No parameter changes. */
#define OPS_IO_ON 1
#define OPS_IO_RELAY 2
#define OPS_IO_BUZZER 4
extern __data uint8_t ops_io;       /* OPS_IO_*, app.c follows it (0 without FW_IOTEST) */
#if FW_IOTEST
void ops_io_test(uint8_t flags);
#endif

/* The status cleared, no jog, no I/O test (power-up). */
void ops_init(void);
/* Manual mode or the I/O test: drive the valve for one jog (+1 more boom flow, -1 less);
 * ignored otherwise. */
void ops_jog(int8_t dir);
/* Acknowledge these alarm bits (they stay active while their cause lasts); the buzzer sounds
 * on while any other is unacknowledged. ops_alarm_ack(): all of them (the serial link's ACK). */
void ops_alarm_ack_bits(uint16_t bits) __reentrant;
#define ops_alarm_ack() ops_alarm_ack_bits(0xFFFFu)
/* Zero the job totals. */
void ops_totals_reset(void);
/* Running pulse totals since start, for the calibration procedures (100 m, tank method). */
uint32_t ops_wheel_pulses(void);
uint32_t ops_flow_pulses(void);

#endif

/* pil_proto.h: the processor-in-the-loop frames between the firmware in s51 (hal_pil.c) and the host plant (sim/pil_host.c). */
#ifndef PIL_PROTO_H
#define PIL_PROTO_H

/*
 * Bytes go through uCsim's simulator interface: the firmware writes 'w' then a byte to the
 * interface's output file and reads the input file with 'f' (a byte waiting?) and 'r'; both
 * files are FIFOs the host holds open. Reads do not block in s51: the firmware polls, with its
 * cycle counter stopped, so waiting for the host costs the measured pass nothing.
 * Multi-byte numbers are little-endian.
 *
 * Start:  fw PIL_HELLO; host PIL_CONFIG n (id lo hi)*n: params_defaults, then these settings;
 *         hal_init(), app_init() (their HAL calls as below); fw PIL_READY; host PIL_CONFIG again.
 * Tick:   host PIL_TICK ms(4) pca(4) keys(2) sections(1) rx(1) n (id lo hi)*n: the tick's
 *         inputs (rx: bytes waiting in the host's UART queue, at most 255) and the settings the
 *         host changed (scenario events); fw: one app_poll(), its HAL calls as below, then
 *         PIL_DONE cycles(4) fresh(1) and, when fresh is not 0, the status the metrics read. The
 *         status is fresh after a pass that measured (a control step: ADC or pulse capture,
 *         fresh 3), that changed a setting (fresh 1) or the alarms (fresh 4: the pass after a
 *         step, app_diag); otherwise it is what the host last got.
 * End:    host PIL_QUIT; fw PIL_REPORT stack_hwm(1) stack_start(1), then stops s51.
 * HAL calls during a pass, fw -> host (host answers only where a reply is listed):
 */
#define PIL_HELLO 'I'
#define PIL_CONFIG 'C'
#define PIL_READY 'J'
#define PIL_TICK 'T'
#define PIL_DONE 'D'
#define PIL_QUIT 'Q'
#define PIL_REPORT 'X'
#define PIL_VALVE 'V'       /* dir(1) duty(1) */
#define PIL_SPRAY 'S'       /* on(1) */
#define PIL_BUZZER 'Z'      /* on(1) */
#define PIL_WDT 'K'
#define PIL_LCD 'L'         /* rs(1) byte(1) */
#define PIL_ADC 'A'         /* ch(1) -> counts(2) */
#define PIL_FLOW 'F'        /* -> count(2) last(4) rejected(1) */
#define PIL_WHEEL 'H'       /* -> count(2) last(4) rejected(1) */
#define PIL_WHEEL_MIN 'N'   /* min_ticks(4) */
#define PIL_RESET_CAUSE 'Y' /* -> cause(1) */
#define PIL_SUPPLY_LOW 'U'  /* -> low(1) */
#define PIL_UART_PUT 'P'    /* byte(1) -> taken(1) */
#define PIL_UART_FRAMING 'B' /* framing(1) -> done(1): hal_uart_framing on the host's line */
#define PIL_UART_GET 'G'    /* -> int16(2), -1: none (only asked while the tick said rx > 0) */
#define PIL_EE_READ 'R'     /* addr(2) -> byte(1) */
#define PIL_EE_ERASE 'E'    /* addr(2) */
#define PIL_EE_WRITE 'W'    /* addr(2) byte(1) -> ok(1) */

/* PIL_DONE's status after the cycles, 2 bytes each: app_status.in.speed_kmh_x100, target_lpm_x100,
 * flow_lpm_x100, pressure_kpa, tank_l, drive, ctl_gain(0..2), alarms, then param_v[P_RATE],
 * param_v[P_METER_K] (settings the console or the serial link may change) */
#define PIL_STATUS_WORDS 12

#endif

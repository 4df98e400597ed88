/* serial.h: the RS232 link to the PC: a log line every second, alarm messages, and checked line commands. */
#ifndef SERIAL_H
#define SERIAL_H

#include "compiler.h"
#include "hil.h"

/*
 * Every line the controller sends ends in "*HH\r\n", HH in hex the CRC-8 of the bytes before
 * '*' (serial.c: polynomial 0x65, initial 0, MSB first; docs/PC.md), so the PC can reject a
 * garbled line:
 *   BOOT <POWER|WATCHDOG|BROWNOUT|PIN>  first, once: why the controller (re)started
 *   EE <OLDER|DEFAULTS|TANKMIN|PSTART|METERHZ>  next, once, when the settings loaded are not
 *                                  the newest saved (store.h: a cut save, none valid, a cross-check)
 *   LOG <t_ms> <speed km/h x100> <pressure kPa> <target L/min x100> <flow L/min x100> <alarms hex>
 *   ALM <code> <LCD text>          an alarm was raised
 *   CLR <code>                     an alarm cleared
 *   OK ...   /   ERR <reason>      the reply to a command
 * Commands from the PC, one a line (CR or LF ends it), at most SERIAL_LINE_MAX characters,
 * upper-case words and plain decimal numbers separated by single spaces, then "*HH", the same
 * CRC-8: the check is verified when present, and required (ERR NOCSUM) by the commands that
 * change something (SET, CTL, JOG, ACK, RST, SAV, HIL), so that a damaged line is never acted
 * on; the read-only queries (GET, TOT, LIF, PUL) may come without it. Every error of one or two
 * bits in a command line (SERIAL_CRC_BYTES before '*' at most: the longest command is 15) is
 * caught. The commands and their replies:
 *   GET <id>          OK <id> <value>          (id: row of params.h)
 *   SET <id> <value>  OK <id> <value>          ERR RANGE, ERR ID; a value that breaks a cross-check
 *                                              (params.h): ERR TANKMIN / PSTART / METERHZ
 *   CTL <n>           OK CTL <n>               choose the controller (P_CONTROLLER)
 *   ACK               OK ACK                   acknowledge the alarms
 *   TOT               OK TOT <job dm^2> <job ml> <L/ha x10>
 *   LIF               OK LIF <life m^2> <life ml>
 *   RST               OK RST                   zero the job totals
 *   PUL               OK PUL <wheel pulses> <meter pulses>   (calibration)
 *   JOG +|-           OK JOG                   manual mode only (ERR MODE otherwise)
 *   SAV               OK SAV                   parameters to the EEPROM, read back (ERR SAVE); the
 *                                              reply comes when the save, some passes long, has
 *                                              ended (one that needs an erase waits for the erase
 *                                              budget, store.h); ERR BUSY while the last SAV's has not
 *   HIL ON*HH         OK HIL                   hardware in the loop (hil.h; the checksum is required)
 * Anything else changes nothing and gets ERR CMD / ARG / NUM / CSUM / NOCSUM / LONG / CHAR.
 * With Remote = Raven the link is a Raven console's (remote.h): at its framing, only '$' lines
 * read, only Raven's lines sent; everything above is off until Remote is off again.
 * A line during which received bytes were lost (the HAL's receive queue overflowed, or an IAP
 * erase held the CPU: hal_uart_get's HAL_UART_LOST) is discarded whole with ERR LOST, at its
 * end (or at the next line end when its own was lost).
 * A command line that stalls unfinished for SERIAL_STALL_S log periods (3 s) is dropped (the
 * log lines go on; ERR LOST when it had lost bytes).
 */
#define SERIAL_STALL_S 3
#define SERIAL_LINE_MAX 31
#define SERIAL_CRC_BYTES 20         /* the CRC-8 catches every 2-bit error up to this length */
#define SERIAL_TX_MAX 56           /* one buffer for the line in and the line out: our own lines
                                    * and their "*HH\r\n", a Raven C1 line at its longest (54 bytes,
                                    * docs/REMOTE.md) and its CR LF */

void serial_init(void);
/* From the main loop: receive, answer at most one command line, send what is pending (never
 * waits for the UART); 1 when it composed a line (a reply, a log line: the pass's work,
 * app_poll). With may_take 0 a whole command line is held, unanswered and unread past its end,
 * until a pass that may take it (app_poll: while a due control step waits for the modules'
 * constants, so that a flood of changes cannot keep it waiting). */
uint8_t serial_poll(uint8_t may_take) __reentrant;
/* Ask for a log line (the application does it every 1000 ms). */
void serial_log_request(void);
/* HIL mode (hil.h): after the step on a frame the application sends its outputs (the frame's
 * other fields are filled here). */
#if FW_HIL
void serial_hil_send(hil_out_t *o) __reentrant;
#endif

#endif

/* serial.c: RS232 log lines, alarm messages and strictly parsed, checksummed commands. */
#include "hal.h"
#include "params.h"
#include "store.h"
#include "ops.h"
#include "diag.h"
#include "totals.h"
#include "serial.h"
#include "fmt.h"
#include "hil.h"
#include "remote.h"
#include "pgn.h"
#include "commands.h"
#include "target.h"
#include "linebuf.h"
#include "linecheck.h"

/* One buffer: it collects a command line, then holds the line being sent (the reply composed
 * over the parsed command). While a line goes out, received bytes wait in the HAL's queue. */
static struct {
    char buf[SERIAL_TX_MAX];
    uint16_t reported;              /* alarm bits the PC has been told about */
    uint8_t quiet;                  /* log periods (seconds) since a byte last came in */
} se;
/* the most used bytes here, in the direct RAM */
static __data uint8_t se_n;         /* bytes in se.buf */
static __data uint8_t se_tx_i;      /* next byte to send */
static __data uint8_t se_state;     /* S_* */
static __data uint8_t se_log_due;   /* log lines asked for and not yet sent */
static __data uint8_t se_framing;   /* the UART's once switched (HAL_UART_*: REMOTE_FRAMING); not
                                     * HAL_UART_38400_8N1: the link is a Raven console's (remote.h) */

#define S_RX 0                      /* collecting a line */
#define S_RX_LONG 1                 /* the line overflowed: skip to its end */
#define S_RX_CHAR 2                 /* a byte that is not printable ASCII: skip to the end */
#define S_TX 3                      /* sending buf */
#define S_RX_LOST 4                 /* bytes of the line were lost (hal_uart_get): skip to its end */
#define S_RX_HELD 5                 /* a whole line waits for a pass that takes it (serial_poll) */
static __bit boot_due;              /* the BOOT line (the reset cause) not yet sent */
static __bit ee_due;                /* the EE line (settings not the newest saved) not yet sent */
static __bit csum_seen;             /* the line being answered carried its check */

static const __code char hexd[] = "0123456789ABCDEF";

void serial_init(void)
{
    se_n = se_tx_i = se_log_due = 0;
    se_state = S_RX;
    se.reported = 0;
    se.quiet = 0;
    se_framing = HAL_UART_38400_8N1;    /* hal_init's */
    boot_due = 1;
    ee_due = store_status() != STORE_OK;    /* (store_load has run) */
}

void serial_log_request(void)
{
    if (se_log_due < 255)
        se_log_due++;
    if (se.quiet < 255)
        se.quiet++;
    remote_tick();
}

/* ---- composing a line (linebuf.h: remote.c composes through it too) ---------------------- */
#define tx_c serial_put_c
#define tx_s serial_put_s
/* c at the line's end, its room known (one copy of the indexed store) */
static void put_raw(char c) __reentrant
{
    se.buf[se_n++] = c;
}

void serial_put_c(char c) __reentrant
{
    if (se_n < SERIAL_TX_MAX - (se_framing ? 2 : 5))    /* room for "\r\n", ours "*HH\r\n" */
        put_raw(c);
}

void serial_put_s(const __code char *s) __reentrant
{
    while (*s)
        tx_c(*s++);
}

/* decimal (fmt.c, the formatter the LCD uses too) */
void serial_put_num(uint32_t v, uint8_t dec) __reentrant
{
    char num[FMT_MAX];
    uint8_t i;
    fmt_u32((__idata char *)num, v, dec, 0);
    for (i = 0; num[i]; i++)
        tx_c(num[i]);
}

static void tx_u32(uint32_t v) __reentrant
{
    serial_put_num(v, 0);
}

/* a space, then v */
static void tx_sp_u32(uint32_t v) __reentrant
{
    tx_c(' ');
    tx_u32(v);
}

static void tx_sp_i16(int16_t v) __reentrant
{
    uint16_t m = (uint16_t)v;       /* |v| (unsigned: -32768's too) */
    tx_c(' ');
    if (v < 0) {
        tx_c('-');
        m = (uint16_t)(0u - m);
    }
    tx_u32(m);
}

/* the line's end, and the line to be sent */
static void tx_crlf(void) __reentrant
{
    put_raw('\r');
    put_raw('\n');
    se_tx_i = 0;
    se_state = S_TX;
}

static void tx_end(void) __reentrant
{
    uint8_t x = line_crc8(se.buf, se_n);
    put_raw('*');
    put_raw(hexd[x >> 4]);
    put_raw(hexd[x & 15]);
    tx_crlf();
}

/* ---- parsing a command -------------------------------------------------------------------- */
static void reply_err(const __code char *why) __reentrant
{
    se_n = 0;
    tx_s("ERR ");
    tx_s(why);
}

/* ---- the commands: link_commands[] (commands.c) ------------------------------------------- */
/* the ERR word of each param_try() verdict (params.h PARAM_*) */
static const char __code *const __code why_word[] = {"", "RANGE", "TANKMIN", "PSTART", "METERHZ", "FLOWMAX"};

/* "OK <word>", the numbers (tx_sp_u32) to follow */
static void ok(const __code char *word) __reentrant
{
    tx_s("OK ");
    tx_s(word);
}

/* The handlers, after the arguments were parsed as the table says. A command answers "OK", its
 * word (GET and SET: the id) and its numbers; a refusal writes its ERR over it (reply_err). */
static void run(const __code command_t *cmd, __idata uint16_t *num) __reentrant
{
    uint8_t handler = cmd->handler, v;
    if (handler == C_SAV) {         /* its reply once its save has ended (compose_next) */
        if (store_asked(STORE_BY_SERIAL))
            reply_err("BUSY");      /* the last SAV's save has not ended */
        else
            store_save_start(STORE_BY_SERIAL);
        return;
    }
    if (handler > C_SET)
        ok(cmd->word);
    switch (handler) {
    case C_GET:
    case C_SET:
        if (num[0] >= P_COUNT) {
            reply_err("ID");
        } else if (handler == C_SET && (v = param_try((uint8_t)num[0], num[1])) != PARAM_OK) {
            reply_err(why_word[v]);     /* out of range, or against another setting */
        } else {
            tx_s("OK ");
            tx_u32(num[0]);
            tx_sp_u32(param_v[num[0]]);
        }
        break;
    case C_CTL:
        if (param_try(P_CONTROLLER, num[0]) != PARAM_OK)
            reply_err("RANGE");
        else
            tx_sp_u32(num[0]);
        break;
    case C_NUD:                     /* the rate in use nudged a step, or back to the preset */
        tx_sp_i16(target_nudge((int8_t)num[0]));
        tx_sp_u32(target_rate_x10());
        break;
    case C_JOG:
        if (!num[0] || !app_status.manual)       /* JOG has no 0 */
            reply_err(num[0] ? "MODE" : link_e_arg);
        else
            ops_jog((int8_t)num[0]);
        break;
    case C_ACK:
        ops_alarm_ack();
        break;
    case C_RST:
        ops_totals_reset();
        break;
    case C_TOT:
        tx_sp_u32(totals.job_dm2);
        tx_sp_u32(totals.job_ml);
        tx_sp_u32(totals_applied_l_ha_x10());
        break;
    case C_LIF:
        tx_sp_u32(totals.life_m2);
        tx_sp_u32(totals.life_ml);
        break;
    case C_PUL:
        tx_sp_u32(ops_wheel_pulses());
        tx_sp_u32(ops_flow_pulses());
        break;
#if FW_HIL
    default:                        /* HIL: never by accident: the exact line with its checksum (CHANGES) */
        hil_begin();                /* its reply goes out first (serial_poll drains before frames) */
        break;
#endif
    }
}

/* The command in se.buf: look its word up, parse its arguments, run its handler. With Remote
 * on, a line starting with '$' goes to Raven's strings (remote.c) and nothing is answered; with
 * it off, such a line is refused. 1 when a reply of ours is to be sent. */
static uint8_t answer(void) __reentrant
{
    const __xdata char *p = se.buf + 3;
    const __code command_t *cmd = link_commands;
    uint8_t n = se_n, c;
    uint16_t num[2];                /* the numbers (ARG_SIGN: the first, its sign) */

    se_n = 0;                       /* the reply is written over the line once it is parsed */
    c = line_check(se.buf, n);      /* (linecheck.h) */
    if (se_framing) {               /* a Raven console: its answers are queued, nothing else */
        if (c < LINE_E_ARG && se.buf[0] == '$')
            remote_command(se.buf);
        return 0;
    }
    if (c >= LINE_E_ARG) {
        reply_err(c == LINE_E_CSUM ? "CSUM" : link_e_arg);
        return 1;
    }
    csum_seen = (c & LINE_CHECKED) != 0;
    if (se.buf[0] == '$') {
        reply_err("REMOTE");
        return 1;
    }
    for (c = 0; c < LINK_N_COMMANDS; c++, cmd++)
        if (se.buf[0] == cmd->word[0] && se.buf[1] == cmd->word[1]
            && se.buf[2] == cmd->word[2] && (se.buf[3] == ' ' || se.buf[3] == 0))
            break;
    if (c == LINK_N_COMMANDS) {
        reply_err(link_e_cmd);
        return 1;
    }
    if (!csum_seen && ((CHANGES >> cmd->handler) & 1u)) {
        reply_err("NOCSUM");
        return 1;
    }
    switch (cmd->args) {
    case ARG_NUM:
    case ARG_NUM2:                  /* (ARG_NUM and ARG_NUM2: the count of numbers) */
        for (c = 0; c < cmd->args; c++)
            if (*p != ' ' || !(p = line_number(p + 1, (__idata uint16_t *)&num[c], ' '))) {
                reply_err(link_e_num);
                return 1;
            }
        break;
    case ARG_SIGN:
        if (!(p[0] == ' ' && (p[1] == '+' || p[1] == '-' || p[1] == '0')))
            goto bad_arg;           /* (what follows the sign: the end's test below) */
        num[0] = p[1] == '+' ? 1 : p[1] == '-' ? (uint16_t)-1 : 0;
        p += 2;
        break;
    case ARG_ON:                    /* the word ON */
        if (!(p[0] == ' ' && p[1] == 'O' && p[2] == 'N'))
            goto bad_arg;
        p += 3;
        break;
    default:
        break;
    }
    if (*p)
        goto bad_arg;
    run(cmd, (__idata uint16_t *)num);
    return se_n != 0;               /* (SAV answers later) */
bad_arg:                            /* (one copy of the refusal) */
    reply_err(link_e_arg);
    return 1;
}

/* ---- the loop's part ----------------------------------------------------------------------- */
/* A SAV's reply, an alarm message or a log line, when one is due and the buffer is free (se_n
 * is 0: serial_poll calls it with no line coming in). */
static void compose_next(void) __reentrant
{
    uint16_t diff = diag_alarms() ^ se.reported;
    uint8_t bit;

    if (se_framing) {               /* a Raven console sends its own lines only */
        boot_due = ee_due = 0;
        se_log_due = 0;
        if (remote_next())          /* Raven's lines carry no checksum */
            tx_crlf();
        return;
    }
    if (store_done(STORE_BY_SERIAL)) {  /* a SAV's save has ended */
        store_result() == STORE_OK ? ok("SAV") : reply_err("SAVE");
    } else if (boot_due) {                 /* first of all: why the controller started */
        boot_due = 0;
        tx_s("BOOT ");
        tx_s(diag_reset_code());
    } else if (ee_due) {                   /* then: the settings are not the newest saved */
        ee_due = 0;
        tx_s("EE ");
        bit = store_status();
        tx_s(bit == STORE_OLDER ? "OLDER" : bit < STORE_CROSS ? "DEFAULTS" : why_word[bit - STORE_CROSS + PARAM_X_TANK]);
    } else if (diff) {
        for (bit = 0; !(diff & 1u); bit++)
            diff >>= 1;
        diff = 1u << bit;
        se.reported ^= diff;
        diff &= se.reported;
        tx_s(diff ? "ALM " : "CLR ");
        tx_s(diag_code(bit));
        if (diff) {
            tx_c(' ');
            tx_s(diag_text(bit));
        }
    } else if (se_log_due) {
        se_log_due = 0;
        tx_s("LOG ");
        tx_u32(hal_ms());
        tx_sp_u32(app_status.in.speed_kmh_x100);
        tx_sp_u32(app_status.in.pressure_kpa);
        tx_sp_i16(app_status.in.target_lpm_x100);
        tx_sp_i16(app_status.in.flow_lpm_x100);
        tx_c(' ');
        for (bit = 16; bit; bit -= 4)
            tx_c(hexd[(app_status.alarms >> (bit - 4)) & 15]);
    } else {
#if FW_PGN
        if ((se_n = pgn_next((__xdata uint8_t *)se.buf)) != 0)
            se_tx_i = 0, se_state = S_TX;   /* a reply frame, as it is */
#endif
        return;
    }
    tx_end();
}

/* Hand the line being sent to the UART as far as it takes it; 1 when all of it went. */
static uint8_t drain(void) __reentrant
{
    while (se_tx_i < se_n) {
        if (!hal_uart_put((uint8_t)se.buf[se_tx_i]))
            return 0;
        se_tx_i++;
    }
    se_n = 0;
    se_state = S_RX;
    return 1;
}

/* the line composed, finished and handed to the UART as far as it takes it */
static void send(void) __reentrant
{
    tx_end();
    drain();
}

#if FW_HIL
void serial_hil_send(hil_out_t *o) __reentrant
{
    hil_answer(o, (uint8_t *)se.buf);
    se_n = HIL_OUT_BYTES;
    se_tx_i = 0;
    se_state = S_TX;
    drain();
}
#endif
/* The line in se.buf, answered: 1 when a reply of ours went out (at most one line a pass) */
static uint8_t take(void) __reentrant
{
    se_state = S_RX;
    if (answer()) {
        send();
        return 1;
    }
    se_n = 0;                       /* taken, answers queued (Raven) */
    return 0;
}

/* A line that could not be read, dropped: ERR <why> sent (1), or nothing as a Raven console
 * (0, Remote on) */
static uint8_t refuse(const __code char *why) __reentrant
{
    if (se_framing) {
        se_n = 0;
        se_state = S_RX;
        return 0;
    }
    reply_err(why);
    send();
    return 1;
}

uint8_t serial_poll(uint8_t may_take) __reentrant
{
    int16_t b;
    uint8_t framing;
    PGN_VERDICT(c)

    if (se_state == S_TX && !drain())
        return 0;
    framing = REMOTE_FRAMING(param_v[P_REMOTE]);
    if (se_framing != framing) {
        if (!hal_uart_framing(framing))
            return 0;               /* the last bytes still going out at the old framing */
        se_framing = framing;
        se_n = 0;                   /* a line half received at the old one is dropped */
        se_state = S_RX;
    }
#if FW_HIL
    if (hil_active()) {             /* frames only (hil.c) */
        hil_poll();
        return 0;
    }
#endif
    if (se_state == S_RX_HELD)      /* the bytes after it wait in the HAL's queue meanwhile */
        return may_take ? take() : 0;
    while ((b = hal_uart_get()) != -1) {
        se.quiet = 0;
        if (b == HAL_UART_LOST) {
            se_state = S_RX_LOST;   /* the line in progress (or the next one) lost bytes */
            pgn_drop();             /* ... or the frame */
        PGN_CHAIN(c, (uint8_t)b)    /* a frame's byte (pgn.h): one frame a pass */
        } else if (b == '\r' || b == '\n') {
            if (se_state != S_RX PGN_NOISY(c))
                return refuse(se_state == S_RX_LONG ? "LONG" : se_state == S_RX_LOST ? "LOST" : "CHAR");
            if (se_n) {
                if (!may_take) {
                    se_state = S_RX_HELD;
                    return 0;
                }
                return take();
            }
        } else if (se_state == S_RX) {
            if (b < 0x20 || b > 0x7E PGN_NOISY(c))
                se_state = S_RX_CHAR;
            else if (se_n >= SERIAL_LINE_MAX)
                se_state = S_RX_LONG;
            else
                put_raw((char)b);
        }
    }
    if (se_n || se_state != S_RX || pgn_busy()) {
        /* a line (or a frame) is coming in; one whose bytes stop for 3 s is dropped so the log
         * goes on (one that lost bytes, its end perhaps among them, is answered ERR LOST then) */
        if (se.quiet < SERIAL_STALL_S)
            return 0;
        pgn_drop();
        if (se_state == S_RX_LOST)
            return refuse("LOST");
        se_n = 0;
        se_state = S_RX;
    }
    compose_next();                 /* S_TX: a line composed (it was not at the drain above) */
    return se_state == S_TX ? (drain(), 1) : 0;
}

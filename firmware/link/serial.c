/* serial.c: RS232 log lines, alarm messages and strictly parsed, checksummed commands. */
#include "hal.h"
#include "params.h"
#include "store.h"
#include "app.h"
#include "diag.h"
#include "totals.h"
#include "serial.h"
#include "fmt.h"

/* One buffer: it collects a command line, then holds the line being sent (the reply is
 * composed over the parsed command). While a line goes out, received bytes wait in the
 * HAL's queue. */
static struct {
    char buf[SERIAL_TX_MAX];
    uint16_t reported;              /* alarm bits the PC has been told about */
    uint8_t n;                      /* bytes in buf */
    uint8_t tx_i;                   /* next byte to send */
    uint8_t state;                  /* S_* */
    uint8_t log_due;                /* log lines asked for and not yet sent */
} se;

#define S_RX 0                      /* collecting a line */
#define S_RX_LONG 1                 /* the line overflowed: skip to its end */
#define S_RX_CHAR 2                 /* a byte that is not printable ASCII: skip to the end */
#define S_TX 3                      /* sending buf */

static const __code char hexd[] = "0123456789ABCDEF";

void serial_init(void)
{
    se.n = 0;
    se.tx_i = 0;
    se.state = S_RX;
    se.reported = 0;
    se.log_due = 0;
}

void serial_log_request(void)
{
    if (se.log_due < 255)
        se.log_due++;
}

/* ---- composing a line ------------------------------------------------------------------ */
static void tx_c(char c) __reentrant
{
    if (se.n < SERIAL_TX_MAX - 5)       /* room for "*HH\r\n" */
        se.buf[se.n++] = c;
}

static void tx_s(const char *s) __reentrant
{
    while (*s)
        tx_c(*s++);
}

/* decimal (fmt.c, the formatter the LCD uses too) */
static void tx_u32(uint32_t v) __reentrant
{
    char num[FMT_MAX];
    fmt_u32(num, v, 0, 0);
    tx_s(num);
}

static void tx_i16(int16_t v) __reentrant
{
    if (v < 0) {
        tx_c('-');
        tx_u32((uint32_t)(-(int32_t)v));
    } else {
        tx_u32((uint32_t)v);
    }
}

static void tx_end(void) __reentrant
{
    uint8_t i, x = 0;
    for (i = 0; i < se.n; i++)
        x ^= (uint8_t)se.buf[i];
    se.buf[se.n++] = '*';
    se.buf[se.n++] = hexd[x >> 4];
    se.buf[se.n++] = hexd[x & 15];
    se.buf[se.n++] = '\r';
    se.buf[se.n++] = '\n';
    se.tx_i = 0;
    se.state = S_TX;
}

/* ---- parsing a command -------------------------------------------------------------------- */
static int8_t hexval(char c) __reentrant
{
    if (c >= '0' && c <= '9')
        return (int8_t)(c - '0');
    if (c >= 'A' && c <= 'F')
        return (int8_t)(c - 'A' + 10);
    if (c >= 'a' && c <= 'f')
        return (int8_t)(c - 'a' + 10);
    return -1;
}

/* A plain decimal 0..65535 from p up to a space or the end; returns the next position or 0. */
static const char *number(const char *p, uint16_t *v) __reentrant
{
    uint32_t x = 0;
    uint8_t n = 0;
    while (*p >= '0' && *p <= '9') {
        x = x * 10u + (uint8_t)(*p - '0');
        if (++n > 5 || x > 65535UL)
            return 0;
        p++;
    }
    if (n == 0 || (*p != ' ' && *p != 0))
        return 0;
    *v = (uint16_t)x;
    return p;
}

static uint8_t word_is(const char *line, const char *w) __reentrant
{
    while (*w)
        if (*line++ != *w++)
            return 0;
    return *line == ' ' || *line == 0;
}

static void reply_err(const char *why) __reentrant
{
    se.n = 0;
    tx_s("ERR ");
    tx_s(why);
}

static void answer(void) __reentrant
{
    char *line = se.buf;
    const char *p;
    uint8_t n = se.n, i, x = 0;
    int8_t h1, h2;
    uint16_t a, b;
    const totals_t *t;

    se.n = 0;                       /* the reply is written over the line once it is parsed */
    /* the optional checksum */
    for (i = 0; i < n && line[i] != '*'; i++)
        x ^= (uint8_t)line[i];
    if (i < n) {
        h1 = i + 3 == n ? hexval(line[i + 1]) : -1;
        h2 = i + 3 == n ? hexval(line[i + 2]) : -1;
        if (h1 < 0 || h2 < 0 || (uint8_t)(h1 << 4 | h2) != x) {
            reply_err("CSUM");
            return;
        }
        n = i;
    }
    line[n] = 0;
    /* strict layout: words of A-Z, 0-9, + or -, single spaces between them */
    if (n == 0 || line[0] == ' ' || line[n - 1] == ' ') {
        reply_err("ARG");
        return;
    }
    for (i = 1; i < n; i++)
        if (line[i] == ' ' && line[i - 1] == ' ') {
            reply_err("ARG");
            return;
        }
    p = line + 3;
    if (word_is(line, "GET") || word_is(line, "SET") || word_is(line, "CTL")) {
        if (*p != ' ' || !(p = number(p + 1, &a))) {
            reply_err("NUM");
            return;
        }
        if (line[0] == 'G') {
            if (*p) {
                reply_err("ARG");
                return;
            }
            if (a >= P_COUNT) {
                reply_err("ID");
                return;
            }
            b = param_v[a];
        } else if (line[0] == 'S') {
            if (*p != ' ' || !(p = number(p + 1, &b))) {
                reply_err("NUM");
                return;
            }
            if (*p) {
                reply_err("ARG");
                return;
            }
            if (a >= P_COUNT) {
                reply_err("ID");
                return;
            }
            if (!param_set((uint8_t)a, b)) {
                reply_err("RANGE");
                return;
            }
        } else {
            if (*p) {
                reply_err("ARG");
                return;
            }
            if (!param_set(P_CONTROLLER, a)) {
                reply_err("RANGE");
                return;
            }
            tx_s("OK CTL ");
            tx_u32(a);
            return;
        }
        tx_s("OK ");
        tx_u32(a);
        tx_c(' ');
        tx_u32(b);
        return;
    }
    if (word_is(line, "JOG")) {
        if (!(p[0] == ' ' && (p[1] == '+' || p[1] == '-') && p[2] == 0)) {
            reply_err("ARG");
            return;
        }
        if (!app_status.manual) {
            reply_err("MODE");
            return;
        }
        app_jog(p[1] == '+' ? 1 : -1);
        tx_s("OK JOG");
        return;
    }
    if (!(word_is(line, "ACK") || word_is(line, "RST") || word_is(line, "TOT") ||
          word_is(line, "LIF") || word_is(line, "PUL") || word_is(line, "SAV"))) {
        reply_err("CMD");
        return;
    }
    if (*p) {                       /* these take no argument */
        reply_err("ARG");
        return;
    }
    if (word_is(line, "ACK")) {
        app_alarm_ack();
        tx_s("OK ACK");
    } else if (word_is(line, "RST")) {
        app_totals_reset();
        tx_s("OK RST");
    } else if (word_is(line, "TOT")) {
        t = totals_get();
        tx_s("OK TOT ");
        tx_u32(t->job_dm2);
        tx_c(' ');
        tx_u32(t->job_ml);
        tx_c(' ');
        tx_u32(totals_applied_l_ha_x10());
    } else if (word_is(line, "LIF")) {
        t = totals_get();
        tx_s("OK LIF ");
        tx_u32(t->life_m2);
        tx_c(' ');
        tx_u32(t->life_ml);
    } else if (word_is(line, "PUL")) {
        tx_s("OK PUL ");
        tx_u32(app_wheel_pulses());
        tx_c(' ');
        tx_u32(app_flow_pulses());
    } else if (word_is(line, "SAV")) {
        if (store_save())
            tx_s("OK SAV");
        else
            reply_err("SAVE");
    } else {
        reply_err("CMD");
    }
}

/* ---- the loop's part ----------------------------------------------------------------------- */
/* An alarm message or a log line, when one is due and the buffer is free. */
static void compose_next(void) __reentrant
{
    uint16_t diff = diag_alarms() ^ se.reported;
    uint8_t bit;

    if (diff) {
        for (bit = 0; !(diff & (1u << bit)); bit++)
            ;
        se.reported ^= 1u << bit;
        se.n = 0;
        if (se.reported & (1u << bit)) {
            tx_s("ALM ");
            tx_s(diag_code(bit));
            tx_c(' ');
            tx_s(diag_text(bit));
        } else {
            tx_s("CLR ");
            tx_s(diag_code(bit));
        }
        tx_end();
        return;
    }
    if (se.log_due) {
        se.log_due = 0;
        se.n = 0;
        tx_s("LOG ");
        tx_u32(hal_ms());
        tx_c(' ');
        tx_u32(app_status.speed_kmh_x100);
        tx_c(' ');
        tx_u32(app_status.pressure_kpa);
        tx_c(' ');
        tx_i16(app_status.target_lpm_x100);
        tx_c(' ');
        tx_i16(app_status.flow_lpm_x100);
        tx_c(' ');
        for (bit = 16; bit; bit -= 4)
            tx_c(hexd[(app_status.alarms >> (bit - 4)) & 15]);
        tx_end();
    }
}

/* Hand the line being sent to the UART as far as it takes it; 1 when all of it went. */
static uint8_t drain(void) __reentrant
{
    while (se.tx_i < se.n) {
        if (!hal_uart_put((uint8_t)se.buf[se.tx_i]))
            return 0;
        se.tx_i++;
    }
    se.n = 0;
    se.state = S_RX;
    return 1;
}

void serial_poll(void) __reentrant
{
    int16_t b;

    if (se.state == S_TX && !drain())
        return;
    while ((b = hal_uart_get()) >= 0) {
        if (b == '\r' || b == '\n') {
            if (se.state != S_RX) {
                reply_err(se.state == S_RX_LONG ? "LONG" : "CHAR");
                tx_end();
                drain();
                return;
            }
            if (se.n) {
                answer();
                tx_end();
                drain();
                return;
            }
        } else if (se.state == S_RX) {
            if (b < 0x20 || b > 0x7E)
                se.state = S_RX_CHAR;
            else if (se.n >= SERIAL_LINE_MAX)
                se.state = S_RX_LONG;
            else
                se.buf[se.n++] = (char)b;
        }
    }
    if (se.n || se.state != S_RX) {
        /* a line is coming in; one that stalls for 3 s is dropped so the log goes on */
        if (se.log_due < 3)
            return;
        se.n = 0;
        se.state = S_RX;
    }
    compose_next();
    if (se.state == S_TX)
        drain();
}

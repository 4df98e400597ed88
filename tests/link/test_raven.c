/* test_raven.c: the link as a Raven console's through the host build, on a line run bit by bit at 9600 (or 1200) 8N2: requests and their lines, multi-product rates, silence, the data logger, US and turf units. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <stdio.h>
#include <string.h>
#include <stdlib.h>
#include <math.h>
#include <cmocka.h>
#include "hal_host.h"
#include "helper_link.h"
#include "link_crc.h"
#include "params.h"
#include "app.h"
#include "target.h"
#include "totals.h"
#include "screen.h"
#include "serial.h"
#include "remote.h"
#include "store.h"
#include "console.h"

static char line[128];
static char part[1];                /* "" */
static uint64_t first_ms, last_ms;  /* when the last line's first and last bytes arrived */

/* our own protocol's next line with Remote off (through the raw queue), its check cut */
static const char *our_line(void)
{
    size_t n = link_read_line(line, sizeof line);
    if (n == 0)
        return line;
    assert_true(n >= 6 && line[n - 1] == '\r' && line[n - 4] == '*');
    unsigned cs;
    assert_int_equal(sscanf(line + n - 3, "%2X", &cs), 1);
    assert_int_equal(cs, link_crc8(line, n - 4));
    line[n - 4] = 0;
    return line;
}

/* The PC's next line, read bit by bit off the wire at its own framing, CR LF cut; the loop
 * runs a millisecond at a time meanwhile, up to ms; "" when no whole line came (the part that
 * did is kept for the next call). */
static size_t n_part;
static const char *pc_line(uint32_t ms)
{
    size_t n = n_part;
    int b;
    for (uint32_t t = 0; t <= ms; t++) {
        while ((b = hal_host_uart_pc_get()) >= 0) {
            if (n == 0)
                first_ms = link_t_ms;
            if (b == '\n') {
                last_ms = link_t_ms;
                assert_true(n >= 1 && line[n - 1] == '\r');
                line[n - 1] = 0;
                n_part = 0;
                return line;
            }
            assert_true(n < sizeof line - 1);
            line[n++] = (char)b;
        }
        link_run_ms(1);
    }
    n_part = n;
    part[0] = 0;
    return part;
}

/* every line that comes within ms, each checked to be a Raven line of this console */
static int pc_lines(uint32_t ms, char out[][64], int max)
{
    int k = 0;
    uint64_t end = link_t_ms + ms;
    while (link_t_ms < end) {
        const char *l = pc_line((uint32_t)(end - link_t_ms));
        if (!l[0])
            break;
        assert_memory_equal(l, "$R124F,", 7);
        assert_true(k < max);
        snprintf(out[k++], 64, "%s", l);
    }
    return k;
}

static void pc_send(const char *s)
{
    link_send(s);
}

static int setup(void **state)
{
    (void)state;
    link_start();
    n_part = 0;
    store_status_clear();                   /* a first boot's "EE: defaults" seen */
    link_run_ms(CONSOLE_MSG_MS + 100);      /* the reset cause's message gone */
    while (our_line()[0])                   /* the BOOT line */
        ;
    return 0;
}

/* Remote = Raven at r (1: 9600, 2: 1200 baud); the PC set to the same; the data logger at
 * every s seconds (0: off) */
static void raven(uint16_t r, uint16_t every)
{
    assert_true(param_set(P_LOG_EVERY, every));
    assert_true(param_set(P_LOG_UNIT, 1));
    assert_true(param_set(P_REMOTE, r));
    hal_host_uart_pc_framing(r);
    link_run_ms(20);
    assert_int_equal(hal_host_uart_framing(), r);
    char l[16][64];
    pc_lines(1100, l, 16);                  /* the logger's first look takes its marks only */
}

/* the screen model's bottom line */
static const char *bottom(void)
{
    static char out[17];
    link_run_ms(600);
    for (int c = 0; c < 16; c++)
        out[c] = screen_char(3, (uint8_t)c);
    out[16] = 0;
    return out;
}

static void test_raven_strings_are_refused_while_remote_is_off(void **state)
{
    (void)state;
    assert_int_equal(param_v[P_REMOTE], 0);
    assert_int_equal(hal_host_uart_framing(), HAL_UART_38400_8N1);
    link_send("$R,RC,1300\r\n");
    link_run_ms(20);
    assert_string_equal(our_line(), "ERR REMOTE");
    assert_int_equal(target_rate_x10(), 1500);
    assert_false(target_rate_remote());
}

/* The line runs at 9600 baud, 11 bits a byte (8N2): the frame time is 11 / 9600 s, a line's
 * bytes come 1.146 ms apart; the documented requests give the documented lines. A PC at 38400
 * 8N1 is not understood, nor understands; one at 9600 8N1 (back-to-back frames) is read. */
static void test_raven_runs_the_uart_at_9600_8n2(void **state)
{
    (void)state;
    raven(1, 0);
    assert_int_equal(hal_host_uart_frame_ns(HAL_UART_9600_8N2), 11u * 104167u);    /* 1.1458 ms */
    pc_send("$R,CR\r\n");
    assert_string_equal(pc_line(200), "$R124F,C1,191,136,300,300,300,300,300,300,392.7");
    /* 47 bytes and CR LF: the first and the last 48 frames apart, 55.0 ms at 9600 8N2 (at 38400
     * 8N1 it would be 12.5 ms) */
    assert_int_equal(strlen(line), 47);
    assert_in_range(last_ms - first_ms, 54, 56);
    assert_string_equal(pc_line(200), "$R124F,C2,380.0,0");
    assert_string_equal(pc_line(200), "$R124F,C3,2123,150.0,0");
    assert_string_equal(pc_line(200), "");
    pc_send("$R,DR\r\n");
    assert_string_equal(pc_line(200), "$R124F,D1,0.0,0.0");
    assert_string_equal(pc_line(200), "$R124F,D2,0,0");
    char want[64];
    snprintf(want, sizeof want, "$R124F,D3,%u,0", app_status.tank_l);
    assert_string_equal(pc_line(200), want);
    assert_string_equal(pc_line(200), "$R124F,TD,00:00,00/00/00,0");
    /* a PC left at 38400 8N1: its request is garbled on the way in, and nothing answers */
    hal_host_uart_pc_framing(HAL_UART_38400_8N1);
    pc_send("$R,CR\r\n");
    assert_string_equal(pc_line(300), "");
    /* 9600 8N1, one stop bit: the chip's receiver does not wait for the second (a line end
     * first ends the garbled line the 38400 baud request left) */
    hal_host_uart_pc_framing(HAL_HOST_UART_9600_8N1);
    pc_send("\r\n$R,CR\r\n");
    assert_string_equal(pc_line(300), "$R124F,C1,191,136,300,300,300,300,300,300,392.7");
}

static void test_raven_1200_baud_is_a_setting(void **state)
{
    (void)state;
    raven(2, 0);
    assert_int_equal(hal_host_uart_framing(), HAL_UART_1200_8N2);
    pc_send("$R,RC,1300\r\n");
    link_run_ms(150);                       /* 12 bytes at 9.17 ms */
    assert_int_equal(target_rate_x10(), 1300);
    pc_send("$R,CR\r\n");
    assert_string_equal(pc_line(1000), "$R124F,C1,191,136,300,300,300,300,300,300,392.7");
    /* 48 frames of 11 / 1200 s: 440 ms */
    assert_in_range(last_ms - first_ms, 439, 441);
    /* back to off: our own protocol at 38400 8N1 */
    assert_true(param_set(P_REMOTE, 0));
    hal_host_uart_pc_framing(-1);
    link_run_ms(1500);
    assert_int_equal(hal_host_uart_framing(), HAL_UART_38400_8N1);
    const char *l = our_line();
    assert_memory_equal(l, "LOG ", 4);
}

/* Nothing but $R lines in Raven mode: our commands, malformed strings, bad characters, long and
 * lost lines, alarms coming and going are all met with silence; no LOG line in 3 s. */
static void test_raven_sends_only_its_own_lines_and_stays_silent(void **state)
{
    (void)state;
    raven(1, 0);
    static const char *const unusable[] = {
        "GET 0\r\n", "SET 0 125*00\r\n", "ACK\r\n", "HELLO\r\n", "$R,RC,13a0\r\n", "$R,RC,-1300\r\n",
        "$R,RC,130.0\r\n", "$R,RC,65536\r\n", "$R,RC,1300;0\r\n", "$R,CR,1\r\n", "$R,DRX\r\n",
        "$R,XX\r\n", "$r,rc,1300\r\n", "$X,RC,1300\r\n", "$R\r\n", "$R,RC 1300\r\n", "$R,RC,1\x01\r\n",
        "$R,RC,1300,0,1027,0,0,0,0,0,0,0,0\r\n", "\r\n", "$R,CX\r\n", "$R,XR\r\n", "$R,RX,1300\r\n",
        "$R,XC,1300\r\n", "$RXRC,1300\r\n", "$R,RC,13:0\r\n",      /* ':' is one past '9' */
        "#R,RC,1300\r\n", "AR,RC,1300\r\n", " $R,RC,1300\r\n",   /* Raven's strings begin with '$' */
    };
    for (size_t i = 0; i < sizeof unusable / sizeof unusable[0]; i++)
        pc_send(unusable[i]);
    hal_host_io.adc[HAL_ADC_LEVEL] = LINK_MA(3.0);         /* a level sensor fault comes */
    char l[8][64];
    assert_int_equal(pc_lines(3000, l, 8), 0);
    hal_host_io.adc[HAL_ADC_LEVEL] = LINK_MA(20.0);
    assert_int_equal(pc_lines(2000, l, 8), 0);
    assert_int_equal(target_rate_x10(), 1500);
    assert_int_equal(param_v[P_RATE], 1500);                /* the SET was not taken */
    /* and a good one after all that is answered */
    pc_send("$R,CR\r\n");
    assert_int_equal(pc_lines(300, l, 8), 3);
}

/* The multi-product forms set product 1; an empty field leaves it; the window still holds, a
 * refusal shows on the LCD and changes nothing. */
static void test_raven_multi_product_rate_lines_set_product_1(void **state)
{
    (void)state;
    raven(1, 0);
    static const struct { const char *s; uint16_t rate; } rc[] = {
        {"$R,RC,1300,,1027\r\n", 1300}, {"$R,RC,1250,0,1027\r\n", 1250}, {"$R,RC,,1027\r\n", 1250},
        {"$R,RC,,\r\n", 1250},          {"$R,RC,1400,\r\n", 1400},     {"$R,RC,1350,1,2,3,4\r\n", 1350},
        {"$R,RC,\r\n", 1350},           {"$R,RC,1200,x\r\n", 1350},    {"$R,RC,1200,65536\r\n", 1350},
        {"$R,RC,1305\r\n", 1305},
    };
    for (size_t i = 0; i < sizeof rc / sizeof rc[0]; i++) {
        pc_send(rc[i].s);
        assert_string_equal(pc_line(100), "");              /* no reply to RC */
        assert_int_equal(target_rate_x10(), rc[i].rate);
    }
    assert_true(target_rate_remote());
    assert_string_equal(bottom(), "T 1000L  RC130.5");
    /* the window: 50 % of 150 L/ha, 75.0 .. 225.0 */
    uint8_t n0 = target_remote_refusals();
    pc_send("$R,RC,2251,,1027\r\n");
    assert_string_equal(pc_line(100), "");
    assert_int_equal(target_rate_x10(), 1305);
    assert_int_equal(target_remote_refusals(), (uint8_t)(n0 + 1));
    assert_string_equal(bottom(), "RC rate refused ");
    pc_send("$R,RC,750,0\r\n");
    link_run_ms(100);
    assert_int_equal(target_rate_x10(), 750);
    /* the target flow follows: 75 L/ha x 8 km/h (given) x 18 m / 600 = 18.0 L/min */
    assert_true(param_set(P_GIVEN_SPEED, 80));
    link_run_ms(200);
    assert_int_equal(app_status.in.target_lpm_x100, 1800);
}

/* DR's lines carry the totals in hectares and litres with the decimal point sent */
static void test_raven_data_lines_carry_the_totals(void **state)
{
    (void)state;
    raven(1, 0);
    totals_set_life(123456u, 9876543u);     /* 12.3456 ha, 9876.543 L */
    totals_set_job(4567890u, 654321u);      /* 4.567890 ha, 654.321 L */
    pc_send("$R,DR\r\n");
    assert_string_equal(pc_line(200), "$R124F,D1,12.3,4.5");
    assert_string_equal(pc_line(200), "$R124F,D2,9876,654");
}

/* The C1 line at its longest: 30,000 (3000.0 mm a pulse) and six booms of 3,200 cm, whole */
static void test_raven_c1_is_never_cut(void **state)
{
    (void)state;
    raven(1, 0);
    assert_true(param_set(P_NOZZLES, 96));
    assert_true(param_set(P_SPACING, 200));
    assert_true(param_set(P_NOZZLE_Q3, 10));
    assert_true(param_set(P_WHEEL, 30000));
    pc_send("$R,CR\r\n");
    assert_string_equal(pc_line(300), "$R124F,C1,191,136,3200,3200,3200,3200,3200,3200,3000.0");
    assert_int_equal(strlen(line), 54);
    /* one section of 96 nozzles: 19,200 cm, the field as wide as it needs */
    assert_true(param_set(P_SECTIONS, 1));
    pc_line(300);
    pc_line(300);
    link_run_ms(1200);
    while (pc_line(0)[0])
        ;
    pc_send("$R,CR\r\n");
    assert_string_equal(pc_line(300), "$R124F,C1,129,136,19200,0,0,0,0,0,3000.0");
}

/* Rate 2 in use: switch byte 2 carries REMOTE_SW2_RATE2 (0x80 | 0x10 = 144) in place of RATE1
 * (0x80 | 0x08 = 136), and C3 the rate in use: Rate 2, 200.0 L/ha, nudged 5 %: 210.0 */
static void test_raven_c1_shows_the_preset_in_use(void **state)
{
    (void)state;
    raven(1, 0);
    assert_true(param_set(P_PRESET, 1));
    target_nudge(1);
    link_run_ms(1200);
    while (pc_line(0)[0])
        ;
    pc_send("$R,CR\r\n");
    assert_string_equal(pc_line(300), "$R124F,C1,191,144,300,300,300,300,300,300,392.7");
    assert_string_equal(pc_line(200), "$R124F,C2,380.0,0");
    assert_string_equal(pc_line(200), "$R124F,C3,2123,210.0,0");
    /* manual: neither rate bit */
    assert_true(param_set(P_MODE, 1));
    link_run_ms(1200);
    while (pc_line(0)[0])
        ;
    pc_send("$R,CR\r\n");
    assert_string_equal(pc_line(300), "$R124F,C1,191,128,300,300,300,300,300,300,392.7");
}

/* The data logger: every Log every seconds AR, D1, D2, D3, TD in that order; a setting changed:
 * C1, C2, C3; a switch changed: D1, D2, D3, TD, C1, C2, C3; with Log every 0 nothing is pushed
 * (DR still answered) */
static void test_raven_data_logger_pushes_on_its_triggers(void **state)
{
    (void)state;
    char l[40][64];
    raven(1, 3);
    int n = pc_lines(9000, l, 40);
    assert_int_equal(n, 15);                /* 3 triggers in 9 s */
    for (int i = 0; i < n; i++) {
        static const char *const order[] = {"AR,", "D1,", "D2,", "D3,", "TD,"};
        assert_memory_equal(l[i] + 7, order[i % 5], 3);
    }
    assert_string_equal(l[0], "$R124F,AR,0.0");
    /* a calibration value changed: C1, C2, C3 within a second, before the next trigger */
    link_run_ms(2500);
    while (pc_line(0)[0])
        ;
    assert_true(param_set(P_METER_K, 4000));
    n = pc_lines(1100, l, 40);
    assert_true(n >= 3);
    assert_memory_equal(l[0] + 7, "C1,", 3);
    assert_string_equal(l[1], "$R124F,C2,400.0,0");
    assert_memory_equal(l[2] + 7, "C3,", 3);
    /* a section switched off: D1 D2 D3 TD C1 C2 C3, C1 showing it */
    link_run_ms(3000 - 1100);
    while (pc_line(0)[0])
        ;
    hal_host_io.sections = 0x3D;
    n = pc_lines(1100, l, 40);
    assert_int_equal(n, 7);
    static const char *const sw_order[] = {"D1,", "D2,", "D3,", "TD,", "C1,", "C2,", "C3,"};
    for (int i = 0; i < n; i++)
        assert_memory_equal(l[i] + 7, sw_order[i], 3);
    assert_memory_equal(l[4], "$R124F,C1,189,136,", 18);
    /* a rate taken from the field computer is a calibration change too: C1, C2, C3 at once */
    pc_send("$R,RC,1400\r\n");
    n = pc_lines(400, l, 40);
    assert_int_equal(n, 3);
    assert_string_equal(l[2], "$R124F,C3,2123,140.0,0");
    /* the logger off: nothing pushed, requests still answered */
    assert_true(param_set(P_LOG_EVERY, 0));
    hal_host_io.sections = 0x3F;
    assert_int_equal(pc_lines(4000, l, 40), 0);
    pc_send("$R,DR\r\n");
    assert_int_equal(pc_lines(400, l, 40), 4);
}

/* The distance trigger: every 10 m of wheel pulses (392.7 mm each), AR D1 D2 D3 TD */
static void test_raven_data_logger_distance_trigger(void **state)
{
    (void)state;
    char l[40][64];
    raven(1, 0);
    assert_true(param_set(P_LOG_UNIT, 0));
    assert_true(param_set(P_LOG_EVERY, 10));
    pc_lines(1100, l, 40);                  /* the first look: marks */
    /* 100 pulses 100 ms apart: 39.27 m at 14 km/h, past 10, 20 and 30 m */
    int n = 0;
    for (int k = 0; k < 100; k++) {
        hal_host_wheel_edge(hal_host_io.time_ns);
        n += pc_lines(100, l + (n < 30 ? n : 30), 10);
    }
    n += pc_lines(1100, l + (n < 30 ? n : 30), 10);
    assert_int_equal(n, 15);
    /* each group at the first look (once a second) past 10, 20, 30 m: D3's distance is
     * past it by at most a second's travel, 3.9 m */
    for (int g = 0; g < 3; g++) {
        unsigned tank, m;
        assert_int_equal(sscanf(l[5 * g + 3], "$R124F,D3,%u,%u", &tank, &m), 2);
        assert_in_range(m, 10u * (g + 1), 10u * (g + 1) + 3u);
    }
}

/* ---- the console's Units: US and turf ---------------------------------------------------- */
/* The conversions from their definitions, not from the firmware's table */
#define GAL_L 3.785411784
#define ACRE_M2 4046.8564224
#define KFT2_M2 92.90304                    /* 1000 ft^2 */
#define IN_CM 2.54
#define FT_M 0.3048

/* the next line the PC reads within 300 ms equals the printf-built want */
static void expect_line(const char *fmt, ...)
{
    char want[96];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(want, sizeof want, fmt, ap);
    va_end(ap);
    assert_string_equal(pc_line(300), want);
}

/* Units = US: C1-C3 and D1-D3 as a Raven console set to US units sends them: the booms in
 * inches, the wheel's cal in inches a pulse, the meter's pulses a gallon, the rate in gal/acre,
 * areas in acres, volumes in gallons; each field worked out here from the metric settings. */
static void test_raven_us_units_lines(void **state)
{
    (void)state;
    assert_true(param_set(P_UNITS, 1));
    raven(1, 0);
    totals_set_life(123456u, 9876543u);     /* 12.3456 ha, 9876.543 L */
    totals_set_job(4567890u, 654321u);      /* 4.567890 ha, 654.321 L */
    pc_send("$R,CR\r\n");
    int b = (int)floor(300 / IN_CM + 0.5);  /* 6 nozzles of 50 cm: 300 cm = 118.1 in */
    expect_line("$R124F,C1,191,136,%d,%d,%d,%d,%d,%d,%.2f", b, b, b, b, b, b, 392.7 / (10 * IN_CM));
    expect_line("$R124F,C2,%.1f,0", 380.0 * GAL_L);                     /* 1438.5 a gallon */
    expect_line("$R124F,C3,2123,%.1f,0", 150.0 / GAL_L * ACRE_M2 / 1e4);   /* 16.0 gal/acre */
    pc_send("$R,DR\r\n");
    expect_line("$R124F,D1,%.2f,%.2f", 123456 / ACRE_M2, 45678.9 / ACRE_M2);  /* 30.51, 11.29 */
    expect_line("$R124F,D2,%.1f,%.1f", 9876.543 / GAL_L, 654.321 / GAL_L);   /* 2609.1, 172.9 */
    expect_line("$R124F,D3,%d,0", (int)floor(app_status.tank_l / GAL_L + 0.5));
    assert_string_equal(pc_line(200), "$R124F,TD,00:00,00/00/00,0");
    /* turf: the rate in gal / 1000 ft^2 (0.37) and the areas in 1000 ft^2, the rest as US */
    assert_true(param_set(P_UNITS, 2));
    link_run_ms(1200);
    while (pc_line(0)[0])
        ;
    pc_send("$R,CR\r\n");
    pc_line(300);
    pc_line(300);
    expect_line("$R124F,C3,2123,%.2f,0", 150.0 / GAL_L * KFT2_M2 / 1e4);
    pc_send("$R,DR\r\n");
    expect_line("$R124F,D1,%.1f,%.1f", 123456 / KFT2_M2, 45678.9 / KFT2_M2);  /* 1328.9, 491.7 */
}

/* A field computer's rate in the console's units: 15.0 gal/acre (RC 150) is 140.3 L/ha, the
 * target flow follows, C3 reads it back as sent; 0.34 gal / 1000 ft^2 (RC 34) in turf units is
 * 138.5 L/ha. A number whose L/ha passes 16 bits is refused, not wrapped into the window. */
static void test_raven_rc_in_the_consoles_units(void **state)
{
    (void)state;
    assert_true(param_set(P_UNITS, 1));
    assert_true(param_set(P_GIVEN_SPEED, 80));
    raven(1, 0);
    pc_send("$R,RC,150\r\n");
    link_run_ms(300);
    assert_int_equal(target_rate_x10(), (int)floor(15.0 * GAL_L / ACRE_M2 * 1e4 * 10 + 0.5));
    assert_int_equal(target_rate_x10(), 1403);
    /* 140.3 L/ha x 8 km/h x 18 m / 600 = 33.67 L/min */
    assert_int_equal(app_status.in.target_lpm_x100, (int)floor(140.3 * 8 * 18 / 600 * 100 + 0.5));
    pc_send("$R,CR\r\n");
    pc_line(300);
    pc_line(300);
    assert_string_equal(pc_line(300), "$R124F,C3,2123,15.0,0");
    /* 716.7 gal/acre = 6703.9 L/ha: 67039 in 0.1 L/ha, 1503 (150.3, in the window) if cut to
     * 16 bits */
    uint8_t n0 = target_remote_refusals();
    pc_send("$R,RC,7167\r\n");
    link_run_ms(300);
    assert_int_equal(target_rate_x10(), 1403);
    assert_int_equal(target_remote_refusals(), (uint8_t)(n0 + 1));
    /* turf */
    assert_true(param_set(P_UNITS, 2));
    pc_send("$R,RC,34\r\n");
    link_run_ms(300);
    assert_int_equal(target_rate_x10(), (int)floor(0.34 * GAL_L / KFT2_M2 * 1e4 * 10 + 0.5));
    assert_int_equal(target_rate_x10(), 1385);
}

/* The actual rate and the distance in US units from the pulses: a wheel pulse (392.7 mm) every
 * 100 ms is 14.14 km/h, a meter pulse (380 a litre) every 2 ms is 78.95 L/min: over 18 m,
 * 186.1 L/ha = 19.9 gal/acre (by hand); 100 wheel pulses are 39.27 m, 128.8 ft (D3's distance
 * is the whole metres counted in feet: within 3.3 ft). */
static void test_raven_us_units_actual_rate_and_distance(void **state)
{
    (void)state;
    char l[16][64];
    assert_true(param_set(P_UNITS, 1));
    raven(1, 1);
    double ar = -1;
    for (int t = 1; t <= 10000; t++) {
        if (t % 100 == 0)
            hal_host_wheel_edge(hal_host_io.time_ns);
        if (t % 2 == 0)
            hal_host_flow_edge(hal_host_io.time_ns);
        int n = pc_lines(1, l, 16);
        for (int i = 0; i < n; i++)
            if (!memcmp(l[i], "$R124F,AR,", 10))
                ar = atof(l[i] + 10);
    }
    double want = 500.0 / 380 * 60 / (0.3927 / 0.1 * 3.6 * 18) * 600 / GAL_L * ACRE_M2 / 1e4;
    printf("# AR %.1f gal/acre, %.2f by hand\n", ar, want);
    assert_true(fabs(ar - want) <= 0.051);     /* to the field's last digit */
    pc_send("$R,DR\r\n");
    unsigned tank, ft;
    for (int i = 0; i < 4 && sscanf(pc_line(300), "$R124F,D3,%u,%u", &tank, &ft) != 2; i++)
        ;
    printf("# D3 distance %u ft, %.1f by hand\n", ft, 100 * 0.3927 / FT_M);
    assert_true(fabs(ft - 100 * 0.3927 / FT_M) <= 1 / FT_M);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_raven_strings_are_refused_while_remote_is_off, setup),
        cmocka_unit_test_setup(test_raven_runs_the_uart_at_9600_8n2, setup),
        cmocka_unit_test_setup(test_raven_1200_baud_is_a_setting, setup),
        cmocka_unit_test_setup(test_raven_sends_only_its_own_lines_and_stays_silent, setup),
        cmocka_unit_test_setup(test_raven_multi_product_rate_lines_set_product_1, setup),
        cmocka_unit_test_setup(test_raven_data_lines_carry_the_totals, setup),
        cmocka_unit_test_setup(test_raven_c1_is_never_cut, setup),
        cmocka_unit_test_setup(test_raven_c1_shows_the_preset_in_use, setup),
        cmocka_unit_test_setup(test_raven_data_logger_pushes_on_its_triggers, setup),
        cmocka_unit_test_setup(test_raven_data_logger_distance_trigger, setup),
        cmocka_unit_test_setup(test_raven_us_units_lines, setup),
        cmocka_unit_test_setup(test_raven_rc_in_the_consoles_units, setup),
        cmocka_unit_test_setup(test_raven_us_units_actual_rate_and_distance, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* test_serial.c: the main loop through the host HAL: fixed period, watchdog only while healthy, the RS232 log, alarm messages and strict commands. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>
#include "hal_host.h"
#include "helper_link.h"
#include "link_crc.h"
#include "params.h"
#include "store.h"
#include "app.h"
#include "diag.h"
#include "totals.h"
#include "serial.h"
#include "hal.h"

static char line[128];

#define MA(x) LINK_MA(x)

static int setup(void **state)
{
    (void)state;
    link_start();
    return 0;
}

/* the next line the firmware sent ("" when none), its checksum verified */
static const char *next_line(void)
{
    size_t n = link_read_line(line, sizeof line);
    if (n == 0)
        return line;
    assert_true(n >= 5 && line[n - 1] == '\r' && line[n - 4] == '*');
    unsigned cs;
    assert_int_equal(sscanf(line + n - 3, "%2X", &cs), 1);
    assert_int_equal(cs, link_crc8(line, n - 4));
    line[n - 4] = 0;
    return line;
}

/* send a command, let the loop answer (the bytes travel at 38400 baud), return the reply line */
static const char *cmd(const char *c)
{
    while (next_line()[0])
        ;
    link_send(c);
    link_run_ms((uint32_t)strlen(c) / 3 + 5);
    return next_line();
}

/* the same with its check, as the commands that change something require: "SET 0 1*HH\r\n" */
static const char *signed_line(const char *c)
{
    static char l[64];
    snprintf(l, sizeof l, "%s*%02X\r\n", c, link_crc8(c, strlen(c)));
    return l;
}

static const char *scmd(const char *c)
{
    return cmd(signed_line(c));
}

/* SAV: its reply comes once the save has ended (a part of it every other millisecond, an
 * erase holding the CPU): let the loop run that long */
static const char *sav(void)
{
    while (next_line()[0])
        ;
    link_send(signed_line("SAV"));
    link_run_ms(150);
    const char *l = next_line();
    while (!strncmp(l, "LOG ", 4))
        l = next_line();            /* the log line of a second that passed meanwhile */
    return l;
}

static void test_serial_loop_runs_every_100_ms_and_feeds_the_watchdog(void **state)
{
    (void)state;
    uint8_t k0 = hal_host_io.wdt_kicks;
    link_run_ms(1002);              /* the 10th step at 1000 ms: its kick in its second pass,
                                       its alarms in the third */
    assert_int_equal((uint8_t)(hal_host_io.wdt_kicks - k0), 10);
    /* a stall of the loop (time jumps 500 ms): that step is late and does not feed (neither in
     * its pass nor in its second) */
    k0 = hal_host_io.wdt_kicks;
    link_t_ms += 500;
    link_run_ms(2);
    assert_int_equal(hal_host_io.wdt_kicks, k0);
    assert_int_equal(app_overruns(), 1);
    link_run_ms(300);
    assert_true((uint8_t)(hal_host_io.wdt_kicks - k0) >= 2);
    /* a parameter corrupted in RAM latches the internal fault: no more feeding */
    param_v[P_NOZZLES] = 0;
    k0 = hal_host_io.wdt_kicks;
    link_run_ms(1000);
    assert_int_equal(hal_host_io.wdt_kicks, k0);
    assert_true(app_status.alarms & (1u << AL_INTERNAL));
    assert_false(hal_host_io.spray_on);
}

static void test_serial_logs_every_second_like_the_paper_s_pc_monitor(void **state)
{
    (void)state;
    link_run_ms(1003);                               /* the 10th step at 1000 ms, its second pass and its
                                                   alarms in the next two, the once-a-second work and
                                                   the line in the one after (app_poll does one heavy
                                                   job a pass) */
    unsigned long t;
    unsigned v, p, al;
    int q1, q3;
    assert_string_equal(next_line(), "BOOT POWER");    /* the reset cause, first */
    assert_string_equal(next_line(), "EE DEFAULTS");   /* an erased EEPROM: the settings are the defaults */
    const char *l = next_line();
    assert_int_equal(sscanf(l, "LOG %lu %u %u %d %d %4X", &t, &v, &p, &q1, &q3, &al), 6);
    assert_int_equal(t, 1003);
    assert_int_equal(v, 0);
    assert_true(p <= 1);                        /* 4 mA = 204.6 counts; 205 reads 0.8 kPa */
    link_run_ms(1000);
    l = next_line();
    assert_int_equal(sscanf(l, "LOG %lu", &t), 1);
    assert_int_equal(t, 2003);
    assert_string_equal(next_line(), "");
}

static void test_serial_commands_read_and_set_parameters_strictly(void **state)
{
    (void)state;
    link_run_ms(200);
    assert_string_equal(cmd("GET 0\r\n"), "OK 0 1500");
    assert_string_equal(scmd("SET 0 1200"), "OK 0 1200");
    assert_int_equal(param_v[P_RATE], 1200);
    assert_string_equal(scmd("SET 0 5"), "ERR RANGE");           /* below 10 L/ha */
    assert_int_equal(param_v[P_RATE], 1200);
    assert_string_equal(scmd("SET 0 70000"), "ERR NUM");
    assert_string_equal(scmd("SET 99 1"), "ERR ID");
    assert_string_equal(scmd("SET 0  100"), "ERR ARG");
    assert_string_equal(scmd("SET 0 -100"), "ERR NUM");
    assert_string_equal(scmd("SET 0 1e2"), "ERR NUM");
    assert_string_equal(cmd("FOO\n"), "ERR CMD");
    assert_string_equal(cmd("set 0 100\n"), "ERR CMD");
    assert_int_equal(param_v[P_RATE], 1200);
    /* the check: CRC-8 of "SET 0 1300", polynomial 0x65, from its definition: 0x1C; a
     * wrong one changes nothing */
    assert_string_equal(cmd("SET 0 1300*1C\r\n"), "OK 0 1300");
    assert_string_equal(cmd("SET 0 1400*1C\r\n"), "ERR CSUM");
    assert_string_equal(cmd("SET 0 1400*4\r\n"), "ERR CSUM");
    assert_int_equal(param_v[P_RATE], 1300);
    /* two bytes wrong, one bit each: "SET 4 110" with the check of "SET 0 150" (0x87), which an
     * XOR of the bytes (0x46 for both) took */
    assert_string_equal(cmd("SET 4 110*87\r\n"), "ERR CSUM");
    assert_string_equal(cmd("SET 4 110*46\r\n"), "ERR CSUM");
    assert_int_equal(param_v[P_WHEEL], 3927);
    /* too long, not ASCII */
    assert_string_equal(cmd("SET 0 1000 0000000000000000000000000000000\n"), "ERR LONG");
    assert_string_equal(cmd("SET 0 1\x01" "00\n"), "ERR CHAR");
    assert_int_equal(param_v[P_RATE], 1300);
    /* controller, pulse totals, totals, ack, jog outside manual */
    assert_string_equal(scmd("CTL 0"), "OK CTL 0");
    link_run_ms(200);
    assert_int_equal(param_v[P_CONTROLLER], 0);
    assert_string_equal(scmd("CTL 9"), "ERR RANGE");
    assert_string_equal(cmd("PUL\n"), "OK PUL 0 0");
    assert_string_equal(scmd("ACK now"), "ERR ARG");
    assert_string_equal(cmd("ACK\n"), "ERR NOCSUM");
    assert_string_equal(scmd("ACK"), "OK ACK");
    assert_string_equal(scmd("JOG +"), "ERR MODE");
    assert_string_equal(cmd("TOT\n"), "OK TOT 0 0 0");
}

/* Every wrong checksum of a changing line is refused, those that share a digit with the right
 * one too (a corruption that moves only the high digit's bits, or only the low's); the right one
 * is taken in either case of its hex letters. */
static void test_serial_every_wrong_checksum_is_refused(void **state)
{
    (void)state;
    link_run_ms(200);
    const char *c = "SET 0 1300";
    unsigned x = link_crc8(c, strlen(c));
    char l[32];
    for (unsigned k = 0; k < 256; k++) {
        if (k == x)
            continue;
        snprintf(l, sizeof l, "%s*%02X\r\n", c, k);
        assert_string_equal(cmd(l), "ERR CSUM");
        assert_int_equal(param_v[P_RATE], 1500);
    }
    /* the hex digits: a letter in either case, 'a' and 'f' too, and no other character. Lines
     * "FO" and two letters: a checksum that passes gets ERR CMD for the word, one refused ERR
     * CSUM. */
    int seen_a = 0, seen_f = 0, seen_0 = 0, seen_hf = 0, seen_ff = 0, seen_9 = 0;
    for (char c1 = 'A'; c1 <= 'Z'; c1++) {
        for (char c2 = 'A'; c2 <= 'Z'; c2++) {
            char w[8];
            snprintf(w, sizeof w, "FO%c%c", c1, c2);
            unsigned y = link_crc8(w, 4), hi = y >> 4, lo = y & 15;
            int a = hi == 10 || lo == 10, f = hi == 15 || lo == 15;
            if ((a && !seen_a) || (f && !seen_f)) {
                snprintf(l, sizeof l, "%s*%02x\r\n", w, y);
                assert_string_equal(cmd(l), "ERR CMD");
                snprintf(l, sizeof l, "%s*%02X\r\n", w, y);
                assert_string_equal(cmd(l), "ERR CMD");
                seen_a |= a;
                seen_f |= f;
            }
            if (hi == 15 && !seen_hf) {     /* a non-hex high digit, where 0xF0 would pass */
                snprintf(l, sizeof l, "%s*G%X\r\n", w, lo);
                assert_string_equal(cmd(l), "ERR CSUM");
                seen_hf = 1;
            }
            if (y == 0xFF && !seen_ff) {    /* a non-hex low digit, where 0xFF would pass */
                snprintf(l, sizeof l, "%s*FG\r\n", w);
                assert_string_equal(cmd(l), "ERR CSUM");
                seen_ff = 1;
            }
            if (hi == 9 && !seen_9) {       /* '@' and '`' are no 9 (the case fold takes them near) */
                snprintf(l, sizeof l, "%s*@%X\r\n", w, lo);
                assert_string_equal(cmd(l), "ERR CSUM");
                snprintf(l, sizeof l, "%s*`%X\r\n", w, lo);
                assert_string_equal(cmd(l), "ERR CSUM");
                snprintf(l, sizeof l, "%s*9%X\r\n", w, lo);
                assert_string_equal(cmd(l), "ERR CMD");
                seen_9 = 1;
            }
            if (hi == 0 && !seen_0) {       /* a non-hex character where the 0 goes */
                snprintf(l, sizeof l, "%s*G%X\r\n", w, lo);
                assert_string_equal(cmd(l), "ERR CSUM");
                snprintf(l, sizeof l, "%s*/%X\r\n", w, lo);
                assert_string_equal(cmd(l), "ERR CSUM");
                snprintf(l, sizeof l, "%s*g%X\r\n", w, lo);
                assert_string_equal(cmd(l), "ERR CSUM");
                snprintf(l, sizeof l, "%s*%X\r\n", w, lo);
                assert_string_equal(cmd(l), "ERR CSUM");
                snprintf(l, sizeof l, "%s*00%X\r\n", w, lo);
                assert_string_equal(cmd(l), "ERR CSUM");
                seen_0 = 1;
            }
        }
    }
    assert_true(seen_a && seen_f && seen_0 && seen_hf && seen_ff && seen_9);
    snprintf(l, sizeof l, "%s*%02x\r\n", c, x);
    assert_string_equal(cmd(l), "OK 0 1300");
    assert_string_equal(scmd("SET 0 1200"), "OK 0 1200");
    snprintf(l, sizeof l, "%s*%02X\r\n", c, x);
    assert_string_equal(cmd(l), "OK 0 1300");
}

/* A number is 0..65535 in at most 5 digits: the edges of the overflow check, each digit
 * position (GET parses its id and refuses one past the table: ERR ID; ERR NUM is the parse's). */
static void test_serial_numbers_up_to_65535_in_five_digits(void **state)
{
    (void)state;
    link_run_ms(200);
    static const char *const id[] = {"GET 65535", "GET 65530", "GET 65529", "GET 65499", "GET 59999",
                                     "GET 6553", "GET 6554", "GET 9999", "GET 99"};
    static const char *const num[] = {"GET 65536", "GET 65539", "GET 65540", "GET 65600", "GET 66000",
                                      "GET 70000", "GET 99999", "GET 100000", "GET 000001", "GET 1x",
                                      "GET x"};
    char l[32];
    for (size_t i = 0; i < sizeof id / sizeof id[0]; i++) {
        snprintf(l, sizeof l, "%s\r\n", id[i]);
        assert_string_equal(cmd(l), "ERR ID");
    }
    for (size_t i = 0; i < sizeof num / sizeof num[0]; i++) {
        snprintf(l, sizeof l, "%s\r\n", num[i]);
        assert_string_equal(cmd(l), "ERR NUM");
    }
    char past[24];
    snprintf(past, sizeof past, "GET %d\r\n", P_COUNT);          /* one past the table */
    assert_string_equal(cmd(past), "ERR ID");
    snprintf(past, sizeof past, "GET %d\r\n", P_COUNT - 1);
    assert_memory_equal(cmd(past), "OK ", 3);
    assert_string_equal(cmd("GET\r\n"), "ERR NUM");
    assert_string_equal(scmd("SET 0"), "ERR NUM");
    assert_string_equal(scmd("SET 0 "), "ERR ARG");
    assert_string_equal(cmd("GET 00000\r\n"), "OK 0 1500");
    assert_string_equal(cmd("GET 00001\r\n"), "OK 1 36");
}

/* The layout: words parted by single spaces, none first or last, and the word exact letter by
 * letter. (A Raven line with a space at its end is refused for the layout, before Raven's own
 * parsing: with Remote off that would say ERR REMOTE.) */
static void test_serial_layout_and_words_letter_by_letter(void **state)
{
    (void)state;
    link_run_ms(200);
    assert_string_equal(cmd(" GET 0\r\n"), "ERR ARG");
    assert_string_equal(cmd("GET 0 \r\n"), "ERR ARG");
    assert_string_equal(cmd("$R,RC,1500 \r\n"), "ERR ARG");
    assert_string_equal(cmd("$R,RC,1500\r\n"), "ERR REMOTE");
    assert_string_equal(cmd("*00\r\n"), "ERR ARG");
    assert_string_equal(cmd("G ET 0\r\n"), "ERR CMD");
    assert_string_equal(cmd("XET 0\r\n"), "ERR CMD");
    assert_string_equal(cmd("GXT 0\r\n"), "ERR CMD");
    assert_string_equal(cmd("GEX 0\r\n"), "ERR CMD");
    assert_string_equal(cmd("GETX 0\r\n"), "ERR CMD");
    assert_string_equal(cmd("GET 0\r\n"), "OK 0 1500");
    /* printable ASCII only: 0x1F and 0x7F refused, ' ' and '~' taken */
    assert_string_equal(cmd("GET 0\x1f\r\n"), "ERR CHAR");
    assert_string_equal(cmd("GET 0\x7f\r\n"), "ERR CHAR");
    assert_string_equal(cmd("~\r\n"), "ERR CMD");
    /* SERIAL_LINE_MAX (31) characters taken, 32 too long */
    assert_string_equal(cmd("FOO 012345678901234567890123456\r\n"), "ERR CMD");
    assert_string_equal(cmd("FOO 0123456789012345678901234567\r\n"), "ERR LONG");
}

/* A line that stops coming holds the link 3 s (the log's lines wait), then it is dropped and the
 * log goes on; one that lost bytes is answered ERR LOST then. */
static void test_serial_a_stalled_line_is_dropped_after_3_s(void **state)
{
    (void)state;
    /* just after a log line (the stall is counted in the log's seconds) */
    int i;
    for (i = 0; i < 1500 && strncmp(next_line(), "LOG ", 4); i++)
        link_run_ms(1);
    assert_true(i < 1500);
    link_send("GET 0");                             /* no line end */
    link_run_ms(2500);
    assert_string_equal(next_line(), "");           /* held: no log line for 2.5 s */
    link_run_ms(1000);
    assert_memory_equal(next_line(), "LOG ", 4);    /* dropped at 3 s, the log goes on */
    while (next_line()[0])
        ;
    /* 20 bytes while the loop is not polled (the 16-byte queue overflows), no line end: the
     * first line out, once it is dropped, says so */
    link_send("GET 0123456789012345");
    link_t_ms += 10;
    hal_host_set_time_ns(link_t_ms * 1000000ull);
    link_run_ms(3500);
    assert_string_equal(next_line(), "ERR LOST");
    assert_string_equal(cmd("GET 0\r\n"), "OK 0 1500");
}

/* Commands that change something are refused without their checksum: a line that lost a
 * digit ("SET 0 1500" arriving as "SET 0 10") would otherwise be a valid command. Those that
 * only read need none. Cross-checks between parameters answer with their reason. */
static void test_serial_changing_commands_require_their_checksum(void **state)
{
    (void)state;
    link_run_ms(200);
    static const char *const changing[] = {"SET 0 1200", "CTL 0", "SAV", "JOG +", "RST", "ACK"};
    uint8_t before[HAL_EEPROM_SIZE];
    memcpy(before, hal_host_eeprom(), sizeof before);
    for (size_t i = 0; i < sizeof changing / sizeof changing[0]; i++) {
        char l[32];
        snprintf(l, sizeof l, "%s\r\n", changing[i]);
        assert_string_equal(cmd(l), "ERR NOCSUM");
    }
    assert_int_equal(param_v[P_RATE], 1500);
    assert_int_equal(param_v[P_CONTROLLER], 3);
    assert_memory_equal(before, hal_host_eeprom(), sizeof before);
    /* the damaged line with the sender's checksum of the intact one */
    char l[32];
    strcpy(l, signed_line("SET 0 1500"));
    memmove(l + 7, l + 8, strlen(l + 8) + 1);   /* "SET 0 100*HH" */
    assert_string_equal(cmd(l), "ERR CSUM");
    assert_int_equal(param_v[P_RATE], 1500);
    /* reading needs no checksum */
    assert_string_equal(cmd("GET 0\r\n"), "OK 0 1500");
    assert_string_equal(cmd("PUL\r\n"), "OK PUL 0 0");
    /* the cross-checks' reasons */
    assert_string_equal(scmd("SET 11 2000"), "ERR TANKMIN");    /* Tank min above the tank */
    assert_string_equal(scmd("SET 15 480"), "ERR PSTART");      /* P start at P max */
    assert_string_equal(scmd("SET 5 60000"), "ERR METERHZ");    /* 6000 p/L: too many pulses */
    assert_int_equal(param_v[P_TANK_MIN], 30);
    assert_int_equal(param_v[P_P_MIN], 100);
    assert_int_equal(param_v[P_METER_K], 3800);
    assert_string_equal(scmd("SET 11 999"), "OK 11 999");
}

/* A line that lost a byte is discarded whole with ERR LOST: the 16-byte receive queue
 * overflowing while the loop does not read, and bytes arriving while an IAP erase holds the
 * CPU. The lines before and after are answered as usual. */
static void test_serial_a_line_that_lost_bytes_is_discarded_with_err_lost(void **state)
{
    (void)state;
    link_run_ms(200);
    while (next_line()[0])
        ;
    /* a stall: 21 bytes arrive in 6 ms while the loop is not polled */
    link_send("GET 0\r\n");
    link_send(signed_line("SET 0 1300"));
    link_t_ms += 10;
    hal_host_set_time_ns(link_t_ms * 1000000ull);
    link_run_ms(10);
    assert_string_equal(next_line(), "OK 0 1500");
    assert_int_equal(param_v[P_RATE], 1500);
    /* the damaged line's end was lost too: the PC's next line end closes it */
    assert_string_equal(cmd("\r\n"), "ERR LOST");
    assert_int_equal(param_v[P_RATE], 1500);
    assert_string_equal(scmd("SET 0 1300"), "OK 0 1300");
    /* an erase: SAVs until one erases a sector (the log's slots full), a token of the erase
     * budget there (none at power-up: store.h) */
    link_run_ms(STORE_ERASE_MS);
    uint32_t erases = hal_host_io.eeprom_erases;
    for (int i = 0; i <= (int)STORE_SLOTS && hal_host_io.eeprom_erases == erases; i++) {
        while (next_line()[0])
            ;
        link_send(signed_line("SAV"));
        for (int k = 0; k < 50 && hal_host_io.eeprom_erases == erases; k++)
            link_run_ms(1);                          /* the save's first parts: the erase, if due */
        if (hal_host_io.eeprom_erases == erases)
            link_run_ms(100);                        /* a save without one: its reply */
    }
    assert_int_equal(hal_host_io.eeprom_erases, erases + 1);
    link_send(signed_line("SET 0 1400"));             /* arrives during the erase */
    link_run_ms(150);
    assert_int_equal(hal_host_io.eeprom_erases, erases + 1);
    /* the SAV's reply comes when its save has ended: before or after the damaged line's */
    int saved = 0, lost = 0;
    for (const char *l = next_line(); l[0]; l = next_line()) {
        assert_true(!strncmp(l, "LOG ", 4) || !strcmp(l, "OK SAV") || !strcmp(l, "ERR LOST"));
        saved += !strcmp(l, "OK SAV");
        lost += !strcmp(l, "ERR LOST");
    }
    if (!lost)
        lost = !strcmp(cmd("\r\n"), "ERR LOST");  /* its end lost as well */
    if (!saved) {                   /* (replies wait while a line comes in) */
        link_run_ms(5);
        const char *l = next_line();
        while (!strncmp(l, "LOG ", 4))
            l = next_line();
        saved = !strcmp(l, "OK SAV");
    }
    assert_int_equal(saved, 1);
    assert_int_equal(lost, 1);
    assert_int_equal(param_v[P_RATE], 1300);
    assert_string_equal(scmd("SET 0 1400"), "OK 0 1400");
}

/* SAV answers when its save has ended, the record read back; a SAV while the last one's save
 * runs gets ERR BUSY (one reply a line), and the next SAV after the reply saves again. */
static void test_serial_sav_answers_when_its_save_has_ended(void **state)
{
    (void)state;
    link_run_ms(200);
    while (next_line()[0])
        ;
    link_send(signed_line("SAV"));
    link_run_ms(5);                                  /* the line is in; its save has only begun */
    assert_string_equal(next_line(), "");
    link_send(signed_line("SAV"));
    link_run_ms(5);
    assert_string_equal(next_line(), "ERR BUSY");
    link_run_ms(150);
    const char *l = next_line();
    while (!strncmp(l, "LOG ", 4))
        l = next_line();
    assert_string_equal(l, "OK SAV");
    assert_string_equal(sav(), "OK SAV");
}

/* A loop that stalls (time jumps as when an IAP erase holds the CPU, or longer) counts the
 * periods it missed into the area and volume: the same totals as a run without the stall. */
static double area_after(uint32_t stall_ms)
{
    link_start_at(8.0);
    assert_true(param_set(P_GIVEN_SPEED, 72));  /* 7.2 km/h = 2 m/s over 18 m */
    link_run_ms(3000);
    assert_true(app_status.spraying);
    link_t_ms += stall_ms;
    link_run_ms(6000 - stall_ms);
    return totals_get()->job_dm2;
}

static void test_serial_a_stalled_loop_loses_no_area(void **state)
{
    (void)state;
    double smooth = area_after(0);
    assert_true(smooth > 1000.0);
    assert_int_equal(app_overruns(), 0);
    for (uint32_t stall = 250; stall <= 2250; stall += 500) {   /* a step 150 ms late or more */
        double a = area_after(stall);
        assert_int_equal(app_overruns(), 1);
        assert_true(a >= smooth - 1.0 && a <= smooth + 1.0);
    }
}

/* The totals are saved a second after the boom shuts, not in the step that shuts it (the
 * relay's switching and the erase's current together), and not while the supply is low. */
static void test_serial_the_totals_are_saved_a_second_after_the_boom_shuts(void **state)
{
    (void)state;
    assert_true(param_set(P_GIVEN_SPEED, 70));
    link_run_ms(3000);                          /* (the changed setting saved 2 s later) */
    assert_true(app_status.spraying);
    uint8_t before[HAL_EEPROM_SIZE];
    memcpy(before, hal_host_eeprom(), sizeof before);
    hal_host_io.sections = 0;                   /* the operator shuts the boom */
    link_run_ms(200);
    assert_false(app_status.spraying);
    assert_false(hal_host_io.spray_on);
    link_run_ms(700);
    assert_memory_equal(before, hal_host_eeprom(), sizeof before);
    link_run_ms(300);
    assert_memory_not_equal(before, hal_host_eeprom(), sizeof before);
    /* again, with the supply low: no save until it recovers */
    hal_host_io.sections = 0x3F;
    link_run_ms(1000);
    assert_true(app_status.spraying);
    memcpy(before, hal_host_eeprom(), sizeof before);
    hal_host_io.supply_low = 1;
    hal_host_io.sections = 0;
    link_run_ms(5000);
    assert_memory_equal(before, hal_host_eeprom(), sizeof before);
    hal_host_io.supply_low = 0;
    link_run_ms(1100);
    assert_memory_not_equal(before, hal_host_eeprom(), sizeof before);
}

/* an alarm is told once when raised (code and LCD text) and once when it clears; the
 * buzzer sounds until it is acknowledged */
static void test_serial_alarm_messages_and_the_buzzer(void **state)
{
    (void)state;
    link_run_ms(500);
    while (next_line()[0])
        ;
    hal_host_io.adc[HAL_ADC_PRESSURE] = MA(3.5);                 /* open pressure sensor */
    link_run_ms(500);
    assert_string_equal(next_line(), "ALM PSENS_FAULT P sensor fault");
    assert_true(hal_host_io.buzzer);
    assert_true(app_status.alarms_unacked & (1u << AL_PSENS));
    ops_alarm_ack();
    link_run_ms(100);
    assert_false(hal_host_io.buzzer);
    assert_true(app_status.alarms & (1u << AL_PSENS));           /* still active */
    hal_host_io.adc[HAL_ADC_PRESSURE] = MA(4.0);
    link_run_ms(2500);                               /* 1 s of good readings, 1 s to clear */
    const char *l;
    int seen = 0;
    while ((l = next_line())[0])
        if (strcmp(l, "CLR PSENS_FAULT") == 0)
            seen = 1;
    assert_true(seen);
    for (uint8_t b = 0; b < AL_COUNT; b++) {
        assert_true(strlen(app_alarm_text(b)) <= 16);
        assert_true(strlen(app_alarm_code(b)) > 0);
    }
}

/* manual mode: the boom stays shut at a standstill; the operator jogs the valve; auto again
 * starts the controller bumplessly */
static void test_serial_manual_jog_drives_the_valve_for_a_jog(void **state)
{
    (void)state;
    assert_true(param_set(P_MODE, 1));
    link_run_ms(200);
    assert_true(app_status.manual);
    assert_false(app_status.spraying);                           /* standing: never sprays */
    assert_true(param_set(P_GIVEN_SPEED, 70));
    link_run_ms(200);
    assert_true(app_status.spraying);                            /* moving, sections on, tank full */
    assert_string_equal(scmd("JOG +"), "OK JOG");
    link_run_ms(100);
    assert_int_equal(hal_host_io.valve_dir, HAL_VALVE_CLOSE);
    link_run_ms(400);
    assert_int_equal(hal_host_io.valve_dir, HAL_VALVE_OFF);
    /* a jog the other way while one runs: the bridge is off for the dead time first */
    assert_string_equal(scmd("JOG +"), "OK JOG");
    link_run_ms(100);
    assert_int_equal(hal_host_io.valve_dir, HAL_VALVE_CLOSE);
    ops_jog(-1);
    int off_ms = 0;
    while (hal_host_io.valve_dir != HAL_VALVE_OPEN && off_ms < 300) {
        link_run_ms(1);
        if (hal_host_io.valve_dir == HAL_VALVE_OFF)
            off_ms++;
    }
    assert_int_equal(hal_host_io.valve_dir, HAL_VALVE_OPEN);
    assert_true(off_ms >= 20);
    /* JOG - through the link: the bypass opens; anything but a lone + or - is refused (JOG 0
     * too, here in manual mode where a jog would run) */
    link_run_ms(600);
    assert_string_equal(scmd("JOG -"), "OK JOG");
    link_run_ms(100);
    assert_int_equal(hal_host_io.valve_dir, HAL_VALVE_OPEN);
    link_run_ms(600);
    assert_int_equal(hal_host_io.valve_dir, HAL_VALVE_OFF);    /* the jog ended */
    static const char *const bad[] = {"JOG", "JOG x", "JOG ++", "JOG +-", "JOG -0", "JOG +x", "JOGX+", "JOG 0"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
        assert_string_equal(scmd(bad[i]), i == 6 ? "ERR CMD" : "ERR ARG");
    link_run_ms(100);
    assert_int_equal(hal_host_io.valve_dir, HAL_VALVE_OFF);     /* none of them jogged */
    /* back to auto: the controller takes over from rest */
    assert_true(param_set(P_MODE, 0));
    link_run_ms(500);
    assert_false(app_status.manual);
}

/* A SET with one number is refused (ERR NUM) for every parameter, whatever its checksum's two
 * hex digits would read as: the second number is looked for after a space only. */
static void test_serial_set_with_one_number_is_refused(void **state)
{
    (void)state;
    for (int id = 0; id < P_COUNT; id++) {
        link_start();
        char c[16];
        snprintf(c, sizeof c, "SET %d", id);
        assert_string_equal(scmd(c), "ERR NUM");
    }
}

/* A line whose end comes in while the loop may not take it (serial_poll(0): the control
 * period's work first) is held, unanswered, and answered at the next pass that may take it. */
static void test_serial_a_held_line_is_answered_at_the_next_pass_that_may_take_it(void **state)
{
    (void)state;
    while (next_line()[0])
        ;
    link_send("PUL\r\n");
    link_t_ms += 5;                             /* the bytes arrive (38400 baud: 1.3 ms) */
    hal_host_set_time_ns(link_t_ms * 1000000ull);
    assert_int_equal(serial_poll(0), 0);
    assert_int_equal(hal_host_uart_tx_pop(), -1);
    assert_int_equal(serial_poll(0), 0);
    assert_int_equal(hal_host_uart_tx_pop(), -1);
    assert_int_equal(serial_poll(1), 1);
    assert_memory_equal(next_line(), "OK PUL ", 7);
}

/* A reply the UART cannot take yet (its queue full) is finished before anything else: a line
 * that comes in meanwhile waits in the receive queue and is answered after it. */
static void test_serial_a_reply_waits_for_room_and_the_next_line_for_it(void **state)
{
    (void)state;
    while (next_line()[0])
        ;
    int fill = 0;
    while (hal_uart_put(' '))
        fill++;
    link_send("PUL\r\n");
    link_run_ms(10);
    link_send("LIF\r\n");
    link_run_ms(10);
    for (int i = 0; i < fill; i++)
        assert_int_equal(hal_host_uart_tx_pop(), ' ');
    link_run_ms(10);
    assert_memory_equal(next_line(), "OK PUL ", 7);
    assert_memory_equal(next_line(), "OK LIF ", 7);
}

/* NUD nudges the rate in use a Rate step (5 % by default) up or down, 0 back to the preset;
 * it changes something: its check is required. JOG has no 0. */
static void test_serial_nud_nudges_the_rate_in_use(void **state)
{
    (void)state;
    link_run_ms(200);
    assert_string_equal(cmd("NUD +\r\n"), "ERR NOCSUM");
    assert_string_equal(scmd("NUD +"), "OK NUD 5 1575");
    assert_string_equal(scmd("NUD +"), "OK NUD 10 1650");
    assert_string_equal(scmd("NUD -"), "OK NUD 5 1575");
    assert_string_equal(scmd("NUD 0"), "OK NUD 0 1500");
    assert_string_equal(scmd("NUD -"), "OK NUD -5 1425");
    assert_string_equal(scmd("NUD 1"), "ERR ARG");
    assert_string_equal(scmd("NUD"), "ERR ARG");
    assert_string_equal(scmd("JOG 0"), "ERR ARG");
    link_run_ms(200);
    assert_int_equal(app_status.in.target_lpm_x100, 0);   /* standing: nothing, whatever the rate */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_serial_loop_runs_every_100_ms_and_feeds_the_watchdog, setup),
        cmocka_unit_test_setup(test_serial_nud_nudges_the_rate_in_use, setup),
        cmocka_unit_test_setup(test_serial_logs_every_second_like_the_paper_s_pc_monitor, setup),
        cmocka_unit_test_setup(test_serial_commands_read_and_set_parameters_strictly, setup),
        cmocka_unit_test_setup(test_serial_alarm_messages_and_the_buzzer, setup),
        cmocka_unit_test_setup(test_serial_manual_jog_drives_the_valve_for_a_jog, setup),
        cmocka_unit_test_setup(test_serial_changing_commands_require_their_checksum, setup),
        cmocka_unit_test_setup(test_serial_every_wrong_checksum_is_refused, setup),
        cmocka_unit_test_setup(test_serial_numbers_up_to_65535_in_five_digits, setup),
        cmocka_unit_test_setup(test_serial_layout_and_words_letter_by_letter, setup),
        cmocka_unit_test_setup(test_serial_a_stalled_line_is_dropped_after_3_s, setup),
        cmocka_unit_test_setup(test_serial_a_line_that_lost_bytes_is_discarded_with_err_lost, setup),
        cmocka_unit_test_setup(test_serial_sav_answers_when_its_save_has_ended, setup),
        cmocka_unit_test_setup(test_serial_the_totals_are_saved_a_second_after_the_boom_shuts, setup),
        cmocka_unit_test_setup(test_serial_a_stalled_loop_loses_no_area, setup),
        cmocka_unit_test_setup(test_serial_set_with_one_number_is_refused, setup),
        cmocka_unit_test_setup(test_serial_a_held_line_is_answered_at_the_next_pass_that_may_take_it, setup),
        cmocka_unit_test_setup(test_serial_a_reply_waits_for_room_and_the_next_line_for_it, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

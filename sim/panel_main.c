/* panel_main.c: the virtual operator panel: the firmware's LCD12864 drawn in a terminal, keys from the keyboard, the simulated sprayer in real time. */
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>
#include "args.h"
#include "sim.h"
#include "hal_host.h"
#include "st7920_emu.h"
#include "keypad.h"
#include "app.h"
#include "params.h"

/* Without --scenario: a field at a constant 8 km/h for an hour, the defaults of docs/SCENARIOS.md. */
static const char default_scn[] =
    "[run]\nduration_s = 3600\n[drive]\n0 0\n5 8\n3600 8\n";

#define KEY_HOLD_MS 80
#define KEY_GAP_MS 80

static void usage(FILE *f)
{
    fputs("usage: panel [--scenario FILE] [--speed X] [--time S] [--keys SEQ] [--screenshot OUT.png]\n"
          "             [--scale N] [--text] [--serial FILE]\n"
          "  the controller's LCD and keypad in the terminal, the simulated sprayer behind them.\n"
          "  keys: 0-9 A B C D * # as on the keypad (a-d too); arrows up/down = A/B, Enter = D,\n"
          "        Backspace = C; q quits.\n"
          "  switches (the console's, beside the keypad, as the scenario event sections_open):\n"
          "        m  the master boom switch: off, every section reads off (the boom shuts); on again\n"
          "        sN the switch of section N (1-8): off / on\n"
          "  --speed X     simulated seconds per wall second (1)\n"
          "  --time S      run S simulated seconds at full speed first\n"
          "  --keys SEQ    press these keys first ('.' waits 0.5 s; m and sN work the switches)\n"
          "  --screenshot  after --time and --keys: write the LCD as PNG, print its text, exit\n"
          "  --text        draw only the 4 text lines (no pixel image)\n"
          "  --serial FILE what the controller sends on its serial link, line by line (a scenario's\n"
          "                serial events are what comes in)\n"
          "  without --scenario: 8 km/h for an hour with the defaults\n", f);
}

/* ---- the switches: the master boom switch in series with the section switches ------------- */
#define SW_BOOM 'm'                 /* in the key queue: the master switch flipped */
#define SW_SECTION 1                /* in the key queue: 1..8, that section's switch flipped */
static int boom_on = 1;             /* the master switch */
static uint8_t section_sw;          /* the section switches, bit n = section n+1 on */
static uint8_t sections_given;      /* what the firmware's inputs got last (hal_host_io.sections) */

/* The inputs the switches give, and the plant's open nozzles with them. */
static void switches_apply(sim_t *sim)
{
    int nps = scenario_nozzles_per_section(sim->scn), n = 0;
    uint8_t on = boom_on ? section_sw : 0;
    on &= (uint8_t)((1u << sim->scn->param[P_SECTIONS]) - 1u);
    for (int b = 0; b < HAL_SECTIONS_MAX; b++)
        n += (on >> b) & 1;
    hal_host_io.sections = sections_given = on;
    sim->plant.open_nozzles = n * nps;
}

/* A scenario's sections_open event sets the switches as a hand would. */
static void switches_follow(sim_t *sim)
{
    if (hal_host_io.sections != sections_given) {
        section_sw = hal_host_io.sections;
        switches_apply(sim);
    }
}

/* ---- keys: a queue of keypad presses, each held KEY_HOLD_MS of simulated time --------------- */
static char keyq[256];
static int keyq_n;
static uint64_t key_until_ns;       /* current press or gap ends */
static int key_phase;               /* 0 idle, 1 held, 2 gap after release */

static void key_push(char k)
{
    if (keyq_n < (int)sizeof keyq)
        keyq[keyq_n++] = k;
}

/* A --keys sequence: keypad keys, '.', m and sN. */
static void keys_push(const char *k)
{
    for (; k && *k; k++) {
        if (*k == 's' && k[1] >= '1' && k[1] <= '8')
            key_push((char)(SW_SECTION + *++k - '1'));
        else if (*k != 's')
            key_push(*k);
    }
}

static int key_bit(char k)
{
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++)
            if (keypad_char((uint8_t)r, (uint8_t)c) == k)
                return 4 * r + c;
    return -1;
}

static void keys_tick(sim_t *sim)
{
    uint64_t t_ns = sim->t_ns;
    switches_follow(sim);
    if (key_phase && t_ns < key_until_ns)
        return;
    if (key_phase == 1) {
        hal_host_io.keys = 0;
        key_phase = 2;
        key_until_ns = t_ns + KEY_GAP_MS * 1000000ull;
        return;
    }
    key_phase = 0;
    if (!keyq_n)
        return;
    char k = keyq[0];
    memmove(keyq, keyq + 1, (size_t)--keyq_n);
    if (k == '.') {
        key_phase = 2;
        key_until_ns = t_ns + 500000000ull;
        return;
    }
    if (k == SW_BOOM || (k >= SW_SECTION && k < SW_SECTION + HAL_SECTIONS_MAX)) {
        if (k == SW_BOOM)
            boom_on = !boom_on;
        else
            section_sw ^= (uint8_t)(1u << (k - SW_SECTION));
        switches_apply(sim);
        key_phase = 2;              /* a gap, as after a key */
        key_until_ns = t_ns + KEY_GAP_MS * 1000000ull;
        return;
    }
    int b = key_bit(k);
    if (b < 0)
        return;
    hal_host_io.keys = (uint16_t)(1u << b);
    key_phase = 1;
    key_until_ns = t_ns + KEY_HOLD_MS * 1000000ull;
}

static int keys_busy(void)
{
    return keyq_n || key_phase;
}

/* ---- the terminal ------------------------------------------------------------------------- */
static struct termios saved_tio;
static int raw_on;

static void raw_off(void)
{
    if (raw_on) {
        tcsetattr(0, TCSANOW, &saved_tio);
        fputs("\033[?25h\033[0m\n", stdout);
        fflush(stdout);
        raw_on = 0;
    }
}

static void on_signal(int sig)
{
    raw_off();
    signal(sig, SIG_DFL);
    raise(sig);
}

static int raw_start(void)
{
    struct termios t;
    if (tcgetattr(0, &saved_tio) < 0)
        return -1;
    t = saved_tio;
    t.c_lflag &= (tcflag_t) ~(ICANON | ECHO);
    t.c_cc[VMIN] = 0;
    t.c_cc[VTIME] = 0;
    if (tcsetattr(0, TCSANOW, &t) < 0)
        return -1;
    raw_on = 1;
    atexit(raw_off);
    signal(SIGINT, on_signal);
    signal(SIGTERM, on_signal);
    fputs("\033[2J\033[?25l", stdout);
    return 0;
}

/* Terminal bytes to keypad keys; 1 when the user asked to quit. */
static int section_prefix;          /* 's' typed: the next digit names a section */

static int read_keys(void)
{
    unsigned char buf[64];
    ssize_t n = read(0, buf, sizeof buf);
    for (ssize_t i = 0; i < n; i++) {
        unsigned char c = buf[i];
        if (c == 'q' || c == 'Q' || c == 3)
            return 1;
        if (section_prefix) {
            section_prefix = 0;
            if (c >= '1' && c <= '8')
                key_push((char)(SW_SECTION + c - '1'));
            continue;
        }
        if (c == 'm' || c == 'M') {
            key_push(SW_BOOM);
        } else if (c == 's' || c == 'S') {
            section_prefix = 1;
        } else if (c == 27 && i + 2 < n && buf[i + 1] == '[') {
            if (buf[i + 2] == 'A')
                key_push('A');
            else if (buf[i + 2] == 'B')
                key_push('B');
            i += 2;
        } else if (c == 27 || c == 127 || c == 8) {
            key_push('C');
        } else if (c == '\r' || c == '\n') {
            key_push('D');
        } else if (c >= 'a' && c <= 'd') {
            key_push((char)(c - 'a' + 'A'));
        } else if ((c >= '0' && c <= '9') || (c >= 'A' && c <= 'D') || c == '*' || c == '#') {
            key_push((char)c);
        }
    }
    return 0;
}

static void term_size(int *cols, int *rows)
{
    struct winsize w;
    *cols = 80;
    *rows = 24;
    if (ioctl(1, TIOCGWINSZ, &w) == 0 && w.ws_col && w.ws_row) {
        *cols = w.ws_col;
        *rows = w.ws_row;
    }
}

/* Pixels as half blocks (2 pixels a cell, 128 x 32 cells) when the terminal is wide enough,
 * as braille (2 x 4 pixels a cell, 64 x 16) otherwise; then the 4 text lines in a box. */
static void draw(const sim_t *sim, int text_only)
{
    static uint8_t px[ST7920_H][ST7920_W];
    char line[17];
    sim_row_t r;
    int cols, rows, y, x;
    term_size(&cols, &rows);
    st7920_emu_render(px);
    fputs("\033[H", stdout);
    if (!text_only && cols >= 132 && rows >= 32 + 10) {
        printf("+"); for (x = 0; x < 128; x++) putchar('-'); printf("+\033[K\n");
        for (y = 0; y < ST7920_H; y += 2) {
            putchar('|');
            for (x = 0; x < ST7920_W; x++) {
                int u = px[y][x], d = px[y + 1][x];
                fputs(u && d ? "\u2588" : u ? "\u2580" : d ? "\u2584" : " ", stdout);
            }
            printf("|\033[K\n");
        }
        printf("+"); for (x = 0; x < 128; x++) putchar('-'); printf("+\033[K\n");
    } else if (!text_only && rows >= 16 + 10) {
        printf("+"); for (x = 0; x < 64; x++) putchar('-'); printf("+\033[K\n");
        for (y = 0; y < ST7920_H; y += 4) {
            putchar('|');
            for (x = 0; x < ST7920_W; x += 2) {
                static const int bit[4][2] = {{0x01, 0x08}, {0x02, 0x10}, {0x04, 0x20}, {0x40, 0x80}};
                int v = 0;
                char u[4];
                for (int dy = 0; dy < 4; dy++)
                    for (int dx = 0; dx < 2; dx++)
                        if (px[y + dy][x + dx])
                            v |= bit[dy][dx];
                v += 0x2800;        /* U+2800.. in UTF-8: three bytes */
                u[0] = (char)(0xE0 | (v >> 12));
                u[1] = (char)(0x80 | ((v >> 6) & 0x3F));
                u[2] = (char)(0x80 | (v & 0x3F));
                u[3] = 0;
                fputs(u, stdout);
            }
            printf("|\033[K\n");
        }
        printf("+"); for (x = 0; x < 64; x++) putchar('-'); printf("+\033[K\n");
    }
    printf("LCD +----------------+\033[K\n");
    for (y = 0; y < 4; y++) {
        st7920_emu_line((uint8_t)y, line);
        printf("    |%s|\033[K\n", line);
    }
    printf("    +----------------+\033[K\n");
    sim_row(sim, &r);
    printf("t %7.1f s  truth: %5.2f km/h  boom %6.2f L/min  width %5.2f m  %4.2f bar  valve %3.0f %%  tank %4.0f L\033[K\n",
           r.t_s, r.v_true_kmh, r.boom_lpm, r.width_m, r.p_bar, 100.0 * r.valve_pos, r.tank_l);
    printf("switches: boom %s  sections ", boom_on ? "ON " : "OFF");
    for (x = 0; x < sim->scn->param[P_SECTIONS]; x++)
        putchar((section_sw >> x) & 1 ? '1' + x : '-');
    printf("  relay %s%s\033[K\n", hal_host_io.spray_on ? "on " : "off", section_prefix ? "  section? 1-8" : "");
    printf("keys: 0-9 A(up/menu) B(down) C(back) D(enter) *(ack) #(point, manual/auto)  m boom switch  "
           "s1-s8 section switch  q quit%s\033[K\n", sim_done(sim) ? "  [scenario over]" : "");
    fflush(stdout);
}

static double wall_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* --serial: where what the firmware sends on its link goes (else it is read and dropped, as a
 * PC would, so that the link takes the scenario's serial lines) */
static FILE *link_out;

/* One simulation tick with the key queue; 0 once the scenario is over. */
static int tick(sim_t *sim)
{
    int b;
    if (sim_done(sim))
        return 0;
    keys_tick(sim);
    sim_step(sim);
    while ((b = hal_host_uart_tx_pop()) >= 0)
        if (link_out)
            fputc(b, link_out);
    return 1;
}

/* Batch: the keys done, the screen settled, its PNG at scale and its text; the exit status. */
static int screenshot(sim_t *sim, const char *shot, int scale)
{
    char line[17];
    while (keys_busy() && tick(sim))
        ;
    for (int i = 0; i < 600 && tick(sim); i++)
        ;
    if (st7920_emu_png(shot, scale) < 0) {
        fprintf(stderr, "panel: cannot write %s: %s\n", shot, strerror(errno));
        return 1;
    }
    for (int y = 0; y < 4; y++) {
        st7920_emu_line((uint8_t)y, line);
        printf("%s\n", line);
    }
    return 0;
}

/* The panel in the terminal at speed x real time, drawn every 0.1 s, until q. */
static void interactive(sim_t *sim, double speed, int text_only)
{
    double w0 = wall_s(), t0 = sim_time_s(sim), next_draw = 0;
    for (;;) {
        double w = wall_s() - w0;
        int steps = 0;
        if (read_keys())
            break;
        while (sim_time_s(sim) - t0 < w * speed && steps < 200000 && tick(sim))
            steps++;
        if (sim_done(sim))
            keys_tick(sim);
        if (w >= next_draw) {
            draw(sim, text_only);
            next_draw = w + 0.1;
        }
        usleep(2000);
    }
}

int main(int argc, char **argv)
{
    const char *scn_path = NULL, *keys = NULL, *shot = NULL;
    double speed = 1.0, pre_s = 0.0;
    int scale = 3, text_only = 0;
    char err[512];
    scenario_t *s = malloc(sizeof *s);
    sim_t *sim = malloc(sizeof *sim);
    if (!s || !sim)
        return 1;
    long scale_l = 3;
    const char *serial_path = NULL;
    const arg_opt_t opts[] = {
        {"--scenario", ARG_TEXT, &scn_path, 0, 0, NULL},
        {"--keys", ARG_TEXT, &keys, 0, 0, NULL},
        {"--serial", ARG_TEXT, &serial_path, 0, 0, NULL},
        {"--screenshot", ARG_TEXT, &shot, 0, 0, NULL},
        {"--text", ARG_FLAG, &text_only, 0, 0, NULL},
        {"--speed", ARG_NUM, &speed, 0.001, 1000, NULL},
        {"--time", ARG_NUM, &pre_s, 0, 1e6, NULL},
        {"--scale", ARG_WHOLE, &scale_l, 1, 16, NULL},
    };
    int r = args_parse("panel", argc, argv, opts, (int)(sizeof opts / sizeof opts[0]), NULL, usage);
    if (r != ARGS_OK)
        return r == ARGS_HELP ? 0 : 2;
    scale = (int)scale_l;
    if (serial_path) {
        if (!(link_out = fopen(serial_path, "w"))) {
            fprintf(stderr, "panel: cannot write %s: %s\n", serial_path, strerror(errno));
            return 2;
        }
        setvbuf(link_out, NULL, _IOLBF, 0);
    }
    if (scn_path ? scenario_load(s, scn_path, err, sizeof err) < 0
                 : scenario_parse(s, default_scn, "(panel default)", err, sizeof err) < 0) {
        fprintf(stderr, "panel: %s\n", err);
        return 1;
    }
    sim_init(sim, s);
    /* sim_init reset the HAL: connect the display now and start the firmware's LCD afresh */
    st7920_emu_reset();
    hal_host_lcd_sink(st7920_emu_write);
    section_sw = sections_given = hal_host_io.sections;     /* the scenario's: all on */
    /* (batch: the time, the keys, the screen settled, PNG and text) */
    while (sim_time_s(sim) < pre_s && tick(sim))
        ;
    keys_push(keys);
    if (shot)
        return screenshot(sim, shot, scale);
    if (!isatty(0) || raw_start() < 0) {
        fprintf(stderr, "panel: stdin is not a terminal (use --screenshot for batch runs)\n");
        return 1;
    }
    interactive(sim, speed, text_only);
    raw_off();
    sim_free(sim);
    free(s);
    return 0;
}

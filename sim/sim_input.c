/* sim_input.c: the operator's timed input of a run (sim --input, a scenario's key and serial
 * events): keys held on the simulated keypad, lines into the UART. */
#include <ctype.h>
#include <stdlib.h>
#include <string.h>
#include "sim.h"
#include "hal_host.h"
#include "keypad.h"

/* "80 81 7F FE .." (or without the spaces) into bytes: their count, 0 for anything else */
static uint8_t hex_bytes(const char *s, char *out, size_t max)
{
    size_t k = 0;
    unsigned v;
    while (*s) {
        if (*s == ' ') {
            s++;
            continue;
        }
        if (k >= max || !isxdigit((unsigned char)s[0]) || !isxdigit((unsigned char)s[1]) || sscanf(s, "%2x", &v) != 1)
            return 0;
        out[k++] = (char)v;
        s += 2;
    }
    return (uint8_t)k;
}

int sim_input_load(sim_t *sim, const char *path, char *err, size_t n)
{
    FILE *f = fopen(path, "r");
    char buf[256];
    int line = 0;
    double last = 0.0;
    if (!f) {
        snprintf(err, n, "%s: cannot read", path);
        return -1;
    }
    while (fgets(buf, sizeof buf, f)) {
        sim_input_t in;
        char what[16];
        int used = 0;
        size_t len;
        line++;
        buf[strcspn(buf, "\r\n")] = 0;
        if (buf[strspn(buf, " \t")] == '#' || buf[strspn(buf, " \t")] == 0)
            continue;
        memset(&in, 0, sizeof in);
        if (sscanf(buf, "%lf %15s %n", &in.t_s, what, &used) < 2 || in.t_s < last) {
            snprintf(err, n, "%s:%d: expected 't_s key K' or 't_s serial TEXT', times ascending", path, line);
            fclose(f);
            return -1;
        }
        last = in.t_s;
        len = strlen(buf + used);
        if (!strcmp(what, "key") && len == 1 && strchr("0123456789ABCD*#", buf[used]))
            in.key = buf[used];
        else if (!strcmp(what, "serial") && len > 0 && len < sizeof in.line)
            memcpy(in.line, buf + used, len + 1);
        else if (!strcmp(what, "frame") && (in.n_bytes = hex_bytes(buf + used, in.line, sizeof in.line)) > 0)
            ;
        else {
            snprintf(err, n, "%s:%d: a key is one of 0-9 A-D * #; a serial line 1-%d characters; a frame 1-%d hex bytes",
                     path, line, (int)sizeof in.line - 1, (int)sizeof in.line);
            fclose(f);
            return -1;
        }
        sim->input = realloc(sim->input, (size_t)(sim->n_input + 1) * sizeof *sim->input);
        if (!sim->input) {
            snprintf(err, n, "out of memory");
            fclose(f);
            return -1;
        }
        sim->input[sim->n_input++] = in;
    }
    fclose(f);
    return 0;
}

static int key_bit(char k)
{
    uint8_t r, c;
    for (r = 0; r < 4; r++)
        for (c = 0; c < 4; c++)
            if (keypad_char(r, c) == k)
                return 4 * r + c;
    return -1;
}

/* One operator input at t1: key k held SIM_KEY_HOLD_MS (k != 0), n_bytes of a frame as they
 * are (n_bytes != 0), or the line and CR LF into the UART. */
static void input_apply_n(sim_t *sim, char k, const char *line, uint8_t n_bytes, uint64_t t1)
{
    if (n_bytes) {
        while (n_bytes--)
            hal_host_uart_rx_push((uint8_t)*line++);
    } else if (k) {
        int b = key_bit(k);
        hal_host_io.keys = b >= 0 ? (uint16_t)(1u << b) : 0;
        sim->key_release_ns = t1 + SIM_KEY_HOLD_MS * 1000000ull;
    } else {
        const char *c;
        for (c = line; *c; c++)
            hal_host_uart_rx_push((uint8_t)*c);
        hal_host_uart_rx_push('\r');
        hal_host_uart_rx_push('\n');
    }
}

void sim_input_step(sim_t *sim, uint64_t t1)
{
    if (sim->key_release_ns && t1 >= sim->key_release_ns) {
        hal_host_io.keys = 0;
        sim->key_release_ns = 0;
    }
    while (sim->next_input < sim->n_input && sim->input[sim->next_input].t_s * 1e9 <= (double)t1) {
        const sim_input_t *in = &sim->input[sim->next_input++];
        input_apply_n(sim, in->key, in->line, in->n_bytes, t1);
    }
}

int sim_event_text(sim_t *sim, int kind, const char *text)
{
    if ((kind != EV_KEY && kind != EV_SERIAL) || scenario_event_text_check(kind, text, NULL, 0) < 0)
        return -1;
    input_apply_n(sim, kind == EV_KEY ? text[0] : 0, text, 0, sim->t_ns + sim->tick_ns);
    return 0;
}

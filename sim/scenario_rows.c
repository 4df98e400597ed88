/* scenario_rows.c: what a scenario holds besides its file's syntax: the defaults, the events (names, values, checks), the controllers by name, the driver's speed at a time. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "scenario.h"
#include "scenario_int.h"
#include "ctl.h"

int scn_is_whole(double v)
{
    return fabs(v - floor(v + 0.5)) < 1e-9 * (fabs(v) > 1 ? fabs(v) : 1);
}

/* ---- messages --------------------------------------------------------------------------------- */
void scenario_printable(char *dst, size_t n, const char *src)
{
    static const char hex[] = "0123456789ABCDEF";
    size_t k = 0;
    if (!n)
        return;
    for (; *src; src++) {
        unsigned char b = (unsigned char)*src;
        if (b >= 0x20 && b < 0x7F) {
            if (k + 1 >= n)
                break;
            dst[k++] = (char)b;
        } else {
            if (k + 4 >= n)
                break;              /* a whole escape or none */
            dst[k++] = '\\';
            dst[k++] = 'x';
            dst[k++] = hex[b >> 4];
            dst[k++] = hex[b & 15];
        }
    }
    dst[k] = 0;
}

/* ---- defaults --------------------------------------------------------------------------------- */
void scenario_default(scenario_t *s, const char *name)
{
    uint8_t i;
    memset(s, 0, sizeof *s);
    snprintf(s->name, sizeof s->name, "%s", name ? name : "scenario");
    s->duration_s = 300;
    s->seed = 7;
    for (i = 0; i < P_COUNT; i++)
        s->param[i] = param_info(i)->def;
    plant_params_default(&s->plant);
}

int scenario_nozzles_per_section(const scenario_t *s)
{
    return s->param[P_NOZZLES] / s->param[P_SECTIONS];
}

/* ---- events ----------------------------------------------------------------------------------- */
typedef struct {
    const char *name;
    int arg;
} ev_info_t;
#define SCN_EV_ROW(id, name, arg) {name, arg},
static const ev_info_t ev_info[EV_COUNT] = { SCN_EVENTS(SCN_EV_ROW) };
#undef SCN_EV_ROW

const char *scenario_event_name(int kind)
{
    return kind >= 0 && kind < EV_COUNT ? ev_info[kind].name : "?";
}

int scenario_event_takes_value(int kind)
{
    return kind >= 0 && kind < EV_COUNT ? ev_info[kind].arg : 0;
}

int scenario_event_text_check(int kind, const char *text, char *msg, size_t n)
{
    size_t len = strlen(text), i;
#define BAD(...) do { if (msg && n) snprintf(msg, n, __VA_ARGS__); return -1; } while (0)
    if (kind == EV_KEY) {
        if (len != 1 || !strchr("0123456789ABCD*#", text[0]))
            BAD("'%s' is not a key (one of 0-9 A-D * #)", text);
        return 0;
    }
    if (kind != EV_SERIAL)
        BAD("takes no text");
    if (len == 0 || len >= SCN_TEXT_MAX)
        BAD("a serial line is 1-%d characters (%zu here)", SCN_TEXT_MAX - 1, len);
    for (i = 0; i < len; i++)
        if ((unsigned char)text[i] < 32 || (unsigned char)text[i] > 126)
            BAD("a serial line is printable ASCII (a byte 0x%02x at %zu)", (unsigned char)text[i], i + 1);
#undef BAD
    return 0;
}

/* The events whose value is a number in a fixed range (the message's unit after it). */
static const struct { int kind; double lo, hi; const char *unit; } ev_ranges[] = {
    {EV_PTO_RPM, 0, 1500, "rpm"},
    {EV_BOUNCE, 0, 100, "%"},
    {EV_LEAK, 0, 200, "L/min"},
    {EV_METER_K, 1, 10000, "pulses/L"},
    {EV_P_OFFSET, -16, 16, "bar"},
    {EV_P_DRIFT, -10, 10, "bar a minute"},
    {EV_WHEEL_MULT, 0.1, 16, "edges a real one"},
    {EV_POWER_CUT, 0.01, 86400, "s"},
};

#define BAD(...) do { if (msg && n) snprintf(msg, n, __VA_ARGS__); return -1; } while (0)

/* A number of nozzles the boom holds; whole sections of them when sections is set. */
static int nozzles_check(const scenario_t *s, double v, int sections, char *msg, size_t n)
{
    int noz = s->param[P_NOZZLES], sec = s->param[P_SECTIONS];
    if (!scn_is_whole(v) || v < 0 || v > noz)
        BAD("%g is not a number of nozzles 0..%d", v, noz);
    if (sections && (int)floor(v + 0.5) % (noz / sec) != 0)
        BAD("%g nozzles is not a whole number of sections (%d nozzles each)", v, noz / sec);
    return 0;
}

int scenario_event_check(const scenario_t *s, int kind, double v, char *msg, size_t n)
{
    size_t i;
    if (kind < 0 || kind >= EV_COUNT)
        BAD("unknown event");
    for (i = 0; i < sizeof ev_ranges / sizeof ev_ranges[0]; i++)
        if (ev_ranges[i].kind == kind) {
            if (v < ev_ranges[i].lo || v > ev_ranges[i].hi)
                BAD("%g out of range %g..%g %s", v, ev_ranges[i].lo, ev_ranges[i].hi, ev_ranges[i].unit);
            return 0;
        }
    switch (kind) {
    case EV_SECTIONS_OPEN:
    case EV_AOG_SECTIONS:
        return nozzles_check(s, v, 1, msg, n);
    case EV_CLOG:
        return nozzles_check(s, v, 0, msg, n);
    case EV_RATE:
        if (!scn_is_whole(v * 10) || v < 0 || v > 6553 || !param_in_range(P_RATE, (uint16_t)floor(v * 10 + 0.5)))
            BAD("%g out of the firmware's range %g..%g L/ha in steps of 0.1", v,
                param_info(P_RATE)->min / 10.0, param_info(P_RATE)->max / 10.0);
        break;
    case EV_PRESET:
        if (v != 1 && v != 2)
            BAD("%g is not a preset (1 or 2)", v);
        break;
    case EV_NUDGE:
        if (v != 1 && v != -1 && v != 0)
            BAD("%g is not a nudge (+1 up, -1 down, 0 back to the preset)", v);
        break;
    case EV_GIVEN_SPEED:
        if (v < 0 || v > 6553 || !scn_is_whole(v * 10) || !param_in_range(P_GIVEN_SPEED, (uint16_t)floor(v * 10 + 0.5)))
            BAD("%g out of the firmware's range 0..%g km/h in steps of 0.1", v, param_info(P_GIVEN_SPEED)->max / 10.0);
        break;
    case EV_TANK:
        if (v < 0 || v > s->plant.tank_l)
            BAD("%g out of range 0..%g L (tank_l)", v, s->plant.tank_l);
        break;
    case EV_LEVEL_OFFSET:
        if (v < -s->plant.tank_l || v > s->plant.tank_l)
            BAD("%g out of range -%g..%g L (tank_l)", v, s->plant.tank_l, s->plant.tank_l);
        break;
    case EV_AOG_HZ:
        if (v != 0 && (v < 0.2 || v > 20))
            BAD("%g out of range 0.2..20 Hz (0: the frames stop)", v);
        break;
    case EV_RC_RATE:
        if (v != 0 && (v < 1 || v > 2000))
            BAD("%g out of range 1..2000 L/ha (0: the frames stop)", v);
        break;
    case EV_KEY:
    case EV_SERIAL:
        if (v != 0)
            BAD("takes text, not a number");
        break;
    default:
        if (v != 0)
            BAD("takes no value");
        break;
    }
    return 0;
}
#undef BAD

/* ---- controllers ------------------------------------------------------------------------------ */
/* Old names still accepted on the command line and in scenario files: the alias table. */
static const struct { const char *alias; int id; } ctl_aliases[] = {
    { "best", CTL_FFMAP },          /* the project's own controller's name before it had one */
};

const char *scenario_controller_alias(size_t i, int *id)
{
    if (i >= sizeof ctl_aliases / sizeof ctl_aliases[0])
        return NULL;
    *id = ctl_aliases[i].id;
    return ctl_aliases[i].alias;
}

int scenario_controller_id(const char *name)
{
    int id;
    size_t a;
    for (a = 0; a < sizeof ctl_aliases / sizeof ctl_aliases[0]; a++)
        if (strcmp(name, ctl_aliases[a].alias) == 0)
            return ctl_aliases[a].id;
    for (id = 0; id < CTL_COUNT; id++)
        if (strcmp(name, ctl_name((uint8_t)id)) == 0)
            return id;
    return -1;
}

static void controller_names(char *buf, size_t n)
{
    int id;
    size_t k = 0;
    buf[0] = 0;
    for (id = 0; id < CTL_COUNT && k < n; id++)
        k += (size_t)snprintf(buf + k, n - k, id ? ", %s" : "%s", ctl_name((uint8_t)id));
}

int scenario_set_controller(scenario_t *s, const char *name, char *err, size_t errlen)
{
    int id = scenario_controller_id(name);
    char names[128];
    if (id < 0) {
        char msg[512];
        controller_names(names, sizeof names);
        snprintf(msg, sizeof msg, "unknown controller '%s' (one of: %s)", name, names);
        if (err && errlen)
            scenario_printable(err, errlen, msg);
        return -1;
    }
    s->param[P_CONTROLLER] = (uint16_t)id;
    return 0;
}

/* ---- a shorter run ---------------------------------------------------------------------------- */
int scenario_cut(scenario_t *s, double t_s, char *err, size_t errlen)
{
    if (!(t_s > 0 && t_s <= 1e6)) {
        if (err && errlen)
            snprintf(err, errlen, "%g is not a duration (0, 1000000] s", t_s);
        return -1;
    }
    if (t_s < s->duration_s)
        s->duration_s = t_s;
    while (s->n_events > 0 && s->events[s->n_events - 1].t_s > s->duration_s)
        s->n_events--;
    return 0;
}

/* ---- the drive -------------------------------------------------------------------------------- */
double scenario_drive_kmh(const scenario_t *s, double t)
{
    int lo = 0, hi = s->n_drive - 1;
    const scn_drive_t *d = s->drive;
    if (s->n_drive == 0)
        return 0.0;
    if (t < d[0].t_s)
        return d[0].kmh;
    if (t >= d[hi].t_s)
        return d[hi].kmh;
    /* the last row with t_s <= t (so a step's second row wins at its own time) */
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (d[mid].t_s <= t)
            lo = mid;
        else
            hi = mid;
    }
    if (d[hi].t_s == d[lo].t_s)
        return d[hi].kmh;
    return d[lo].kmh + (d[hi].kmh - d[lo].kmh) * (t - d[lo].t_s) / (d[hi].t_s - d[lo].t_s);
}

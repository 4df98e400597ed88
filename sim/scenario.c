/* scenario.c: the strict reader of scenario files: every error names file, line and key, and nothing half-read runs. */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "scenario.h"
#include "ctl.h"

/* [config] keys: what the operator sets on the console, in the unit the key names, and the
 * factor to the parameter's stored unit (params.h). */
typedef struct {
    const char *key;
    uint8_t id;
    double scale;
} cfg_key_t;

static const cfg_key_t cfg_keys[] = {
    {"rate_l_ha", P_RATE, 10},                      /* Rate 1, stored in 0.1 L/ha */
    {"rate2_l_ha", P_RATE2, 10},                    /* Rate 2 */
    {"rate_step_pct", P_RATE_STEP, 1},              /* a nudge's step */
    {"nozzles", P_NOZZLES, 1},
    {"spacing_cm", P_SPACING, 1},
    {"sections", P_SECTIONS, 1},
    {"meter_cal_ppl", P_METER_K, 10},               /* stored in 0.1 p/L */
    {"wheel_m_per_pulse", P_WHEEL, 10000},          /* stored in 0.1 mm */
    {"min_flow_speed_kmh", P_MINF_SPEED, 10},
    {"given_speed_kmh", P_GIVEN_SPEED, 10},
    {"tank_min_l", P_TANK_MIN, 1},
    {"valve_travel_s", P_VALVE_TRAVEL, 10},         /* what the firmware believes */
    {"valve_stiction_duty", P_VALVE_BRK, 100},      /* ... its Min duty, stored in % */
    {"valve_backlash", P_VALVE_SLACK, 1000},        /* ... its Backlash, stored in 0.1 % */
    {"nozzle_lpm_at_3bar", P_NOZZLE_Q3, 100},
    {"wheel_pulses_per_rev", P_WHEEL_PPR, 1},      /* the elements a turn whose spacing is learnt */
    {"aog_kp", P_AOG_KP, 1},                        /* aog's settings as the RateControl app sets them */
    {"aog_ki", P_AOG_KI, 1},
    {"aog_brake_pct", P_AOG_BRAKE, 10},             /* ... % of the target, 0.1 steps */
    {"aog_slow_pct", P_AOG_SLOW, 1},
    {"aog_min_pwm", P_AOG_MIN, 1},                  /* ... PWM counts of 255 */
    {"aog_max_pwm", P_AOG_MAX, 1},
    {"raven_valve_cal", P_RAVEN_CAL, 1},            /* raven's four digits */
    {"remote", P_REMOTE, 1},                        /* 0 off, 1 Raven, 2 AgOpenGPS frames */
    {"speed_source", P_SPEED_SRC, 1},               /* 0 wheel, 1 GPS, 2 both */
    {"speed_diff_pct", P_SPEED_DIFF, 1},
    {"aog_sections", P_AOG_SECT, 1},                /* 1: the sections also from the frames */
    {"frames_lost_s", P_FRAMES_LOST, 10},           /* stored in 0.1 s */
    {"rc_module", P_RC_ID, 1},
};
#define N_CFG (sizeof cfg_keys / sizeof cfg_keys[0])

typedef struct {
    const char *key;
    double lo, hi;
    int isint;
} plant_key_t;

#define PLANT_KEY_ROW(key, def, lo, hi, isint) {#key, lo, hi, isint},
static const plant_key_t plant_keys[] = { PLANT_KEYS(PLANT_KEY_ROW) };
#undef PLANT_KEY_ROW
#define N_PLANT (sizeof plant_keys / sizeof plant_keys[0])

static double *plant_field(plant_params_t *p, size_t i)
{
    size_t k = 0;
#define PLANT_KEY_PTR(key, def, lo, hi, isint) if (k++ == i) return &p->key;
    PLANT_KEYS(PLANT_KEY_PTR)
#undef PLANT_KEY_PTR
    return NULL;
}

/* ---- errors --------------------------------------------------------------------------------- */
typedef struct {
    const char *name;
    char *err;
    size_t errlen;
} ctx_t;

/* "file:line: key 'k': what is wrong" into c->err, every byte a file may hold that does not
 * print (control codes, bytes past ASCII) written as \xHH, so no terminal shows it raw */
static int fail(const ctx_t *c, int line, const char *key, const char *fmt, ...)
{
    char msg[256], whole[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (c->err && c->errlen) {
        if (line > 0)
            snprintf(whole, sizeof whole, "%s:%d: key '%s': %s", c->name, line, key, msg);
        else
            snprintf(whole, sizeof whole, "%s: key '%s': %s", c->name, key, msg);
        scenario_printable(c->err, c->errlen, whole);
    }
    return -1;
}

/* A plain decimal number (sign, digits, point, exponent) and nothing else: no hex, inf or nan. */
static int parse_num(const char *s, double *v)
{
    const char *p = s;
    char *end;
    int digits = 0;
    if (*p == '+' || *p == '-')
        p++;
    while (isdigit((unsigned char)*p) || *p == '.') {
        digits += isdigit((unsigned char)*p) != 0;
        p++;
    }
    if (!digits)
        return -1;
    if (*p == 'e' || *p == 'E') {
        p++;
        if (*p == '+' || *p == '-')
            p++;
        if (!isdigit((unsigned char)*p))
            return -1;
        while (isdigit((unsigned char)*p))
            p++;
    }
    if (*p)
        return -1;
    errno = 0;
    *v = strtod(s, &end);
    if (*end || errno == ERANGE || !isfinite(*v))
        return -1;
    return 0;
}

static int is_whole(double v)
{
    return fabs(v - floor(v + 0.5)) < 1e-9 * (fabs(v) > 1 ? fabs(v) : 1);
}

static char *trim(char *s)
{
    char *e;
    while (*s && isspace((unsigned char)*s))
        s++;
    e = s + strlen(s);
    while (e > s && isspace((unsigned char)e[-1]))
        *--e = 0;
    return s;
}

/* ---- sections -------------------------------------------------------------------------------- */
enum { SEC_NONE, SEC_RUN, SEC_CONFIG, SEC_PLANT, SEC_DRIVE, SEC_EVENTS };
static const char *const sec_names[] = {"", "run", "config", "plant", "drive", "events"};

#define MAX_KEYS 64
typedef struct {
    int sec;
    char key[40];
} seen_t;

static int run_key(const ctx_t *c, scenario_t *s, int line, const char *key, const char *val)
{
    double v;
    if (strcmp(key, "duration_s") == 0) {
        if (parse_num(val, &v) < 0)
            return fail(c, line, key, "'%s' is not a number", val);
        if (v <= 0 || v > 1e6)
            return fail(c, line, key, "%g out of range (0, 1000000] s", v);
        s->duration_s = v;
        return 0;
    }
    if (strcmp(key, "seed") == 0) {
        const char *p;
        char *end;
        unsigned long long u;
        for (p = val; *p; p++)
            if (!isdigit((unsigned char)*p))
                return fail(c, line, key, "'%s' is not a whole number 0..2^64-1", val);
        errno = 0;
        u = strtoull(val, &end, 10);
        if (errno == ERANGE || *end || !*val)
            return fail(c, line, key, "'%s' is not a whole number 0..2^64-1", val);
        s->seed = (uint64_t)u;
        return 0;
    }
    return fail(c, line, key, "unknown key in [run] (keys: duration_s, seed)");
}

/* where the whole-file checks find the keys they name: the line of each [config] value given,
 * the later of two keys a check compares (and which it was), the [drive] header */
typedef struct {
    int cfg[P_COUNT];
    int nozzles, tank, duty, drive;
    const char *nozzles_key, *tank_key, *duty_key;
} lines_t;

static int config_key(const ctx_t *c, scenario_t *s, int line, const char *key, const char *val, lines_t *at)
{
    size_t i;
    double v, scaled;
    if (strcmp(key, "controller") == 0) {
        char msg[200];
        if (scenario_set_controller(s, val, msg, sizeof msg) < 0)
            return fail(c, line, key, "%s", msg);
        return 0;
    }
    for (i = 0; i < N_CFG; i++)
        if (strcmp(key, cfg_keys[i].key) == 0)
            break;
    if (i == N_CFG)
        return fail(c, line, key, "unknown key in [config]");
    if (parse_num(val, &v) < 0)
        return fail(c, line, key, "'%s' is not a number", val);
    scaled = v * cfg_keys[i].scale;
    {
        const param_info_t *pi = param_info(cfg_keys[i].id);
        double lo = pi->min / cfg_keys[i].scale, hi = pi->max / cfg_keys[i].scale;
        if (scaled < pi->min - 1e-9 || scaled > pi->max + 1e-9)
            return fail(c, line, key, "%g out of the firmware's range %g..%g %s", v, lo, hi, pi->unit);
        if (!is_whole(scaled))
            return fail(c, line, key, "%g has more decimals than the firmware keeps (steps of %g)",
                        v, 1.0 / cfg_keys[i].scale);
        if (!param_in_range(cfg_keys[i].id, (uint16_t)floor(scaled + 0.5)))
            return fail(c, line, key, "%g refused by the firmware (a valve cal's last digit, the dead band, is 1-9)", v);
        s->param[cfg_keys[i].id] = (uint16_t)floor(scaled + 0.5);
        at->cfg[cfg_keys[i].id] = line;
    }
    return 0;
}

static int plant_key(const ctx_t *c, scenario_t *s, int line, const char *key, const char *val)
{
    size_t i;
    double v;
    for (i = 0; i < N_PLANT; i++)
        if (strcmp(key, plant_keys[i].key) == 0)
            break;
    if (i == N_PLANT)
        return fail(c, line, key, "unknown key in [plant]");
    if (parse_num(val, &v) < 0)
        return fail(c, line, key, "'%s' is not a number", val);
    if (v < plant_keys[i].lo || v > plant_keys[i].hi)
        return fail(c, line, key, "%g out of range %g..%g", v, plant_keys[i].lo, plant_keys[i].hi);
    if (plant_keys[i].isint && !is_whole(v))
        return fail(c, line, key, "%g is not a whole number", v);
    *plant_field(&s->plant, i) = v;
    return 0;
}

/* Split a row into at most 4 whitespace-separated words; returns their count (4: too many). */
static int words(char *s, char *w[4])
{
    int n = 0;
    char *p = s;
    while (*p && n < 4) {
        while (*p && isspace((unsigned char)*p))
            p++;
        if (!*p)
            break;
        w[n++] = p;
        while (*p && !isspace((unsigned char)*p))
            p++;
        if (*p)
            *p++ = 0;
    }
    return n;
}

static int drive_row(const ctx_t *c, scenario_t *s, int line, char *row)
{
    char *w[4];
    double t, v;
    int n = words(row, w);
    if (n != 2)
        return fail(c, line, "drive", "a row is 'time_s speed_kmh' (%d words here)", n);
    if (parse_num(w[0], &t) < 0)
        return fail(c, line, "drive", "time '%s' is not a number", w[0]);
    if (parse_num(w[1], &v) < 0)
        return fail(c, line, "drive", "speed '%s' is not a number", w[1]);
    if (t < 0)
        return fail(c, line, "drive", "time %g is negative", t);
    if (s->n_drive > 0 && t < s->drive[s->n_drive - 1].t_s)
        return fail(c, line, "drive", "time goes backwards (%g after %g)", t, s->drive[s->n_drive - 1].t_s);
    if (v < 0 || v > 60)
        return fail(c, line, "drive", "speed %g out of range 0..60 km/h", v);
    if (s->n_drive >= SCN_MAX_DRIVE)
        return fail(c, line, "drive", "more than %d rows", SCN_MAX_DRIVE);
    s->drive[s->n_drive].t_s = t;
    s->drive[s->n_drive].kmh = v;
    s->n_drive++;
    return 0;
}

static int event_row(const ctx_t *c, scenario_t *s, int line, char *row)
{
    char *w[4];
    double t, v = 0;
    int n = words(row, w), k;
    if (n < 2 || n > 3)
        return fail(c, line, "events", "a row is 'time_s event [value]' (%d words here)", n);
    if (parse_num(w[0], &t) < 0)
        return fail(c, line, "events", "time '%s' is not a number", w[0]);
    for (k = 0; k < EV_COUNT; k++)
        if (strcmp(w[1], scenario_event_name(k)) == 0)
            break;
    if (k == EV_COUNT)
        return fail(c, line, w[1], "unknown event");
    if (t < 0)
        return fail(c, line, w[1], "time %g is negative", t);
    if (s->n_events > 0 && t < s->events[s->n_events - 1].t_s)
        return fail(c, line, w[1], "time goes backwards (%g after %g)", t, s->events[s->n_events - 1].t_s);
    if (scenario_event_takes_value(k) && n != 3)
        return fail(c, line, w[1], "needs a value");
    if (!scenario_event_takes_value(k) && n != 2)
        return fail(c, line, w[1], "takes no value ('%s' given)", w[2]);
    if (n == 3 && parse_num(w[2], &v) < 0)
        return fail(c, line, w[1], "value '%s' is not a number", w[2]);
    if (s->n_events >= SCN_MAX_EVENTS)
        return fail(c, line, w[1], "more than %d events", SCN_MAX_EVENTS);
    s->events[s->n_events].t_s = t;
    s->events[s->n_events].kind = k;
    s->events[s->n_events].value = v;
    s->events[s->n_events].line = line;
    s->n_events++;
    return 0;
}

/* A key or serial row: `time_s key K` or `time_s serial TEXT`, the text running to the row's end
 * ('#' is a key and a checksum's place there, not a comment). 1 when the row is one (rc says
 * how it went), 0 when it is another event's (read as usual). */
static int text_event_row(const ctx_t *c, scenario_t *s, int line, char *row, int *rc)
{
    char *w[4], copy[128], *text = row;
    double t;
    int k, n;
    if (row[0] == '#')
        return 0;
    snprintf(copy, sizeof copy, "%s", row);
    n = words(copy, w);
    if (n < 2 || (strcmp(w[1], "key") != 0 && strcmp(w[1], "serial") != 0))
        return 0;
    k = strcmp(w[1], "key") == 0 ? EV_KEY : EV_SERIAL;
    text += strcspn(text, " \t");          /* past the time */
    text += strspn(text, " \t");
    text += strcspn(text, " \t");          /* past the event's name */
    text = trim(text);
    {
        char msg[200];
        if (parse_num(w[0], &t) < 0)
            *rc = fail(c, line, "events", "time '%s' is not a number", w[0]);
        else if (t < 0)
            *rc = fail(c, line, w[1], "time %g is negative", t);
        else if (s->n_events > 0 && t < s->events[s->n_events - 1].t_s)
            *rc = fail(c, line, w[1], "time goes backwards (%g after %g)", t, s->events[s->n_events - 1].t_s);
        else if (scenario_event_text_check(k, text, msg, sizeof msg) < 0)
            *rc = fail(c, line, w[1], "%s", msg);
        else if (s->n_events >= SCN_MAX_EVENTS)
            *rc = fail(c, line, w[1], "more than %d events", SCN_MAX_EVENTS);
        else {
            scn_event_t *e = &s->events[s->n_events++];
            e->t_s = t;
            e->kind = k;
            e->value = 0;
            e->line = line;
            snprintf(e->text, sizeof e->text, "%s", text);
        }
    }
    return 1;
}

/* The parameters each of the firmware's cross-checks (params.h) compares, PARAM_X_TANK on
 * (P_COUNT: no more). */
static const uint8_t cross_params[][4] = {
    {P_TANK_MIN, P_TANK_L, P_COUNT, P_COUNT},
    {P_P_MIN, P_P_MAX, P_COUNT, P_COUNT},
    {P_METER_K, P_NOZZLES, P_NOZZLE_Q3, P_P_MAX},
};

/* A cross-check the set breaks, named by the latest line that gave one of its values. */
static int cross_fail(const ctx_t *c, const lines_t *at, uint8_t why)
{
    int line = 0, k, id = -1;
    size_t i;
    if (why >= PARAM_X_TANK && why - PARAM_X_TANK < (int)(sizeof cross_params / sizeof cross_params[0]))
        for (k = 0; k < 4; k++) {
            uint8_t p = cross_params[why - PARAM_X_TANK][k];
            if (p < P_COUNT && at->cfg[p] > line) {
                line = at->cfg[p];
                id = p;
            }
        }
    for (i = 0; i < N_CFG; i++)
        if (cfg_keys[i].id == id)
            return fail(c, line, cfg_keys[i].key, "the firmware refuses this value with the others: %s",
                        param_why_text(why));
    return fail(c, 0, "[config]", "the firmware refuses this set of values: %s", param_why_text(why));
}

/* Checks that need the whole file: the boom's sections, the tank, the events' values, a drive. */
static int check_whole(const ctx_t *c, scenario_t *s, const lines_t *at)
{
    int noz = s->param[P_NOZZLES], sec = s->param[P_SECTIONS], i;
    if (noz % sec != 0)
        return fail(c, at->nozzles, at->nozzles_key,
                    "%d nozzles do not split evenly over %d sections", noz, sec);
    if (s->plant.tank_start_l > s->plant.tank_l)
        return fail(c, at->tank, at->tank_key, "tank_start_l %g L is more than the tank holds (tank_l %g)",
                    s->plant.tank_start_l, s->plant.tank_l);
    if (s->plant.valve_running_duty > s->plant.valve_stiction_duty)
        return fail(c, at->duty, at->duty_key, "running duty %g is above the break-away duty %g "
                    "(valve_running_duty <= valve_stiction_duty)",
                    s->plant.valve_running_duty, s->plant.valve_stiction_duty);
    {
        /* the firmware's cross-checks between parameters (params.h), on this set */
        uint16_t live[P_COUNT];
        uint8_t why;
        memcpy(live, param_v, sizeof live);
        memcpy(param_v, s->param, sizeof live);
        why = params_cross();
        memcpy(param_v, live, sizeof live);
        if (why != PARAM_OK)
            return cross_fail(c, at, why);
    }
    for (i = 0; i < s->n_events; i++) {
        const scn_event_t *e = &s->events[i];
        char msg[200];
        if (e->t_s > s->duration_s)
            return fail(c, e->line, scenario_event_name(e->kind), "at %g s, after the end of the run (duration_s %g)",
                        e->t_s, s->duration_s);
        if (scenario_event_check(s, e->kind, e->value, msg, sizeof msg) < 0)
            return fail(c, e->line, scenario_event_name(e->kind), "%s", msg);
    }
    /* nothing to run without a driver: an empty file, or a [drive] without rows, is a mistake */
    if (s->n_drive == 0)
        return fail(c, at->drive, "[drive]", at->drive ? "no rows: a run needs at least one 'time_s speed_kmh'"
                    : "missing: a run needs a [drive] section with at least one 'time_s speed_kmh' row");
    s->plant.nozzles = noz;
    s->plant.spacing_m = s->param[P_SPACING] / 100.0;
    return 0;
}

int scenario_parse(scenario_t *out, const char *text, const char *name, char *err, size_t errlen)
{
    static scenario_t tmp;          /* large: built aside, copied to out only when all is well */
    ctx_t c;
    seen_t seen[MAX_KEYS];
    int n_seen = 0, sec = SEC_NONE, line = 0, rc = 0;
    lines_t at;
    size_t len = strlen(text);
    char *buf, *p;
    int sec_seen[6] = {0};

    c.name = name ? name : "scenario";
    c.err = err;
    c.errlen = errlen;
    if (err && errlen)
        err[0] = 0;
    memset(&at, 0, sizeof at);
    at.nozzles_key = "nozzles";
    at.tank_key = "tank_start_l";
    at.duty_key = "valve_running_duty";
    scenario_default(&tmp, c.name);
    buf = malloc(len + 1);
    if (!buf)
        return fail(&c, 0, "-", "out of memory");
    memcpy(buf, text, len + 1);
    if ((unsigned char)buf[0] == 0xEF && (unsigned char)buf[1] == 0xBB && (unsigned char)buf[2] == 0xBF)
        memmove(buf, buf + 3, len - 2);     /* a UTF-8 byte order mark (editors on Windows) */

    for (p = buf; rc == 0 && p && *p;) {
        char *nl = strchr(p, '\n'), *s, *hash, *eq;
        if (nl)
            *nl = 0;
        line++;
        s = p;
        p = nl ? nl + 1 : NULL;
        if (sec == SEC_EVENTS && text_event_row(&c, &tmp, line, trim(s), &rc))
            continue;
        hash = strchr(s, '#');
        if (hash)
            *hash = 0;
        s = trim(s);
        if (!*s)
            continue;
        if (*s == '[') {
            char *close = strchr(s, ']');
            int k;
            if (!close || close[1])
                { rc = fail(&c, line, s, "a section header is '[name]' alone on its line"); break; }
            *close = 0;
            for (k = 1; k <= SEC_EVENTS; k++)
                if (strcmp(trim(s + 1), sec_names[k]) == 0)
                    break;
            if (k > SEC_EVENTS)
                { rc = fail(&c, line, s + 1, "unknown section (run, config, plant, drive, events)"); break; }
            if (sec_seen[k])
                { rc = fail(&c, line, s + 1, "section given twice"); break; }
            sec_seen[k] = 1;
            sec = k;
            if (sec == SEC_DRIVE)
                at.drive = line;
            continue;
        }
        if (sec == SEC_NONE)
            { rc = fail(&c, line, s, "comes before any [section]"); break; }
        if (sec == SEC_DRIVE) {
            rc = drive_row(&c, &tmp, line, s);
            continue;
        }
        if (sec == SEC_EVENTS) {
            rc = event_row(&c, &tmp, line, s);
            continue;
        }
        eq = strchr(s, '=');
        if (!eq)
            { rc = fail(&c, line, s, "expected 'key = value'"); break; }
        *eq = 0;
        {
            char *key = trim(s), *val = trim(eq + 1);
            int i;
            if (!*key)
                { rc = fail(&c, line, "", "a value without a key"); break; }
            if (!*val)
                { rc = fail(&c, line, key, "missing value"); break; }
            for (i = 0; i < n_seen; i++)
                if (seen[i].sec == sec && strcmp(seen[i].key, key) == 0)
                    break;
            if (i < n_seen)
                { rc = fail(&c, line, key, "given twice in [%s]", sec_names[sec]); break; }
            if (n_seen < MAX_KEYS && strlen(key) < sizeof seen[0].key) {
                seen[n_seen].sec = sec;
                strcpy(seen[n_seen].key, key);
                n_seen++;
            }
            if (sec == SEC_RUN)
                rc = run_key(&c, &tmp, line, key, val);
            else if (sec == SEC_CONFIG) {
                rc = config_key(&c, &tmp, line, key, val, &at);
                if (strcmp(key, "nozzles") == 0 || strcmp(key, "sections") == 0) {
                    at.nozzles = line;          /* the later of the two is named */
                    at.nozzles_key = strcmp(key, "nozzles") == 0 ? "nozzles" : "sections";
                }
            } else {
                rc = plant_key(&c, &tmp, line, key, val);
                if (strcmp(key, "tank_start_l") == 0 || strcmp(key, "tank_l") == 0) {
                    at.tank = line;             /* the later of the two is named */
                    at.tank_key = strcmp(key, "tank_l") == 0 ? "tank_l" : "tank_start_l";
                }
                if (strcmp(key, "valve_running_duty") == 0 || strcmp(key, "valve_stiction_duty") == 0) {
                    at.duty = line;             /* the later of the two is named */
                    at.duty_key = strcmp(key, "valve_running_duty") == 0 ? "valve_running_duty" : "valve_stiction_duty";
                }
            }
        }
    }
    free(buf);
    if (rc == 0)
        rc = check_whole(&c, &tmp, &at);
    if (rc == 0)
        *out = tmp;
    return rc;
}

int scenario_load(scenario_t *s, const char *path, char *err, size_t errlen)
{
    FILE *f = fopen(path, "rb");
    char *text, msg[512];
    size_t n;
    int rc;
    if (!f) {
        snprintf(msg, sizeof msg, "%s: cannot open: %s", path, strerror(errno));
        if (err && errlen)
            scenario_printable(err, errlen, msg);
        return -1;
    }
    text = malloc(SCN_MAX_BYTES + 1);
    if (!text) {
        fclose(f);
        if (err && errlen)
            snprintf(err, errlen, "%s: out of memory", path);
        return -1;
    }
    n = fread(text, 1, SCN_MAX_BYTES + 1, f);
    if (ferror(f) || n > SCN_MAX_BYTES) {
        fclose(f);
        free(text);
        snprintf(msg, sizeof msg, "%s: %s", path, n > SCN_MAX_BYTES ? "larger than 1 MB" : "read error");
        if (err && errlen)
            scenario_printable(err, errlen, msg);
        return -1;
    }
    fclose(f);
    text[n] = 0;
    if (memchr(text, 0, n)) {
        free(text);
        snprintf(msg, sizeof msg, "%s: not a text file (NUL byte)", path);
        if (err && errlen)
            scenario_printable(err, errlen, msg);
        return -1;
    }
    rc = scenario_parse(s, text, path, err, errlen);
    free(text);
    return rc;
}

/* scenario_keys.c: the keys and rows of a scenario file's sections: [run]'s, [config]'s (the firmware's settings in the operator's units), [plant]'s, [drive]'s and [events]' rows. */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "scenario.h"
#include "scenario_int.h"

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
    {"tank_size_l", P_TANK_L, 1},                   /* what the firmware believes the level's span is */
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

int scn_run_key(const scn_ctx_t *c, scenario_t *s, int line, const char *key, const char *val)
{
    double v;
    if (strcmp(key, "duration_s") == 0) {
        if (parse_num(val, &v) < 0)
            return scn_fail(c, line, key, "'%s' is not a number", val);
        if (v <= 0 || v > 1e6)
            return scn_fail(c, line, key, "%g out of range (0, 1000000] s", v);
        s->duration_s = v;
        return 0;
    }
    if (strcmp(key, "seed") == 0) {
        const char *p;
        char *end;
        unsigned long long u;
        for (p = val; *p; p++)
            if (!isdigit((unsigned char)*p))
                return scn_fail(c, line, key, "'%s' is not a whole number 0..2^64-1", val);
        errno = 0;
        u = strtoull(val, &end, 10);
        if (errno == ERANGE || *end || !*val)
            return scn_fail(c, line, key, "'%s' is not a whole number 0..2^64-1", val);
        s->seed = (uint64_t)u;
        return 0;
    }
    return scn_fail(c, line, key, "unknown key in [run] (keys: duration_s, seed)");
}

int scn_config_key(const scn_ctx_t *c, scenario_t *s, int line, const char *key, const char *val, scn_lines_t *at)
{
    size_t i;
    double v, scaled;
    if (strcmp(key, "controller") == 0) {
        char msg[200];
        if (scenario_set_controller(s, val, msg, sizeof msg) < 0)
            return scn_fail(c, line, key, "%s", msg);
        return 0;
    }
    for (i = 0; i < N_CFG; i++)
        if (strcmp(key, cfg_keys[i].key) == 0)
            break;
    if (i == N_CFG)
        return scn_fail(c, line, key, "unknown key in [config]");
    if (parse_num(val, &v) < 0)
        return scn_fail(c, line, key, "'%s' is not a number", val);
    scaled = v * cfg_keys[i].scale;
    {
        const param_info_t *pi = param_info(cfg_keys[i].id);
        double lo = pi->min / cfg_keys[i].scale, hi = pi->max / cfg_keys[i].scale;
        if (scaled < pi->min - 1e-9 || scaled > pi->max + 1e-9)
            return scn_fail(c, line, key, "%g out of the firmware's range %g..%g %s", v, lo, hi, pi->unit);
        if (!scn_is_whole(scaled))
            return scn_fail(c, line, key, "%g has more decimals than the firmware keeps (steps of %g)",
                        v, 1.0 / cfg_keys[i].scale);
        if (!param_in_range(cfg_keys[i].id, (uint16_t)floor(scaled + 0.5)))
            return scn_fail(c, line, key, "%g refused by the firmware (a valve cal's last digit, the dead band, is 1-9)", v);
        s->param[cfg_keys[i].id] = (uint16_t)floor(scaled + 0.5);
        at->cfg[cfg_keys[i].id] = line;
    }
    return 0;
}

int scn_plant_key(const scn_ctx_t *c, scenario_t *s, int line, const char *key, const char *val)
{
    size_t i;
    double v;
    for (i = 0; i < N_PLANT; i++)
        if (strcmp(key, plant_keys[i].key) == 0)
            break;
    if (i == N_PLANT)
        return scn_fail(c, line, key, "unknown key in [plant]");
    if (parse_num(val, &v) < 0)
        return scn_fail(c, line, key, "'%s' is not a number", val);
    if (v < plant_keys[i].lo || v > plant_keys[i].hi)
        return scn_fail(c, line, key, "%g out of range %g..%g", v, plant_keys[i].lo, plant_keys[i].hi);
    if (plant_keys[i].isint && !scn_is_whole(v))
        return scn_fail(c, line, key, "%g is not a whole number", v);
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

int scn_drive_row(const scn_ctx_t *c, scenario_t *s, int line, char *row)
{
    char *w[4];
    double t, v;
    int n = words(row, w);
    if (n != 2)
        return scn_fail(c, line, "drive", "a row is 'time_s speed_kmh' (%d words here)", n);
    if (parse_num(w[0], &t) < 0)
        return scn_fail(c, line, "drive", "time '%s' is not a number", w[0]);
    if (parse_num(w[1], &v) < 0)
        return scn_fail(c, line, "drive", "speed '%s' is not a number", w[1]);
    if (t < 0)
        return scn_fail(c, line, "drive", "time %g is negative", t);
    if (s->n_drive > 0 && t < s->drive[s->n_drive - 1].t_s)
        return scn_fail(c, line, "drive", "time goes backwards (%g after %g)", t, s->drive[s->n_drive - 1].t_s);
    if (v < 0 || v > 60)
        return scn_fail(c, line, "drive", "speed %g out of range 0..60 km/h", v);
    if (s->n_drive >= SCN_MAX_DRIVE)
        return scn_fail(c, line, "drive", "more than %d rows", SCN_MAX_DRIVE);
    s->drive[s->n_drive].t_s = t;
    s->drive[s->n_drive].kmh = v;
    s->n_drive++;
    return 0;
}

int scn_event_row(const scn_ctx_t *c, scenario_t *s, int line, char *row)
{
    char *w[4];
    double t, v = 0;
    int n = words(row, w), k;
    if (n < 2 || n > 3)
        return scn_fail(c, line, "events", "a row is 'time_s event [value]' (%d words here)", n);
    if (parse_num(w[0], &t) < 0)
        return scn_fail(c, line, "events", "time '%s' is not a number", w[0]);
    for (k = 0; k < EV_COUNT; k++)
        if (strcmp(w[1], scenario_event_name(k)) == 0)
            break;
    if (k == EV_COUNT)
        return scn_fail(c, line, w[1], "unknown event");
    if (t < 0)
        return scn_fail(c, line, w[1], "time %g is negative", t);
    if (s->n_events > 0 && t < s->events[s->n_events - 1].t_s)
        return scn_fail(c, line, w[1], "time goes backwards (%g after %g)", t, s->events[s->n_events - 1].t_s);
    if (scenario_event_takes_value(k) && n != 3)
        return scn_fail(c, line, w[1], "needs a value");
    if (!scenario_event_takes_value(k) && n != 2)
        return scn_fail(c, line, w[1], "takes no value ('%s' given)", w[2]);
    if (n == 3 && parse_num(w[2], &v) < 0)
        return scn_fail(c, line, w[1], "value '%s' is not a number", w[2]);
    if (s->n_events >= SCN_MAX_EVENTS)
        return scn_fail(c, line, w[1], "more than %d events", SCN_MAX_EVENTS);
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
int scn_text_event_row(const scn_ctx_t *c, scenario_t *s, int line, char *row, int *rc)
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
    text = scn_trim(text);
    {
        char msg[200];
        if (parse_num(w[0], &t) < 0)
            *rc = scn_fail(c, line, "events", "time '%s' is not a number", w[0]);
        else if (t < 0)
            *rc = scn_fail(c, line, w[1], "time %g is negative", t);
        else if (s->n_events > 0 && t < s->events[s->n_events - 1].t_s)
            *rc = scn_fail(c, line, w[1], "time goes backwards (%g after %g)", t, s->events[s->n_events - 1].t_s);
        else if (scenario_event_text_check(k, text, msg, sizeof msg) < 0)
            *rc = scn_fail(c, line, w[1], "%s", msg);
        else if (s->n_events >= SCN_MAX_EVENTS)
            *rc = scn_fail(c, line, w[1], "more than %d events", SCN_MAX_EVENTS);
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
int scn_cross_fail(const scn_ctx_t *c, const scn_lines_t *at, uint8_t why)
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
            return scn_fail(c, line, cfg_keys[i].key, "the firmware refuses this value with the others: %s",
                        param_why_text(why));
    return scn_fail(c, 0, "[config]", "the firmware refuses this set of values: %s", param_why_text(why));
}

/* scenario.c: the strict reader of scenario files: every error names file, line and key, and nothing half-read runs. */
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <ctype.h>
#include "scenario.h"
#include "scenario_int.h"

/* "file:line: key 'k': what is wrong" into c->err, every byte a file may hold that does not
 * print (control codes, bytes past ASCII) written as \xHH, so no terminal shows it raw */
int scn_fail(const scn_ctx_t *c, int line, const char *key, const char *fmt, ...)
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

char *scn_trim(char *s)
{
    char *e;
    while (*s && isspace((unsigned char)*s))
        s++;
    e = s + strlen(s);
    while (e > s && isspace((unsigned char)e[-1]))
        *--e = 0;
    return s;
}

/* Checks that need the whole file: the boom's sections, the tank, the events' values, a drive. */
static int check_whole(const scn_ctx_t *c, scenario_t *s, const scn_lines_t *at)
{
    int noz = s->param[P_NOZZLES], sec = s->param[P_SECTIONS], i;
    if (noz % sec != 0)
        return scn_fail(c, at->nozzles, at->nozzles_key,
                    "%d nozzles do not split evenly over %d sections", noz, sec);
    if (s->plant.tank_start_l > s->plant.tank_l)
        return scn_fail(c, at->tank, at->tank_key, "tank_start_l %g L is more than the tank holds (tank_l %g)",
                    s->plant.tank_start_l, s->plant.tank_l);
    if (s->plant.valve_running_duty > s->plant.valve_stiction_duty)
        return scn_fail(c, at->duty, at->duty_key, "running duty %g is above the break-away duty %g "
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
            return scn_cross_fail(c, at, why);
    }
    for (i = 0; i < s->n_events; i++) {
        const scn_event_t *e = &s->events[i];
        char msg[200];
        if (e->t_s > s->duration_s)
            return scn_fail(c, e->line, scenario_event_name(e->kind), "at %g s, after the end of the run (duration_s %g)",
                        e->t_s, s->duration_s);
        if (scenario_event_check(s, e->kind, e->value, msg, sizeof msg) < 0)
            return scn_fail(c, e->line, scenario_event_name(e->kind), "%s", msg);
    }
    /* nothing to run without a driver: an empty file, or a [drive] without rows, is a mistake */
    if (s->n_drive == 0)
        return scn_fail(c, at->drive, "[drive]", at->drive ? "no rows: a run needs at least one 'time_s speed_kmh'"
                    : "missing: a run needs a [drive] section with at least one 'time_s speed_kmh' row");
    s->plant.nozzles = noz;
    s->plant.spacing_m = s->param[P_SPACING] / 100.0;
    return 0;
}

/* ---- the lines -------------------------------------------------------------------------------- */
enum { SEC_NONE, SEC_RUN, SEC_CONFIG, SEC_PLANT, SEC_DRIVE, SEC_EVENTS };
static const char *const sec_names[] = {"", "run", "config", "plant", "drive", "events"};

#define MAX_KEYS 64
/* the reader's state from line to line */
typedef struct {
    scn_ctx_t c;
    scenario_t *s;                  /* what the file sets so far */
    int line, sec;                  /* the line read, its section (SEC_*) */
    int sec_seen[6];
    struct { int sec; char key[40]; } seen[MAX_KEYS];   /* the keys given so far */
    int n_seen;
    scn_lines_t at;
} reader_t;

/* a section header `[name]` */
static int header(reader_t *r, char *s)
{
    char *close = strchr(s, ']');
    int k;
    if (!close || close[1])
        return scn_fail(&r->c, r->line, s, "a section header is '[name]' alone on its line");
    *close = 0;
    for (k = 1; k <= SEC_EVENTS; k++)
        if (strcmp(scn_trim(s + 1), sec_names[k]) == 0)
            break;
    if (k > SEC_EVENTS)
        return scn_fail(&r->c, r->line, s + 1, "unknown section (run, config, plant, drive, events)");
    if (r->sec_seen[k])
        return scn_fail(&r->c, r->line, s + 1, "section given twice");
    r->sec_seen[k] = 1;
    r->sec = k;
    if (r->sec == SEC_DRIVE)
        r->at.drive = r->line;
    return 0;
}

/* the line of the later of two keys a whole-file check compares, and which it was */
static void later(reader_t *r, const char *key, const char *a, const char *b, int *line, const char **which)
{
    if (strcmp(key, a) == 0 || strcmp(key, b) == 0) {
        *line = r->line;
        *which = strcmp(key, a) == 0 ? a : b;
    }
}

/* a `key = value` of [run], [config] or [plant], each key once a section */
static int key_value(reader_t *r, char *s)
{
    char *eq = strchr(s, '='), *key, *val;
    int i, rc;
    if (!eq)
        return scn_fail(&r->c, r->line, s, "expected 'key = value'");
    *eq = 0;
    key = scn_trim(s);
    val = scn_trim(eq + 1);
    if (!*key)
        return scn_fail(&r->c, r->line, "", "a value without a key");
    if (!*val)
        return scn_fail(&r->c, r->line, key, "missing value");
    for (i = 0; i < r->n_seen; i++)
        if (r->seen[i].sec == r->sec && strcmp(r->seen[i].key, key) == 0)
            return scn_fail(&r->c, r->line, key, "given twice in [%s]", sec_names[r->sec]);
    if (r->n_seen < MAX_KEYS && strlen(key) < sizeof r->seen[0].key) {
        r->seen[r->n_seen].sec = r->sec;
        strcpy(r->seen[r->n_seen].key, key);
        r->n_seen++;
    }
    if (r->sec == SEC_RUN)
        return scn_run_key(&r->c, r->s, r->line, key, val);
    if (r->sec == SEC_CONFIG) {
        rc = scn_config_key(&r->c, r->s, r->line, key, val, &r->at);
        later(r, key, "nozzles", "sections", &r->at.nozzles, &r->at.nozzles_key);
        return rc;
    }
    rc = scn_plant_key(&r->c, r->s, r->line, key, val);
    later(r, key, "tank_l", "tank_start_l", &r->at.tank, &r->at.tank_key);
    later(r, key, "valve_running_duty", "valve_stiction_duty", &r->at.duty, &r->at.duty_key);
    return rc;
}

/* one line of the file (its end cut off): 0, or scn_fail's -1 */
static int one_line(reader_t *r, char *s)
{
    char *hash;
    int rc = 0;
    if (r->sec == SEC_EVENTS && scn_text_event_row(&r->c, r->s, r->line, scn_trim(s), &rc))
        return rc;
    hash = strchr(s, '#');
    if (hash)
        *hash = 0;
    s = scn_trim(s);
    if (!*s)
        return 0;
    if (*s == '[')
        return header(r, s);
    if (r->sec == SEC_NONE)
        return scn_fail(&r->c, r->line, s, "comes before any [section]");
    if (r->sec == SEC_DRIVE)
        return scn_drive_row(&r->c, r->s, r->line, s);
    if (r->sec == SEC_EVENTS)
        return scn_event_row(&r->c, r->s, r->line, s);
    return key_value(r, s);
}

int scenario_parse(scenario_t *out, const char *text, const char *name, char *err, size_t errlen)
{
    static scenario_t tmp;          /* large: built aside, copied to out only when all is well */
    reader_t r;
    int rc = 0;
    size_t len = strlen(text);
    char *buf, *p;

    memset(&r, 0, sizeof r);
    r.c.name = name ? name : "scenario";
    r.c.err = err;
    r.c.errlen = errlen;
    r.s = &tmp;
    r.sec = SEC_NONE;
    if (err && errlen)
        err[0] = 0;
    r.at.nozzles_key = "nozzles";
    r.at.tank_key = "tank_start_l";
    r.at.duty_key = "valve_running_duty";
    scenario_default(&tmp, r.c.name);
    buf = malloc(len + 1);
    if (!buf)
        return scn_fail(&r.c, 0, "-", "out of memory");
    memcpy(buf, text, len + 1);
    if ((unsigned char)buf[0] == 0xEF && (unsigned char)buf[1] == 0xBB && (unsigned char)buf[2] == 0xBF)
        memmove(buf, buf + 3, len - 2);     /* a UTF-8 byte order mark (editors on Windows) */
    for (p = buf; rc == 0 && p && *p;) {
        char *nl = strchr(p, '\n'), *s = p;
        if (nl)
            *nl = 0;
        r.line++;
        p = nl ? nl + 1 : NULL;
        rc = one_line(&r, s);
    }
    free(buf);
    if (rc == 0)
        rc = check_whole(&r.c, &tmp, &r.at);
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

/* scenario_int.h: what the scenario reader's files share: the error's context, the lines the whole-file checks name, the sections' key and row readers. */
#ifndef SIM_SCENARIO_INT_H
#define SIM_SCENARIO_INT_H

#include <stddef.h>
#include <stdint.h>
#include "scenario.h"

/* the file being read, and where its first error goes */
typedef struct {
    const char *name;
    char *err;
    size_t errlen;
} scn_ctx_t;

/* where the whole-file checks find the keys they name: the line of each [config] value given,
 * the later of two keys a check compares (and which it was), the [drive] header */
typedef struct {
    int cfg[P_COUNT];
    int nozzles, tank, duty, drive;
    const char *nozzles_key, *tank_key, *duty_key;
} scn_lines_t;

/* "file:line: key 'k': what is wrong" into c->err, every byte a file may hold that does not
 * print (control codes, bytes past ASCII) written as \xHH, so no terminal shows it raw; -1 */
int scn_fail(const scn_ctx_t *c, int line, const char *key, const char *fmt, ...);
/* s without its leading and trailing white space (cut in place) */
char *scn_trim(char *s);
/* v is a whole number (to a relative 1e-9) */
int scn_is_whole(double v);

/* One `key = value` of [run], [config] (its line into at) or [plant]: 0, or scn_fail's -1. */
int scn_run_key(const scn_ctx_t *c, scenario_t *s, int line, const char *key, const char *val);
int scn_config_key(const scn_ctx_t *c, scenario_t *s, int line, const char *key, const char *val, scn_lines_t *at);
int scn_plant_key(const scn_ctx_t *c, scenario_t *s, int line, const char *key, const char *val);
/* One row of [drive] or [events]: 0, or scn_fail's -1. */
int scn_drive_row(const scn_ctx_t *c, scenario_t *s, int line, char *row);
int scn_event_row(const scn_ctx_t *c, scenario_t *s, int line, char *row);
/* A key or serial row of [events], read before comments are cut: 1 when the row is one (*rc
 * says how it went), 0 when it is another event's. */
int scn_text_event_row(const scn_ctx_t *c, scenario_t *s, int line, char *row, int *rc);
/* The error of a firmware cross-check (params.h PARAM_X_*) the [config] set breaks, named by
 * the latest line that gave one of its values. */
int scn_cross_fail(const scn_ctx_t *c, const scn_lines_t *at, uint8_t why);

#endif

/* fuzz_scenario.c: the scenario reader (sim/scenario.c) on any text: refused with a located, printable message, or read whole and valid. */
#include <string.h>
#include "fuzz.h"
#include "scenario.h"
#include "params.h"

static scenario_t *scn;             /* large (the drive table): once, on the heap */

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char err[256], *text;
    int rc, i;
    if (size > 65536)
        return 0;
    if (!scn && !(scn = malloc(sizeof *scn)))
        abort();
    text = malloc(size + 1);
    if (!text)
        abort();
    memcpy(text, data, size);
    text[size] = 0;
    memset(err, 'x', sizeof err);
    rc = scenario_parse(scn, text, "fuzz.scn", err, sizeof err);
    free(text);
    FUZZ_CHECK(rc == 0 || rc == -1, "rc %d", rc);
    FUZZ_CHECK(memchr(err, 0, sizeof err) != NULL, "message not terminated");
    if (rc < 0) {
        FUZZ_CHECK(strncmp(err, "fuzz.scn:", 9) == 0, "message without the file: '%s'", err);
        for (i = 0; err[i]; i++)
            FUZZ_CHECK((unsigned char)err[i] >= 0x20 && (unsigned char)err[i] < 0x7F,
                       "message holds byte 0x%02X at %d", (unsigned char)err[i], i);
        return 0;
    }
    FUZZ_CHECK(scn->n_drive >= 1, "read without a drive row");
    /* read: everything the simulator relies on holds */
    FUZZ_CHECK(scn->duration_s > 0 && scn->duration_s < 1e9, "duration %g", scn->duration_s);
    for (i = 0; i < P_COUNT; i++)
        FUZZ_CHECK(param_in_range((uint8_t)i, scn->param[i]), "param %d = %u", i, scn->param[i]);
    FUZZ_CHECK(scn->n_drive >= 0 && scn->n_drive <= SCN_MAX_DRIVE, "n_drive %d", scn->n_drive);
    FUZZ_CHECK(scn->n_events >= 0 && scn->n_events <= SCN_MAX_EVENTS, "n_events %d", scn->n_events);
    for (i = 0; i < scn->n_drive; i++) {
        FUZZ_CHECK(scn->drive[i].t_s >= 0 && scn->drive[i].kmh >= 0, "drive row %d", i);
        FUZZ_CHECK(i == 0 || scn->drive[i].t_s >= scn->drive[i - 1].t_s, "drive time backwards at %d", i);
    }
    for (i = 0; i < scn->n_events; i++) {
        FUZZ_CHECK(scn->events[i].kind >= 0 && scn->events[i].kind < EV_COUNT, "event kind");
        FUZZ_CHECK(i == 0 || scn->events[i].t_s >= scn->events[i - 1].t_s, "event time backwards at %d", i);
        FUZZ_CHECK(scenario_event_check(scn, scn->events[i].kind, scn->events[i].value, NULL, 0) == 0,
                   "event %d (line %d) accepted but invalid", i, scn->events[i].line);
    }
    FUZZ_CHECK(scenario_nozzles_per_section(scn) > 0, "nozzles per section");
    for (i = 0; i < 8; i++) {
        double t = scn->duration_s * i / 7.0, v = scenario_drive_kmh(scn, t);
        FUZZ_CHECK(v == v && v >= 0 && v < 1000, "drive at %g s: %g", t, v);
    }
    return 0;
}

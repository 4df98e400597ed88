/* console_choice.c: the names of the settings chosen by name, in the order of their values. */
#if defined(__SDCC)
#pragma stackauto           /* locals on the stack, not each its own XRAM (docs/MEMORY.md) */
#endif
#include "hal.h"
#include "params.h"
#include "ctl.h"
#include "console_int.h"

/* The settings chosen by name (besides Control, named by ctl.h): each one's names in the
 * order of its values, from choice_first[k] in choice_names */
static const __code uint8_t choice_ids[] = {P_MODE, P_LOG_UNIT, P_PRESET, P_UNITS, P_REMOTE
#if FW_PGN
    , P_SPEED_SRC, P_AOG_SECT       /* and Remote's AgOpenGPS */
#endif
};
static const __code uint8_t choice_first[] = {0, 2, 4, 6, 9
#if FW_PGN
    , 13, 16
#endif
};
static const __code char *const __code choice_names[] = {
    "Auto", "Manual", "m", "s", "Rate 1", "Rate 2", "Metric", "US", "Turf", "off", "Raven 9600", "Raven 1200",
#if FW_PGN
    "AgOpenGPS", "wheel", "GPS", "both", "switches", "frames",
#endif
};

/* id's row in choice_ids, sizeof choice_ids when it has none */
static uint8_t choice_row(uint8_t id) __reentrant
{
    uint8_t k;
    for (k = 0; k < sizeof choice_ids && choice_ids[k] != id; k++)
        ;
    return k;
}

uint8_t con_is_choice(uint8_t id)
{
    return id == P_CONTROLLER || choice_row(id) < sizeof choice_ids;
}

const __code char *con_choice_name(uint8_t id, uint16_t v)
{
    uint8_t k = choice_row(id);
    return k < sizeof choice_ids ? choice_names[choice_first[k] + v] : ctl_name((uint8_t)v);
}

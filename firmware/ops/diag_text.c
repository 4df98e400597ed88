/* diag_text.c: the alarms' codes (the serial link's) and texts (the display's), by alarm bit. */
#include "hal.h"
#include "diag.h"

#define DIAG_AL_CODE(bit, code, text) code,
#define DIAG_AL_TEXT(bit, code, text) text,
static const char __code *const __code codes[AL_COUNT] = { DIAG_ALARMS(DIAG_AL_CODE) };
static const char __code *const __code texts[AL_COUNT] = { DIAG_ALARMS(DIAG_AL_TEXT) };
#undef DIAG_AL_CODE
#undef DIAG_AL_TEXT

const __code char *diag_code(uint8_t bit) __reentrant
{
    return bit < AL_COUNT ? codes[bit] : "";
}

const __code char *diag_text(uint8_t bit) __reentrant
{
    return bit < AL_COUNT ? texts[bit] : "";
}

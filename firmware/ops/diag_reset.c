/* diag_reset.c: the reset cause as the serial link's BOOT word and an LCD line. */
#include "hal.h"
#include "diag.h"

/* the reset cause (hal.h HAL_RESET_*): a word for the serial link, a line for the LCD */
static const char __code *const __code reset_codes[] = {"POWER", "WATCHDOG", "BROWNOUT", "PIN"};
static const char __code *const __code reset_texts[] = {
    "Reset: power-on", "Reset: watchdog", "Reset:brown-out", "Reset: reset pin"
};

const __code char *diag_reset_code(void)
{
    uint8_t c = hal_reset_cause();
    return c <= HAL_RESET_OTHER ? reset_codes[c] : "?";
}

const __code char *diag_reset_text(void)
{
    uint8_t c = hal_reset_cause();
    return c <= HAL_RESET_OTHER ? reset_texts[c] : "Reset: ?";
}

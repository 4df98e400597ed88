/* wdt.c: the watchdog, the reset cause and the supply's low-voltage detector. */
#include <stc12.h>
#include "hal.h"
#include "stc12_int.h"

/* ---- supply: the low-voltage detector's flag (PCON.LVDF) ------------------------------------ */

/* The flag latches a dip below the threshold since it was last cleared: clear it, give the
 * detector a few microseconds, and read it again. */
uint8_t hal_supply_low(void)
{
    uint8_t i;
    PCON &= (unsigned char)~PCON_LVDF;
    for (i = 0; i < 40; i++)
        NOP();
    return (PCON & PCON_LVDF) ? 1 : 0;
}

/* ---- watchdog: prescaler 32 -> 12 * 32 * 32768 / 11059200 = 1.14 s ------------------------ */
void hal_wdt_kick(void)
{
    WDT_CONTR = 0x34;               /* EN_WDT | CLR_WDT | PS = 4 (writes WDT_FLAG 0) */
}

/* ---- the reset cause, read once before anything clears the flags -------------------------- */
static uint8_t reset_cause;

uint8_t hal_reset_cause(void)
{
    return reset_cause;
}

/* WDT_FLAG: the watchdog overflowed; POF: the supply came up from off; LVDF without POF: the
 * supply fell below the low-voltage threshold since power-on and the chip reset (brown-out);
 * none of them: the reset pin or a software reset. Then all three cleared for the next one. */
void reset_cause_read(void)
{
    if (WDT_CONTR & 0x80)
        reset_cause = HAL_RESET_WATCHDOG;
    else if (PCON & PCON_POF)
        reset_cause = HAL_RESET_POWER;
    else if (PCON & PCON_LVDF)
        reset_cause = HAL_RESET_BROWNOUT;
    else
        reset_cause = HAL_RESET_OTHER;
    WDT_CONTR = 0x34;
    PCON &= (unsigned char)~(PCON_POF | PCON_LVDF);
}

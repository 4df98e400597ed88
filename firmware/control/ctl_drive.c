/* ctl_drive.c: what every controller's output takes: the error clamp, du to drive (ctl_int.h). */
#if defined(__SDCC)
#pragma stackauto           /* locals on the stack, not each its own XRAM (docs/MEMORY.md) */
#endif
#include "ctl_int.h"

int16_t ctl_clamp_e(int16_t e)
{
    if (e > CTL_E_MAX)
        return CTL_E_MAX;
    if (e < -CTL_E_MAX)
        return -CTL_E_MAX;
    return e;
}

int32_t ctl_du_to_drive(int32_t du)
{
    int16_t s4 = fx_sat16((du + 128) >> 8);        /* du in Q4 */
    return (MUL(s4, ctl_kf) + 128) >> 8;
}

/* ffmap_learnt.c: what ffmap learnt of the valve (ctl_int.h ffmap_state_t's learnt bytes): restored at power-up, forgotten when the valve is told anew, saved byte by byte. */
#include "ctl_int.h"
#include "store.h"

/* the state: at a fixed address (no pointer to load) */
#define M (&ctl_st.fm)

void ffmap_init(void)
{
    uint8_t i;
    M->dir = 0;
    M->stall_flow = 0;
    M->brk_age = 0;
    M->rev_age = 255;
    M->moved = 0;
    /* what was learnt of this valve before: the EEPROM's record (CRC-checked, written by this
     * firmware) or, without one, 0xFF bytes */
    for (i = 0; i < STORE_LEARN_CTL; i++)
        ((uint8_t *)&M->gain)[i] = store_learnt(i);
    if (M->gain <= 0)
        ffmap_forget();
    M->slow_n = 0;
    M->ff_run = 0;
    M->cap = 255;
    /* (the errors, the deadband, the start's counters: the first step sets them, ctl_first) */
}

void ffmap_forget(void)
{
    M->brk_extra = 0;
    M->brk_age = 0;
    M->gain = FFMAP_G_INIT;
    M->rev_min = FFMAP_REV_MIN;
    M->ff_gain = 0;
    M->cap = 255;
}

uint8_t ffmap_learnt_byte(uint8_t i) __reentrant
{
    return ((const uint8_t *)&M->gain)[i];
}

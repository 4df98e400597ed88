/* ffmap_learnt.c: what ffmap learnt of the valve (ctl_int.h ffmap_state_t's learnt bytes): restored at power-up, forgotten when the valve is told anew, saved byte by byte. */
#include "ctl_int.h"
#include "store.h"
#include "params.h"


void ffmap_init(void)
{
    uint8_t i;
    ctl_st.fm.dir = 0;
    ctl_st.fm.stall_flow = 0;
    ctl_st.fm.brk_age = 0;
    ctl_st.fm.rev_age = 255;
    ctl_st.fm.moved = 0;
    ctl_st.fm.lone_n = 0;
    /* what was learnt of this valve before: the EEPROM's record (CRC-checked, written by this
     * firmware) or, without one, 0xFF bytes */
    for (i = 0; i < STORE_LEARN_CTL; i++)
        ((uint8_t *)&ctl_st.fm.gain)[i] = store_learnt(i);
    if (ctl_st.fm.gain <= 0)
        ffmap_forget();
    ctl_st.fm.slow_n = 0;
    ctl_st.fm.ff_run = 0;
    ctl_st.fm.cap = 255;
    /* (the errors, the deadband, the start's counters: the first step sets them, ctl_first) */
}

/* The reversal's threshold a valve starts with: 3/4 of the backlash the valve was told, as motion
 * (Backlash x Valve time in periods: 20 x 40 x 24.58 = 19,662 for the defaults), within
 * FFMAP_REV_LOW .. FFMAP_REV_MIN. A fast valve told its stroke time takes up its backlash in less
 * motion: 0.26 of a period at full duty for 1.7 s, against 0.6 for 4 s, whose reversal was worth
 * 3.5 % of the stroke, a swing of +-13 % of the flow at each one until cycles had learnt it down. */
static int16_t ffmap_rev_told(void)
{
    uint32_t r = UMUL(param_v[P_VALVE_SLACK] * param_v[P_VALVE_TRAVEL], 3146u) >> 7;
    return r > FFMAP_REV_MIN ? FFMAP_REV_MIN : r < FFMAP_REV_LOW ? FFMAP_REV_LOW : (int16_t)r;
}

void ffmap_forget(void)
{
    ctl_st.fm.brk_extra = 0;
    ctl_st.fm.brk_age = 0;
    ctl_st.fm.gain = FFMAP_G_INIT;
    ctl_st.fm.rev_min = ffmap_rev_told();
    ctl_st.fm.ff_gain = 0;
    ctl_st.fm.cap = 255;
}

uint8_t ffmap_learnt_byte(uint8_t i) __reentrant
{
    return ((const uint8_t *)&ctl_st.fm.gain)[i];
}

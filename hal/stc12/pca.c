/* pca.c: the PCA counter at SYSCLK/12 as a 32-bit time, the flow meter's captures (module 0) and
 * the wheel's INT0 time stamps. */
#include <stc12.h>
#include "hal.h"
#include "stc12_int.h"
#include "isr.h"

/* ---- PCA: counter at SYSCLK/12, extended to 32 bits by its overflow count ----------------- */
#define PCA_CH CH
#define PCA_CL CL
#define PCA_CF CF
#define PCA_CF_CLEAR() do { CF = 0; } while (0)
#define PCA_IRQ_STATE uint8_t
#define PCA_IRQ_OFF IRQ_OFF
#define PCA_IRQ_RESTORE IRQ_RESTORE
#include "pca_clock.h"

void stc12_pca_isr(void) __interrupt(7)
{
    uint16_t cap = (uint16_t)CCAP0H << 8 | CCAP0L;
    uint8_t captured = CCF0;
    CCF0 = 0;
    PCA_ISR_WORK(captured, cap);
}

uint32_t hal_pca_now(void)
{
    uint32_t t;
    uint8_t ea;
#if FW_HIL
    if (stc12_hil)
        return stc12_hil->pca_now;
#endif
    IRQ_OFF(ea);
    t = pca_read();
    IRQ_RESTORE(ea);
    return t;
}

void stc12_int0_isr(void) __interrupt(0)
{
    WHEEL_ISR_WORK();
}

void hal_wheel_min_interval(uint32_t min_ticks) __reentrant
{
    uint8_t ea;
#if FW_HIL
    if (stc12_hil) {
        stc12_hil->wheel_min = min_ticks;
        return;
    }
#endif
    IRQ_OFF(ea);
    wheel_min = min_ticks;
    IRQ_RESTORE(ea);
}

#if FW_HIL
/* a frame's capture, taken: the next take sees only the next frame's */
static void hil_take(hal_capture_t __xdata *f, __idata hal_capture_t *c)
{
    c->count = f->count;
    c->last = f->last;
    c->rejected = f->rejected;
    f->count = 0;
    f->rejected = 0;
}
#endif

void hal_flow_capture_take(__idata hal_capture_t *c) __reentrant
{
    uint8_t ea;
#if FW_HIL
    if (stc12_hil) {
        hil_take(&stc12_hil->meter, c);
        return;
    }
#endif
    IRQ_OFF(ea);
    c->count = flow_count;
    c->last = flow_last;
    c->rejected = 0;
    flow_count = 0;
    IRQ_RESTORE(ea);
}

void hal_wheel_capture_take(__idata hal_capture_t *c) __reentrant
{
    uint8_t ea;
#if FW_HIL
    if (stc12_hil) {
        hil_take(&stc12_hil->wheel, c);
        return;
    }
#endif
    IRQ_OFF(ea);
    c->count = wheel_count;
    c->last = wheel_last;
    c->rejected = wheel_rejected;
    wheel_count = 0;
    wheel_rejected = 0;
    IRQ_RESTORE(ea);
}

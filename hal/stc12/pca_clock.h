/* pca_clock.h: the 32-bit PCA time and the pulse time stamps, shared by the STC12 backend and its host test. */
#ifndef PCA_CLOCK_H
#define PCA_CLOCK_H

/*
 * The includer defines how to reach the hardware (hal/stc12/pca.c: the SFRs; the host test
 * tests/hal/test_pca_clock.c: a model of the counter with interrupts it can inject):
 *   PCA_CH, PCA_CL   the counter's bytes        PCA_CF, PCA_CF_CLEAR()  its overflow flag
 *   PCA_IRQ_OFF(s)   s = interrupts on?, all off    PCA_IRQ_RESTORE(s)  back as they were
 *   PCA_IRQ_STATE    the type of s
 *   PCA_PREEMPT()    nothing on the chip: the points where the host test lets an interrupt in
 *
 * The race this layout closes: the PCA interrupt (high priority) preempts INT0 (low). Both
 * used to extend a 16-bit reading through one function that SDCC makes non-reentrant (its
 * arguments in fixed XRAM), and INT0 read the counter, the flag and the overflow count with
 * interrupts on: a PCA overflow served between the flag and the count added a second 65536
 * ticks (+71 ms), a meter capture between the arguments and their use gave the wheel the
 * meter's time. Now every reading and its extension happen with interrupts off (the
 * extension is a macro, nothing shared), and the handlers' critical sections nest.
 */
#ifndef PCA_PREEMPT
#define PCA_PREEMPT()
#endif

/* 32-bit time of a 16-bit reading lo taken while the overflow flag read cf, hi overflows
 * counted: a reading in the lower half with an overflow still pending came after it. */
#define PCA_EXTEND(hi, lo, cf) \
    ((uint32_t)(uint16_t)((hi) + (((cf) && (uint16_t)(lo) < 0x8000u) ? 1u : 0u)) << 16 | (uint16_t)(lo))

static volatile uint16_t pca_hi;    /* overflows of the 16-bit PCA counter */
static volatile uint16_t flow_count;
static volatile uint32_t flow_last;
static volatile uint16_t wheel_count;
static volatile uint32_t wheel_last;
static volatile uint32_t wheel_min;     /* hal_wheel_min_interval: sooner is not a pulse */
static volatile uint8_t wheel_rejected;

/* PCA time now; the caller has interrupts off. (The reading one 16-bit value: SDCC keeps it
 * in registers, where two bytes took a byte of XRAM each.) */
static uint32_t pca_read(void)
{
    uint16_t t;
    uint8_t cf;
    do {
        t = (uint16_t)PCA_CH << 8;
        PCA_PREEMPT();
        t |= PCA_CL;
        PCA_PREEMPT();
        cf = PCA_CF;
        PCA_PREEMPT();
    } while ((uint8_t)(t >> 8) != PCA_CH);
    PCA_PREEMPT();
    return PCA_EXTEND(pca_hi, t, cf);
}

/* The PCA interrupt's work: a meter capture (its 16-bit latch cap) and the overflow count. A
 * macro, as INT0's below: no call, and no parameters in XRAM. */
#define PCA_ISR_WORK(captured, cap) do {                                        \
        if (captured) {                                                         \
            flow_last = PCA_EXTEND(pca_hi, (cap), PCA_CF);                      \
            flow_count++;                                                       \
        }                                                                       \
        if (PCA_CF) {                                                           \
            PCA_CF_CLEAR();                                                     \
            pca_hi++;                                                           \
        }                                                                       \
    } while (0)

/* INT0's work: time-stamp a wheel pulse, or drop an edge too early to be one (bounce,
 * interference). Interrupts stay off from the first counter read to the stored stamp, so
 * neither the overflow count nor the flag can change under it. A macro, so the handler
 * calls no deeper than pca_read (the stack has no byte to spare). */
#define WHEEL_ISR_WORK() do {                                                   \
        PCA_IRQ_STATE ea_;                                                      \
        uint32_t t_;                                                            \
        PCA_IRQ_OFF(ea_);                                                       \
        t_ = pca_read();                                                        \
        if (t_ - wheel_last < wheel_min) {                                      \
            if (wheel_rejected != 255)                                          \
                wheel_rejected++;                                               \
        } else {                                                                \
            wheel_last = t_;                                                    \
            wheel_count++;                                                      \
        }                                                                       \
        PCA_IRQ_RESTORE(ea_);                                                   \
    } while (0)

#endif

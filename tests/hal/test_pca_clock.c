/* test_pca_clock.c: the wheel's time stamp stays true when the PCA interrupt preempts INT0 at any point (the STC12 backend's own code, on a model counter). */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

/*
 * hal/stc12/pca_clock.h is the chip's code for the 32-bit PCA time and the two handlers'
 * work. Here it runs on a model: a 16-bit counter, its overflow flag, the global interrupt
 * enable, and the PCA interrupt, which the test raises at a chosen preemption point inside
 * INT0's work (a counter overflow, a meter capture, or both) and which is served at once
 * when interrupts are on, or when they come back on.
 */
static uint16_t m_cnt;              /* the PCA counter */
static uint8_t m_cf;                /* its overflow flag */
static uint8_t m_ea = 1;            /* interrupts enabled */
static unsigned m_point, m_fire_at; /* preemption points passed; where the event happens */
static uint8_t m_overflow, m_capture;   /* what happens there */
static uint8_t m_pending, m_captured;
static uint16_t m_cap;
static void (*m_isr)(uint8_t captured, uint16_t cap);   /* the PCA handler's work */

static void m_serve(void)
{
    if (m_pending && m_ea) {
        m_pending = 0;
        m_isr(m_captured, m_cap);
        m_captured = 0;
    }
}

static void m_point_hit(void)
{
    if (m_point++ == m_fire_at) {
        if (m_overflow) {
            m_cnt = 0x0001;         /* the counter wrapped since the last look */
            m_cf = 1;
        }
        if (m_capture) {
            m_captured = 1;
            m_cap = m_cnt;
        }
        m_pending = m_overflow || m_capture;
    }
    m_serve();
}

#define PCA_CH ((uint8_t)(m_cnt >> 8))
#define PCA_CL ((uint8_t)m_cnt)
#define PCA_CF m_cf
#define PCA_CF_CLEAR() (m_cf = 0)
#define PCA_IRQ_STATE uint8_t
#define PCA_IRQ_OFF(s) do { (s) = m_ea; m_ea = 0; } while (0)
#define PCA_IRQ_RESTORE(s) do { m_ea = (s); m_serve(); } while (0)
#define PCA_PREEMPT() m_point_hit()
#include "stc12/pca_clock.h"
static void wheel_isr_body(void) { WHEEL_ISR_WORK(); }
static void pca_isr_body(uint8_t captured, uint16_t cap) { PCA_ISR_WORK(captured, cap); }

/* The handler as it was before (INT0 read the counter with interrupts on), the same code
 * under other names: the model must find its race, or the test above proves nothing. */
#undef PCA_CLOCK_H
#undef PCA_IRQ_OFF
#undef PCA_IRQ_RESTORE
#define PCA_IRQ_OFF(s) do { (s) = m_ea; } while (0)
#define PCA_IRQ_RESTORE(s) do { (void)(s); m_serve(); } while (0)
#define pca_hi old_pca_hi
#define flow_count old_flow_count
#define flow_last old_flow_last
#define wheel_count old_wheel_count
#define wheel_last old_wheel_last
#define pca_read old_pca_read
#define pca_isr_body old_pca_isr_body
#define wheel_isr_body old_wheel_isr_body
#undef WHEEL_ISR_WORK
#undef PCA_ISR_WORK
#include "stc12/pca_clock.h"
static void wheel_isr_body(void) { WHEEL_ISR_WORK(); }
static void pca_isr_body(uint8_t captured, uint16_t cap) { PCA_ISR_WORK(captured, cap); }
#undef pca_hi
#undef flow_count
#undef flow_last
#undef wheel_count
#undef wheel_last
#undef pca_read
#undef pca_isr_body
#undef wheel_isr_body

#define HI0 0x1234u
#define BEFORE (((uint32_t)HI0 << 16) | 0xFFFEu)    /* the counter at INT0's entry */
#define AFTER (((uint32_t)(HI0 + 1u) << 16) | 0x0001u) /* and just after it wrapped */

static void arm(unsigned at, uint8_t overflow, uint8_t capture)
{
    m_cnt = 0xFFFE;
    m_cf = 0;
    m_ea = 1;
    m_point = 0;
    m_fire_at = at;
    m_overflow = overflow;
    m_capture = capture;
    m_pending = m_captured = 0;
}

/* a stamp is true when it is the time before or after the wrap, never 65536 ticks off */
static int stamp_true(uint32_t t)
{
    return t == BEFORE || t == AFTER;
}

/* the preemption points one run of a handler passes */
static unsigned points_of(void (*handler)(void))
{
    arm(1000, 0, 0);
    handler();
    return m_point;
}

static void test_pca_clock_wheel_stamp_is_true_whatever_preempts_it_and_where(void **state)
{
    (void)state;
    m_isr = pca_isr_body;
    unsigned n = points_of(wheel_isr_body);
    assert_true(n >= 4);
    for (unsigned at = 0; at < n; at++)
        for (int ev = 1; ev <= 3; ev++) {
            arm(at, ev & 1, (ev >> 1) & 1);
            pca_hi = HI0;
            wheel_count = flow_count = 0;
            wheel_isr_body();
            m_serve();              /* anything still pending runs once INT0 has returned */
            assert_int_equal(wheel_count, 1);
            assert_true(stamp_true(wheel_last));
            assert_int_equal(m_ea, 1);
            if (ev & 1) {           /* the overflow counted once, its flag cleared */
                assert_int_equal(pca_hi, HI0 + 1u);
                assert_int_equal(m_cf, 0);
            }
            if (ev & 2) {           /* the meter's capture stamped with its own time */
                assert_int_equal(flow_count, 1);
                assert_true(stamp_true(flow_last));
            }
        }
}

/* INT0's critical section nests: called with interrupts already off, it leaves them off */
static void test_pca_clock_critical_sections_nest(void **state)
{
    (void)state;
    m_isr = pca_isr_body;
    arm(100, 0, 0);
    m_ea = 0;
    wheel_isr_body();
    assert_int_equal(m_ea, 0);
    m_ea = 1;
}

static void test_pca_clock_the_model_finds_the_old_race(void **state)
{
    (void)state;
    m_isr = old_pca_isr_body;
    int wrong = 0;
    unsigned n = points_of(old_wheel_isr_body);
    for (unsigned at = 0; at < n; at++) {
        arm(at, 1, 0);
        old_pca_hi = HI0;
        old_wheel_isr_body();
        m_serve();
        if (!stamp_true(old_wheel_last)) {
            /* 65536 ticks (71 ms) ahead: the overflow counted twice */
            assert_true(old_wheel_last - BEFORE == 0x10000u || old_wheel_last - AFTER == 0x10000u);
            wrong++;
        }
    }
    assert_true(wrong > 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pca_clock_wheel_stamp_is_true_whatever_preempts_it_and_where),
        cmocka_unit_test(test_pca_clock_critical_sections_nest),
        cmocka_unit_test(test_pca_clock_the_model_finds_the_old_race),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

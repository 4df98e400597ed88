/* test_ops.c: what ops owns: the status block's reset, the jog the control step takes a period at a time, the alarms raised and acknowledged, the buzzer. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <string.h>
#include <cmocka.h>
#include "hal_host.h"
#include "params.h"
#include "ops.h"
#include "diag.h"

static int setup(void **state)
{
    (void)state;
    hal_host_reset();
    params_defaults();
    diag_init();
    ops_init();
    return 0;
}

/* every byte of the block cleared, whatever a run before left there */
static void test_ops_init_clears_the_status(void **state)
{
    static const app_status_t zero;
    (void)state;
    memset(&app_status, 0xA5, sizeof app_status);
    ops_init();
    assert_memory_equal(&app_status, &zero, sizeof zero);
}

/* a jog in auto is refused; in manual mode it drives OPS_JOG_PERIODS (3) periods its way, then
 * nothing; a new one starts the count again */
static void test_ops_jog_counts_its_periods(void **state)
{
    (void)state;
    ops_jog(1);
    assert_int_equal(ops_jog_take(), 0);
    ops_set_manual(1);
    ops_jog(-1);
    assert_int_equal(ops_jog_take(), -1);
    assert_int_equal(ops_jog_take(), -1);
    ops_jog(1);                     /* the other way: three periods from now */
    assert_int_equal(ops_jog_take(), 1);
    assert_int_equal(ops_jog_take(), 1);
    assert_int_equal(ops_jog_take(), 1);
    assert_int_equal(ops_jog_take(), 0);
    ops_jog(0);                     /* no direction: no jog */
    assert_int_equal(ops_jog_take(), 0);
}

/* a jog not yet driven is dropped when the mode changes (ops_jog_cancel) or the I/O test ends */
static void test_ops_jog_dropped(void **state)
{
    (void)state;
    ops_set_manual(1);
    ops_jog(1);
    assert_int_equal(ops_jog_take(), 1);
    ops_jog_cancel();
    assert_int_equal(ops_jog_take(), 0);
    ops_set_manual(0);
    ops_io_test(OPS_IO_ON);
    ops_jog(-1);
    assert_int_equal(ops_jog_take(), -1);
    ops_io_test(0);
    assert_int_equal(ops_jog_take(), 0);
}

/* a raised alarm is unacknowledged and sounds the buzzer; acknowledged it stays shown and
 * silent, and the next period's update does not raise it again while it lasts */
static void test_ops_alarms_raised_and_acknowledged(void **state)
{
    const uint16_t bit = 1u << AL_INTERNAL;
    (void)state;
    ops_alarms_step();
    assert_int_equal(app_status.alarms, 0);
    assert_int_equal(hal_host_io.buzzer, 0);
    diag_internal_fault();
    ops_alarms_step();
    assert_int_equal(app_status.alarms, bit);
    assert_int_equal(app_status.alarms_unacked, bit);
    assert_int_equal(hal_host_io.buzzer, 1);
    ops_alarm_ack_bits(bit);
    assert_int_equal(app_status.alarms_unacked, 0);
    assert_int_equal(hal_host_io.buzzer, 0);
    ops_alarms_step();
    assert_int_equal(app_status.alarms, bit);
    assert_int_equal(app_status.alarms_unacked, 0);
    assert_int_equal(hal_host_io.buzzer, 0);
}

/* the I/O test holds the buzzer to the technician's switch, whatever is unacknowledged, an
 * acknowledgement included; after it the buzzer follows the alarms again */
static void test_ops_alarms_io_test_buzzer(void **state)
{
    (void)state;
    diag_internal_fault();
    ops_io_test(OPS_IO_ON);
    ops_alarms_step();
    assert_int_equal(app_status.alarms_unacked, 1u << AL_INTERNAL);
    assert_int_equal(hal_host_io.buzzer, 0);
    ops_io_test(OPS_IO_ON | OPS_IO_BUZZER);
    ops_alarms_step();
    assert_int_equal(hal_host_io.buzzer, 1);
    ops_alarm_ack_bits(1u << AL_INTERNAL);
    assert_int_equal(hal_host_io.buzzer, 1);
    ops_io_test(0);
    assert_int_equal(hal_host_io.buzzer, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_ops_init_clears_the_status, setup),
        cmocka_unit_test_setup(test_ops_jog_counts_its_periods, setup),
        cmocka_unit_test_setup(test_ops_jog_dropped, setup),
        cmocka_unit_test_setup(test_ops_alarms_raised_and_acknowledged, setup),
        cmocka_unit_test_setup(test_ops_alarms_io_test_buzzer, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

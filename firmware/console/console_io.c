/* console_io.c: the console's I/O test screen: every input raw, the outputs by hand (keys in console.h). */
#if defined(__SDCC)
#pragma stackauto           /* locals on the stack, not each its own XRAM (docs/MEMORY.md) */
#endif
#include "hal.h"
#include "ops.h"
#include "screen.h"
#include "console.h"
#include "console_int.h"
#include "umath.h"
#include "mul.h"

#if FW_IOTEST                       /* the bench's images only (hal/compiler.h) */

/*
 * The I/O test, for checking every wire from the keypad (docs/bringup.md):
 *   "P 512 10.01mA R0"   pressure input: raw ADC counts, loop current; spray relay (key 1)
 *   "L 205  4.01mA B0"   level input; buzzer (key 3)
 *   "W 1234   12Hz V0"   wheel pulses since start and their rate; valve drive (2 / 8 jog it)
 *   "M45678  340Hz"      meter pulses and rate
 * The rates are counted over windows of a second or more. C leaves (outputs back to the
 * application); no parameter is touched.
 */
static void cat_ma(uint8_t ch)
{
    uint16_t counts = hal_adc_read(ch);
    con_cat_num(counts, 4, 0);
    /* I = counts * 5 V / 1023 / 250 ohm, in hundredths of a mA: counts * 2000 / 1023 */
    con_cat_num((UMUL(counts, 32032u) + 8192u) >> 14, 6, 2);
    con_cat("mA ");
}

/* "W 1234   12Hz ": a pulse input's count (5 digits) and rate */
static void cat_pulses(char name, uint32_t pulses, uint16_t hz)
{
    con_line[0] = name;
    con_at = 1;
    con_cat_num(pulses - pulses / 100000u * 100000u, 5, 0);     /* pulses % 100000 */
    con_cat_num(hz, 5, 0);
    con_cat("Hz ");
}

void con_iotest_start(void)
{
    ops_io_test(OPS_IO_ON);
    con.cal_pulses = ops_wheel_pulses();
    con.u.io.meter0 = (uint16_t)ops_flow_pulses();
    con.cal_value = (uint16_t)hal_ms();
    con.u.io.wheel_hz = con.u.io.meter_hz = 0;
    con_say("1R 3B 2/8V C:end");
}

void con_draw_iotest(void)
{
    uint16_t now = (uint16_t)hal_ms(), dt = (uint16_t)(now - con.cal_value);
    if (dt >= 1000u) {
        con.u.io.wheel_hz = (uint16_t)um_muldiv(ops_wheel_pulses() - con.cal_pulses, 1000u, dt);
        con.u.io.meter_hz = (uint16_t)um_muldiv((uint16_t)((uint16_t)ops_flow_pulses() - con.u.io.meter0), 1000u, dt);
        con.cal_pulses = ops_wheel_pulses();
        con.u.io.meter0 = (uint16_t)ops_flow_pulses();
        con.cal_value = now;
    }
    con_start("P");
    cat_ma(HAL_ADC_PRESSURE);
    con_cat((ops_io & OPS_IO_RELAY) ? "R1" : "R0");
    con_show(0);
    con_start("L");
    cat_ma(HAL_ADC_LEVEL);
    con_cat((ops_io & OPS_IO_BUZZER) ? "B1" : "B0");
    con_show(1);
    cat_pulses('W', ops_wheel_pulses(), con.u.io.wheel_hz);
    con_cat(app_status.drive > 0 ? "V+" : app_status.drive < 0 ? "V-" : "V0");
    con_show(2);
    if (con_msg_on())
        return;                     /* con_draw puts the message on the bottom line */
    cat_pulses('M', ops_flow_pulses(), con.u.io.meter_hz);
    con_show(3);
}
#endif

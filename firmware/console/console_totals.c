/* console_totals.c: the totals page: the job's area, volume and average rate, the work rate now, the area left, the lifetime's totals. */
#if defined(__SDCC)
#pragma stackauto           /* locals on the stack, not each its own XRAM (docs/MEMORY.md) */
#endif
#include "hal.h"
#include "params.h"
#include "ops.h"
#include "target.h"
#include "screen.h"
#include "console_int.h"
#include "totals.h"
#include "mul.h"

/* The area the tank's contents above Tank min (where the boom stops) cover at the rate in
 * use, m^2: L x 100000 / (L/ha x10). */
static uint32_t area_left_m2(void)
{
    uint16_t l = app_status.tank_l, r = target_rate_x10();
    l = l > param_v[P_TANK_MIN] ? l - param_v[P_TANK_MIN] : 0;
    return r ? UMUL(l, 50000u) * 2u / r : 0;
}

/* an area (m^2) in ha, acres or 1000 ft^2, right-aligned in width, its unit after a space */
static void cat_area(uint32_t m2, uint8_t width)
{
    con_cat_q(m2, width, 2 | CON_DROP(2) | CON_Q(CU_AREA));
    con_cat(" ");
    con_cat_unit(CU_AREA);
}

/* The job's area and volume (con_draw: the rest in the next pass) */
void con_draw_totals_top(void)
{
    con_start("Job ");
    cat_area(app_status.job_area_m2, 9);
    con_show(0);
    con_start("Job ");
    con_cat_q(totals.job_ml, 10, 1 | CON_DROP(2) | CON_Q(CU_ML));
    con_cat(" ");
    con_cat_unit(CU_ML);
    con_show(1);
}

/* The job's average rate; the work rate now (the speed times the open width), the area left,
 * the lifetime's volume and area take turns every 2 s. */
void con_draw_totals(void)
{
    uint32_t v;
    con_start(param_v[P_UNITS] ? "Avg" : "Job avg");
    con_cat_q(app_status.applied_l_ha_x10, 5, CON_DROP(1) | CON_Q(CU_RATE));
    con_cat_unit(CU_RATE);
    con_show(2);
    if (con_msg_on()) {
        con_draw_msg();
    } else if (con_step) {
        screen_line("Reset job? D=yes", 3);
    } else {
        switch ((uint8_t)(hal_ms() / 2000u) & 3u) {
        case 0:
            con_start("Life");
            cat_area(totals.life_m2, 9);
            break;
        case 1:
            con_start("Life");
            con_cat_q(totals.life_ml, 10, (uint8_t)(CON_DROP(3) | CON_Q(CU_ML)));
            con_cat(" ");
            con_cat_unit(CU_ML);
            break;
        case 2:                     /* m^2 an hour: km/h x100 x cm / 10 */
            con_start("Work");
            v = app_status.spraying ? UMUL(app_status.in.speed_kmh_x100, target_width_cm()) / 10u : 0;
            cat_area(v, 7);
            con_cat("/h");
            break;
        default:
            con_start("Left");
            cat_area(area_left_m2(), 9);
            break;
        }
        con_show(3);
    }
}

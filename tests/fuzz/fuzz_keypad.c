/* fuzz_keypad.c: the operator console's keys and number entry (firmware/console/) on any key sequence:
 * no setting leaves its range, and every accepted change is the one in the EEPROM. */
#include <string.h>
#include "fuzz.h"
#include "hal_host.h"
#include "params.h"
#include "store.h"
#include "totals.h"
#include "app.h"

static uint64_t t_ms;

static void run_ms(unsigned ms)
{
    while (ms--) {
        t_ms++;
        hal_host_set_time_ns(t_ms * 1000000ull);
        app_poll();
    }
}

/* Each byte is one key: low 4 bits the key (row * 4 + column of the 4x4 matrix), bit 4 holds it
 * past the auto-repeat delay. */
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    uint16_t now[P_COUNT];
    size_t k;
    int i;
    if (size > 96)
        return 0;
    hal_host_reset();
    hal_init();
    hal_host_io.adc[HAL_ADC_PRESSURE] = 205;
    hal_host_io.adc[HAL_ADC_LEVEL] = 1023 - 100;
    hal_host_io.sections = 0x3F;
    t_ms = 0;
    app_init();
    run_ms(50);
    for (k = 0; k < size; k++) {
        hal_host_io.keys = (uint16_t)(1u << (data[k] & 15));
        run_ms(data[k] & 16 ? 820 : 40);
        hal_host_io.keys = 0;
        run_ms(40);
        for (i = 0; i < P_COUNT; i++)
            FUZZ_CHECK(param_in_range((uint8_t)i, param_v[i]), "param %d = %u after key %zu", i, param_v[i], k);
    }
    /* what the console accepted is saved: at once, or by the loop a while later (app.c), the
     * save that needs an erase when the budget allows (store.h); then a fresh load gives the
     * same settings */
    if (store_generation() != param_generation)
        run_ms(2100);
    for (i = 0; i < 2 * (int)(STORE_ERASE_MS / 10) && store_busy(); i++)
        run_ms(10);
    memcpy(now, param_v, sizeof now);
    params_defaults();
    totals_init();
    store_load();
    for (i = 0; i < P_COUNT; i++)
        FUZZ_CHECK(param_v[i] == now[i], "param %d: %u in RAM, %u in the EEPROM", i, now[i], param_v[i]);
    return 0;
}

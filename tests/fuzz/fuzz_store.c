/* fuzz_store.c: the EEPROM record loader (firmware/store/store.c) on any EEPROM contents: it loads
 * only valid values, and what it saves next it loads back. */
#include <string.h>
#include "fuzz.h"
#include "hal_host.h"
#include "params.h"
#include "store.h"
#include "totals.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    uint16_t before[P_COUNT];
    uint32_t life_m2, life_ml;
    uint8_t st;
    int i;
    if (size > HAL_EEPROM_SIZE)
        return 0;
    hal_host_reset();
    hal_init();
    params_defaults();
    totals_init();
    memcpy(hal_host_eeprom(), data, size);      /* the rest stays erased (0xFF) */
    st = store_load();
    FUZZ_CHECK(st == STORE_OK || st == STORE_OLDER || st == STORE_DEFAULTS, "status %u", st);
    FUZZ_CHECK(st == store_status(), "status %u, store_status %u", st, store_status());
    for (i = 0; i < P_COUNT; i++)
        FUZZ_CHECK(param_in_range((uint8_t)i, param_v[i]), "param %d = %u loaded out of range", i, param_v[i]);
    /* a save after any load writes a copy the next load takes, values and totals alike */
    memcpy(before, param_v, sizeof before);
    life_m2 = totals_get()->life_m2;
    life_ml = totals_get()->life_ml;
    hal_host_set_time_ns(STORE_ERASE_MS * 1000000ull);     /* a token of the erase budget (store.h) */
    FUZZ_CHECK(store_save() == 1, "save after load failed");
    params_defaults();
    totals_init();
    st = store_load();
    FUZZ_CHECK(st == STORE_OK, "reload status %u", st);
    FUZZ_CHECK(memcmp(before, param_v, sizeof before) == 0, "values changed over save and load");
    FUZZ_CHECK(totals_get()->life_m2 == life_m2 && totals_get()->life_ml == life_ml, "lifetime totals changed");
    return 0;
}

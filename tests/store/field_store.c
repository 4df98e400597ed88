/* field_store.c (build/host-test/test_store_field): the store as an image without the frames
 * (FW_PGN 0: params.c and store.c built so) reads and writes the records of one with them (the
 * library's, FW_PGN 1): one table, one layout. Remote = AgOpenGPS is refused here by its range;
 * a record holding it loads, Remote off, every other value as written. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <string.h>
#include <cmocka.h>
#include "hal_host.h"
#include "params.h"
#include "store.h"

typedef char built_without_the_frames[(FW_PGN == 0) ? 1 : -1];

/* CRC-16/CCITT (0x1021, from 0xFFFF, MSB first), bit by bit, stored high byte first */
static uint16_t twin_crc(const uint8_t *p, size_t n)
{
    uint16_t crc = 0xFFFF;
    for (size_t i = 0; i < n; i++) {
        crc ^= (uint16_t)(p[i] << 8);
        for (int k = 0; k < 8; k++)
            crc = (crc & 0x8000) ? (uint16_t)((crc << 1) ^ 0x1021) : (uint16_t)(crc << 1);
    }
    return crc;
}

static uint8_t save(void)
{
    hal_host_set_time_ns(hal_host_io.time_ns + STORE_ERASE_MS * 1000000ull);
    return store_save();
}

static int setup(void **state)
{
    (void)state;
    hal_host_reset();
    params_defaults();
    return 0;
}

static void test_field_store_one_layout_for_every_image(void **state)
{
    (void)state;
    /* the frames' six settings are in this image's table, stored though unused */
    assert_int_equal(P_COUNT, 45);
    assert_int_equal(PARAMS_VERSION, 11);
    assert_int_equal(P_RC_ID, 44);
    /* Remote: off and Raven only */
    assert_true(param_set(P_REMOTE, 2));
    assert_false(param_set(P_REMOTE, 3));
    assert_int_equal(param_v[P_REMOTE], 2);
    assert_true(param_set(P_SPEED_SRC, 2));
    assert_true(param_set(P_RC_ID, 7));
    assert_true(param_set(P_FRAMES_LOST, 40));
    assert_true(save());
    /* the record as the image with the frames reads it: version 11, 45 values, in table order */
    uint8_t *e = hal_host_eeprom();
    while (e[0] != 0x5A && e < hal_host_eeprom() + 2 * HAL_EEPROM_SECTOR)
        e += STORE_SLOT_BYTES;                  /* the slot it went to */
    assert_int_equal(e[0], 0x5A);
    assert_int_equal(e[1], 11);
    assert_int_equal(e[2], 45);
    assert_int_equal(e[5 + 2 * 30], 2);         /* Remote, parameter 30 */
    assert_int_equal(e[5 + 2 * 39], 2);         /* Speed src, 39 */
    assert_int_equal(e[5 + 2 * 44], 7);         /* RC module, 44 */
    size_t n = 5 + 2 * 45 + 8 + 12 + 8;
    assert_int_equal(e[n], (uint8_t)(twin_crc(e, n) >> 8));
    assert_int_equal(e[n + 1], (uint8_t)twin_crc(e, n));
    /* that image sets Remote = AgOpenGPS and saves: this one loads the record, Remote off */
    uint8_t *w = e;
    w[5 + 2 * 30] = 3;
    uint16_t crc = twin_crc(w, n);
    w[n] = (uint8_t)(crc >> 8);
    w[n + 1] = (uint8_t)crc;
    params_defaults();
    assert_int_equal(store_load(), STORE_OK);
    assert_int_equal(param_v[P_REMOTE], 0);
    assert_int_equal(param_v[P_SPEED_SRC], 2);
    assert_int_equal(param_v[P_RC_ID], 7);
    assert_int_equal(param_v[P_FRAMES_LOST], 40);
    /* a value out of every image's range still spoils the record */
    w[5 + 2 * 30] = 4;
    crc = twin_crc(w, n);
    w[n] = (uint8_t)(crc >> 8);
    w[n + 1] = (uint8_t)crc;
    assert_int_equal(store_load(), STORE_DEFAULTS);
    w[5 + 2 * 30] = 3;
    w[5 + 2 * 39] = 3;                          /* Speed src 0-2 */
    crc = twin_crc(w, n);
    w[n] = (uint8_t)(crc >> 8);
    w[n + 1] = (uint8_t)crc;
    assert_int_equal(store_load(), STORE_DEFAULTS);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_field_store_one_layout_for_every_image, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

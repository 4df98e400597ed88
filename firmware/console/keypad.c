/* keypad.c: 4x4 keypad scan every KEYPAD_SCAN_MS from the main loop, debounce by stable readings, auto-repeat. */
#if defined(__SDCC)
#pragma stackauto           /* locals on the stack, not each its own XRAM (docs/MEMORY.md) */
#endif
#include "hal.h"
#include "keypad.h"

static __code const char keymap[16] = {
    '1', '2', '3', 'A',
    '4', '5', '6', 'B',
    '7', '8', '9', 'C',
    '*', '0', '#', 'D'
};

#define NO_KEY 0xFF
static uint16_t next_scan_ms;       /* low 16 bits of hal_ms(): the intervals are short */
static uint16_t repeat_ms;          /* when the held key repeats next */
static uint8_t reading;             /* key index seen in the last scans, NO_KEY for none */
static uint8_t same;                /* scans in a row that saw it */
static uint8_t held;                /* the debounced key */

void keypad_init(void)
{
    next_scan_ms = (uint16_t)hal_ms();
    reading = NO_KEY;
    held = NO_KEY;
    same = 0;
}

#if FW_PROBES
char keypad_char(uint8_t row, uint8_t col)
{
    return keymap[((row & 3) << 2) | (col & 3)];
}
#endif

/* The one key pressed now; NO_KEY for none, and also for two or more (a chord is ignored). */
static uint8_t scan(void)
{
    uint8_t row, cols, col, k = NO_KEY;
    for (row = 0; row < 4; row++) {
        cols = hal_keypad_row(row) & 0x0F;
        for (col = 0; col < 4; col++, cols >>= 1) {
            if (!(cols & 1u))
                continue;
            if (k != NO_KEY)
                return NO_KEY;
            k = (uint8_t)((row << 2) | col);
        }
    }
    return k;
}

static uint8_t repeats(char c)
{
    return c != 'C' && c != 'D' && c != '*' && c != '#';
}

char keypad_poll(void)
{
    uint16_t now = (uint16_t)hal_ms();
    uint8_t k;
    if ((int16_t)(now - next_scan_ms) < 0)
        return KEY_NONE;
    next_scan_ms = now + KEYPAD_SCAN_MS;
    k = scan();
    if (k != reading) {
        reading = k;
        same = 1;
        return KEY_NONE;
    }
    if (same < KEYPAD_STABLE_SCANS)
        same++;
    if (same < KEYPAD_STABLE_SCANS)
        return KEY_NONE;
    if (k != held) {
        held = k;
        if (k == NO_KEY)
            return KEY_NONE;
        repeat_ms = now + KEYPAD_DELAY_MS;
        return keymap[k];
    }
    if (k != NO_KEY && repeats(keymap[k]) && (int16_t)(now - repeat_ms) >= 0) {
        repeat_ms += KEYPAD_REPEAT_MS;
        return keymap[k];
    }
    return KEY_NONE;
}

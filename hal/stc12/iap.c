/* iap.c: the IAP EEPROM (1 KB, two sectors). An operation holds the CPU: the UART's byte that
 * waited through it marks a loss (uart.c's stc12_rx_lost). */
#pragma stackauto           /* locals on the stack, not each its own XRAM (docs/MEMORY.md) */
#include <stc12.h>
#include "hal.h"
#include "stc12_int.h"

/* ---- IAP EEPROM: 1 KB at IAP addresses 0x0000-0x03FF, two 512-byte sectors ------------------ */
#define IAP_EN_WT 0x83              /* IAPEN, wait time for SYSCLK < 12 MHz */
#define IAP_READ 1
#define IAP_PROGRAM 2
#define IAP_ERASE 3

/*
 * One IAP operation; returns IAP_DATA (a read's byte). The CPU is held until the operation
 * ends (a sector erase about 21 ms, a byte program about 55 us, datasheet's IAP timing):
 * no interrupt is served meanwhile. The UART keeps one received byte in SBUF and, in mode 1,
 * drops the next while RI is still set. So a byte waiting after an erase, or after any
 * operation that found one already waiting, may have had others lost before it: it is
 * dropped and the loss marked there, and the serial link discards that line with ERR LOST.
 */
static uint8_t iap_cmd(uint8_t cmd, uint16_t addr)
{
    uint8_t d;
    uint8_t ea, ri0;
    IAP_CONTR = IAP_EN_WT;
    IAP_CMD = cmd;
    IAP_ADDRL = (uint8_t)addr;
    IAP_ADDRH = (uint8_t)(addr >> 8);
    IRQ_OFF(ea);                    /* the trigger pair must not be split */
    ri0 = RI;
    IAP_TRIG = 0x5A;
    IAP_TRIG = 0xA5;
    NOP();
    d = IAP_DATA;                   /* before the unit is idled, as STC's examples read it */
    IAP_CONTR = 0;                  /* leave IAP disabled and pointing outside the EEPROM */
    IAP_CMD = 0;
    IAP_TRIG = 0;
    IAP_ADDRH = 0x80;
    IAP_ADDRL = 0;
    if (RI && (ri0 || cmd == IAP_ERASE)) {
        RI = 0;                     /* that byte and any before it since the hold: a gap */
        stc12_rx_lost = 1;
    }
    IRQ_RESTORE(ea);
    return d;
}

uint8_t hal_eeprom_read(uint16_t addr)
{
    if (addr >= HAL_EEPROM_SIZE)
        return 0xFF;
    return iap_cmd(IAP_READ, addr);
}

void hal_eeprom_erase(uint16_t addr)
{
    if (addr >= HAL_EEPROM_SIZE)
        return;
    iap_cmd(IAP_ERASE, addr & (uint16_t)~(HAL_EEPROM_SECTOR - 1));
}

uint8_t hal_eeprom_write(uint16_t addr, uint8_t b) __reentrant
{
    if (addr >= HAL_EEPROM_SIZE)
        return 0;
    IAP_DATA = b;
    iap_cmd(IAP_PROGRAM, addr);
    return hal_eeprom_read(addr) == b;
}

/* uart_echo.c: UART 1 of the STC12C5A60S2 at a baud and framing set at build time (-DBAUD, -DSTOP2),
 * clocked by the BRT in 1T mode; every received byte goes back plus one. tests/scripts/chip_uart.py
 * drives it in the model (sim/ucsim/) to check the UART's timing and framing, as hal/stc12 sets it. */
#include <stc12.h>

#ifndef BAUD
#define BAUD 38400UL
#endif
#define BRT_RELOAD (256u - 11059200UL / 32u / BAUD)

void main(void)
{
#ifdef STOP2
    SCON = 0xD8;                    /* mode 3 (9 bits), REN, TB8 = 1: the 9th bit a second stop bit */
#else
    SCON = 0x50;                    /* mode 1 (8N1), REN */
#endif
    BRT = (unsigned char)BRT_RELOAD;
    AUXR = 0x15;                    /* BRTR | BRTx12 | S1BRS: UART 1 from the BRT at SYSCLK */
    for (;;) {
        if (RI) {
            unsigned char b = SBUF;
            RI = 0;
            SBUF = (unsigned char)(b + 1u);
            while (!TI)
                ;
            TI = 0;
        }
    }
}

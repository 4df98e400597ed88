/* stc12_int.h: what the STC12 backend's files share among themselves (not the firmware's business). */
#ifndef STC12_INT_H
#define STC12_INT_H

/* critical sections: interrupts off, then back as they were (they nest) */
#define IRQ_OFF(s) do { (s) = EA; EA = 0; } while (0)
#define IRQ_RESTORE(s) do { EA = (s); } while (0)

#if FW_HIL
/* hal_hil (ports.c): the inputs from the PC's frames while its plant stands in, else 0 */
extern hal_hil_t __xdata *stc12_hil;
#endif

/* tick.c's millisecond count and where the next one ends on the PCA counter (hal_init starts them) */
extern volatile uint32_t tick_ms;
extern uint16_t tick_next_pca;
extern uint8_t tick_fifths;

/* wdt.c: the reset cause read, and the flags cleared for the next (hal_init, first) */
void reset_cause_read(void);
#define PCON_LVDF 0x20
#define PCON_POF 0x10

/* adc.c: ADC_CONTR's power bit (hal_init powers the converter) */
#define ADC_POWER 0x80

/* uart.c: a received byte was lost (iap.c marks the bytes an IAP operation held off) */
extern volatile __bit stc12_rx_lost;

#endif

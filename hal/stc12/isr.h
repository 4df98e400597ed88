/* isr.h: the interrupt handlers of the STC12 backend; SDCC needs their prototypes where main() is. */
#ifndef ISR_H
#define ISR_H

void stc12_int0_isr(void) __interrupt(0);   /* wheel pulse */
void stc12_timer0_isr(void) __interrupt(1); /* 1 ms system tick */
void stc12_uart_isr(void) __interrupt(4);   /* RS232 */
void stc12_pca_isr(void) __interrupt(7);    /* PCA overflow and flow meter capture */

#endif

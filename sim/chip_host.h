/* chip_host.h: chip in the loop: the field image in the STC12C5A60S2 model (build/ucsim/s51 -t STC12) with the simulator's plant on its pins. */
#ifndef SIM_CHIP_HOST_H
#define SIM_CHIP_HOST_H

#include <stdio.h>
#include "sim.h"

/*
 * chip_start() runs the model on the field image (hal/stc12, its interrupt handlers) and makes
 * sim_step() hand each 1 ms tick to it in lock step (sim/ucsim/stc12_link.h): the plant's wheel
 * and meter edges go to INT0 and CCP0 at their exact clocks, the pressure and level counts to
 * the ADC, the keys and section switches to their ports, the operator's serial bytes to RXD at
 * 38400 baud; back come the pins the board's drivers see (the H-bridge, its PWM enable, the
 * boom relay, the buzzer: a pin drives only when push-pull at 1, as the board's pull-downs
 * hold a quasi-bidirectional pin's weak pull-up low), the bytes on TXD decoded at the host's
 * baud, and the status the metrics read from the image's XRAM (app_status, param_v at their
 * addresses in IMAGE.map). The image starts from the EEPROM the host build saved with the
 * scenario's settings (the operator's set-up); a setting a scenario event changes goes to the
 * link as the PC would send it ("SET id value").
 */
typedef struct chip chip_t;

chip_t *chip_start(sim_t *sim, const char *ihx, const char *s51, char *err, size_t n);
/* An input to the model's own pins at t_s (STC12_EV_RESET, STC12_EV_HANG,
 * STC12_EV_WHEEL_SWEEP of sim/ucsim/stc12_link.h); -1 when the list is full. */
int chip_at(chip_t *c, double t_s, int kind, uint32_t value);
/* Stop the model (its interrupt handler figures come back); 0 when it answered. */
int chip_finish(chip_t *c);
/* "chip:" lines: passes and interrupt handlers in 1T clocks and us, watchdog resets. */
void chip_report(const chip_t *c, FILE *f);
void chip_free(chip_t *c);

#endif

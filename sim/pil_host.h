/* pil_host.h: processor in the loop, host side: the firmware built for s51 (hal/pil) in lock step with the simulator's plant. */
#ifndef SIM_PIL_HOST_H
#define SIM_PIL_HOST_H

#include <stdio.h>
#include "sim.h"

/*
 * pil_start() runs s51 on the image (build/pil/sprayer_pil.ihx) through its command console,
 * with the simulator interface's input and output files on two FIFOs (hal/pil/pil_proto.h),
 * starts the firmware as sim_init() starts it on the host and makes sim_step() hand each
 * tick's pass to it: the inputs the host HAL holds go out in a frame, the firmware's HAL calls
 * are served by the host HAL (the same edges, conversions, EEPROM and UART queues the host
 * build sees), its outputs land in hal_host_io and app_status. Call after sim_init(); then
 * sim_run() as usual; pil_finish() stops s51 and takes the stack's high-water mark.
 * One PIL run a process.
 */
#define PIL_CYCLES_PER_MS 921.6     /* classic 8051 at 11.0592 MHz: machine cycles a millisecond */

typedef struct pil pil_t;

/* NULL with a message in err when s51 cannot be started or the firmware does not answer. */
pil_t *pil_start(sim_t *sim, const char *ihx, char *err, size_t n);
/* Stop the firmware and s51; 0 when both ended as expected. */
int pil_finish(pil_t *p);
/* The pass timing of the run: "pil: ..." lines (cycles of every pass, the worst one and what it
 * did, the control period's share, the stack). */
void pil_report(const pil_t *p, FILE *f);
void pil_free(pil_t *p);

#endif

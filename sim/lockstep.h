/* lockstep.h: a firmware in s51 in lock step with the host's plant: the s51 process, its two FIFOs, its console, the frames' bytes. */
#ifndef SIM_LOCKSTEP_H
#define SIM_LOCKSTEP_H

#include <stddef.h>
#include <stdint.h>
#include <sys/types.h>

/*
 * What pil_host.c (the firmware built for s51, its HAL calls served here) and chip_host.c (the
 * field image in the STC12C5A60S2 model, its pins driven here) share: s51 runs as a child with
 * its command console on a pipe, its log in a temporary folder, and its frames on two FIFOs in
 * that folder; a broken link fails the run (`failed`) and every later read gives zeros.
 */
typedef struct {
    pid_t pid;                      /* s51 (-1: not running) */
    int to_s51, from_s51, console;  /* the FIFOs' ends and s51's standard input (-1: closed) */
    char dir[64];                   /* the folder of the FIFOs and s51.log */
    char fifo_in[96], fifo_out[96]; /* s51's input and output FIFOs */
    int failed;
    uint8_t buf[4096];              /* bytes read from s51 and not yet taken */
    size_t n_buf, i_buf;
} lockstep_t;

/* No process, nothing open (before lockstep_fifos; lockstep_close is safe from here on). */
void lockstep_init(lockstep_t *l);
/* The folder (tmpl: "/tmp/name.XXXXXX") and its two FIFOs; -1 and why in err. */
int lockstep_fifos(lockstep_t *l, const char *tmpl, char *err, size_t n);
/* Start s51 (argv[0] its path or a name on PATH; env_link: STC12_LINK_IN and STC12_LINK_OUT
 * name the FIFOs, as the STC12 model reads them), open the FIFOs as s51 does (its input
 * first, then its output) and type "run" on its console; -1 when it did not open them. */
int lockstep_spawn(lockstep_t *l, char *const argv[], int env_link);
/* The host build's own start (sim_init) left its traces in the shared HAL: the firmware in s51
 * starts from an erased EEPROM that no power cut interrupts ... */
void lockstep_erase_eeprom(void);
/* ... and an empty UART queue. */
void lockstep_drop_uart(void);

void lockstep_write(lockstep_t *l, const uint8_t *b, size_t n);
/* n bytes from s51: 0, or -1 (and zeros) when the link broke. */
int lockstep_read(lockstep_t *l, uint8_t *b, size_t n);
/* One byte, or -1 when the link broke. */
int lockstep_byte(lockstep_t *l);
/* Little-endian fields of a frame: v into b's n bytes; n bytes of b. */
size_t lockstep_put(uint8_t *b, uint64_t v, int n);
uint64_t lockstep_get(const uint8_t *b, int n);
/* A little-endian 16-bit field from s51 (0 when the link broke). */
unsigned lockstep_u16(lockstep_t *l);

/* Wait for s51 to end: 0 when it exited with status 0 (any status: exit_any). */
int lockstep_wait(lockstep_t *l, int exit_any);
/* Stop s51 if it still runs, close the FIFOs and the console, remove the folder. */
void lockstep_close(lockstep_t *l);

/* *a (of *cap elements of size each) grown to hold n + 1; -1 when memory ran out. */
int lockstep_grow(void **a, size_t *cap, size_t n, size_t size);
/* A sorted copy of n values (the caller frees it); NULL when memory ran out. */
uint32_t *lockstep_sorted_u32(const uint32_t *v, size_t n);

#endif

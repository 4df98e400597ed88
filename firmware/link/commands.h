/* commands.h: the serial link's commands, one table of word, arguments and handler (commands.c);
 * serial.c parses a line against it and runs the handler's case. */
#ifndef COMMANDS_H
#define COMMANDS_H
#include "hal.h"

#define ARG_NONE 0                  /* nothing after the word */
#define ARG_NUM 1                   /* one number */
#define ARG_NUM2 2                  /* two numbers */
#define ARG_SIGN 3                  /* + or - (or 0, for NUD) */
#define ARG_ON 4                    /* the word ON */
enum { C_GET, C_SET, C_CTL, C_JOG, C_ACK, C_RST, C_TOT, C_LIF, C_PUL, C_SAV, C_NUD, C_HIL };
typedef struct {
    char word[4];                   /* three letters and the end */
    uint8_t args;                   /* ARG_* */
    uint8_t handler;                /* C_*: the case of serial.c's run() (no function pointers: the
                                     * stack check follows every call, and SDCC's calls stay plain) */
} command_t;
/* the table, HIL last and only where hardware in the loop is built (FW_HIL) */
extern const __code command_t link_commands[];
#define LINK_N_COMMANDS (FW_HIL ? C_HIL + 1 : C_HIL)
/* The commands that change something: refused without their check, so that a damaged line
 * ("SET 0 150" losing a digit is the valid "SET 0 10") is never acted on. */
#define CHANGES ((1u << C_SET) | (1u << C_CTL) | (1u << C_JOG) | (1u << C_ACK) | (1u << C_RST) | (1u << C_SAV) \
                 | (1u << C_NUD) | (1u << C_HIL))

#endif

/* commands.c: the serial link's command table (commands.h). */
#include "commands.h"

const __code command_t link_commands[LINK_N_COMMANDS] = {
    {"GET", ARG_NUM, C_GET},        /* GET <id>          OK <id> <value> */
    {"SET", ARG_NUM2, C_SET},       /* SET <id> <value>  OK <id> <value> */
    {"CTL", ARG_NUM, C_CTL},        /* CTL <n>           OK CTL <n> */
    {"JOG", ARG_SIGN, C_JOG},       /* JOG +|-           OK JOG */
    {"ACK", ARG_NONE, C_ACK},       /* ACK               OK ACK */
    {"RST", ARG_NONE, C_RST},       /* RST               OK RST */
    {"TOT", ARG_NONE, C_TOT},       /* TOT               OK TOT <job dm^2> <job ml> <L/ha x10> */
    {"LIF", ARG_NONE, C_LIF},       /* LIF               OK LIF <life m^2> <life ml> */
    {"PUL", ARG_NONE, C_PUL},       /* PUL               OK PUL <wheel pulses> <meter pulses> */
    {"SAV", ARG_NONE, C_SAV},       /* SAV               OK SAV */
    {"NUD", ARG_SIGN, C_NUD},       /* NUD +|-|0         OK NUD <offset %> <rate in use L/ha x10> */
#if FW_HIL
    {"HIL", ARG_ON, C_HIL},         /* HIL ON*HH         OK HIL, then frames (hil.h); the checksum required */
#endif
};

/* args.h: the command-line options of sim/'s programs, read by one parser (a table an option). */
#ifndef ARGS_H
#define ARGS_H

#include <stdio.h>

typedef enum {
    ARG_FLAG,                       /* no value: *(int *)to = 1 */
    ARG_TEXT,                       /* *(const char **)to = the value */
    ARG_NUM,                        /* *(double *)to, a number in [lo, hi] */
    ARG_WHOLE,                      /* *(long *)to, a whole number in [lo, hi] */
    ARG_U64,                        /* *(unsigned long long *)to, 0..2^64-1 */
    ARG_NUMS                        /* (arg_nums_t *)to: each time given, one more number in [lo, hi] */
} arg_kind_t;

#define ARG_NUMS_MAX 8

typedef struct {
    double v[ARG_NUMS_MAX];
    int n;
} arg_nums_t;

typedef struct {
    const char *name;               /* "--scenario" */
    arg_kind_t kind;
    void *to;
    double lo, hi;                  /* ARG_NUM, ARG_WHOLE: the values taken */
    int *given;                     /* set to 1 when the option is given (NULL: not kept) */
} arg_opt_t;

#define ARGS_OK 0
#define ARGS_HELP 1                 /* -h or --help: the usage printed on stdout (exit 0) */
#define ARGS_BAD 2                  /* refused, said on stderr as "PROG: ..." with the usage (exit 2) */

/* Read argv against the table: each option once or more (the last wins; ARG_NUMS keeps each), a value in the next
 * argument; a bare argument goes to *positional (one at most; NULL: none is taken). */
int args_parse(const char *prog, int argc, char **argv, const arg_opt_t *opts, int n_opts,
               const char **positional, void (*usage)(FILE *));

#endif

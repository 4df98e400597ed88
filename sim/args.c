/* args.c: one command-line parser for sim/'s programs (args.h). */
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include "args.h"

/* v as the option's kind into o->to; 0, or -1 said on stderr */
static int take(const char *prog, const arg_opt_t *o, const char *v)
{
    char *end;
    double x;
    errno = 0;
    switch (o->kind) {
    case ARG_TEXT:
        *(const char **)o->to = v;
        return 0;
    case ARG_U64:
        if (*v && *v != '-' && *v != '+') {
            unsigned long long u = strtoull(v, &end, 10);
            if (!*end && !errno) {
                *(unsigned long long *)o->to = u;
                return 0;
            }
        }
        fprintf(stderr, "%s: %s '%s' is not a whole number 0..2^64-1\n", prog, o->name, v);
        return -1;
    case ARG_WHOLE: {
        long n = strtol(v, &end, 10);
        if (*v && !*end && !errno && n >= o->lo && n <= o->hi) {
            *(long *)o->to = n;
            return 0;
        }
        fprintf(stderr, "%s: %s '%s' is not a whole number %.12g..%.12g\n", prog, o->name, v, o->lo, o->hi);
        return -1;
    }
    default:
        x = strtod(v, &end);
        if (*v && !*end && !errno && x >= o->lo && x <= o->hi) {
            if (o->kind != ARG_NUMS) {
                *(double *)o->to = x;
                return 0;
            }
            if (((arg_nums_t *)o->to)->n < ARG_NUMS_MAX) {
                arg_nums_t *l = o->to;
                l->v[l->n++] = x;
                return 0;
            }
            fprintf(stderr, "%s: %s given more than %d times\n", prog, o->name, ARG_NUMS_MAX);
            return -1;
        }
        fprintf(stderr, "%s: %s '%s' is not a number %.12g..%.12g\n", prog, o->name, v, o->lo, o->hi);
        return -1;
    }
}

int args_parse(const char *prog, int argc, char **argv, const arg_opt_t *opts, int n_opts,
               const char **positional, void (*usage)(FILE *))
{
    int i, k;
    for (i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage(stdout);
            return ARGS_HELP;
        }
        if (a[0] != '-' && positional) {
            if (*positional) {
                fprintf(stderr, "%s: one file at a time ('%s' and '%s')\n", prog, *positional, a);
                return ARGS_BAD;
            }
            *positional = a;
            continue;
        }
        for (k = 0; k < n_opts && strcmp(a, opts[k].name); k++)
            ;
        if (k == n_opts) {
            fprintf(stderr, "%s: unknown option '%s'\n", prog, a);
            usage(stderr);
            return ARGS_BAD;
        }
        if (opts[k].kind == ARG_FLAG) {
            *(int *)opts[k].to = 1;
        } else if (i + 1 == argc) {
            fprintf(stderr, "%s: %s needs a value\n", prog, a);
            usage(stderr);
            return ARGS_BAD;
        } else if (take(prog, &opts[k], argv[++i]) < 0) {
            return ARGS_BAD;
        }
        if (opts[k].given)
            *opts[k].given = 1;
    }
    return ARGS_OK;
}

/* test_args.c: the one option parser of sim/'s programs (sim/args.c): what it takes, what it refuses and how it says so. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>
#include "args.h"

static const char *text, *pos;
static double num;
static long whole;
static unsigned long long big;
static int flag, big_given, usages;
static const arg_opt_t opts[] = {
    {"--text", ARG_TEXT, &text, 0, 0, NULL},
    {"--num", ARG_NUM, &num, 0.5, 10, NULL},
    {"--whole", ARG_WHOLE, &whole, 1, 16, NULL},
    {"--big", ARG_U64, &big, 0, 0, &big_given},
    {"--flag", ARG_FLAG, &flag, 0, 0, NULL},
};
static void usage(FILE *f)
{
    (void)f;
    usages++;
}

/* argv from a NULL-terminated list; the parser's result, its stderr in err */
static char err[512];
static int run(int with_pos, ...)
{
    char *argv[16] = {"prog"};
    int argc = 1, r, saved;
    va_list ap;
    FILE *tmp = tmpfile();
    va_start(ap, with_pos);
    while ((argv[argc] = va_arg(ap, char *)) != NULL)
        argc++;
    va_end(ap);
    text = pos = NULL;
    num = -1;
    whole = -1;
    big = 0;
    flag = big_given = usages = 0;
    fflush(stderr);
    saved = dup(fileno(stderr));
    dup2(fileno(tmp), fileno(stderr));
    r = args_parse("prog", argc, argv, opts, (int)(sizeof opts / sizeof opts[0]), with_pos ? &pos : NULL, usage);
    fflush(stderr);
    dup2(saved, fileno(stderr));
    close(saved);
    rewind(tmp);
    memset(err, 0, sizeof err);
    if (fread(err, 1, sizeof err - 1, tmp) == 0)
        err[0] = 0;
    fclose(tmp);
    return r;
}

static void test_args_takes_each_kind(void **state)
{
    (void)state;
    assert_int_equal(run(1, "--text", "a b", "--num", "2.5", "--whole", "16", "--big", "18446744073709551615",
                         "--flag", "file.csv", NULL), ARGS_OK);
    assert_string_equal(text, "a b");
    assert_true(num == 2.5);
    assert_int_equal(whole, 16);
    assert_true(big == 18446744073709551615ULL && big_given && flag);
    assert_string_equal(pos, "file.csv");
    assert_string_equal(err, "");
    /* nothing given: nothing set, nothing marked */
    assert_int_equal(run(0, NULL), ARGS_OK);
    assert_true(text == NULL && num == -1 && whole == -1 && !big_given && !flag);
}

static void test_args_ranges_are_inclusive_and_refused_outside(void **state)
{
    (void)state;
    assert_int_equal(run(0, "--num", "0.5", "--whole", "1", NULL), ARGS_OK);
    assert_true(num == 0.5 && whole == 1);
    assert_int_equal(run(0, "--num", "10.01", NULL), ARGS_BAD);
    assert_string_equal(err, "prog: --num '10.01' is not a number 0.5..10\n");
    assert_int_equal(run(0, "--num", "3x", NULL), ARGS_BAD);
    assert_int_equal(run(0, "--num", "", NULL), ARGS_BAD);
    assert_int_equal(run(0, "--num", "nan", NULL), ARGS_BAD);
    assert_int_equal(run(0, "--whole", "2.5", NULL), ARGS_BAD);
    assert_string_equal(err, "prog: --whole '2.5' is not a whole number 1..16\n");
    assert_int_equal(run(0, "--whole", "17", NULL), ARGS_BAD);
    assert_int_equal(run(0, "--big", "-1", NULL), ARGS_BAD);
    assert_string_equal(err, "prog: --big '-1' is not a whole number 0..2^64-1\n");
    assert_int_equal(run(0, "--big", "18446744073709551616", NULL), ARGS_BAD);
    assert_false(big_given);
}

static void test_args_refusals_say_what_and_show_the_usage(void **state)
{
    (void)state;
    assert_int_equal(run(0, "--what", NULL), ARGS_BAD);
    assert_string_equal(err, "prog: unknown option '--what'\n");
    assert_int_equal(usages, 1);
    assert_int_equal(run(0, "--text", NULL), ARGS_BAD);
    assert_string_equal(err, "prog: --text needs a value\n");
    assert_int_equal(usages, 1);
    assert_int_equal(run(0, "file.csv", NULL), ARGS_BAD);          /* no bare argument taken */
    assert_int_equal(run(1, "a.csv", "b.csv", NULL), ARGS_BAD);
    assert_string_equal(err, "prog: one file at a time ('a.csv' and 'b.csv')\n");
    assert_int_equal(run(1, "--num", "1", "-h", "--what", NULL), ARGS_HELP);
    assert_int_equal(usages, 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_args_takes_each_kind),
        cmocka_unit_test(test_args_ranges_are_inclusive_and_refused_outside),
        cmocka_unit_test(test_args_refusals_say_what_and_show_the_usage),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* progress.c: a one-line progress of a long run on stderr (done / total, elapsed, estimate), only on a terminal. */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <unistd.h>
#include "progress.h"

static double wall_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* "m:ss" */
static void mmss(char *buf, size_t n, double s)
{
    long t = (long)(s + 0.5);
    snprintf(buf, n, "%ld:%02ld", t / 60, t % 60);
}

int progress_line(char *buf, int n, const char *label, double done, double total, double elapsed)
{
    char e[48], left[48] = "?";
    if (done > 0 && total >= done)
        mmss(left, sizeof left, elapsed * (total - done) / done);
    mmss(e, sizeof e, elapsed);
    return snprintf(buf, (size_t)n, "%s: %.0f / %.0f s simulated, %s elapsed, about %s left", label, done, total, e,
                    left);
}

void progress_start(progress_t *p, const char *label, double total)
{
    const char *ci = getenv("CI"), *after = getenv("PROGRESS_AFTER_S");
    p->label = label;
    p->total = total;
    p->t0 = wall_s();
    p->next = p->t0 + (after && *after ? atof(after) : PROGRESS_AFTER_S);
    p->on = isatty(STDERR_FILENO) && !(ci && *ci);
    p->shown = 0;
}

void progress_show(progress_t *p, double done)
{
    char line[256];
    double now;
    if (!p->on || (now = wall_s()) < p->next)
        return;
    p->next = now + PROGRESS_EVERY_S;
    progress_line(line, sizeof line, p->label, done, p->total, now - p->t0);
    fprintf(stderr, "\r\033[K%s", line);
    fflush(stderr);
    p->shown = 1;
}

void progress_end(progress_t *p)
{
    if (p->shown)
        fputs("\r\033[K", stderr);
    p->shown = 0;
}

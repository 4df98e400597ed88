/* progress.h: a one-line progress of a long run on stderr (done / total, elapsed, estimate), only on a terminal. */
#ifndef PROGRESS_H
#define PROGRESS_H

/* Shown only when stderr is a terminal and CI is not set (a pipe, a log or CI gets nothing),
 * and only once the run has taken PROGRESS_AFTER_S of wall time (the environment's
 * PROGRESS_AFTER_S in its place: tests); redrawn at most every PROGRESS_EVERY_S; progress_end
 * clears the line. */
#define PROGRESS_AFTER_S 3.0
#define PROGRESS_EVERY_S 0.25

typedef struct {
    const char *label;
    double total;                   /* in the caller's unit (simulated seconds) */
    double t0, next;                /* wall times: the start, the next redraw */
    int on;                         /* stderr is a terminal and CI is not set */
    int shown;                      /* a line is on the screen */
} progress_t;

void progress_start(progress_t *p, const char *label, double total);
void progress_show(progress_t *p, double done);
void progress_end(progress_t *p);
/* The line for done of total after elapsed seconds, as progress_show writes it (for the tests). */
int progress_line(char *buf, int n, const char *label, double done, double total, double elapsed);

#endif

#!/usr/bin/env python3
"""progress.py: a one-line progress (done / total, elapsed, estimate) on stderr for the long host
commands (make report, family, faults, redraw), only when stderr is a terminal and CI is not set:
a pipe, a log (make test's) or CI gets nothing. Shown once the work has taken PROGRESS_AFTER_S of
wall time (the environment's PROGRESS_AFTER_S in its place), redrawn at most 4 times a second;
the line is cleared at the end. The simulator's own runs do the same (sim/progress.c)."""
import os
import sys
import time

AFTER_S = 3.0
EVERY_S = 0.25


def wanted(stream=None):
    s = stream or sys.stderr
    return s.isatty() and not os.environ.get("CI")


def mmss(s):
    s = int(s + 0.5)
    return "%d:%02d" % (s // 60, s % 60)


def line(label, done, total, elapsed):
    left = mmss(elapsed * (total - done) / done) if done > 0 and total >= done else "?"
    return "%s: %d / %d runs, %s elapsed, about %s left" % (label, done, total, mmss(elapsed), left)


class Progress:
    def __init__(self, label, total, stream=None):
        self.label, self.total, self.done = label, total, 0
        self.stream = stream or sys.stderr
        self.on = wanted(self.stream)
        self.t0 = time.monotonic()
        after = os.environ.get("PROGRESS_AFTER_S")
        self.next = self.t0 + (float(after) if after else AFTER_S)
        self.shown = False

    def add(self, n=1):
        self.done += n
        now = time.monotonic()
        if not self.on or now < self.next:
            return
        self.next = now + EVERY_S
        self.stream.write("\r\033[K" + line(self.label, self.done, self.total, now - self.t0))
        self.stream.flush()
        self.shown = True

    def end(self):
        if self.shown:
            self.stream.write("\r\033[K")
            self.stream.flush()
        self.shown = False


def pool_map(pool, func, jobs, label):
    """pool.map(func, jobs) with its progress shown: the results in the jobs' order."""
    p = Progress(label, len(jobs))
    out = []
    try:
        for r in pool.imap(func, jobs, chunksize=1):
            out.append(r)
            p.add()
    finally:
        p.end()
    return out

#!/usr/bin/env python3
"""ctl_tail.py DIR [DIR ..] [--controller ffmap]: where the tail of the loop's dose share comes from.

Reads the runs.csv of one or more `make family` / tools/family.py output directories (each
written with this simulator, which reports `dose_ctl_start_pct`), takes the controller's runs
above the 95th percentile of abs(dose_ctl_pct) over them all, and counts them by the kind of
drive, the pump (PTO coupled to the wheels or fixed), the valve (over or under 6 s of travel)
and the sign of their share in the start (power-up until 5 s after the boom first opened:
short, the boom sprayed less than the target; over, more). Then the share of those runs whose
start carries over half of their whole share, and the 95th percentiles of the whole share and
of the share past the start.
"""
import argparse
import collections
import csv
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from family import pct  # noqa: E402      # (the family table's percentile: the same cut as its 95th)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dirs", nargs="+")
    ap.add_argument("--controller", default="ffmap")
    a = ap.parse_args()
    runs = []
    for d in a.dirs:
        path = os.path.join(d, "runs.csv")
        try:
            with open(path) as f:
                rows = [r for r in csv.DictReader(f) if r["controller"] == a.controller]
        except OSError as e:
            sys.exit("ctl_tail: %s: %s" % (path, e.strerror))
        if rows and "dose_ctl_start_pct" not in rows[0]:
            sys.exit("ctl_tail: %s: no dose_ctl_start_pct (written by an older simulator)" % path)
        runs += [r for r in rows if r["dose_ctl_abs_pct"] and r["dose_ctl_start_pct"]]
    if not runs:
        sys.exit("ctl_tail: no runs of %s" % a.controller)
    whole = [float(r["dose_ctl_abs_pct"]) for r in runs]
    past = [float(r["dose_ctl_after_abs_pct"]) for r in runs]
    cut = pct(whole, 0.95)
    tail = [r for r in runs if float(r["dose_ctl_abs_pct"]) > cut]
    kinds = collections.Counter()
    start_most = 0
    for r in tail:
        start = float(r["dose_ctl_start_pct"])
        kinds[(r["kind"], "coupled PTO" if r["pto_coupled"] == "1" else "fixed PTO",
               "valve over 6 s" if float(r["valve_travel_s"]) > 6 else "valve under 6 s",
               "start over" if start > 0 else "start short")] += 1
        start_most += abs(start) > 0.5 * float(r["dose_ctl_abs_pct"])
    print("%s: %d runs; 95th percentile of abs(dose_ctl_pct) %.3f %%, past the start %.3f %%"
          % (a.controller, len(runs), cut, pct(past, 0.95)))
    print("the %d runs above it, by drive, pump, valve and the start's share:" % len(tail))
    for k, n in kinds.most_common():
        print("  %-52s %5d" % (", ".join(k), n))
    print("the start over half of the run's share: %d of %d (%.0f %%)"
          % (start_most, len(tail), 100.0 * start_most / len(tail)))


if __name__ == "__main__":
    main()

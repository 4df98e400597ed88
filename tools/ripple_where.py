#!/usr/bin/env python3
"""ripple_where.py: where in a run the flow hunts, for the family's runs over the ripple bound.

Usage: tools/ripple_where.py SIM [--family build/family] [--controller ffmap] [--bound 5]

For every run of the controller in FAMILY/runs.csv (written by `make family`) whose ripple_p95_pct
is over the bound, runs the simulator again on its scenario (FAMILY/scn) with --samples and takes
ripple_p95_pct's samples as sim/metrics.c does (spraying at working speed, the reference within
1 % of the sample's for the 8 s before): the 95th percentile (checked against runs.csv), the
samples over the bound in the first 25 s of the run, from 25 to 60 s and after (the start, the
loop's first learning, the steady run), and the 95th percentile without the first 60 s.
"""
import argparse
import csv
import math
import os
import subprocess
import sys
import tempfile

HOLD_S = 8.0    # sim/metrics.h METRICS_RIPPLE_HOLD_S
FRAC = 0.01     # sim/metrics.h METRICS_RIPPLE_FRAC
SPLIT_S = (25.0, 60.0)


def ripple_samples(path):
    """(t, abs(flow / target - 1) in %) of ripple_p95_pct's samples in a --samples file."""
    with open(path) as f:
        rows = list(csv.DictReader(f))
    t = [float(r["t_s"]) for r in rows]
    ref = [float(r["ref_lpm"]) for r in rows]
    tgt = [float(r["target_lpm"]) for r in rows]
    flow = [float(r["flow_lpm"]) for r in rows]
    ok = [float(r["work"]) != 0 and float(r["spray"]) != 0 for r in rows]
    if len(t) < 3:
        return []
    hold = int(HOLD_S / (t[2] - t[1]) + 0.5)
    out = []
    for k in range(hold, len(rows)):
        if not (tgt[k] > 0 and ref[k] > 0):
            continue
        band = FRAC * ref[k]
        if all(ok[j] and abs(ref[j] - ref[k]) <= band for j in range(k - hold, k + 1)):
            out.append((t[k], abs(flow[k] / tgt[k] - 1.0) * 100.0))
    return out


def p95(values):
    """nearest-rank 95th percentile (sim/metrics.c metrics_ripple_p95), NaN for none"""
    v = sorted(values)
    return v[math.ceil(0.95 * len(v)) - 1] if v else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("sim")
    ap.add_argument("--family", default="build/family")
    ap.add_argument("--controller", default="ffmap")
    ap.add_argument("--bound", type=float, default=5.0)
    a = ap.parse_args()
    with open(os.path.join(a.family, "runs.csv")) as f:
        runs = [r for r in csv.DictReader(f) if r["controller"] == a.controller
                and r["ripple_p95_pct"] not in ("", "nan") and float(r["ripple_p95_pct"]) > a.bound]
    print("plant told  p95 %%   samples  over %g %%: <%gs %g-%gs >%gs   p95 %% after %gs"
          % (a.bound, SPLIT_S[0], SPLIT_S[0], SPLIT_S[1], SPLIT_S[1], SPLIT_S[1]))
    bad = 0
    with tempfile.TemporaryDirectory() as tmp:
        for r in runs:
            told = r["told"]
            name = "plant_%03d%s.scn" % (int(r["plant"]), {"1": "_told", "0": "_untold"}.get(told, ""))
            scn = os.path.join(a.family, "scn", name)
            if not os.path.exists(scn):
                scn = os.path.join(a.family, "scn", "plant_%03d.scn" % int(r["plant"]))
            smp = os.path.join(tmp, "s.csv")
            subprocess.run([a.sim, "--scenario", scn, "--controller", a.controller, "--samples", smp],
                           check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            s = ripple_samples(smp)
            whole = p95([e for _, e in s])
            if abs(whole - float(r["ripple_p95_pct"])) > 1e-3:
                bad += 1        # (another simulator than the family's, or the metric changed)
            over = [t for t, e in s if e > a.bound]
            print("%5s %4s %6.2f %9d %14d %7d %6d %14.2f" % (
                r["plant"], told, whole, len(s), sum(t < SPLIT_S[0] for t in over),
                sum(SPLIT_S[0] <= t < SPLIT_S[1] for t in over), sum(t >= SPLIT_S[1] for t in over),
                p95([e for t, e in s if t >= SPLIT_S[1]])))
    if bad:
        print("ripple_where: %d runs' 95th percentile differs from runs.csv" % bad, file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())

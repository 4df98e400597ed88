#!/usr/bin/env python3
"""sim_same.py: do two simulator builds compute the same runs, up to rounding?

usage: sim_same.py OLD_SIM NEW_SIM [--seeds A-B] [--rel R] [--traces]
Runs every scenarios/*.scn with each build, at the file's own seed and at seeds A-B (1-3), and
compares every number of the metrics JSON (wall and CPU time aside): a figure differs when it
moves by more than R of itself (1e-9) and by more than R in absolute terms. --traces also
compares the CSV traces (0.1 s rows) byte for byte. A speed-up that leaves the physics alone
(reordered arithmetic, cached constants) shows rounding-level differences only; one that changes
the random draws or the model shows up here, and belongs to tools/seed_spread.py instead.
Prints the runs that differ and a summary line; exit status 1 when any does. Stdlib only.
"""
import glob
import json
import os
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor

TIMES = ("wall_s", "cpu_s", "speed_x_realtime")


def flat(x, path=""):
    if isinstance(x, dict):
        for k, v in x.items():
            if k not in TIMES:
                yield from flat(v, path + "." + k)
    elif isinstance(x, list):
        for i, v in enumerate(x):
            yield from flat(v, "%s[%d]" % (path, i))
    else:
        yield path, x


def run(sim, scn, seed, csv):
    cmd = [sim, "--scenario", scn] + (["--seed", str(seed)] if seed is not None else [])
    cmd += ["--csv", csv] if csv else []
    out = subprocess.run(cmd, capture_output=True, text=True)
    if out.returncode != 0:
        raise SystemExit("sim_same.py: %s failed: %s" % (" ".join(cmd), out.stderr.strip()))
    return dict(flat(json.loads(out.stdout.strip().splitlines()[-1])))


def compare(job):
    old, new, scn, seed, rel, traces, tmp = job
    tag = "%s%s" % (os.path.basename(scn), "" if seed is None else " seed %d" % seed)
    csv_a = csv_b = None
    if traces and seed is None:
        csv_a = os.path.join(tmp, os.path.basename(scn) + ".old.csv")
        csv_b = os.path.join(tmp, os.path.basename(scn) + ".new.csv")
    a, b = run(old, scn, seed, csv_a), run(new, scn, seed, csv_b)
    diffs, worst = [], 0.0
    for k in sorted(set(a) | set(b)):
        x, y = a.get(k), b.get(k)
        if isinstance(x, (int, float)) and isinstance(y, (int, float)) and not isinstance(x, bool):
            d = abs(x - y)
            r = d / max(abs(x), abs(y), 1e-300)
            if d > rel and r > rel:
                diffs.append("%s %g -> %g" % (k, x, y))
            elif d > 0:
                worst = max(worst, min(d, r))
        elif x != y:
            diffs.append("%s %r -> %r" % (k, x, y))
    if csv_a:
        with open(csv_a, "rb") as fa, open(csv_b, "rb") as fb:
            if fa.read() != fb.read():
                diffs.append("the CSV trace differs")
    return tag, diffs, worst


def main():
    args = sys.argv[1:]
    if len(args) < 2:
        sys.exit(__doc__)
    old, new, rest = args[0], args[1], args[2:]
    seeds, rel, traces = (1, 3), 1e-9, False
    i = 0
    while i < len(rest):
        if rest[i] == "--traces":
            traces = True
            i += 1
            continue
        if i + 1 >= len(rest):
            sys.exit(__doc__)
        if rest[i] == "--seeds":
            try:
                lo, hi = (int(v) for v in rest[i + 1].split("-"))
            except ValueError:
                sys.exit("sim_same.py: --seeds '%s' is not A-B" % rest[i + 1])
            if not 0 <= lo <= hi:
                sys.exit("sim_same.py: --seeds '%s' is not A-B with A <= B" % rest[i + 1])
            seeds = (lo, hi)
        elif rest[i] == "--rel":
            try:
                rel = float(rest[i + 1])
            except ValueError:
                sys.exit("sim_same.py: --rel '%s' is not a number" % rest[i + 1])
            if not 0.0 <= rel < 1.0:
                sys.exit("sim_same.py: --rel %g is not a fraction 0..1" % rel)
        else:
            sys.exit(__doc__)
        i += 2
    for sim in (old, new):
        if not os.access(sim, os.X_OK):
            sys.exit("sim_same.py: %s is not an executable simulator" % sim)
    scns = sorted(glob.glob("scenarios/*.scn"))
    if not scns:
        sys.exit("sim_same.py: no scenarios/*.scn here (run it from the repository's top)")
    with tempfile.TemporaryDirectory() as tmp:
        jobs = [(old, new, scn, seed, rel, traces, tmp)
                for scn in scns for seed in [None] + list(range(seeds[0], seeds[1] + 1))]
        with ThreadPoolExecutor(2) as ex:
            results = list(ex.map(compare, jobs))
    bad = [(tag, d) for tag, d, _ in results if d]
    for tag, d in bad:
        print("%s: %d figures differ: %s" % (tag, len(d), "; ".join(d[:4])))
    print("sim_same: %d of %d runs differ beyond %g (largest difference within it %.2g)%s"
          % (len(bad), len(results), rel, max(w for _, _, w in results), ", traces compared" if traces else ""))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())

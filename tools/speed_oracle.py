#!/usr/bin/env python3
"""speed_oracle.py [--seeds A-B] [--scenario FILE]: what the start owes to the measured speed.

While the wheel's spacing offsets are unlearnt (the first turns of a run) the firmware's speed is
a tracker's filter on the wheel's edges (speed.c; a window of pulses before the twenty-seventh
round, which lagged the tractor and moved only at pulses). This
tool copies the tracked files of the working tree to a temporary folder, applies
tools/speed_oracle.patch (the simulator keeps the true speed of each 0.1 s sample; speed.c, once
the wheel gave a speed and until its offsets are learnt, returns that true speed ORACLE_LAG
samples late, every period or, ORACLE_HELD, taken only when a pulse comes), builds the host
simulator once a variant, and runs FILE (default scenarios/paper_dynamic_150.scn) with `ffmap` on
seeds A-B (default 1-64) with each and with the unpatched firmware. Prints per variant the mean
`start_s`, the seeds over 3 s, the mean step overshoot and CV. Nothing in the tree is changed;
the builds are deleted at the end. docs/CONTROLLERS.md (the twenty-sixth and twenty-seventh rounds) quotes it.
"""
import os
import shutil
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor

from robust import run

# (label, ORACLE_LAG in 0.1 s samples, ORACLE_HELD); None: the firmware as it is
VARIANTS = [
    ("the firmware's tracker (as built)", None, None),
    ("true speed, every period", 0, 0),
    ("true speed 0.2 s late, every period", 2, 0),
    ("true speed 0.3 s late, every period", 3, 0),
    ("true speed 0.4 s late, every period", 4, 0),
    ("true speed 0.5 s late, every period", 5, 0),
    ("true speed 0.6 s late, every period", 6, 0),
    ("true speed 0.7 s late, every period", 7, 0),
    ("true speed, taken at pulses", 0, 1),
    ("true speed 0.3 s late, taken at pulses", 3, 1),
    ("true speed 0.5 s late, taken at pulses", 5, 1),
]


def main():
    args = sys.argv[1:]
    first, last = 1, 64
    scn = "scenarios/paper_dynamic_150.scn"
    if "--seeds" in args:
        a, b = args[args.index("--seeds") + 1].split("-")
        first, last = int(a), int(b)
    if "--scenario" in args:
        scn = args[args.index("--scenario") + 1]
    if not os.path.isfile("tools/speed_oracle.patch"):
        sys.exit("speed_oracle.py: run it from the repository's top")
    scn = os.path.abspath(scn)
    seeds = list(range(first, last + 1))
    tmp = tempfile.mkdtemp(prefix="speed_oracle_")
    try:
        files = subprocess.run(["git", "ls-files", "-z"], capture_output=True, check=True).stdout
        for f in files.decode().split("\0"):
            if f and os.path.isfile(f):
                os.makedirs(os.path.join(tmp, "plain", os.path.dirname(f)), exist_ok=True)
                shutil.copy2(f, os.path.join(tmp, "plain", f))
        shutil.copytree(os.path.join(tmp, "plain"), os.path.join(tmp, "oracle"))
        with open("tools/speed_oracle.patch") as p:
            if subprocess.run(["patch", "-s", "-p1"], stdin=p, cwd=os.path.join(tmp, "oracle")).returncode:
                sys.exit("speed_oracle.py: tools/speed_oracle.patch no longer applies to speed.c and sim.c: "
                         "make it again against them")
        print("speed_oracle: %s, ffmap, seeds %d-%d" % (os.path.basename(scn), first, last))
        print("| speed the firmware's target takes while the wheel is unlearnt | `start_s` | seeds over 3 s | overshoot | CV |")
        print("|---|---|---|---|---|")
        for label, lag, held in VARIANTS:
            tree = os.path.join(tmp, "plain" if lag is None else "oracle")
            build = os.path.join(tmp, "b%s_%s" % (lag, held))
            cc = "cc" if lag is None else "cc -DORACLE_LAG=%d -DORACLE_HELD=%d" % (lag, held)
            sim = os.path.join(build, "host", "bin", "sim")
            subprocess.run(["make", "-s", "BUILD=" + build, "CC=" + cc, sim], cwd=tree, check=True,
                           stdout=subprocess.DEVNULL)
            with ThreadPoolExecutor(2) as ex:
                res = list(ex.map(run, [(sim, scn, "ffmap", s) for s in seeds]))
            n = len(res)
            print("| %s | %.2f s | %d of %d | %.3f %% | %.3f %% |" % (
                label, sum(r["start_s"] for r in res) / n, sum(r["start_s"] > 3 for r in res), n,
                sum(r["overshoot_mean_pct"] for r in res) / n, sum(r["cv_pct"] for r in res) / n))
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())

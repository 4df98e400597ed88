#!/usr/bin/env python3
"""seeds.py: best against bp_pid over seeds, counting the metric checks where best is worse.

usage: seeds.py [SIM_BIN] [--seeds 1-7] [--own] [-v]
SIM_BIN defaults to build/rob/host/bin/sim. For each scenario and seed, both controllers run
on the same plant; the checks are dose_error_pct (abs), cv_pct, overshoot_mean_pct and
settle_mean_s where present, and for the target steps (only) the mean rise, overshoot and settling
(settle_5pct_s) of the JSON's "steps". --own adds the scenarios' own seeds. Prints the
worse-count (and with -v every check); stdlib only.
"""
import json
import subprocess
import sys

SCENARIOS = ["target_step_150", "paper_dynamic_150", "paper_dynamic_150_fixed_pto"]
KEYS = ["dose_error_pct", "cv_pct", "overshoot_mean_pct", "settle_mean_s"]


def run(sim, scn, ctl, seed):
    cmd = [sim, "--scenario", "scenarios/%s.scn" % scn, "--controller", ctl]
    if seed is not None:
        cmd += ["--seed", str(seed)]
    out = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def mean(xs):
    xs = [x for x in xs if x is not None]
    return sum(xs) / len(xs) if xs else None


def metrics(m, steps):
    r = {}
    for k in KEYS:
        v = m.get(k)
        if v is not None:
            r[k] = abs(v) if k == "dose_error_pct" else v
    st = m.get("steps") or []
    if st and steps:
        r["step_rise"] = mean([s.get("rise_s") for s in st])
        r["step_ovs"] = mean([s.get("overshoot_pct") for s in st])
        r["step_settle"] = mean([s.get("settle_5pct_s") for s in st])
    return {k: v for k, v in r.items() if v is not None}


def main():
    args = sys.argv[1:]
    sim = next((a for a in args if not a.startswith("-") and "/" in a), "build/rob/host/bin/sim")
    seeds = list(range(1, 8))
    if "--seeds" in args:
        a, _, b = args[args.index("--seeds") + 1].partition("-")
        seeds = list(range(int(a), int(b or a) + 1))
    if "--own" in args:
        seeds = [None] + seeds
    verbose = "-v" in args
    worse, total = [], 0
    sums = {}
    for scn in SCENARIOS:
        for seed in seeds:
            b = metrics(run(sim, scn, "best", seed), scn.startswith("target_step"))
            n = metrics(run(sim, scn, "bp_pid", seed), scn.startswith("target_step"))
            for k in b:
                if k not in n:
                    continue
                total += 1
                s = sums.setdefault((scn, k), [0.0, 0.0])
                s[0] += b[k]
                s[1] += n[k]
                bad = b[k] > n[k]
                if bad:
                    worse.append("%s/%s/seed %s: %.4g > %.4g" % (scn, k, seed, b[k], n[k]))
                if verbose:
                    print("%-28s %-18s seed %-4s best %9.4f bp_pid %9.4f %s" % (scn, k, seed, b[k], n[k],
                                                                               "WORSE" if bad else ""))
    print("sums over seeds (best / bp_pid):")
    for (scn, k), (sb, sn) in sums.items():
        print("  %-28s %-18s %9.3f %9.3f %s" % (scn, k, sb, sn, "*" if sb > sn else ""))
    for w in worse:
        print("worse: " + w)
    print("best worse than bp_pid on %d of %d checks" % (len(worse), total))


if __name__ == "__main__":
    main()

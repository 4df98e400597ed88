#!/usr/bin/env python3
"""seed_spread.py: the simulator's metrics over a set of seeds, saved or checked against saved ones.

usage: seed_spread.py SIM_BIN --save REF.json [--seeds A-B]
       seed_spread.py SIM_BIN --check REF.json [--args "SIM_OPTIONS"] [--rel R] [--skip SCN:FIG,..]
A change that alters the random draws (when noise is drawn, how the pulsation is computed) must
leave the physics alone: for every scenario and figure below, the mean over the seeds may move by
no more than the seed-to-seed spread (the sample standard deviation over the seeds, the larger
of the reference's and the new one's). --check prints one TAP line per scenario; --args runs the
simulator with those options (e.g. "--fast": an approximate mode held to the same spread of the
1 ms model's reference), where --rel R also lets a mean move by R of itself (figures the seed
barely moves, such as the pressure's extremes, which a longer tick smooths); --skip names figures
of a scenario that mode is known not to hold (printed, not judged). Stdlib only.
"""
import json
import statistics
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

SCENARIOS = ["paper_dynamic_150", "paper_dynamic_100_fixed_pto", "target_step_125", "field_3220m_150"]
FIGURES = ["applied_l_ha", "dose_error_pct", "cv_pct", "cv_all_pct", "zone_error_min_pct",
           "zone_error_max_pct", "overshoot_mean_pct", "settle_mean_s", "valve_reversals_per_min",
           "valve_travel_strokes", "pressure_min_bar", "pressure_max_bar", "volume_l"]


def run(job):
    sim, scn, seed, args = job
    out = subprocess.run([sim, "--scenario", "scenarios/%s.scn" % scn, "--seed", str(seed)] + args,
                         capture_output=True, text=True, check=True).stdout
    m = json.loads(out.strip().splitlines()[-1])
    return scn, {k: m[k] for k in FIGURES if isinstance(m.get(k), (int, float))}


def measure(sim, seeds, args=()):
    jobs = [(sim, scn, s, list(args)) for scn in SCENARIOS for s in seeds]
    per = {scn: {k: [] for k in FIGURES} for scn in SCENARIOS}
    with ThreadPoolExecutor(2) as ex:
        for scn, figs in ex.map(run, jobs):
            for k, v in figs.items():
                per[scn][k].append(v)
    return {scn: {k: {"mean": statistics.fmean(v), "sd": statistics.stdev(v), "n": len(v)}
                  for k, v in figs.items() if len(v) >= 2} for scn, figs in per.items()}


def main():
    if len(sys.argv) < 4 or sys.argv[2] not in ("--save", "--check"):
        sys.exit(__doc__)
    sim, mode, ref = sys.argv[1], sys.argv[2], sys.argv[3]
    if mode == "--save":
        a, b = (sys.argv[5] if len(sys.argv) > 5 else "1-16").split("-")
        seeds = list(range(int(a), int(b) + 1))
        with open(ref, "w") as f:
            json.dump({"seeds": seeds, "scenarios": measure(sim, seeds)}, f, indent=1, sort_keys=True)
        return 0
    args, rel, skip = [], 0.0, set()
    rest = sys.argv[4:]
    while rest:
        if len(rest) < 2 or rest[0] not in ("--args", "--rel", "--skip"):
            sys.exit(__doc__)
        opt, val, rest = rest[0], rest[1], rest[2:]
        if opt == "--args":
            args = val.split()
        elif opt == "--skip":
            skip.update(tuple(x.split(":", 1)) for x in val.split(",") if ":" in x)
        else:
            try:
                rel = float(val)
            except ValueError:
                sys.exit("seed_spread.py: --rel '%s' is not a number" % val)
            if not 0.0 <= rel < 1.0:
                sys.exit("seed_spread.py: --rel %g is not a fraction 0..1" % rel)
    mode = " (%s)" % " ".join(args) if args else ""
    old = json.load(open(ref))
    new = measure(sim, old["seeds"], args)
    bad = 0
    for scn in SCENARIOS:
        moved = []
        for k, o in old["scenarios"][scn].items():
            n = new[scn].get(k)
            if (scn, k) in skip:
                print("# seed spread %s%s: %s not held (--skip): %.4g -> %.4g (spread %.3g)"
                      % (scn, mode, k, o["mean"], n["mean"] if n else float("nan"), o["sd"]))
                continue
            if n is None:
                moved.append("%s missing" % k)
                continue
            spread = max(o["sd"], n["sd"], max(rel, 1e-9) * abs(o["mean"]))
            if abs(n["mean"] - o["mean"]) > spread:
                moved.append("%s %.4g -> %.4g (spread %.3g)" % (k, o["mean"], n["mean"], spread))
        worst = max((abs(new[scn][k]["mean"] - o["mean"]) / max(o["sd"], new[scn][k]["sd"], rel * abs(o["mean"]), 1e-12)
                     for k, o in old["scenarios"][scn].items() if k in new[scn] and (scn, k) not in skip),
                    default=0.0)
        if moved:
            bad += 1
            print("not ok - seed spread %s%s: means left the seed-to-seed spread: %s" % (scn, mode, "; ".join(moved)))
        else:
            print("ok - seed spread %s%s: %d figures over %d seeds within the spread (largest move %.2f of it)"
                  % (scn, mode, len(old["scenarios"][scn]), len(old["seeds"]), worst))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())

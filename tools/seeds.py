#!/usr/bin/env python3
"""seeds.py: ffmap against bp_pid (or a peer) over many seeds and every scenario family, figure by figure.

usage: seeds.py SIM_BIN [--seeds A-B] [-v] [--against bp_pid|aog|raven|pid|fuzzy_pid] [--four | --split SCENARIO]
One seed is one draw of the plant's noise (pump pulsation phase, sensor noise, meter and wheel
pulse timing); a single run can favour either controller by luck. For each scenario below and
each seed (default 1-16) both controllers run on the same plant; the figures of docs/SCENARIOS.md are
averaged over the seeds, and ffmap's mean is compared with bp_pid's on every figure (dose error
as its absolute value, the worst zone as its magnitude; lower is better everywhere). Prints a
table and the count of figures where ffmap's mean is worse; -v also prints the per-seed values
of those; for a worse dose error, the split of the signed means into the target's, the meter's
and the controller's shares (the JSON's dose_target_pct, dose_meter_pct, dose_ctl_pct,
dose_ctl_stop_pct). --against C: ffmap against C instead of bp_pid (the peers aog and raven at
their default settings). --four: instead, the means of the paper's four controllers and the two
peers on the 150 L/ha scenarios (the paper's ordering, without the luck of one seed). Also
prints the valve's wear a minute (motor reversals, strokes travelled), which the count of worse
figures leaves out. Two runs at
a time; stdlib only.
--split SCENARIO: instead, where ffmap's and bp_pid's flow leaves its target on that scenario
(mean over the seeds, % of the target volume at v >= 4 km/h, from a 0.1 s trace): while the
target rose by more than 1 % over the last second, while it fell, while it was steady, and while
the valve sat at an end stop.
"""
import csv
import json
import os
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor

SCENARIOS = [
    "target_step_100", "target_step_125", "target_step_150",
    "paper_dynamic_100", "paper_dynamic_125", "paper_dynamic_150",
    "paper_dynamic_100_fixed_pto", "paper_dynamic_125_fixed_pto", "paper_dynamic_150_fixed_pto",
    "field_3220m_100", "field_3220m_125", "field_3220m_150",
]
FIELD = ["dose_error_pct", "cv_pct", "cv_all_pct", "zone_error_min_pct", "zone_error_max_pct",
         "overshoot_mean_pct", "overshoot_max_pct", "settle_mean_s"]
STEP = ["rise_mean_s", "overshoot_mean_pct", "overshoot_max_pct", "settle_mean_s", "sse_mean_abs_pct"]
SHORT = {"dose_error_pct": "|dose|%", "cv_pct": "cv%", "cv_all_pct": "cv_all%",
         "zone_error_min_pct": "|zmin|%", "zone_error_max_pct": "zmax%", "overshoot_mean_pct": "ovs%",
         "overshoot_max_pct": "ovs_max%", "settle_mean_s": "settle_s", "rise_mean_s": "rise_s",
         "sse_mean_abs_pct": "|sse|%"}


def run(job):
    sim, scn, ctl, seed = job
    cmd = [sim, "--scenario", "scenarios/%s.scn" % scn, "--controller", ctl, "--seed", str(seed)]
    out = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def figure(m, k):
    if k == "rise_mean_s":
        r = [s["rise_s"] for s in m.get("steps", []) if s.get("rise_s") is not None]
        return sum(r) / len(r) if r else None
    if k == "sse_mean_abs_pct":
        r = [abs(s["sse_pct"]) for s in m.get("steps", []) if s.get("sse_pct") is not None]
        return sum(r) / len(r) if r else None
    v = m.get(k)
    if v is None:
        return None
    return abs(v) if k in ("dose_error_pct", "zone_error_min_pct") else v


def split_run(job):
    sim, scn, ctl, seed = job
    fd, path = tempfile.mkstemp(prefix="split_", suffix=".csv")
    os.close(fd)
    try:
        subprocess.run([sim, "--scenario", "scenarios/%s.scn" % scn, "--controller", ctl, "--seed", str(seed),
                        "--csv", path, "--trace-period", "0.1"], capture_output=True, check=True)
        with open(path) as f:
            rows = list(csv.DictReader(f))
    finally:
        os.unlink(path)
    tgt = [float(r["target_lpm"]) for r in rows]
    acc = {"rising": 0.0, "falling": 0.0, "steady": 0.0, "at a stop": 0.0}
    total = 0.0
    for i, r in enumerate(rows):
        if float(r["v_true_kmh"]) < 4:
            continue
        total += tgt[i]
        th, d = float(r["valve_pos"]), tgt[i] - tgt[max(0, i - 10)]
        k = ("at a stop" if th <= 0.0 or th >= 1.0 else "rising" if d > 0.01 * tgt[i]
             else "falling" if d < -0.01 * tgt[i] else "steady")
        acc[k] += float(r["flow_true_lpm"]) - tgt[i]
    return {k: 100.0 * v / total for k, v in acc.items()} if total > 0 else acc


def split(sim, scn, seeds):
    jobs = [(sim, scn, c, sd) for c in ("ffmap", "bp_pid") for sd in seeds]
    with ThreadPoolExecutor(2) as ex:
        res = list(ex.map(split_run, jobs))
    print("%s: flow beyond the target, %% of the target volume at v >= 4 km/h, means over seeds %d-%d"
          % (scn, seeds[0], seeds[-1]))
    for n, c in enumerate(("ffmap", "bp_pid")):
        part = res[n * len(seeds):(n + 1) * len(seeds)]
        print("  %-6s " % c + "; ".join("%s %+.4f" % (k, sum(p[k] for p in part) / len(part)) for k in part[0]))
    return 0


def four(sim, seeds):
    scns = ["target_step_150", "paper_dynamic_150", "paper_dynamic_150_fixed_pto", "field_3220m_150"]
    ctls = ["pid", "fuzzy_pid", "bp_pid", "ffmap", "aog", "raven"]
    jobs = [(sim, s, c, seed) for s in scns for c in ctls for seed in seeds]
    with ThreadPoolExecutor(2) as ex:
        res = dict(zip([(j[1], j[2], j[3]) for j in jobs], ex.map(run, jobs)))
    print("the paper's four controllers and the two peers: means over seeds %d-%d" % (seeds[0], seeds[-1]))
    for s in scns:
        keys = (["rise_mean_s", "overshoot_mean_pct", "settle_mean_s", "sse_mean_abs_pct"] if s.startswith("target")
                else ["dose_error_pct", "cv_pct", "zone_error_min_pct", "zone_error_max_pct", "overshoot_mean_pct",
                      "settle_mean_s"])
        print("  %s" % s)
        print("    %-10s" % "" + "".join("%11s" % SHORT[k] for k in keys))
        for c in ctls:
            vals = []
            for k in keys:
                v = [figure(res[(s, c, sd)], k) for sd in seeds]
                vals.append(sum(v) / len(v) if all(x is not None for x in v) else float("nan"))
            print("    %-10s" % c + "".join("%11.3f" % v for v in vals))
    return 0


def sim_and_seeds(args, doc, first, last):
    """The simulator (the first argument) and the seeds (--seeds A-B, else first..last) of a
    command line; (None, None) after printing the usage when there is no simulator."""
    if not args or args[0].startswith("-"):
        print(doc.strip(), file=sys.stderr)
        return None, None
    seeds = list(range(first, last + 1))
    if "--seeds" in args:
        a, b = args[args.index("--seeds") + 1].split("-")
        seeds = list(range(int(a), int(b) + 1))
    return args[0], seeds


def main():
    args = sys.argv[1:]
    sim, seeds = sim_and_seeds(args, __doc__, 1, 16)
    if sim is None:
        return 2
    verbose = "-v" in args
    if "--four" in args:
        return four(sim, seeds)
    if "--split" in args:
        return split(sim, args[args.index("--split") + 1], seeds)
    other = args[args.index("--against") + 1] if "--against" in args else "bp_pid"
    jobs = [(sim, s, c, seed) for s in SCENARIOS for c in ("ffmap", other) for seed in seeds]
    with ThreadPoolExecutor(2) as ex:
        res = dict(zip([(j[1], j[2], j[3]) for j in jobs], ex.map(run, jobs)))
    print("ffmap against %s: means over seeds %d-%d (same plant, same seed for both)" % (other, seeds[0], seeds[-1]))
    worse, total = [], 0
    for s in SCENARIOS:
        keys = STEP if s.startswith("target_step") else FIELD
        cells = []
        for k in keys:
            va = [figure(res[(s, "ffmap", sd)], k) for sd in seeds]
            vb = [figure(res[(s, other, sd)], k) for sd in seeds]
            if any(v is None for v in va + vb):
                continue
            ma, mb = sum(va) / len(va), sum(vb) / len(vb)
            total += 1
            bad = ma > mb * (1 + 1e-6) + 1e-12
            cells.append("%s %.3g/%.3g%s" % (SHORT[k], ma, mb, " WORSE" if bad else ""))
            if bad:
                worse.append((s, k, ma, mb, va, vb))
        print("  %-28s %s" % (s, "; ".join(cells)))
    # the valve's wear (not counted above): motor reversals a minute of spraying (the sim JSON's
    # valve_reversals_per_min) and strokes travelled a minute of the run
    if all("valve_reversals_per_min" in r for r in res.values()):
        print("valve wear, a minute (ffmap/%s; not counted below):" % other)
        for s in SCENARIOS:
            w = {}
            for c in ("ffmap", other):
                w[c] = (sum(res[(s, c, sd)]["valve_reversals_per_min"] or 0 for sd in seeds) / len(seeds),
                        sum(res[(s, c, sd)]["valve_travel_strokes"] * 60 / res[(s, c, sd)]["sim_s"] for sd in seeds)
                        / len(seeds))
            print("  %-28s reversals %.1f/%.1f; travel %.2f/%.2f strokes"
                  % (s, w["ffmap"][0], w[other][0], w["ffmap"][1], w[other][1]))
    print("ffmap worse than %s on %d of %d mean figures%s" % (other, len(worse), total, ":" if worse else ""))
    for s, k, ma, mb, va, vb in worse:
        print("  %s/%s: %.4g > %.4g (%+.2g %%)" % (s, k, ma, mb, 100 * (ma - mb) / mb if mb else float("inf")))
        if verbose:
            print("    ffmap   " + " ".join("%.4g" % v for v in va))
            print("    %-6s " % other + " ".join("%.4g" % v for v in vb))
        if k == "dose_error_pct" and all("dose_ctl_pct" in res[(s, c, sd)] for c in ("ffmap", other) for sd in seeds):
            # the split of the signed dose error (sim JSON): the target's own share, the same for
            # both, and the controller's share, with the part while the valve sat at an end stop
            for c in ("ffmap", other):
                m = {x: sum(res[(s, c, sd)][x] for sd in seeds) / len(seeds)
                     for x in ("dose_error_pct", "dose_target_pct", "dose_meter_pct", "dose_ctl_pct",
                               "dose_ctl_stop_pct")}
                print("    %-6s signed dose %+.4f %% = target's share %+.4f + meter's %+.4f + controller's %+.4f "
                      "(%+.4f at an end stop, %+.4f elsewhere)"
                      % (c, m["dose_error_pct"], m["dose_target_pct"], m["dose_meter_pct"], m["dose_ctl_pct"],
                         m["dose_ctl_stop_pct"], m["dose_ctl_pct"] - m["dose_ctl_stop_pct"]))
    return 0


if __name__ == "__main__":
    sys.exit(main())

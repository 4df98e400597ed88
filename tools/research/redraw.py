#!/usr/bin/env python3
"""redraw.py: plants of the family run again with more noise draws.

Usage: tools/research/redraw.py SIM [SEED/PLANT/told|untold ...] [--select fast-high|fast-stiff [--seeds 1-140]]
                       [--draws 12] [--controller ffmap] [--jobs N] [--out build/redraw]

A family run is one noise draw of its plant: the pump's pulsation, the meter's blades, the
wheel's pulses and the pressure's noise come from the scenario's seed. An alarm run on the
family can be a plant where a few draws in a dozen raise an alarm, so one family run says little
about a change that aims at it. This runs each named plant (plant 35 of SEED=28, told 4 s:
28/35/untold) with its own seed and with --seed 1 .. DRAWS-1, and counts the runs with an alarm.
The scenario is the one `make family SEED=28` writes (tools/family.py's draw), written to
OUT/scn. Without plants, a default set (ALARM_PLANTS in this file): fast valves where a few
draws in a dozen raised OVERPRESSURE or OFF_RATE.
--select picks every plant of the seeds (each told and untold) of a class where the family's
alarm runs come from: fast-high, a valve under 3 s whose nozzles need 4 bar or more somewhere in
the drive (P max is 4.8: OVERPRESSURE); fast-stiff, a valve under 3 s that breaks away at 0.25
or more (Min duty says 0.2: a gain cut too deep creeps, OFF_RATE; from 0.25, not 0.30: valves
that break away at 0.28 crept too). A change aimed at one class is judged on both.
Prints per plant the alarm runs (the first alarm's code and time of each) and the median CV, then
the total; a bad plant name is refused in one line.
"""
import argparse
import os
import sys
from multiprocessing import Pool

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import family  # noqa: E402  (tools/family.py: the family's draw and scenario files)
import progress  # noqa: E402  (tools/progress.py: the progress line on a terminal)

FAMILY_N = 200  # plants a seed (make family N=200)
# fast valves where a few noise draws in a dozen raised OVERPRESSURE or OFF_RATE: the classes
# --select picks
ALARM_PLANTS = ["236/192/untold", "28/35/untold", "29/34/untold", "50/155/untold",
                "69/171/untold", "89/42/untold", "120/124/told", "57/9/untold"]


def parse_plant(text):
    parts = text.split("/")
    if len(parts) != 3 or not parts[0].isdigit() or not parts[1].isdigit() or parts[2] not in ("told", "untold"):
        raise ValueError("%s: a plant is SEED/NUMBER/told or SEED/NUMBER/untold (28/35/untold)" % text)
    return int(parts[0]), int(parts[1]), parts[2] == "told"


def select(kind, first, last):
    """Every plant of seeds first..last in the class, told and untold (SEED/NUMBER/told names)."""
    out = []
    for seed in range(first, last + 1):
        for i in range(FAMILY_N):
            d = family.draw(seed, i, "both")
            p = d["plant"]
            if p["valve_travel_s"] >= 3.0:
                continue
            if kind == "fast-high":
                vmax = max(v for _, v in d["drive"])
                hit = family.nozzle_bar(d["rate"], vmax, p["nozzle_wear_pct"], p["check_valve_bar"]) >= 4.0
            else:
                hit = p["valve_stiction_duty"] >= 0.25
            if hit:
                out += ["%d/%d/told" % (seed, i), "%d/%d/untold" % (seed, i)]
    return out


def run_one(job):
    return family.run_sim(*job)     # (sim, scenario, controller, draw: 0 the plant's own seed)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("sim")
    ap.add_argument("plants", nargs="*")
    ap.add_argument("--select", choices=("fast-high", "fast-stiff"))
    ap.add_argument("--seeds", default="1-140")
    ap.add_argument("--draws", type=int, default=12)
    ap.add_argument("--controller", default="ffmap")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 2)
    ap.add_argument("--out", default="build/redraw")
    a = ap.parse_args()
    if not os.access(a.sim, os.X_OK):
        sys.exit("redraw: %s: not an executable simulator (make sim-progs)" % a.sim)
    if a.draws < 1:
        sys.exit("redraw: --draws must be at least 1")
    names = list(a.plants)
    if a.select:
        r = a.seeds.split("-")
        if len(r) != 2 or not r[0].isdigit() or not r[1].isdigit() or int(r[0]) > int(r[1]):
            sys.exit("redraw: --seeds %s: give a range FIRST-LAST (1-140)" % a.seeds)
        picked = select(a.select, int(r[0]), int(r[1]))
        if not picked:
            sys.exit("redraw: no plant of seeds %s is %s" % (a.seeds, a.select))
        names += picked
    try:
        plants = [parse_plant(p) for p in (names or ALARM_PLANTS)]
    except ValueError as e:
        sys.exit("redraw: %s" % e)
    scn_dir = os.path.join(a.out, "scn")
    os.makedirs(scn_dir, exist_ok=True)
    jobs, labels = [], []
    for seed, i, told in plants:
        d = dict(family.draw(seed, i, "both"), told=told)
        t = "told" if told else "untold"
        name = "%d/%d/%s" % (seed, i, t)
        path = os.path.join(scn_dir, "seed%d_plant_%03d_%s.scn" % (seed, i, t))
        with open(path, "w") as f:
            f.write(family.scenario_text(i, d))
        labels.append(name)
        jobs += [(a.sim, path, a.controller, k) for k in range(a.draws)]
    with Pool(max(1, a.jobs)) as pool:
        results = progress.pool_map(pool, run_one, jobs, "redraw")
    bad = [(j, m) for j, m in zip(jobs, results) if "error" in m]
    if bad:
        sys.exit("redraw: %d runs failed, first: %s --seed %d: %s" % (len(bad), bad[0][0][1], bad[0][0][3], bad[0][1]["error"]))
    total = 0
    print("%s, %d draws a plant (the plant's own seed, then --seed 1..%d): runs with an alarm"
          % (a.controller, a.draws, a.draws - 1))
    for n, name in enumerate(labels):
        ms = results[n * a.draws:(n + 1) * a.draws]
        hits = ["%s: %.1f s %s" % ("own" if k == 0 else "seed %d" % k, m["alarms"][0]["t_s"], m["alarms"][0]["code"])
                for k, m in enumerate(ms) if m["alarms"]]
        total += len(hits)
        cvs = sorted(m["cv_pct"] for m in ms)
        print("%-16s %2d of %d   median CV %.2f %%   %s" % (name, len(hits), a.draws, family.pct(cvs, 0.5),
                                                          "; ".join(hits)))
    print("alarm runs: %d of %d" % (total, len(jobs)))


if __name__ == "__main__":
    main()

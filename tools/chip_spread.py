#!/usr/bin/env python3
"""chip_spread.py: make chip's metrics beside make sim's seed-to-seed spread on the same scenario.

usage: chip_spread.py SIM_BIN IHX S51 [--scenario F] [--input F] [--seeds A-B] [--chip-seeds A-B]
Runs the host build over the seeds (default 1-16) and the field image in the STC12C5A60S2 model.
By default the model runs once, at the scenario's seed: each figure is printed with the host's
mean, sample standard deviation and range over the seeds, and whether the chip's value lies within
the range. One run is one sample: drawn from the host's own distribution, it would fall outside
the range of N other samples with probability 2/(N+1) for each figure.
With --chip-seeds the model runs at each of those seeds too (two at a time, about 25 s of CPU a
run for pil_bench), and each figure's mean over the chip's seeds is set against the host's: the
difference in standard errors of the difference (Welch), "differs" beyond 3; then the ratio of
the two standard deviations, "wider" or "narrower" beyond 2 (the chip's seed-to-seed spread
against the host's).
Stdlib only.
"""
import json
import math
import statistics
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

FIGURES = ["applied_l_ha", "dose_error_pct", "dose_ctl_pct", "valve_reversals_per_min", "valve_travel_strokes",
           "silent_wrong_s", "pressure_min_bar", "pressure_max_bar", "volume_l"]
Z_DIFFERS = 3.0
SD_RATIO = 2.0


def last_json(out):
    return json.loads(out.strip().splitlines()[-1])


def seed_range(text):
    lo, hi = text.split("-")
    return range(int(lo), int(hi) + 1)


def values(runs, f):
    return [r[f] for r in runs if r.get(f) is not None]


def one_run(chip, runs, seeds):
    print("figure                     chip (seed %d)   host mean    sd      min .. max (seeds %d-%d)" %
          (chip["seed"], seeds[0], seeds[-1]))
    inside = 0
    for f in FIGURES:
        v, c = values(runs, f), chip.get(f)
        if not v or c is None:
            continue
        ok = min(v) <= c <= max(v)
        inside += ok
        print("%-26s %12.4g %12.4g %8.3g %10.4g .. %-10.4g %s" % (f, c, statistics.mean(v), statistics.stdev(v),
                                                               min(v), max(v), "within" if ok else "OUTSIDE"))
    print("chip alarms: %s" % ", ".join("%s at %.1f s" % (x["code"], x["t_s"]) for x in chip["alarms"]))
    print("%d of %d figures within the host's range over the seeds (a sample of the host's own distribution: "
          "outside with probability %.2f a figure)" % (inside, len(FIGURES), 2.0 / (len(runs) + 1)))


def many_runs(chips, runs, seeds, cseeds):
    print("figure                     chip mean (sd) seeds %d-%d     host mean (sd) seeds %d-%d    difference / SE"
          "   sd chip / host" % (cseeds[0], cseeds[-1], seeds[0], seeds[-1]))
    same, wider = 0, []
    for f in FIGURES:
        c, h = values(chips, f), values(runs, f)
        if len(c) < 2 or len(h) < 2:
            continue
        mc, mh, sc, sh = statistics.mean(c), statistics.mean(h), statistics.stdev(c), statistics.stdev(h)
        se = math.sqrt(sc * sc / len(c) + sh * sh / len(h))
        z = (mc - mh) / se if se > 0 else (0.0 if mc == mh else math.inf)
        ok = abs(z) <= Z_DIFFERS
        same += ok
        ratio = sc / sh if sh > 0 else (1.0 if sc == 0 else math.inf)
        spread = "wider" if ratio > SD_RATIO else "narrower" if ratio < 1 / SD_RATIO else ""
        if spread == "wider":
            wider.append(f)
        print("%-26s %10.4g (%8.3g) [%.4g .. %.4g]  %10.4g (%8.3g) [%.4g .. %.4g]  %+6.2f %-7s %5.2f %s" %
              (f, mc, sc, min(c), max(c), mh, sh, min(h), max(h), z, "same" if ok else "DIFFERS", ratio, spread))
    print("%d of %d figures: the chip's mean over its seeds within %.0f standard errors of the host's; its "
          "spread over %.0f times the host's: %s" % (same, len(FIGURES), Z_DIFFERS, SD_RATIO, ", ".join(wider) or "none"))


def main(argv):
    if len(argv) < 4:
        print(__doc__, file=sys.stderr)
        return 2
    sim, ihx, s51 = argv[1:4]
    scn, inp, seeds, cseeds = "scenarios/pil_bench.scn", "scenarios/pil_bench.input", range(1, 17), None
    a = argv[4:]
    while a:
        if a[0] == "--scenario":
            scn = a[1]
        elif a[0] == "--input":
            inp = a[1]
        elif a[0] == "--seeds":
            seeds = seed_range(a[1])
        elif a[0] == "--chip-seeds":
            cseeds = seed_range(a[1])
        else:
            print("chip_spread: unknown option %s" % a[0], file=sys.stderr)
            return 2
        a = a[2:]
    base = ["--scenario", scn] + (["--input", inp] if inp else [])

    def chip(seed):
        return last_json(subprocess.run([sim, "--chip", ihx, "--s51", s51] + base + (["--seed", str(seed)] if seed else []),
                                        capture_output=True, text=True, check=True).stdout)

    def host(seed):
        return last_json(subprocess.run([sim, "--seed", str(seed)] + base, capture_output=True, text=True,
                                        check=True).stdout)
    with ThreadPoolExecutor(2) as ex:
        runs = list(ex.map(host, seeds))
        if cseeds:
            many_runs(list(ex.map(chip, cseeds)), runs, seeds, cseeds)
        else:
            one_run(chip(None), runs, seeds)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

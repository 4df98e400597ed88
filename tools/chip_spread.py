#!/usr/bin/env python3
"""chip_spread.py: make chip's metrics beside make sim's seed-to-seed spread on the same scenario.

usage: chip_spread.py SIM_BIN IHX S51 [--scenario F] [--input F] [--seeds A-B]
Runs the field image in the STC12C5A60S2 model once (the scenario's seed) and the host build over
the seeds (default 1-16), and prints each figure: the chip's value, the host's mean, its sample
standard deviation and range over the seeds, and whether the chip's lies within the range.
Stdlib only.
"""
import json
import statistics
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

FIGURES = ["applied_l_ha", "dose_error_pct", "dose_ctl_pct", "valve_reversals_per_min", "valve_travel_strokes",
           "silent_wrong_s", "pressure_min_bar", "pressure_max_bar", "volume_l"]


def last_json(out):
    return json.loads(out.strip().splitlines()[-1])


def main(argv):
    if len(argv) < 4:
        print(__doc__, file=sys.stderr)
        return 2
    sim, ihx, s51 = argv[1:4]
    scn, inp, seeds = "scenarios/pil_bench.scn", "scenarios/pil_bench.input", (1, 16)
    a = argv[4:]
    while a:
        if a[0] == "--scenario":
            scn = a[1]
        elif a[0] == "--input":
            inp = a[1]
        elif a[0] == "--seeds":
            lo, hi = a[1].split("-")
            seeds = (int(lo), int(hi))
        else:
            print("chip_spread: unknown option %s" % a[0], file=sys.stderr)
            return 2
        a = a[2:]
    base = ["--scenario", scn] + (["--input", inp] if inp else [])
    chip = last_json(subprocess.run([sim, "--chip", ihx, "--s51", s51] + base, capture_output=True, text=True,
                                    check=True).stdout)

    def host(seed):
        return last_json(subprocess.run([sim, "--seed", str(seed)] + base, capture_output=True, text=True,
                                        check=True).stdout)
    with ThreadPoolExecutor(2) as ex:
        runs = list(ex.map(host, range(seeds[0], seeds[1] + 1)))
    print("figure                     chip (seed %d)   host mean    sd      min .. max (seeds %d-%d)" %
          (chip["seed"], seeds[0], seeds[1]))
    inside = 0
    for f in FIGURES:
        v = [r[f] for r in runs if r.get(f) is not None]
        c = chip.get(f)
        if not v or c is None:
            continue
        ok = min(v) <= c <= max(v)
        inside += ok
        print("%-26s %12.4g %12.4g %8.3g %10.4g .. %-10.4g %s" % (f, c, statistics.mean(v), statistics.stdev(v),
                                                               min(v), max(v), "within" if ok else "OUTSIDE"))
    print("chip alarms: %s" % ", ".join("%s at %.1f s" % (x["code"], x["t_s"]) for x in chip["alarms"]))
    print("%d of %d figures within the host's range over the seeds" % (inside, len(FIGURES)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

#!/usr/bin/env python3
"""overshoot_split.py SIM [--seeds N] [--scenario FILE]: the paper run's step overshoot taken apart.

Runs FILE (default scenarios/paper_dynamic_150.scn) with `ffmap` on seeds 1..N (default 32), each
with --samples, and for every scored change finds the sample where sign(D) (y - r) peaks over
[t_a, t_e - 1 s) (docs/SCENARIOS.md's overshoot). It prints the mean `overshoot_mean_pct`; the
share of the overshoot that peaks within 1 s, 1-3 s, 3-6 s and 6 s or more after t_a; at the
peaks, the mean of sign(D) (y - ref) / abs(D) (the flow against the target of the true speed)
and of sign(D) (ref - r) / abs(D) (the firmware's target behind that reference); and the mean
overshoot the same flows would score against the reference instead of the firmware's target.
"""
import argparse
import csv
import json
import os
import subprocess
import tempfile


def peaks(rows, steps, target_key):
    """Per scored change, against target_key: (overshoot %, seconds from t_a to the peak, the peak's
    sample index, sign(D), abs(D)); t_a is found on the firmware's target, as the simulator does."""
    t = [float(r["t_s"]) for r in rows]
    r_ = [float(r[target_key]) for r in rows]
    fw = [float(r["target_lpm"]) for r in rows]
    y = [float(r["flow_lpm"]) for r in rows]
    out = []
    for i, s in enumerate(steps):
        t0 = s["t_s"]
        t1 = steps[i + 1]["t_s"] if i + 1 < len(steps) else t[-1]
        d = s["to_lpm"] - s["from_lpm"]
        sg = 1 if d > 0 else -1
        ta, peak, at = None, 0.0, None
        for k, tk in enumerate(t):
            if tk < t0 or tk >= t1 - 1:
                continue
            if ta is None and abs(fw[k] - s["to_lpm"]) <= 0.01 * abs(s["to_lpm"]):
                ta = tk
            if ta is not None and (at is None or sg * (y[k] - r_[k]) > peak):
                peak, at = sg * (y[k] - r_[k]), k
        if ta is not None:
            out.append((max(peak, 0.0) / abs(d) * 100, t[at] - ta, at, sg, abs(d)))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("sim")
    ap.add_argument("--seeds", type=int, default=32)
    ap.add_argument("--scenario", default="scenarios/paper_dynamic_150.scn")
    a = ap.parse_args()
    reported, n = 0.0, 0
    buckets = {"<1 s": 0.0, "1-3 s": 0.0, "3-6 s": 0.0, ">=6 s": 0.0}
    total = flow_part = target_part = vs_ref = 0.0
    with tempfile.TemporaryDirectory() as tmp:
        for seed in range(1, a.seeds + 1):
            path = os.path.join(tmp, "s.csv")
            out = subprocess.run([a.sim, "--scenario", a.scenario, "--controller", "ffmap", "--seed", str(seed),
                                  "--samples", path], capture_output=True, text=True, check=True)
            m = json.loads(out.stdout.strip().splitlines()[-1])
            reported += m["overshoot_mean_pct"]
            rows = list(csv.DictReader(open(path)))
            for (os_, dt, k, sg, ad) in peaks(rows, m["steps"], "target_lpm"):
                total += os_
                n += 1
                buckets["<1 s" if dt < 1 else "1-3 s" if dt < 3 else "3-6 s" if dt < 6 else ">=6 s"] += os_
                y, ref, r = (float(rows[k][c]) for c in ("flow_lpm", "ref_lpm", "target_lpm"))
                flow_part += sg * (y - ref) / ad * 100
                target_part += sg * (ref - r) / ad * 100
            vs_ref += sum(p[0] for p in peaks(rows, m["steps"], "ref_lpm"))
    print("overshoot_split: %s, seeds 1-%d, %d changes scored" % (a.scenario, a.seeds, n))
    print("  mean overshoot_mean_pct %.2f %%" % (reported / a.seeds))
    print("  where it peaks after t_a: " + ", ".join("%s %.0f %%" % (b, v / total * 100) for b, v in buckets.items()))
    print("  at the peaks: the flow %.2f %% of D past the reference, the firmware's target %.2f %% of D behind it"
          % (flow_part / n, target_part / n))
    print("  the same flows against the reference: mean overshoot %.2f %%" % (vs_ref / n))


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""demo_report.py: the simulator's metrics (the JSON line of `sim`) beside the paper's figures (PAPER.md 5.1, Table 4)."""
import json
import sys

PAPER = [
    # (label, metric key or function, BP-PID, fuzzy PID)
    ("mean overshoot, %", "overshoot_mean_pct", "2.1", "17.6"),
    ("mean settling time, s", "settle_mean_s", "0.72", "2.54"),
    ("applied dose, L/ha (set 150)", "applied_l_ha", "151.9", "142.1"),
    ("dose error, % (v >= 4 km/h)", "dose_error_pct", "1.3", "5.9"),
    ("dose error, % (whole run)", "dose_error_all_pct", "-", "-"),
    ("CV of 5 m zones, % (v >= 4 km/h)", "cv_pct", "4.2-5.9", "6.9-9.2"),
    ("CV of 5 m zones, % (whole run)", "cv_all_pct", "5.1-7.4", "-"),
    ("zone error min, %", "zone_error_min_pct", "-5", "-9.9"),
    ("zone error max, %", "zone_error_max_pct", "+5", "+9.8"),
]


def fmt(v):
    if v is None:
        return "n/a"
    if isinstance(v, float):
        return "%.2f" % v
    return str(v)


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: demo_report.py METRICS.json")
    try:
        with open(sys.argv[1]) as f:
            m = json.loads(f.read().strip().splitlines()[-1])
    except (OSError, ValueError, IndexError) as e:
        sys.exit("demo_report.py: %s: no metrics JSON line (%s)" % (sys.argv[1], e))
    print()
    print("%s, controller %s, seed %s" % (m.get("scenario"), m.get("controller"), m.get("seed")))
    print("%-36s %12s %12s %12s" % ("figure", "this run", "paper BP-PID", "paper fuzzy"))
    print("-" * 75)
    for label, key, bp, fz in PAPER:
        print("%-36s %12s %12s %12s" % (label, fmt(m.get(key)), bp, fz))
    print("-" * 75)
    steps = m.get("steps", [])
    print("changes of the target found: %d (max overshoot %s %%, max settling %s s)"
          % (len(steps), fmt(m.get("overshoot_max_pct")), fmt(m.get("settle_max_s"))))
    print("pressure at v >= 4 km/h: %s .. %s bar; volume %s L over %s ha"
          % (fmt(m.get("pressure_min_bar")), fmt(m.get("pressure_max_bar")), fmt(m.get("volume_l")),
             fmt(m.get("area_ha"))))
    alarms = m.get("alarms", [])
    print("alarms: %s" % (", ".join("%s at %.1f s" % (a["code"], a["t_s"]) for a in alarms) or "none"))
    print("simulated %s s in %s s of wall time" % (fmt(m.get("sim_s")), fmt(m.get("wall_s"))))
    print("paper: field test of section 5.1 (150 L/ha, 4-11 km/h, throttle) and Table 4 (3220 m run);")
    print("here the sprayer is the model of docs/SCENARIOS.md, so the figures compare control, not the field.")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""compare.py: the paper's four controllers and the two peers (aog, raven) on the same plant and seed, beside the paper's Table 2 and section 5.1.

usage: compare.py SIM_BIN [--json OUT.json]
Runs SIM_BIN --scenario S --controller C for every scenario below and every controller, reads
the metrics JSON on the last line of each run, and prints one table per scenario.
"""
import json
import subprocess
import sys

CONTROLLERS = ["pid", "fuzzy_pid", "bp_pid", "ffmap", "aog", "raven"]
PEERS = ["bp_pid", "aog", "raven"]      # ffmap is compared with each, figure by figure
SCENARIOS = [
    ("target_step_150", "target steps (given speed 6/8/7 km/h, PTO 540 rpm)"),
    ("paper_dynamic_150", "paper's dynamic following, 150 L/ha, 4-11 km/h, PTO coupled"),
    ("paper_dynamic_150_fixed_pto", "paper's dynamic following, 150 L/ha, 4-11 km/h, PTO fixed 540 rpm"),
    ("field_3220m_150", "field run of 3220 m, 150 L/ha: start, headland slow-downs, stop (cf. Table 4)"),
]
# the paper's figures: Table 2 (simulated step) and section 5.1 / Table 4 (field, 150 L/ha)
PAPER_T2 = {"pid": (0.30, 50.9, 1.21), "fuzzy_pid": (0.64, 18.2, 0.94), "bp_pid": (0.25, 1.30, 0.26)}
PAPER_51 = {"fuzzy_pid": (17.6, 2.54, 5.9, 8.1), "bp_pid": (2.1, 0.72, 1.3, 5.1)}
GOAL_BEST = {"dose_error_pct": 0.5, "cv_pct": 2.0, "overshoot_mean_pct": 1.0, "settle_mean_s": 0.5, "start_s": 3.0}


def run(sim, scn, ctl):
    out = subprocess.run([sim, "--scenario", "scenarios/%s.scn" % scn, "--controller", ctl],
                         capture_output=True, text=True, check=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def mean_rise(m):
    r = [s.get("rise_s") for s in m.get("steps", []) if s.get("rise_s") is not None]
    return sum(r) / len(r) if r else None


def mean_abs_sse(m):
    r = [abs(s.get("sse_pct")) for s in m.get("steps", []) if s.get("sse_pct") is not None]
    return sum(r) / len(r) if r else None


def f(x, w=8, p=2):
    return ("%*.*f" % (w, p, x)) if isinstance(x, (int, float)) else "%*s" % (w, "-")


def main():
    sim = sys.argv[1] if len(sys.argv) > 1 else "build/host/bin/sim"
    res = {}
    for scn, title in SCENARIOS:
        res[scn] = {c: run(sim, scn, c) for c in CONTROLLERS}
    print("Step response (cf. paper Table 2: rise s / overshoot % / steady-state error %)")
    scn = "target_step_150"
    print("  %-10s %8s %8s %8s %8s %8s | %8s %8s %8s" % ("controller", "rise_s", "ovs_%", "|sse|_%", "settle_s",
                                                       "ovs_max", "paper:", "ovs_%", "sse_%"))
    for c in CONTROLLERS:
        m = res[scn][c]
        p = PAPER_T2.get(c, (None, None, None))
        print("  %-10s %s %s %s %s %s | %s %s %s" % (c, f(mean_rise(m)), f(m.get("overshoot_mean_pct")),
              f(mean_abs_sse(m)), f(m.get("settle_mean_s")), f(m.get("overshoot_max_pct")), f(p[0]), f(p[1]), f(p[2])))
    for scn, title in SCENARIOS[1:]:
        print("\n%s (cf. paper section 5.1 and Table 4)" % title)
        print("  %-10s %8s %8s %8s %8s %8s %8s %8s %8s %8s | %6s %6s %6s %6s" % (
            "controller", "dose_%", "L/ha", "cv_%", "zmin_%", "zmax_%", "ovs_%", "settle", "start_s", "rev/min",
            "p:ovs", "p:set", "p:dose", "p:cv"))
        for c in CONTROLLERS:
            m = res[scn][c]
            p = PAPER_51.get(c, (None, None, None, None))
            print("  %-10s %s %s %s %s %s %s %s %s %s | %s %s %s %s" % (
                c, f(m.get("dose_error_pct")), f(m.get("applied_l_ha"), 8, 1), f(m.get("cv_pct")),
                f(m.get("zone_error_min_pct")), f(m.get("zone_error_max_pct")), f(m.get("overshoot_mean_pct")),
                f(m.get("settle_mean_s")), f(m.get("start_s")), f(m.get("valve_reversals_per_min"), 8, 1),
                f(p[0], 6, 1), f(p[1], 6, 2), f(p[2], 6, 1), f(p[3], 6, 1)))
    m = res["paper_dynamic_150"]["ffmap"]
    print("\nbest on paper_dynamic_150 against the project's goals:")
    for k, g in GOAL_BEST.items():
        v = m.get(k)
        v = abs(v) if k == "dose_error_pct" and v is not None else v
        print("  %-20s %8s  goal <= %-5s %s" % (k, f(v), g, "met" if v is not None and v <= g else "NOT met"))
    # every figure printed above, in the sense "smaller is better" (magnitudes for signed ones)
    keys = ["dose_error_pct", "cv_pct", "cv_all_pct", "zone_error_min_pct", "zone_error_max_pct",
            "overshoot_mean_pct", "overshoot_max_pct", "settle_mean_s"]
    for other in PEERS:
        worse = []
        for scn, _ in SCENARIOS:
            both = {c: dict(res[scn][c], rise_mean_s=mean_rise(res[scn][c]), sse_mean_abs_pct=mean_abs_sse(res[scn][c]))
                    for c in ("ffmap", other)}
            for k in keys + (["rise_mean_s", "sse_mean_abs_pct"] if scn.startswith("target_step") else []):
                b, n = both["ffmap"].get(k), both[other].get(k)
                if not isinstance(b, (int, float)) or not isinstance(n, (int, float)):
                    continue
                if round(abs(b), 2) > round(abs(n), 2):
                    worse.append("%s/%s %.3g > %.3g" % (scn, k, b, n))
        print("ffmap at least as good as %s on every metric: %s" % (other, "yes" if not worse else "no: " + "; ".join(worse)))
    print("valve wear (motor reversals a minute while spraying, not counted above): "
          + "; ".join("%s %s" % (c, " / ".join("%.1f" % res[scn][c].get("valve_reversals_per_min", float("nan"))
                                                for scn, _ in SCENARIOS)) for c in CONTROLLERS))
    if "--json" in sys.argv:
        with open(sys.argv[sys.argv.index("--json") + 1], "w") as fp:
            json.dump(res, fp)


if __name__ == "__main__":
    main()

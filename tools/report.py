#!/usr/bin/env python3
"""report.py: the field report of a recorded run (the paper's Excel work): the simulator's metrics, plots like
Figs. 8-9 and Table 4.

    report.py RUN.csv [--scenario FILE | --rate L_HA --nozzles N --spacing-cm CM] [--out DIR] [--title T]

RUN.csv: a recording of tools/monitor.py or tools/serial_log.py (a real board, a HIL run, a
simulated board), or a simulator trace (`sim --csv`). The metrics are computed by
build/host/bin/score, which feeds the rows to the simulator's own sim/metrics.c (one definition);
a recording of a real board carries the firmware's measured speed and flow, not the truth, and
the report says which it scored ("score_source"). Writes DIR/metrics.json, DIR/flow.png (speed,
target and actual flow, pressure, valve drive: Figs. 8-9), DIR/zones.csv and DIR/zones.png
(volume per 5 m zone: Table 4); the last line printed is the metrics JSON.
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCORE = os.path.join(ROOT, "build", "host", "bin", "score")

ROWS = [
    ("applied dose, L/ha", "applied_l_ha"),
    ("dose error, % (v >= 4 km/h)", "dose_error_pct"),
    ("dose error, % (whole run)", "dose_error_all_pct"),
    ("CV of 5 m zones, % (v >= 4 km/h)", "cv_pct"),
    ("CV of 5 m zones, % (whole run)", "cv_all_pct"),
    ("zone error min / max, %", ("zone_error_min_pct", "zone_error_max_pct")),
    ("target changes scored", "steps_scored"),
    ("mean / largest overshoot, %", ("overshoot_mean_pct", "overshoot_max_pct")),
    ("mean / longest settling (5 %), s", ("settle_mean_s", "settle_max_s")),
    ("start until within 5 %, s", "start_s"),
    ("pressure min / max, bar", ("pressure_min_bar", "pressure_max_bar")),
    ("volume, L / area, ha", ("volume_l", "area_ha")),
    ("run, s", "sim_s"),
]


def fail(msg):
    print("report: " + msg, file=sys.stderr)
    sys.exit(1)


def fmt(v):
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return "n/a"
    if isinstance(v, float):
        return "%.3f" % v
    return str(v)


def score(a, zones_csv):
    if not os.path.exists(SCORE):
        r = subprocess.run(["make", "-C", ROOT, "--no-print-directory", "build/host/bin/score"],
                           stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        if r.returncode != 0:
            fail("cannot build %s: %s" % (SCORE, r.stderr.strip().splitlines()[-1] if r.stderr.strip() else "make failed"))
    cmd = [SCORE, a.csv, "--zones", zones_csv]
    if a.scenario:
        cmd += ["--scenario", a.scenario]
    for opt in ("rate", "nozzles", "spacing_cm"):
        v = getattr(a, opt)
        if v is not None:
            cmd += ["--" + opt.replace("_", "-"), str(v)]
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if r.returncode != 0:
        fail(r.stderr.strip().replace("score: ", "", 1) or "score failed")
    try:
        return json.loads(r.stdout.strip().splitlines()[-1])
    except (ValueError, IndexError):
        fail("score gave no metrics for %s" % a.csv)


def read_cols(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    cols = {}
    for k in rows[0]:
        out = []
        for r in rows:
            try:
                out.append(float(r[k]))
            except (TypeError, ValueError):
                try:
                    out.append(float(int(r[k], 16)))
                except (TypeError, ValueError):
                    out.append(float("nan"))
        cols[k] = out
    return cols


def pick(c, *names):
    for n in names:
        if n in c:
            return c[n]
    return None


def plot_flow(c, out, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    t = c["t_s"]
    fig, ax = plt.subplots(3, 1, figsize=(12, 9), sharex=True, gridspec_kw={"height_ratios": [1, 2, 1]})
    v_meas = pick(c, "speed_kmh", "v_meas_kmh")
    if "v_true_kmh" in c:
        ax[0].plot(t, c["v_true_kmh"], color="0.3", lw=1.2, label="true speed (simulator)")
    if v_meas:
        ax[0].plot(t, v_meas, color="tab:orange", lw=0.8, ls="--", label="measured speed")
    ax[0].set_ylabel("speed, km/h")
    ax[1].plot(t, c["target_lpm"], color="tab:blue", lw=1.4, label="target flow")
    meas = pick(c, "flow_lpm", "flow_meas_lpm")
    if meas:
        ax[1].plot(t, meas, color="tab:red", lw=0.8, label="measured flow")
    if "flow_true_lpm" in c:
        ax[1].plot(t, c["flow_true_lpm"], color="tab:green", lw=0.8, alpha=0.8, label="true flow (simulator)")
    ax[1].set_ylabel("boom flow, L/min")
    p = pick(c, "p_bar")
    if p is None and "pressure_kpa" in c:
        p = [x / 100.0 for x in c["pressure_kpa"]]
    if p is None and "pressure_mpa" in c:
        p = [x * 10.0 for x in c["pressure_mpa"]]
    if p:
        ax[2].plot(t, p, color="tab:purple", lw=0.8, label="pressure, bar")
    ax[2].set_ylabel("pressure, bar")
    drive = pick(c, "valve_drive")
    if drive:
        a2 = ax[2].twinx()
        a2.plot(t, drive, color="tab:brown", lw=0.6, label="valve drive (+ opens the bypass)")
        a2.set_ylabel("valve drive")
        a2.set_ylim(-1.05, 1.05)
        a2.legend(loc="upper right", fontsize=8)
    for a in ax:
        a.grid(alpha=0.3)
        a.legend(loc="upper left", fontsize=8)
    ax[2].set_xlabel("time, s")
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("csv", help="the recorded run")
    ap.add_argument("--scenario", help="the settings (rate, nozzles, spacing) from this scenario file")
    ap.add_argument("--rate", type=float, help="set rate, L/ha (default: the firmware's default)")
    ap.add_argument("--nozzles", type=int)
    ap.add_argument("--spacing-cm", type=float)
    ap.add_argument("--out", help="folder for the report (default: RUN.csv without .csv, + _report)")
    ap.add_argument("--title")
    ap.add_argument("--no-plots", action="store_true")
    a = ap.parse_args(argv)
    if not os.path.isfile(a.csv):
        fail("cannot read %s: no such file" % a.csv)
    out = a.out or (os.path.splitext(a.csv)[0] + "_report")
    try:
        os.makedirs(out, exist_ok=True)
    except OSError as e:
        fail("cannot make %s: %s" % (out, e.strerror))
    zones_csv = os.path.join(out, "zones.csv")
    m = score(a, zones_csv)
    with open(os.path.join(out, "metrics.json"), "w") as f:
        json.dump(m, f)
        f.write("\n")
    title = a.title or os.path.basename(a.csv)
    print("%s: %d rows every %.2f s, scored on the %s values" % (
        title, m.get("score_rows", 0), m.get("score_sample_s", 0), m.get("score_source")))
    print("%-36s %s" % ("figure", "this run"))
    print("-" * 60)
    for label, key in ROWS:
        v = " / ".join(fmt(m.get(k)) for k in key) if isinstance(key, tuple) else fmt(m.get(key))
        print("%-36s %s" % (label, v))
    for s in m.get("steps", []):
        print("  change at %7.1f s: %6.2f -> %6.2f L/min, rise %s s, overshoot %s %%, settled (5 %%) %s s" % (
            s["t_s"], s["from_lpm"], s["to_lpm"], fmt(s["rise_s"]), fmt(s["overshoot_pct"]), fmt(s["settle_5pct_s"])))
    for al in m.get("alarms", []):
        print("  alarm at %7.1f s: %s" % (al["t_s"], al["code"]))
    if not a.no_plots:
        c = read_cols(a.csv)
        plot_flow(c, os.path.join(out, "flow.png"), title + ": flow following (cf. paper Figs. 8-9)")
        with open(zones_csv) as f:
            has_zones = sum(1 for _ in f) > 1
        if has_zones:
            sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
            import plot
            plot.plot_zones(argparse.Namespace(input=zones_csv, output=os.path.join(out, "zones.png"),
                                               rate=a.rate,
                                               title=title + ": volume per 5 m zone (cf. paper Table 4)"))
        print("report: wrote %s/metrics.json, flow.png%s" % (out, ", zones.csv, zones.png" if has_zones else
                                                              " (no zones: the run never moved)"))
    print(json.dumps(m))
    return 0


if __name__ == "__main__":
    sys.exit(main())

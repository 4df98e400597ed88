#!/usr/bin/env python3
"""results.py: docs/RESULTS.md and its plots: the paper's experiments reproduced, and beyond.

usage: results.py [--sim build/host/bin/sim] [--out docs] [--jobs N] [--family-n 200]
Every figure in the report comes from the runs this program makes (fixed seeds: run twice, the
same figures); the paper's own numbers are typed in below and marked as the paper's. It also
rewrites the headline table in README.md between its results markers. `make report` builds what
it needs first (the simulator, the firmware's memory report, the s51 benchmark, bench-sim) and
hands their outputs over with --bench, --memory and --bench-sim.
"""
import argparse
import csv
import json
import math
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
from multiprocessing import Pool

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import progress  # noqa: E402  (tools/progress.py: the progress line on a terminal)

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# ---- the paper's own numbers (reference/PAPER.md: Tables 2-4, section 5.1) ----------------------
PAPER_T2 = {"pid": (0.30, 50.9, 1.21), "fuzzy_pid": (0.64, 18.2, 0.94), "bp_pid": (0.25, 1.30, 0.26)}
PAPER_51 = {"fuzzy_pid": {"ovs": 17.6, "settle": 2.54, "l_ha": 142.1, "dose": 5.9},
            "bp_pid": {"ovs": 2.1, "settle": 0.72, "l_ha": 151.9, "dose": 1.3}}
PAPER_T4 = {"bp_pid": "CV 5.1-7.4 % (whole run), 4.2-5.9 % at v >= 4 km/h, errors -5..+5 %",
            "fuzzy_pid": "CV 6.9-9.2 % at v >= 4 km/h, errors -9.9..+9.8 %"}

ALL_CONTROLLERS = ["pid", "fuzzy_pid", "bp_pid", "aog", "raven", "ffmap"]
SEEDS = [1, 2, 3]
RATES = [100, 125, 150]


# ---- running the simulator ----------------------------------------------------------------------
def run_sim(job):
    """job: (sim, scenario path, controller, seed, extra args) -> the metrics JSON (+ outputs)."""
    sim, path, ctl, seed, extra = job
    cmd = [sim, "--scenario", path, "--controller", ctl, "--seed", str(seed)] + list(extra)
    out = subprocess.run(cmd, capture_output=True, text=True)
    if out.returncode != 0:
        return {"error": (out.stderr or out.stdout).strip()[-300:], "cmd": " ".join(cmd)}
    return json.loads(out.stdout.strip().splitlines()[-1])


class Runner:
    def __init__(self, sim, jobs, scn_dir):
        self.sim, self.pool, self.scn_dir = sim, Pool(jobs), scn_dir
        os.makedirs(scn_dir, exist_ok=True)

    def scenario(self, name, text):
        path = os.path.join(self.scn_dir, name + ".scn")
        with open(path, "w") as f:
            f.write(text)
        return path

    def many(self, jobs):
        """jobs: list of (path, controller, seed, extra) -> results in order; any failure stops."""
        res = progress.pool_map(self.pool, run_sim, [(self.sim, p, c, s, e) for p, c, s, e in jobs], "report")
        bad = [r for r in res if "error" in r]
        if bad:
            sys.exit("results: a run failed: %s\n  %s" % (bad[0]["cmd"], bad[0]["error"]))
        return res


def controllers_known(sim):
    """The controllers this simulator accepts (the peers exist only once built in)."""
    have = []
    probe = tempfile.NamedTemporaryFile("w", suffix=".scn", delete=False)
    probe.write("[run]\nduration_s = 1\n[drive]\n0 0\n")
    probe.close()
    for c in ALL_CONTROLLERS:
        r = subprocess.run([sim, "--scenario", probe.name, "--controller", c], capture_output=True, text=True)
        if r.returncode == 0:
            have.append(c)
    os.unlink(probe.name)
    return have


# ---- small helpers -----------------------------------------------------------------------------
def mean(xs):
    xs = [x for x in xs if x is not None and not (isinstance(x, float) and math.isnan(x))]
    return sum(xs) / len(xs) if xs else None


def fmt(x, p=2):
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "-"
    return "%.*f" % (p, x)


def step_means(m, key):
    vals = [s.get(key) for s in m.get("steps", [])]
    if key == "sse_pct":
        vals = [abs(v) for v in vals if v is not None]
    return mean(vals)


def table(head, rows):
    out = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(out)


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    cols = {}
    for k in rows[0]:
        vals = []
        for r in rows:
            try:
                vals.append(float(r[k]))
            except ValueError:
                vals.append(float("nan"))
        cols[k] = vals
    return cols


def base_config(rate, extra=""):
    return "[config]\nrate_l_ha = %d\nnozzles = 36\nspacing_cm = 50\n%s" % (rate, extra)


# ---- 1. Table 2: given-speed target steps --------------------------------------------------------
def section_steps(R, ctls):
    jobs = [("scenarios/target_step_%d.scn" % r, c, s, []) for r in RATES for c in ctls for s in SEEDS]
    res = R.many(jobs)
    by = {}
    for (p, c, s, _), m in zip(jobs, res):
        by.setdefault(c, []).append(m)
    rows = []
    for c in ctls:
        ms = by[c]
        p = PAPER_T2.get(c)
        rows.append([c, fmt(mean(step_means(m, "rise_s") for m in ms)), fmt(mean(m["overshoot_mean_pct"] for m in ms)),
                     fmt(mean(step_means(m, "sse_pct") for m in ms), 3), fmt(mean(m["settle_mean_s"] for m in ms)),
                     fmt(mean(m["valve_reversals_per_min"] for m in ms), 1),
                     "%s / %s / %s" % p if p else "-"])
    text = ("## 1. Step response at a given speed (cf. Table 2)\n\n"
            "Given-speed bench steps 6 -> 8 -> 7 -> 6 -> 8 km/h at 100, 125 and 150 L/ha "
            "(`scenarios/target_step_*.scn`, fixed 540 rpm PTO), seeds %s: means over the 9 runs of each "
            "controller. Rise 10-90 %%, overshoot and settling (5 %% band) against the firmware's target at the "
            "same instant, |sse| the mean steady error. The paper's column is its simulation (rise s / "
            "overshoot %% / steady error %%), on its own model, not this plant.\n\n" % SEEDS)
    text += table(["controller", "rise s", "overshoot %", "abs sse %", "settle s", "reversals/min",
                   "paper (rise / overshoot / sse)"], rows)
    return text + "\n", {c: by[c] for c in ctls}


# ---- 2. Section 5.1: dynamic following -----------------------------------------------------------
def section_dynamic(R, ctls, out):
    jobs = []
    sdir = os.path.join(R.scn_dir, "samples")
    os.makedirs(sdir, exist_ok=True)
    for r in RATES:
        for kind in ("", "_fixed_pto"):
            for c in ctls:
                for s in SEEDS:
                    # the first controller's series also give the reference's own figures (below)
                    extra = ["--samples", os.path.join(sdir, "dyn%d%s_%d.csv" % (r, kind, s))] if c == ctls[0] else []
                    jobs.append(("scenarios/paper_dynamic_%d%s.scn" % (r, kind), c, s, extra))
    res = R.many(jobs)
    agg = {}
    for (p, c, s, _), m in zip(jobs, res):
        agg.setdefault((os.path.basename(p)[:-4], c), []).append(m)
    # A flow exactly on the reference (the target the true speed gives), scored like a controller's
    # against the firmware's target (sim/steps.c --flow ref_lpm): what the measured speed's own lag
    # and jitter cost the step figures before any controller acts.
    steps_bin = os.path.join(os.path.dirname(R.sim), "steps")
    for r in RATES:
        for kind in ("", "_fixed_pto"):
            for s in SEEDS:
                st = subprocess.run([steps_bin, os.path.join(sdir, "dyn%d%s_%d.csv" % (r, kind, s)), "--flow", "ref_lpm"],
                                     capture_output=True, text=True, check=True)
                agg.setdefault(("paper_dynamic_%d%s" % (r, kind), "ref"), []).append(
                    json.loads(st.stdout.strip().splitlines()[-1]))
    text = ("## 2. Dynamic flow following (cf. section 5.1, Figs. 8-9)\n\n"
            "The speed changed at random between 4 and 11 km/h with the throttle (`scenarios/paper_dynamic_*`), "
            "the PTO coupled to the wheel (pump and speed move together, as on the paper's tractor) or held at "
            "540 rpm (the valve does all the work); means over seeds %s. Paper: its field figures at 150 L/ha, "
            "coupled. \"flow = true reference\": a flow exactly equal to the target the true speed gives, scored "
            "the same way against the firmware's target (`build/host/bin/steps SAMPLES --flow ref_lpm` on the "
            "first controller's `--samples`): the overshoot, settling and start that the measured speed's lag and "
            "jitter alone give, before any controller acts (its start: from the boom's opening, with no line to "
            "fill, until it has stayed within 5 %% of the firmware's target for 2 s).\n\n" % SEEDS)
    for kind, title in (("", "PTO coupled"), ("_fixed_pto", "PTO fixed at 540 rpm")):
        rows = []
        for r in RATES:
            for c in ctls:
                ms = agg[("paper_dynamic_%d%s" % (r, kind), c)]
                rows.append(["%d" % r, c, fmt(mean(m["overshoot_mean_pct"] for m in ms)),
                             fmt(mean(m["settle_mean_s"] for m in ms)), fmt(mean(m["applied_l_ha"] for m in ms), 1),
                             fmt(mean(m["dose_error_pct"] for m in ms), 3), fmt(mean(m["cv_pct"] for m in ms)),
                             fmt(mean(m["valve_reversals_per_min"] for m in ms), 1),
                             fmt(mean(m["start_s"] for m in ms), 1)])
            ms = agg[("paper_dynamic_%d%s" % (r, kind), "ref")]
            rows.append(["%d" % r, "flow = true reference", fmt(mean(m["overshoot_mean_pct"] for m in ms)),
                         fmt(mean(m["settle_mean_s"] for m in ms)), "-", "-", "-", "-",
                         fmt(mean(m["start_s"] for m in ms), 1)])
            if kind == "" and r == 150:
                for c, pv in PAPER_51.items():
                    rows.append(["150", "paper %s" % c, fmt(pv["ovs"]), fmt(pv["settle"]), fmt(pv["l_ha"], 1),
                                 fmt(pv["dose"], 1), "-", "-", "-"])
        text += "### %s\n\n" % title + table(["L/ha", "controller", "mean overshoot %", "mean settling s", "applied L/ha",
                                              "dose error %", "CV %", "reversals/min", "start s"], rows) + "\n\n"
    # Fig. 8 / 9: the 150 L/ha coupled run, seed 1, every controller
    traces = {}
    tdir = os.path.join(R.scn_dir, "traces")
    os.makedirs(tdir, exist_ok=True)
    jobs = [("scenarios/paper_dynamic_150.scn", c, 1, ["--csv", os.path.join(tdir, "dyn150_%s.csv" % c)]) for c in ctls]
    R.many(jobs)
    for c in ctls:
        traces[c] = read_csv(os.path.join(tdir, "dyn150_%s.csv" % c))
    fig, axes = plt.subplots(len(ctls) + 1, 1, figsize=(10, 2.0 * (len(ctls) + 1)), sharex=True)
    t0 = traces[ctls[0]]
    axes[0].plot(t0["t_s"], t0["v_true_kmh"], "k-", lw=0.8, label="true speed")
    axes[0].set_ylabel("km/h")
    axes[0].set_ylim(bottom=0)
    for ax, c in zip(axes[1:], ctls):
        t = traces[c]
        # the target a pale band under the flow, so that a flow on it stays visible
        ax.plot(t["t_s"], t["target_lpm"], color="tab:blue", lw=3.5, alpha=0.3, label="target flow (firmware)")
        ax.plot(t["t_s"], t["flow_true_lpm"], color="tab:red", lw=0.6, label="actual flow (plant)")
        ax.set_ylabel("%s\nL/min" % c, fontsize=8)
        ax.set_ylim(bottom=0)
    h0, l0 = axes[0].get_legend_handles_labels()
    h1, l1 = axes[1].get_legend_handles_labels()
    axes[0].legend(h0 + h1, l0 + l1, loc="lower left", bbox_to_anchor=(0, 1.0), ncol=3, fontsize=7, frameon=False)
    axes[-1].set_xlabel("s")
    fig.suptitle("paper_dynamic_150 (PTO coupled, seed 1): target and actual flow (cf. paper Figs. 8-9)", fontsize=9)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "results_dynamic150.png"), dpi=90)
    plt.close(fig)
    text += "![dynamic following](results_dynamic150.png)\n"
    return text, agg


# ---- 3. Table 3: flow accuracy -------------------------------------------------------------------
def section_accuracy(R, ctl):
    jobs, keys = [], []
    for r in RATES:
        for v in (6, 7, 8):
            text = ("# Table 3 analogue: given speed %d km/h at %d L/ha, tractor still (bench)\n"
                    "[run]\nduration_s = 60\n%sgiven_speed_kmh = %d\n[plant]\npto_coupled = 0\n[drive]\n0 0\n" % (v, r, base_config(r), v))
            path = R.scenario("t3_given_%d_%d" % (r, v), text)
            jobs.append((path, ctl, 1, ["--csv", path[:-4] + ".csv"]))
            keys.append(("given", r, v))
        drive = "[drive]\n0 0\n"
        t = 5.0
        for v in (2, 4, 6, 8, 10, 11):
            drive += "%g %g\n%g %g\n" % (t, v, t + 30, v)
            t += 32
        text = ("# Table 3 analogue: driving 0-11 km/h at %d L/ha, holds of 30 s\n"
                "[run]\nduration_s = %d\n%s[plant]\npto_coupled = 1\n%s" % (r, t, base_config(r), drive))
        path = R.scenario("t3_drive_%d" % r, text)
        jobs.append((path, ctl, 1, ["--csv", path[:-4] + ".csv"]))
        keys.append(("drive", r, None))
    R.many(jobs)
    rows = []
    for (kind, r, v), (path, _, _, _) in zip(keys, jobs):
        tr = read_csv(path[:-4] + ".csv")
        if kind == "given":
            idx = [i for i, t in enumerate(tr["t_s"]) if t >= 30]
            tg = mean(tr["target_lpm"][i] for i in idx)
            q = mean(tr["flow_true_lpm"][i] for i in idx)
            rows.append(["%d" % r, "given %d km/h" % v, fmt(tg), fmt(q), fmt(100 * (q / tg - 1), 2)])
        else:
            t = 5.0
            for v2 in (2, 4, 6, 8, 10, 11):
                idx = [i for i, ts in enumerate(tr["t_s"]) if t + 10 <= ts < t + 30]
                tg = mean(tr["target_lpm"][i] for i in idx)
                q = mean(tr["flow_true_lpm"][i] for i in idx)
                rows.append(["%d" % r, "driving %d km/h" % v2, fmt(tg), fmt(q), fmt(100 * (q / tg - 1), 2)])
                t += 32
    text = ("## 3. Flow accuracy (cf. Table 3)\n\n"
            "`%s`, seed 1. Given speed: the tractor stands, the firmware is given 6, 7 or 8 km/h (the paper's "
            "bench test), flow averaged over 30-60 s. Driving: holds of 30 s at 2-11 km/h, the PTO coupled, flow "
            "averaged over the last 20 s of each hold (below 4 km/h the target is Table 1's minimum flow). The "
            "error is the true flow through the meter against the firmware's target. Paper: within +-2 %% at a "
            "given speed, +-3 %% driving (worst -2.4 %%).\n\n" % ctl)
    text += table(["L/ha", "condition", "target L/min", "measured L/min", "error %"], rows)
    return text + "\n"


# ---- 4. Table 4: field runs ----------------------------------------------------------------------
def section_field(R, ctls, out):
    jobs = []
    zdir = os.path.join(R.scn_dir, "zones")
    os.makedirs(zdir, exist_ok=True)
    for r in RATES:
        for c in ctls:
            for s in SEEDS:
                jobs.append(("scenarios/field_3220m_%d.scn" % r, c, s,
                             ["--zones", os.path.join(zdir, "field%d_%s_%d.csv" % (r, c, s))]))
    res = R.many(jobs)
    rows = []
    agg = {}
    for (p, c, s, e), m in zip(jobs, res):
        z = read_csv(e[1])
        errs = [x for x in z["error_pct"] if not math.isnan(x)]
        agg.setdefault((p, c), []).append((m, errs[0] if errs else None, errs[-1] if errs else None))
    for r in RATES:
        for c in ctls:
            ms = agg[("scenarios/field_3220m_%d.scn" % r, c)]
            rows.append(["%d" % r, c, fmt(mean(m["cv_all_pct"] for m, _, _ in ms)), fmt(mean(m["cv_pct"] for m, _, _ in ms)),
                         "%s .. %s" % (fmt(min(m["zone_error_min_pct"] for m, _, _ in ms), 1),
                                       fmt(max(m["zone_error_max_pct"] for m, _, _ in ms), 1)),
                         fmt(mean(a for _, a, _ in ms), 1), fmt(mean(b for _, _, b in ms), 1),
                         fmt(mean(m["dose_error_pct"] for m, _, _ in ms), 3),
                         fmt(mean(m["valve_reversals_per_min"] for m, _, _ in ms), 1)])
    text = ("## 4. Longitudinal uniformity over a 3220 m field run (cf. Table 4)\n\n"
            "`scenarios/field_3220m_*`: start from rest, 8 passes at 7-9 km/h, headland slow-downs to 3 km/h, "
            "stop; volume per 5 m zone (0.9 / 1.125 / 1.35 L expected), seeds %s (CV: means; error range: over "
            "the three runs; start and stop: the first and last zone's error, means). Paper: BP-PID %s; fuzzy "
            "PID %s.\n\n" % (SEEDS, PAPER_T4["bp_pid"], PAPER_T4["fuzzy_pid"]))
    text += table(["L/ha", "controller", "CV whole run %", "CV v>=4 km/h %", "zone errors %", "start zone %",
                   "stop zone %", "dose error %", "reversals/min"], rows) + "\n\n"
    fig, ax = plt.subplots(2, 1, figsize=(10, 5), sharex=True)
    lim = 2.0
    for c in ctls:
        if c in ("ffmap", "bp_pid", "fuzzy_pid"):
            z = read_csv(os.path.join(zdir, "field150_%s_1.csv" % c))
            ax[0].plot(z["start_m"], z["vol_l"], lw=0.7, label=c)
            ax[1].plot(z["start_m"], z["error_pct"], lw=0.7)
            fast = [abs(e) for e, v in zip(z["error_pct"], z["mean_kmh"]) if v >= 4 and not math.isnan(e)]
            lim = max([lim] + [1.2 * x for x in fast])
    ax[0].axhline(1.35, color="k", lw=0.6, ls="--", label="expected 1.35 L")
    ax[0].set_ylim(bottom=0)
    ax[0].set_ylabel("L per 5 m zone")
    ax[0].legend(loc="lower left", bbox_to_anchor=(0, 1.0), ncol=4, fontsize=7, frameon=False)
    ax[1].axhline(0, color="k", lw=0.6)
    ax[1].set_ylim(-lim, lim)       # the zones at 4 km/h and more; a headland's slower zones leave the frame
    ax[1].set_ylabel("zone error %")
    ax[1].set_xlabel("m travelled")
    fig.suptitle("field_3220m_150, seed 1: volume per 5 m zone and its error (cf. paper Table 4)", fontsize=9)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "results_zones150.png"), dpi=90)
    plt.close(fig)
    return text + "![zones](results_zones150.png)\n"


# ---- 5. ISO 5682-3 style tests -------------------------------------------------------------------
ISO_TESTS = [
    ("speed", "speed steps 5.4 -> 7.2 -> 9 -> 7.2 -> 5.4 km/h, PTO fixed at 540 rpm",
     "[plant]\npto_coupled = 0\n[drive]\n0 0\n5 5.4\n%s", None),
    ("pto", "PTO steps 300 -> 400 -> 500 -> 400 -> 300 rpm at 7.2 km/h",
     "[plant]\npto_coupled = 0\npto_rpm = 300\n[drive]\n0 0\n5 7.2\n200 7.2\n[events]\n%s", None),
    ("dose", "dose resets 150 -> 100 -> 150 -> 125 -> 150 L/ha at 7.2 km/h, PTO fixed",
     "[plant]\npto_coupled = 0\n[drive]\n0 0\n5 7.2\n200 7.2\n[events]\n%s", None),
    ("sections", "sections 36 -> 18 -> 36 -> 6 -> 36 nozzles at 7.2 km/h, PTO fixed",
     "[plant]\npto_coupled = 0\n[drive]\n0 0\n5 7.2\n200 7.2\n[events]\n%s", None),
]
ISO_T = [40, 70, 100, 130, 160]  # change times; each level held 30 s; the run ends at 190 s


def iso_scenario(kind):
    if kind == "speed":
        speeds = [5.4, 7.2, 9.0, 7.2, 5.4]
        rows = "".join("%g %g\n%g %g\n" % (t, v, t + 30, v) for t, v in zip(ISO_T, speeds))
        return "[plant]\npto_coupled = 0\n[drive]\n0 0\n5 5.4\n" + rows
    ev = {"pto": ("pto_rpm", [400, 500, 400, 300]), "dose": ("rate_l_ha", [100, 150, 125, 150]),
          "sections": ("sections_open", [18, 36, 6, 36])}[kind]
    head = "[plant]\npto_coupled = 0\n%s[drive]\n0 0\n5 7.2\n200 7.2\n[events]\n" % (
        "pto_rpm = 300\n" if kind == "pto" else "")
    return head + "".join("%d %s %d\n" % (t, ev[0], v) for t, v in zip(ISO_T[1:], ev[1]))


def iso_figures(tr, t0, t1):
    """Response time (from the change until the flow stays within 5 % of the target up to t1) and
    the deviation (mean and largest abs(flow - target) / target over the second half)."""
    idx = [i for i, t in enumerate(tr["t_s"]) if t0 <= t < t1]
    err = [abs(tr["flow_true_lpm"][i] / tr["target_lpm"][i] - 1) * 100 if tr["target_lpm"][i] > 0 else 0 for i in idx]
    last_out = None
    for j, e in enumerate(err):
        if e > 5.0:
            last_out = j
    resp = 0.0 if last_out is None else (tr["t_s"][idx[last_out]] + 0.1 - t0)
    half = err[len(err) // 2:]
    return resp, mean(half), max(err) if err else None


def section_iso(R, ctls):
    jobs, keys = [], []
    for kind, title, _, _ in ISO_TESTS:
        text = "# ISO 5682-3 style: %s\n[run]\nduration_s = 190\n%s%s" % (title, base_config(150), iso_scenario(kind))
        path = R.scenario("iso_%s" % kind, text)
        for c in ctls:
            jobs.append((path, c, 1, ["--csv", "%s_%s.csv" % (path[:-4], c)]))
            keys.append((kind, c))
    R.many(jobs)
    text = ("## 5. Response to changes, after ISO 5682-3\n\n"
            "Each level is held 30 s (changes at 70, 100, 130 and 160 s, after a first hold from 40 s), 150 L/ha, "
            "seed 1. Response time: from the change until the true flow stays within 5 % of the firmware's target "
            "to the next change; deviation: abs(flow - target) / target, mean over the second half of each hold; "
            "largest: the largest deviation in the hold. Means over the four changes (the worst response in "
            "brackets).\n\n")
    rows = []
    for (kind, c), (path, _, _, e) in zip(keys, jobs):
        tr = read_csv(e[1])
        figs = [iso_figures(tr, t, t + 30) for t in ISO_T[1:]]
        title = [t for k, t, _, _ in ISO_TESTS if k == kind][0]
        rows.append([title.split(",")[0] if c == ctls[0] else "", c, "%s (%s)" % (fmt(mean(f[0] for f in figs), 1),
                                                                               fmt(max(f[0] for f in figs), 1)),
                     fmt(mean(f[1] for f in figs), 2), fmt(max(f[2] for f in figs), 1)])
    text += table(["test", "controller", "response s (worst)", "deviation %", "largest %"], rows)
    return text + "\n"


# ---- 6. Robustness: the family and single-factor sweeps ------------------------------------------
SWEEPS = [
    ("valve_travel_s", [1.5, 3, 4, 6, 9, 12], "valve stroke time s (untold: the firmware believes 4 s)", False),
    ("valve_travel_s", [1.5, 3, 4, 6, 9, 12], "valve stroke time s (told)", True),
    ("valve_backlash", [0.005, 0.01, 0.02, 0.03, 0.04], "valve backlash (stroke)", False),
    ("pump_pulsation_pct", [2, 4, 6, 8, 10], "pump pulsation %", False),
    ("speed_bounce_pct", [0, 1, 2, 3, 5], "wheel sensor bounce %", False),
    ("nozzle_wear_pct", [0, 5, 10, 15], "nozzle wear %", False),
]


def section_family(sim, ctls, n, jobs_n, out):
    # the peers also with settings tuned for each plant's valve (tools/family.py tuned_config)
    ctls = ctls + ["%s_tuned" % c for c in ("aog", "raven") if c in ctls]
    fam_out = os.path.join("build", "family-report")
    cmd = [sys.executable, "tools/family.py", sim, "--n", str(n), "--controllers", ",".join(ctls), "--seed", "1",
           "--out", fam_out, "--jobs", str(jobs_n)]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit("results: %s failed:\n%s" % (" ".join(cmd), r.stderr))
    with open(os.path.join(fam_out, "summary.json")) as f:
        s = json.load(f)
    rows = []
    for c in ctls:
        cs = s["controllers"][c]
        cell = lambda k, p=2: "%s / %s" % (fmt(cs[k]["median"], p), fmt(cs[k]["p95"], p))  # noqa: E731
        rows.append([c, cell("dose_abs_pct"), cell("dose_ctl_abs_pct"), cell("cv_pct"), cell("zone_worst_pct", 1),
                     cell("reversals_per_min", 1), cell("settle_mean_s"), "%d (%d)" % (cs["alarm_runs"], cs["uncaused_runs"]),
                     fmt(cs["cv_median_told"]), fmt(cs["cv_median_untold"])])
    text = ("## 6. Robustness\n\n### The plant family\n\n"
            "`make family N=%d SEED=1` (`tools/family.py`, docs/SCENARIOS.md): %d sprayers drawn from the family "
            "(valve 1.5-12 s, break-away 0.10-0.35, backlash 0.5-4 %%, pump, pulsation, PTO, meter, "
            "wheel, bounce, nozzle wear, check valves), each run with every controller twice: the firmware "
            "told the valve's stroke time, and told 4 s. Median / 95th "
            "percentile; alarm runs: runs with any alarm, warning or notice, in brackets those the draw gave no "
            "cause for (the family has no faults: a worn-nozzle notice where the draw wore the nozzles over 10 %%, "
            "the minimum-flow warning where the drive slowed under 4 km/h are caused); the last two columns: "
            "median CV where the firmware was told the valve's stroke time and where it was told 4 s "
            "(the same sprayers). "
            "The peers aog and raven run at their default settings, and as `aog_tuned` / `raven_tuned` with "
            "settings for each plant's valve as a careful user would set them (docs/PEERS.md).\n\n"
            % (n, n))
    text += table(["controller", "abs dose %", "abs ctl share %", "CV %", "worst zone %", "reversals/min",
                   "settle s", "alarm runs (without cause)", "CV told", "CV untold"], rows) + "\n\n"
    text += family_judge_text(s, ctls)
    by_run = {(False, 1): s}
    for corners, seed in ([(False, x) for x in FAMILY_TUNED + FAMILY_HELD_OUT]
                          + [(True, x) for x in CORNERS_TUNED + CORNERS_HELD_OUT]):
        out_s = os.path.join("build", "family-report-%s%d" % ("corners-" if corners else "", seed))
        cmd = [sys.executable, "tools/family.py", sim, "--n", str(min(CORNERS_N, n) if corners else n), "--controllers",
               "ffmap", "--seed", str(seed), "--out", out_s, "--jobs", str(jobs_n)] + (["--corners"] if corners else [])
        r = subprocess.run(cmd, capture_output=True, text=True)
        if r.returncode != 0:
            sys.exit("results: %s failed:\n%s" % (" ".join(cmd), r.stderr))
        with open(os.path.join(out_s, "summary.json")) as f:
            by_run[(corners, seed)] = json.load(f)
    text += family_seeds_text(n, by_run)
    return text, s


# seeds of the family ffmap is tuned on beside SEED=1, and seeds never tuned on: it is judged on both;
# the same for its corners (each of the 64 once, told and not)
FAMILY_TUNED = (7, 23)
FAMILY_HELD_OUT = (151, 173)
CORNERS_TUNED = (1,)
CORNERS_HELD_OUT = (10,)
CORNERS_N = 64   # (fewer with a smaller --family-n)


def judge_cell(j, unit):
    """median / p95 / max (worst plant), runs over the bound, of a family summary's judge entry"""
    if j["median"] is None:
        return "-", "-"
    return ("%.3g / %.3g / %.3g %s (%s)" % (j["median"], j["p95"], j["max"], unit, j["worst_plant"]),
            "%d of %d" % (j["over"], j["runs"]))


def family_judge_text(s, ctls):
    """Told or not, and the hunt, per controller of the SEED=1 family (tools/family.py JUDGE)."""
    rows = []
    for c in ctls:
        cs = s["controllers"][c]
        sw, swn = judge_cell(cs["silent_wrong_s"], "s")
        rp, rpn = judge_cell(cs["ripple_p95_pct"], "%")
        rows.append([c, sw, swn, rp, rpn, " ".join("%s:%d" % kv for kv in cs["alarm_codes"].items()) or "-"])
    return ("The same runs, told or not and how the flow hunts (docs/SCENARIOS.md): `silent_wrong_s`, the "
            "longest stretch of a wrong dose the operator was not told of, and `ripple_p95_pct`, the 95th "
            "percentile of the flow's error on a held target; median / 95th percentile / maximum (its plant, "
            "`SEED/NUMBER/told`, for `make redraw`), and the runs over issue 51's bounds (10 s, 5 %). Alarm "
            "codes: the runs with each (the family has no faults: MIN_FLOW is the minimum-flow rule's warning "
            "on the field runs' headland slow-downs, NOZZLE_WEAR the notice for nozzles the draw wore beyond "
            "about 10 %).\n\n"
            + table(["controller", "silent_wrong_s", "runs over 10 s", "ripple_p95_pct", "runs over 5 %",
                     "alarm codes (runs)"], rows) + "\n\n")


def family_seeds_text(n, by_run):
    """ffmap over the draws and corners it is tuned on and held-out ones: the figures issues 14 and 51
    judge it by."""
    rows = []
    for (corners, seed), s in by_run.items():
        cs = s["controllers"]["ffmap"]
        held = seed in (CORNERS_HELD_OUT if corners else FAMILY_HELD_OUT)
        cell = lambda k, p=2: "%s / %s" % (fmt(cs[k]["median"], p), fmt(cs[k]["p95"], p))  # noqa: E731
        sw, swn = judge_cell(cs["silent_wrong_s"], "s")
        rp, rpn = judge_cell(cs["ripple_p95_pct"], "%")
        rows.append(["`make family N=%d%s SEED=%d CONTROLLERS=ffmap`" % (min(CORNERS_N, n) if corners else n,
                                                                       " CORNERS=1" if corners else "", seed),
                     "held out" if held else "tuned on", cell("cv_pct"),
                     cell("dose_ctl_abs_pct"), cell("reversals_per_min", 1),
                     " ".join("%s:%d" % kv for kv in cs["alarm_codes"].items()) or "-", sw, swn, rp, rpn])
    return ("`ffmap` on the family's draws and corners (`CORNERS=1`: the valve's figures at the ends of "
            "their ranges, every noise at its top) it is tuned on, and on seeds never tuned on (held out): "
            "median / 95th percentile, and the two judges as above.\n\n"
            + table(["command", "seed", "CV %", "abs ctl share %", "reversals/min", "alarm codes (runs)",
                     "silent_wrong_s", "runs over 10 s", "ripple_p95_pct", "runs over 5 %"], rows) + "\n\n")


def section_faults(sim, jobs_n):
    """Issue 51's faults at two sizes (tools/faults.py, make faults): its table, as it stands."""
    cmd = [sys.executable, "tools/faults.py", sim, "--out", os.path.join("build", "faults"), "--jobs", str(jobs_n)]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit("results: %s failed:\n%s" % (" ".join(cmd), r.stderr))
    with open(os.path.join("build", "faults", "table.md")) as f:
        table_md = f.read()
    return ("\n### Faults: told or not\n\n"
            "`make faults` (`tools/faults.py`): every fault of issue 51's first table at its size and about "
            "half of it, on `ffmap` at 150 L/ha, 36 nozzles, 8 km/h unless the row says otherwise, the fault "
            "from 90 s (or from the start). The first alarm or warning at or after the fault's start and its "
            "delay; the dose while the operator was not told (the nozzles' volume against the operator's rate "
            "over the true speed and the flowing width, the boom shut at 2 km/h or more counting as nothing); "
            "`silent_wrong_s` (docs/SCENARIOS.md). \"none\" is what the firmware tells today, not a goal. "
            "A meter off its calibration is what the tank balance tells (issue 51: before 15 % of the tank is "
            "sprayed): its rows' note gives the share of the tank (full at the start) sprayed before "
            "the first METER_CAL (the trace's true volume at the two instants).\n\n"
            + table_md + "\n")


def section_sweeps(R, ctls, out):
    base = open("scenarios/paper_dynamic_150_fixed_pto.scn").read()
    jobs, keys = [], []
    for key, vals, label, told in SWEEPS:
        for v in vals:
            text = base.replace("[plant]\n", "[plant]\n%s = %g\n" % (key, v), 1)
            if key == "valve_travel_s" and told:
                text = text.replace("[config]\n", "[config]\nvalve_travel_s = %g\n" % v, 1)
            name = "sweep_%s_%s_%g" % (key, "told" if told else "untold", v)
            path = R.scenario(name, text)
            for c in ctls:
                for s in (1, 2):
                    jobs.append((path, c, s, []))
                    keys.append((label, v, c))
    res = R.many(jobs)
    agg = {}
    for k, m in zip(keys, res):
        agg.setdefault(k, []).append(m)
    text = ("### Single-factor sweeps\n\n`scenarios/paper_dynamic_150_fixed_pto.scn` (the hard case: the valve "
            "does all the work) with one plant key changed, seeds 1-2, the firmware at its defaults unless told. "
            "CV and valve reversals a minute against the factor.\n\n")
    fig, axes = plt.subplots(len(SWEEPS), 2, figsize=(10, 2.2 * len(SWEEPS)))
    for row, (key, vals, label, told) in enumerate(SWEEPS):
        for col, fig_key in enumerate(("cv_pct", "valve_reversals_per_min")):
            ax = axes[row][col]
            for c in ctls:
                ax.plot(vals, [mean(m[fig_key] for m in agg[(label, v, c)]) for v in vals], marker="o", ms=3,
                        lw=0.8, label=c)
            ax.set_xlabel(label, fontsize=8)
            ax.set_ylabel("CV %" if col == 0 else "reversals/min", fontsize=8)
            ax.set_ylim(bottom=0)
            ax.tick_params(labelsize=7)
    h, lb = axes[0][0].get_legend_handles_labels()
    fig.legend(h, lb, loc="upper center", ncol=len(ctls), fontsize=7, frameon=False)
    fig.tight_layout(rect=(0, 0, 1, 0.97))
    fig.savefig(os.path.join(out, "results_sweeps.png"), dpi=80)
    plt.close(fig)
    rows = []
    for key, vals, label, told in SWEEPS:
        for c in ctls:
            rows.append([label if c == ctls[0] else "", c] +
                        ["%s / %s" % (fmt(mean(m["cv_pct"] for m in agg[(label, v, c)])),
                                      fmt(mean(m["valve_reversals_per_min"] for m in agg[(label, v, c)]), 0))
                         for v in vals] + [""] * (6 - len(vals)))
    text += table(["factor", "controller"] + ["value %d: CV %% / rev" % (i + 1) for i in range(6)], rows)
    text += "\n\nValues in order: " + "; ".join("%s: %s" % (label, ", ".join("%g" % v for v in vals))
                                               for _, vals, label, _ in SWEEPS)
    return text + "\n\n![sweeps](results_sweeps.png)\n"


# ---- 7. Cost -------------------------------------------------------------------------------------
def section_cost(bench, memory, bench_sim):
    text = "## 7. Cost on the chip and in the simulator\n\n"
    for title, path, note in (("`make firmware`: memory of the STC12C5A60S2 image", memory, ""),
                              ("`make bench`: machine cycles in s51 (classic 12-clock timing; the STC12 is a 1T "
                               "core, about eight times faster on this code)", bench, ""),
                              ("`make bench-sim`: the simulator's speed on one core", bench_sim, "")):
        text += "%s:\n\n" % title
        if path and os.path.exists(path):
            lines = [l.rstrip() for l in open(path) if l.strip() and not l.startswith("make")]
            text += "```\n" + "\n".join(lines[-60:]) + "\n```\n\n"
        else:
            text += "(not measured in this run)\n\n"
    return text


# ---- the headline --------------------------------------------------------------------------------
def headline(dyn, ctls):
    m150 = {c: dyn[("paper_dynamic_150", c)] for c in ctls}
    rows = []
    for c in ctls:
        ms = m150[c]
        rows.append([c, fmt(mean(abs(m["dose_error_pct"]) for m in ms), 2), fmt(mean(m["cv_pct"] for m in ms), 2),
                     fmt(mean(m["overshoot_mean_pct"] for m in ms), 2), fmt(mean(m["settle_mean_s"] for m in ms), 2),
                     fmt(mean(m["valve_reversals_per_min"] for m in ms), 1)])
    ms = dyn[("paper_dynamic_150", "ref")]
    rows.append(["a flow exactly on the true reference", "-", "-", fmt(mean(m["overshoot_mean_pct"] for m in ms), 2),
                 fmt(mean(m["settle_mean_s"] for m in ms), 2), "-"])
    for c, pv in PAPER_51.items():
        rows.append(["paper's %s (field)" % c, fmt(pv["dose"], 1), "5.1" if c == "bp_pid" else "8.1",
                     fmt(pv["ovs"], 1), fmt(pv["settle"], 2), "-"])
    return table(["paper's dynamic run, 150 L/ha, PTO coupled", "abs dose error %", "CV %", "mean overshoot %",
                  "mean settling s", "reversals/min"], rows)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sim", default="build/host/bin/sim")
    ap.add_argument("--out", default="docs")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 2)
    ap.add_argument("--family-n", type=int, default=200)
    ap.add_argument("--bench")
    ap.add_argument("--memory")
    ap.add_argument("--bench-sim")
    ap.add_argument("--readme", default="README.md")
    a = ap.parse_args()
    if not os.access(a.sim, os.X_OK):
        sys.exit("results: %s: no simulator (make sim-progs)" % a.sim)
    t0 = time.time()
    os.makedirs(a.out, exist_ok=True)
    ctls = controllers_known(a.sim)
    R = Runner(a.sim, a.jobs, os.path.join("build", "report"))
    parts = []
    s1, _ = section_steps(R, ctls)
    s2, dyn = section_dynamic(R, ctls, a.out)
    s3 = section_accuracy(R, "ffmap")
    s4 = section_field(R, ctls, a.out)
    s5 = section_iso(R, ctls)
    t_fam = time.time()
    s6, fam = section_family(a.sim, ctls, a.family_n, a.jobs, a.out)
    print("results: the family of %d plants x %d controllers in %.0f s" % (a.family_n, len(ctls), time.time() - t_fam))
    s6b = section_sweeps(R, ctls, a.out)
    s6c = section_faults(a.sim, a.jobs)
    s7 = section_cost(a.bench, a.memory, a.bench_sim)
    head = headline(dyn, ctls)
    intro = ("# Results: the paper's experiments reproduced, and beyond\n\n"
             "Written by `make report` (`tools/results.py`) from the runs it makes on the simulated sprayer of "
             "docs/SCENARIOS.md; nothing below is typed in except the paper's own numbers, which are marked as "
             "the paper's. Seeds are fixed, so a second run gives the same figures (but the timings of the cost section, which measure the machine the report runs on). Controllers: %s (`ffmap` is the "
             "project's own, the firmware's default). The paper's figures come from its own field tests and "
             "simulation, not from this plant: they are a yardstick, not a like-for-like comparison.\n\n"
             "## Headline\n\n%s\n\n" % (", ".join(ctls), head))
    with open(os.path.join(a.out, "RESULTS.md"), "w") as f:
        f.write(intro + "\n".join([s1, s2, s3, s4, s5, s6 + s6b + s6c, s7]))
    # the README's headline table, between its markers
    if os.path.exists(a.readme):
        txt = open(a.readme).read()
        begin, end = "<!-- results:begin -->", "<!-- results:end -->"
        if begin in txt and end in txt:
            new = (begin + "\n" + head + "\n\n(means over seeds %s of `scenarios/paper_dynamic_150.scn`; written by "
                   "`make report`, the whole report in [docs/RESULTS.md](docs/RESULTS.md). The step figures score "
                   "the flow against the firmware's target, which the measured speed gives: \"a flow exactly on the "
                   "true reference\" is what they give before any controller acts.)\n" % SEEDS + end)
            txt = re.sub(re.escape(begin) + ".*?" + re.escape(end), lambda _: new, txt, flags=re.S)
            with open(a.readme, "w") as f:
                f.write(txt)
    print("results: wrote %s/RESULTS.md and its plots in %.0f s" % (a.out, time.time() - t0))


if __name__ == "__main__":
    main()

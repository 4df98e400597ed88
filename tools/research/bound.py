#!/usr/bin/env python3
"""bound.py: what an IDEAL controller could reach on a run: the limit the plant itself sets.

usage: bound.py TRACE.csv --samples SAMPLES.csv [--travel S] [--scenario SCN] [--json SIM_STDOUT]
       bound.py --run SIM_BIN SCENARIO [CONTROLLER] [--travel S] [--substeps N] [--seed N]

TRACE.csv is a 0.1 s trace of the simulator (sim --csv), SAMPLES.csv its step series (sim --samples). The target flow, the PTO speed, the
boom switch and the open nozzles in it do not depend on the controller, so any controller's
run will do. --run runs SIM_BIN on SCENARIO (controller 'ffmap' unless given) to a temporary
trace first (--seed N: the sim's --seed, another noise draw of the run), reads the scenario's
[plant] keys and checks the step metrics against the sim's own JSON.

The ideal controller knows the true pump flow and the target exactly, has no measurement delay,
no backlash, no stiction, and moves the bypass valve at most at the valve's full speed (one
stroke per valve_travel_s). For every sample it computes the valve position theta_req that makes
the boom flow equal the target (steady state of the line with the plant of sim/plant.c), and a
follower moves toward it at most at full speed (10 substeps of 10 ms a sample, PTO speed
interpolated). The boom flow the follower gives is the steady solution of the line equation at
its position, averaged over the sample like the sim's flow_true_lpm, and scored by the
simulator's own step code (build/host/bin/steps) against the run's reference and target series
(sim --samples).

The summary adds the same follower seeing the pump's speed 0.1, 0.2 and 0.3 s late (it aims at
the position that suits the target now and the pump as it was then): what the meter, the control
period and the valve's response cost a controller that is otherwise ideal. Each row gives the
steps' mean overshoot and settling, and start_s (the boom's opening until the flow stays within
5 % of the firmware's target for 2 s).

Left out, both on the kind side (the bound is optimistic): the pump pulsation, the line
compliance (the pressure follows the valve at once instead of in about 0.1 s) and the turbine's
lag (the metrics use the true flow anyway). Also held optimistic: inside each 0.1 s sample the
follower aims at that sample's target (the sim's firmware may change it anywhere in the 0.1 s),
and the boom is taken open for the whole sample in which spray_on turns 1.
The start: "right" puts the valve where theta_req is at the first sample that sprays (the ideal
parks it there beforehand); "open" starts it parked fully open (theta 1), as the firmware parks it.
Stdlib only.
"""
import json
import math
import os
import subprocess
import sys
import tempfile

# ---- the plant of sim/plant.c, default parameters (sim/plant.h PLANT_KEYS) --------------------
DEFAULTS = {
    "pump_lpm_at_540": 120.0,
    "pump_slip_per_bar": 0.01,
    "relief_bar": 5.0,
    "relief_lpm_per_bar": 200.0,
    "valve_cv_open": 120.0,
    "valve_rangeability": 30.0,
    "valve_travel_s": 4.0,
    "line_loss_bar_at_50lpm": 0.025,
    "nozzle_lpm_at_3bar": 1.18,
    "check_valve_bar": 0.3,
    "nozzle_wear_pct": 0.0,
}

# ---- the step metrics: the simulator's own code (build/host/bin/steps) ------------------------
SAMPLE_S = 0.1
STEPS_BIN = [None]


def read_samples(path):
    """The step series of `sim --samples` (sample 0 at t = 0): ref, target, work, spray."""
    with open(path) as f:
        head = f.readline().strip().split(",")
        need = ["t_s", "ref_lpm", "target_lpm", "flow_lpm", "work", "spray"]
        if head[:len(need)] != need:
            sys.exit("bound: %s: not a sim --samples file (header %s)" % (path, ",".join(need)))
        rows = [line.strip().split(",") for line in f if line.strip()]
    return {k: [float(r[i]) for r in rows] for i, k in enumerate(need)}


def find_steps(samples, Y):
    """The step figures of flow Y against the series' reference and target, scored by `steps`."""
    return find_scores(samples, Y)[0]


def find_scores(samples, Y):
    """(the step figures, start_s) of flow Y, scored by `steps`: start_s is the time from the
    boom's opening until Y stays within 5 % of the firmware's target for 2 s (None: never)."""
    fd, path = tempfile.mkstemp(prefix="bound_samples_", suffix=".csv")
    try:
        with os.fdopen(fd, "w") as f:
            f.write("t_s,ref_lpm,target_lpm,flow_lpm,work,spray\n")
            for k in range(min(len(Y), len(samples["t_s"]))):
                f.write("%.1f,%.17g,%.17g,%.17g,%d,%d\n" % (samples["t_s"][k], samples["ref_lpm"][k],
                                                        samples["target_lpm"][k], Y[k], samples["work"][k],
                                                        samples["spray"][k]))
        out = subprocess.run([STEPS_BIN[0], path], capture_output=True, text=True)
        if out.returncode != 0:
            sys.exit("bound: %s failed: %s" % (STEPS_BIN[0], out.stderr.strip()))
        js = json.loads(out.stdout)
        return js["steps"], js.get("start_s")
    finally:
        os.unlink(path)


class Plant:
    def __init__(self, p):
        self.p = dict(p)
        self.qnom = p["pump_lpm_at_540"]
        self.ks = p["pump_slip_per_bar"]
        self.ps = p["relief_bar"]
        self.kr = p["relief_lpm_per_bar"]
        self.cv_open = p["valve_cv_open"]
        self.r = p["valve_rangeability"]
        self.pc = p["check_valve_bar"]
        self.kn = p["nozzle_lpm_at_3bar"] / math.sqrt(3.0) * (1.0 + p["nozzle_wear_pct"] / 100.0)
        self.k_line = p["line_loss_bar_at_50lpm"] / 2500.0

    def cv(self, theta):
        """plant_cv: equal percentage, shifted so that Cv(0) = 0, Cv(1) = valve_cv_open."""
        if theta <= 0.0:
            return 0.0
        theta = min(theta, 1.0)
        r = self.r
        return self.cv_open * (math.exp((theta - 1.0) * math.log(r)) - 1.0 / r) / (1.0 - 1.0 / r)

    def theta_of_cv(self, cv):
        """The inverse of cv(), clipped to [0, 1]."""
        if cv <= 0.0:
            return 0.0
        if cv >= self.cv_open:
            return 1.0
        r = self.r
        x = cv / self.cv_open * (1.0 - 1.0 / r) + 1.0 / r
        return min(1.0, max(0.0, 1.0 + math.log(x) / math.log(r)))

    def boom_coef(self, m):
        """A = mK / sqrt(1 + (mK)^2 k): Q = A sqrt(P - Pc) with the line loss folded in."""
        a = m * self.kn
        return a / math.sqrt(1.0 + a * a * self.k_line)

    def qp0(self, pto_rpm):
        return self.qnom * pto_rpm / 540.0

    def pump(self, qp0, p):
        return qp0 * max(0.0, 1.0 - self.ks * p)

    def relief(self, p):
        return self.kr * (p - self.ps) if p > self.ps else 0.0

    def theta_req(self, pto_rpm, target, m):
        """The valve position whose steady boom flow is the target (clipped to [0, 1])."""
        a = self.boom_coef(m)
        p = self.pc + (target / a) ** 2
        cv = (self.pump(self.qp0(pto_rpm), p) - target - self.relief(p)) / math.sqrt(p)
        return self.theta_of_cv(cv)

    def boom_flow(self, pto_rpm, theta, m):
        """Steady line: pump(P) - relief(P) - Cv sqrt(P) - A sqrt(P - Pc) = 0 (bisection); the boom flow."""
        qp0 = self.qp0(pto_rpm)
        if qp0 <= 0.0 or m <= 0:
            return 0.0
        cv = self.cv(theta)
        a = self.boom_coef(m)
        lo = 0.0
        hi = min(1.0 / self.ks if self.ks > 0 else 1e9, self.ps + qp0 / self.kr) + 1e-9
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            f = self.pump(qp0, mid) - self.relief(mid) - cv * math.sqrt(mid)
            if mid > self.pc:
                f -= a * math.sqrt(mid - self.pc)
            if f > 0.0:
                lo = mid
            else:
                hi = mid
            if hi - lo < 1e-12:
                break
        p = 0.5 * (lo + hi)
        return a * math.sqrt(p - self.pc) if p > self.pc else 0.0



def means(steps):
    if not steps:
        return float("nan"), float("nan")
    return (sum(s["overshoot_pct"] for s in steps) / len(steps),
            sum(s["settle_5pct_s"] for s in steps) / len(steps))


# ---- input -------------------------------------------------------------------------------------
def read_trace(path):
    with open(path) as f:
        head = f.readline().strip().split(",")
        col = {c: i for i, c in enumerate(head)}
        need = ["t_s", "target_lpm", "flow_true_lpm", "boom_lpm", "pto_rpm", "spray_on", "open_nozzles", "valve_pos"]
        miss = [c for c in need if c not in col]
        if miss:
            sys.exit("bound: %s: no column %s" % (path, ", ".join(miss)))
        rows = {c: [] for c in need}
        for line in f:
            v = line.strip().split(",")
            if len(v) < len(head):
                continue
            for c in need:
                rows[c].append(float(v[col[c]]))
    t = rows["t_s"]
    if len(t) < 30:
        sys.exit("bound: %s: too short a trace" % path)
    for i, ti in enumerate(t):
        if abs(ti - SAMPLE_S * (i + 1)) > 1e-6:
            sys.exit("bound: %s: row %d at t=%g: needs a %.1f s trace starting at %.1f s (sim --trace-period 0.1)"
                     % (path, i + 2, ti, SAMPLE_S, SAMPLE_S))
    return rows


def read_plant_keys(scn_path):
    """The [plant] keys of a scenario that this model uses (the others do not matter here)."""
    got = {}
    sec = None
    with open(scn_path) as f:
        for line in f:
            line = line.split("#", 1)[0].strip()
            if not line:
                continue
            if line.startswith("[") and line.endswith("]"):
                sec = line[1:-1].strip()
                continue
            if sec == "plant" and "=" in line:
                k, v = (x.strip() for x in line.split("=", 1))
                if k in DEFAULTS:
                    got[k] = float(v)
    return got


# ---- the ideal follower ------------------------------------------------------------------------
def ideal(plant, rows, travel, start, substeps, late=0):
    """Samples of the ideal follower's flow (sample 0 at t = 0 first, as metrics_sample) and stats.
    late: substeps by which the follower sees the pump's speed late (0: at once)."""
    n = len(rows["t_s"])
    pto, tgt, on, noz = rows["pto_rpm"], rows["target_lpm"], rows["spray_on"], rows["open_nozzles"]
    h = SAMPLE_S / substeps
    vmax = h / travel                               # stroke per substep at full speed
    theta = None
    flow = [0.0]                                    # sample 0: the sim samples 0 L/min at t = 0
    behind = sprayed = 0

    def rpm_at(i, j):                               # the PTO speed at substep j of sample i
        while j <= 0 and i > 0:
            i, j = i - 1, j + substeps
        if j <= 0:
            return pto[0]
        p0 = pto[i - 1] if i > 0 else pto[i]
        return p0 + (pto[i] - p0) * j / substeps

    for i in range(n):
        m = int(noz[i])
        if not (on[i] >= 0.5 and m > 0):
            flow.append(0.0)                        # boom shut: the valve stays where it is
            continue
        p0 = pto[i - 1] if i > 0 else pto[i]
        acc = 0.0
        for j in range(1, substeps + 1):
            n_rpm = p0 + (pto[i] - p0) * j / substeps
            if tgt[i] > 0.0:
                req = plant.theta_req(rpm_at(i, j - late) if late else n_rpm, tgt[i], m)
            else:
                req = theta if theta is not None else 1.0    # nothing asked: no move needed
            if theta is None:
                theta = req if start == "right" else 1.0
            d = req - theta
            if abs(d) > vmax:
                theta += vmax if d > 0 else -vmax
                behind += 1
            else:
                theta = req
            sprayed += 1
            acc += plant.boom_flow(n_rpm, theta, m)
        flow.append(acc / substeps)
    return flow, (behind / sprayed if sprayed else 0.0)


def required_speed(plant, rows, travel):
    """theta_req at the sample times; its speed between samples while the boom sprays."""
    n = len(rows["t_s"])
    pto, tgt, on, noz, t = rows["pto_rpm"], rows["target_lpm"], rows["spray_on"], rows["open_nozzles"], rows["t_s"]
    req = [None] * n
    for i in range(n):
        if on[i] >= 0.5 and noz[i] > 0 and tgt[i] > 0:
            req[i] = plant.theta_req(pto[i], tgt[i], int(noz[i]))
    speeds = []                                     # (stroke/s, t)
    for i in range(1, n):
        if req[i] is not None and req[i - 1] is not None:
            speeds.append((abs(req[i] - req[i - 1]) / SAMPLE_S, t[i]))
    # the same over 1 s (10 samples): the target's 0.1 s staircase averaged out
    speeds1 = []
    for i in range(10, n):
        if req[i] is not None and all(req[k] is not None for k in range(i - 10, i + 1)):
            speeds1.append((abs(req[i] - req[i - 10]) / (10 * SAMPLE_S), t[i]))
    vlim = 1.0 / travel

    def stat(sp):
        if not sp:
            return 0.0, 0.0, 0.0
        fast = sum(1 for s, _ in sp if s > vlim + 1e-12)
        mx = max(sp)
        return fast / len(sp), mx[0], mx[1]
    on_req = [r for r in req if r is not None]
    return stat(speeds), stat(speeds1), (min(on_req), max(on_req)) if on_req else (0, 0), \
        sum(1 for r in on_req if r <= 0.0 or r >= 1.0) / max(1, len(on_req))


# ---- report ------------------------------------------------------------------------------------
def fmt(x, p=2):
    return "-" if x is None or (isinstance(x, float) and math.isnan(x)) else "%.*f" % (p, x)


def print_steps(title, steps):
    print(title)
    print("  %8s %8s %8s %10s %9s %8s" % ("t_s", "from", "to", "overshoot%", "settle_s", "settled"))
    for s in steps:
        print("  %8.1f %8.2f %8.2f %10.2f %9.2f %8s" % (s["t_s"], s["from_lpm"], s["to_lpm"], s["overshoot_pct"],
                                                       s["settle_5pct_s"], "yes" if s["settled_5pct"] else "NO"))
    o, st = means(steps)
    print("  mean overshoot %s %%, mean settle (+-5 %%) %s s, %d steps" % (fmt(o), fmt(st), len(steps)))


def main(argv):
    args = list(argv)
    opts = {"--travel": None, "--scenario": None, "--json": None, "--substeps": "10", "--samples": None,
            "--steps": None, "--seed": None}
    pos = []
    run = None
    i = 0
    while i < len(args):
        a = args[i]
        if a in ("-h", "--help"):
            print(__doc__)
            return 0
        if a == "--run":
            run = args[i + 1:]
            break
        if a in opts:
            if i + 1 >= len(args):
                sys.exit("bound: %s needs a value" % a)
            opts[a] = args[i + 1]
            i += 2
            continue
        pos.append(a)
        i += 1
    sim_json = None
    tmp = None
    if run is not None:
        rest = []
        j = 0
        while j < len(run):                         # options may also follow --run's arguments
            if run[j] in opts and j + 1 < len(run):
                opts[run[j]] = run[j + 1]
                j += 2
            else:
                rest.append(run[j])
                j += 1
        if len(rest) < 2 or len(rest) > 3:
            sys.exit("usage: bound.py --run SIM_BIN SCENARIO [CONTROLLER] [--travel S] [--substeps N] [--seed N]")
        if opts["--seed"] is not None and not opts["--seed"].isdigit():
            sys.exit("bound: --seed %s: give a seed 0 or above" % opts["--seed"])
        sim, scn = rest[0], rest[1]
        ctl = rest[2] if len(rest) > 2 else "ffmap"
        fd, tmp = tempfile.mkstemp(prefix="bound_", suffix=".csv")
        os.close(fd)
        fd, tmp_s = tempfile.mkstemp(prefix="bound_s_", suffix=".csv")
        os.close(fd)
        cmd = [sim, "--scenario", scn, "--controller", ctl, "--csv", tmp, "--trace-period", "0.1", "--samples", tmp_s]
        if opts["--seed"] is not None:
            cmd += ["--seed", opts["--seed"]]
        out = subprocess.run(cmd, capture_output=True, text=True)
        if out.returncode != 0:
            os.unlink(tmp)
            os.unlink(tmp_s)
            sys.exit("bound: %s failed:\n%s" % (sim, out.stderr))
        samples = read_samples(tmp_s)
        os.unlink(tmp_s)
        opts["--steps"] = opts["--steps"] or os.path.join(os.path.dirname(sim), "steps")
        sim_json = json.loads(out.stdout.strip().splitlines()[-1])
        opts["--scenario"] = opts["--scenario"] or scn
        trace = tmp
        label = "%s, controller %s%s" % (os.path.basename(scn), ctl,
                                         ", seed %s" % opts["--seed"] if opts["--seed"] is not None else "")
    else:
        if len(pos) != 1 or not opts["--samples"]:
            sys.exit("usage: bound.py TRACE.csv --samples SAMPLES.csv [--travel S] [--scenario SCN] [--json SIM_STDOUT]\n"
                     "                [--substeps N] [--steps STEPS_BIN]\n"
                     "       bound.py --run SIM_BIN SCENARIO [CONTROLLER] [--travel S] [--substeps N]")
        samples = read_samples(opts["--samples"])
        trace = pos[0]
        label = trace
        if opts["--json"]:
            with open(opts["--json"]) as f:
                sim_json = json.loads(f.read().strip().splitlines()[-1])
    try:
        rows = read_trace(trace)
    finally:
        if tmp:
            os.unlink(tmp)

    params = dict(DEFAULTS)
    if opts["--scenario"]:
        over = read_plant_keys(opts["--scenario"])
        params.update(over)
    travel = float(opts["--travel"]) if opts["--travel"] else params["valve_travel_s"]
    params["valve_travel_s"] = travel
    substeps = max(1, int(opts["--substeps"]))
    plant = Plant(params)

    print("bound: %s" % label)
    print("plant: %s" % ", ".join("%s %g" % (k, params[k]) for k in DEFAULTS)
          + ("  (from %s where set)" % opts["--scenario"] if opts["--scenario"] else "  (defaults)"))
    STEPS_BIN[0] = opts["--steps"] or "build/host/bin/steps"
    if not os.access(STEPS_BIN[0], os.X_OK):
        sys.exit("bound: %s: no step scorer (make build/host/bin/steps)" % STEPS_BIN[0])
    T = samples                                              # sample 0 at t = 0 (metrics_sample in sim_init)
    Y = [0.0] + rows["flow_true_lpm"]

    # the scorer against the sim's own figures
    own, start_own = find_scores(T, Y)
    o_own, s_own = means(own)
    print("\nthe step scorer on the trace's own flow_true_lpm: %d steps, overshoot mean %.4f %%, settle mean %.4f s"
          % (len(own), o_own, s_own))
    if sim_json is not None:
        js = sim_json.get("steps", [])
        o_js, s_js = sim_json.get("overshoot_mean_pct"), sim_json.get("settle_mean_s")
        print("  the sim's JSON:                              %d steps, overshoot mean %s %%, settle mean %s s"
              % (len(js), o_js, s_js))
        if len(js) == len(own):
            d_o = max(abs(a["overshoot_pct"] - (b["overshoot_pct"] or 0)) for a, b in zip(own, js))
            d_s = max(abs(a["settle_5pct_s"] - (b["settle_5pct_s"] or 0)) for a, b in zip(own, js))
            d_t = max(abs(a["t_s"] - b["t_s"]) for a, b in zip(own, js))
            print("  largest per-step difference: overshoot %.2g %%, settle %.2g s, t %.2g s"
                  " (the trace prints flow with 4 decimals)" % (d_o, d_s, d_t))
        else:
            print("  STEP COUNTS DIFFER")

    # the plant port: the steady model at the sim's own valve position against the sim's boom flow
    rel = []
    for i in range(len(rows["t_s"])):
        q = rows["boom_lpm"][i]
        if rows["spray_on"][i] >= 0.5 and q > 1.0:
            rel.append(abs(plant.boom_flow(rows["pto_rpm"][i], rows["valve_pos"][i], int(rows["open_nozzles"][i])) - q) / q)
    if rel:
        rel.sort()
        print("plant port: steady model at the run's valve_pos vs its boom_lpm: |error| median %.2f %%, 95th %.2f %%,"
              " largest %.1f %% (pulsation, line compliance in transients)"
              % (100 * rel[len(rel) // 2], 100 * rel[int(0.95 * (len(rel) - 1))], 100 * rel[-1]))

    on_idx = [i for i, v in enumerate(rows["spray_on"]) if v >= 0.5]
    if on_idx:
        k = on_idx[0]
        print("\nboom opens at t = %.1f s; the sim's valve stood at %.3f before it"
              % (rows["t_s"][k], rows["valve_pos"][k - 1] if k > 0 else rows["valve_pos"][k]))

    perfect, start_pf = find_scores(T, T["target_lpm"])
    o_pf, s_pf = means(perfect)
    print("\nflow = target exactly (no plant at all): overshoot mean %.2f %%, settle mean %.2f s" % (o_pf, s_pf))

    res = {}
    for start, what in (("right", "from the right place"), ("open", "from parked open (theta 1)")):
        flow, behind = ideal(plant, rows, travel, start, substeps)
        st, start_s = find_scores(T, flow)
        res[start] = (means(st), behind, start_s)
        print()
        print_steps("ideal follower, valve %g s a stroke, start %s:" % (travel, what), st)
        print("  the follower is at full speed and still behind in %.1f %% of the spraying time" % (100.0 * behind))

    # the same follower, but seeing the pump's speed late, as a real controller does through the
    # meter and its period (the target it knows at once: it computes it)
    for late_s in (0.1, 0.2, 0.3):
        flow, _ = ideal(plant, rows, travel, "open", substeps, int(round(late_s / (SAMPLE_S / substeps))))
        st, start_s = find_scores(T, flow)
        res["late %.1f" % late_s] = (means(st), late_s, start_s)

    (f01, m01, t01), (f1, m1, t1), (rmin, rmax), clip = required_speed(plant, rows, travel)
    print("\ntheta_req while spraying: %.3f .. %.3f (%.1f %% of the samples clipped at an end)" % (rmin, rmax, 100 * clip))
    print("theta_req faster than the valve (%.3f stroke/s): %.1f %% of the 0.1 s intervals, largest %.3f stroke/s at t = %.1f s"
          % (1.0 / travel, 100 * f01, m01, t01))
    print("  over 1 s windows (the target's 0.1 s staircase averaged): %.1f %%, largest %.3f stroke/s at t = %.1f s"
          % (100 * f1, m1, t1))

    # start_s: the start is no step (docs/SCENARIOS.md), scored on its own; the late followers'
    # starts show what seeing the pump late costs it
    print("\nsummary: %-34s %12s %12s %9s" % ("", "overshoot %", "settle s", "start s"))
    print("  %-42s %12s %12s %9s" % ("goal", "<= 1.00", "<= 0.50", "<= 3.0"))
    print("  %-42s %12s %12s %9s" % ("flow = target (no plant limit)", fmt(o_pf), fmt(s_pf), fmt(start_pf, 1)))
    for start, what in (("right", "ideal, from the right place"), ("open", "ideal, from parked open")):
        (o, s), _, start_s = res[start]
        print("  %-42s %12s %12s %9s" % (what, fmt(o), fmt(s), fmt(start_s, 1)))
    for late_s in (0.1, 0.2, 0.3):
        (o, s), _, start_s = res["late %.1f" % late_s]
        print("  %-42s %12s %12s %9s" % ("ideal, parked open, pump seen %.1f s late" % late_s, fmt(o), fmt(s),
                                         fmt(start_s, 1)))
    print("  %-42s %12s %12s %9s" % ("the run's own controller (trace)", fmt(o_own), fmt(s_own), fmt(start_own, 1)))
    if sim_json is not None:
        print("  %-42s %12s %12s %9s" % ("the run's own controller (sim JSON)", fmt(sim_json.get("overshoot_mean_pct")),
                                         fmt(sim_json.get("settle_mean_s")), fmt(sim_json.get("start_s"), 1)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

#!/usr/bin/env python3
"""faults.py: every fault of issue 51's first table at two sizes, told or not (`make faults`).

Usage: tools/faults.py SIM [--out build/faults] [--controller ffmap] [--jobs N] [--only NAME,..] [--tank-l L]

For each fault (FAULTS below: the issue's size and about half of it) it writes a scenario into
OUT (150 L/ha, 36 nozzles at 50 cm, 8 km/h unless the fault says otherwise; the fault starts at
T0 = 90 s, after the firmware's first minute of clean spraying, unless it is there from the
start), runs it in the simulator with a trace and the serial link recorded, and prints a table:
the fault, its size, the first alarm or warning raised at or after the fault's start (code and
LCD text) and its delay, the dose error while the operator was not told, silent_wrong_s, and a
note where the fault is about the link or the EEPROM more than the dose. The table goes to
OUT/table.md (Markdown), every figure to OUT/summary.json.

A wrong meter calibration is one that only the tank balance may tell (issue 51: told before 15 %
of the tank is sprayed): for those rows the note gives the share of the tank sprayed from the
fault's start to the first METER_CAL, from the trace's true tank volume at the two instants over
the tank's size (the scenario's `tank_l`, full at the start), and whether it is under 15 %.

The dose error while silent: over the 0.1 s trace rows from the fault's start with no alarm
active, the nozzles' volume against what the operator's rate asks for over the true speed and
the width of the open nozzles that are not clogged (sections on, 0.5 km/h or more; the boom
shut at 2 km/h or more counts as nothing applied), in %; what the boom sprayed meanwhile at a
standstill is given apart, in litres, in the note. The operator's rate is the row's own
(a `SET` the operator sent stays what he asked for, whatever a reboot loads).
It reports what the firmware does, no more: a fault the firmware does not tell shows no alarm.
"""
import argparse
import csv
import json
import os
import re
import subprocess
import sys
from multiprocessing import Pool

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import progress  # noqa: E402  (tools/progress.py: the progress line on a terminal)

PARAMS_H = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "firmware", "store", "params.h")
T0 = 90.0                       # the fault's start, unless the fault is there from the start
RATE, NOZZLES, SPACING_M, KMH = 150, 36, 0.5, 8.0
TANK_L = 1000                   # the meter rows' tank, full at the start
BALANCE_CODE, BALANCE_MAX_PCT = "METER_CAL", 15.0   # the tank balance's alarm; issue 51's bound


def param_id(name):
    """A parameter's number on the link: its place in firmware/store/params.h's table."""
    ids = re.findall(r"^\s*X\((P_\w+)\s*,", open(PARAMS_H).read(), re.M)
    return ids.index(name)


def csum(line):
    """The serial link's line with its check, as the firmware's parser checks it: the CRC-8 of the
    body (polynomial 0x65, initial 0, MSB first; docs/PC.md)."""
    c = 0
    for ch in line.encode("ascii"):
        c ^= ch
        for _ in range(8):
            c = ((c << 1) ^ 0x65) & 0xFF if c & 0x80 else (c << 1) & 0xFF
    return "%s*%02X" % (line, c)


def xor_check(line):
    """The link's former check, the XOR of the body's bytes: the attack of the xor_collision row."""
    x = 0
    for ch in line:
        x ^= ord(ch)
    return "%02X" % x


def drive_rows(*rows):
    return "\n".join("%g %g" % r for r in rows)


def base_drive(kmh=KMH):
    return drive_rows((0, 0), (2, 0), (12, kmh))


def scenario(name, events, drive=None, duration=300, config=None, plant="pto_coupled = 1\n"):
    cfg = dict({"rate_l_ha": RATE, "nozzles": NOZZLES, "spacing_cm": int(SPACING_M * 100)}, **(config or {}))
    return ("# %s: made by tools/faults.py (make faults)\n[run]\nduration_s = %g\nseed = 5\n[config]\n%s"
            "[plant]\n%s[drive]\n%s\n[events]\n%s\n"
            % (name, duration, "".join("%s = %g\n" % kv for kv in cfg.items()), plant, drive or base_drive(),
               "\n".join(events)))


# ---- the faults: each a function of its size giving the scenario, the fault's start, the
# operator's rate over time [(t, L/ha)] and the clogged nozzles over time [(t, n)] ----------------
def leak_growing(size):
    ev = ["%g leak_lpm %d" % (T0 + 20 * k, k + 1) for k in range(size)]
    return dict(text=scenario("leak growing", ev), start=T0)


def clog_growing(size):
    ev = ["%g clog_nozzles %d" % (T0 + 20 * k, k + 1) for k in range(size)]
    return dict(text=scenario("clogging", ev), start=T0, clogs=[(T0 + 20 * k, k + 1) for k in range(size)])


def meter_k(k, tank_l=TANK_L):
    """The meter's true K off the calibration; the tank (full at the start) and the firmware's
    Tank size both tank_l."""
    plant = "pto_coupled = 1\ntank_l = %d\ntank_start_l = %d\n" % (tank_l, tank_l)
    return dict(text=scenario("meter K %g" % k, ["0 meter_k_ppl %g" % k], plant=plant,
                              config={"tank_size_l": tank_l}), start=0.0, tank_l=tank_l)


def creep(kmh):
    d = drive_rows((0, 0), (2, 0), (12, KMH), (T0, KMH), (T0 + 5, kmh), (T0 + 65, kmh), (T0 + 70, KMH))
    return dict(text=scenario("creep at %g km/h" % kmh, [], drive=d, duration=T0 + 120), start=T0)


def wheel_dies(kmh):
    d = drive_rows((0, 0), (2, 0), (12, KMH), (T0, KMH), (T0 + 6, kmh), (T0 + 12, kmh), (T0 + 17, KMH))
    return dict(text=scenario("wheel sensor dies at %g km/h" % kmh, ["%g speed_sensor_fail" % (T0 + 10)],
                              drive=d, duration=T0 + 120), start=T0 + 10)


def wheel_mult(m):
    return dict(text=scenario("wheel pulses x%g" % m, ["%g wheel_pulse_mult %g" % (T0, m)]), start=T0)


def level_high(litres):
    return dict(text=scenario("level %g L high" % litres, ["0 level_offset_l %g" % litres], duration=360,
                              plant="pto_coupled = 1\ntank_start_l = 150\n"), start=0.0)


def pressure_high(bar):
    ev = ["%g pressure_offset_bar %g" % (T0, bar), "%g meter_fail" % (T0 + 60)]
    return dict(text=scenario("pressure %g bar high" % bar, ev, drive=base_drive(11.0), duration=T0 + 150),
                start=T0)


def large_boom(kmh):
    cfg = {"nozzles": 72, "rate_l_ha": 250, "nozzle_lpm_at_3bar": 5.2}
    plant = ("pto_coupled = 1\nnozzle_lpm_at_3bar = 5.2\npump_lpm_at_540 = 700\nvalve_cv_open = 1400\nv_rated_kmh = 28\n"
             "tank_l = 6000\ntank_start_l = 6000\n")
    return dict(text=scenario("large boom at %g km/h" % kmh, [], drive=base_drive(kmh), config=cfg, plant=plant),
                start=0.0, rate=[(0, 250)])


def manual_hash(dv):
    d = drive_rows((0, 0), (2, 0), (12, KMH), (T0 + 30, KMH), (T0 + 35, KMH + dv), (T0 + 90, KMH + dv),
                   (T0 + 100, 0))
    ev = ["%g key #" % T0, "%g power_cut 2" % (T0 + 110)]
    return dict(text=scenario("manual, speed +%g km/h, PTO fixed" % dv, ev, drive=d, duration=T0 + 150,
                              plant="pto_coupled = 0\n"), start=T0)


def set_then_cut(rate):
    # Rate 1 over the link in 0.1 L/ha
    ev = ["%g serial %s" % (T0, csum("SET 0 %d" % (rate * 10))), "%g power_cut 2" % (T0 + 20)]
    return dict(text=scenario("SET 0 %d, power cut" % (rate * 10), ev), start=T0 + 20, rate=[(0, RATE), (T0, rate)])


def xor_collision(line):
    # the checksum of the line the operator sent, on a line two bytes away from it
    sent, got = line
    return dict(text=scenario("%s for %s" % (got, sent), ["%g serial %s*%s" % (T0, got, xor_check(sent))]),
                start=T0)


def set_flood(n):
    ev = ["%.3f serial %s" % (T0 + 0.004 * k, csum("SET 0 %d" % (RATE * 10))) for k in range(n)]
    return dict(text=scenario("%d SETs" % n, ev), start=T0,
                note="the host build's pass takes no time: the control period under the flood is PIL's "
                     "(make pil)")


def bypass_stop(rpm):
    return dict(text=scenario("pump at %g rpm" % rpm, ["%g pto_rpm %g" % (T0, rpm)]), start=T0)


def sav_loop(period):
    ev = ["%.1f serial %s" % (T0 + period * k, csum("SAV")) for k in range(int(120 / period))]
    return dict(text=scenario("SAV every %g s" % period, ev), start=T0, count="SAV")


def raven_cr(cal):
    p = param_id("P_REMOTE")
    # the wheel cal over our own protocol first: with Remote on the link is a Raven console's
    ev = ["%g serial %s" % (T0 - 1, csum("SET %d %d" % (param_id("P_WHEEL"), cal))),
          "%g serial %s" % (T0, csum("SET %d 1" % p)),
          "%g serial $R,CR" % (T0 + 1)]
    return dict(text=scenario("wheel cal %d, $R,CR" % cal, ev), start=T0, c1=True)


# (name, what the issue saw, builder, [(size label, argument) x 2]: the issue's, about half)
FAULTS = [
    ("leak_growing", "a leak after the meter growing 1 L/min every 20 s", leak_growing,
     [("to 10 L/min", 10), ("to 5 L/min", 5)]),
    ("clog_growing", "one more nozzle clogged every 20 s", clog_growing,
     [("10 of 36", 10), ("5 of 36", 5)]),
    ("meter_high", "the meter reading high from the start (true K over the calibration 380)", meter_k,
     [("+20 % (K 456)", 456), ("+10 % (K 418)", 418)]),
    ("meter_low", "the meter reading low from the start", meter_k,
     [("-20 % (K 304)", 304), ("-10 % (K 342)", 342)]),
    ("creep", "creeping under the minimum-flow speed (4 km/h) for 60 s", creep,
     [("1 km/h", 1.0), ("2 km/h", 2.0)]),
    ("wheel_dies", "the wheel sensor dies on a headland, back to 8 km/h", wheel_dies,
     [("at 2 km/h", 2.0), ("at 1 km/h", 1.0)]),
    ("wheel_double", "the wheel's pulses multiplied mid-run", wheel_mult,
     [("x2", 2.0), ("x1.5", 1.5)]),
    ("level_high", "the level sensor reading high, the tank running empty", level_high,
     [("+100 L", 100), ("+50 L", 50)]),
    ("pressure_high", "the pressure sensor reading high at 11 km/h, the meter lost 60 s later", pressure_high,
     [("+1 bar", 1.0), ("+0.5 bar", 0.5)]),
    ("large_boom", "72 nozzles of 5.2 L/min at 250 L/ha", large_boom,
     [("25 km/h", 25.0), ("12.5 km/h", 12.5)]),
    ("manual_hash", "one '#' on the run screen, the speed changes (PTO fixed), a power-up at standstill", manual_hash,
     [("8 -> 11 km/h", 3.0), ("8 -> 9.5 km/h", 1.5)]),
    ("set_then_cut", "a rate SET over the link, a power cut 20 s later", set_then_cut,
     [("SET 0 1000", 100), ("SET 0 1250", 125)]),
    ("xor_collision", "a line two bytes away from the one sent, the same XOR checksum", xor_collision,
     [("SET 4 110 for SET 0 150", ("SET 0 150", "SET 4 110")),
      ("SET 4 3297 for SET 4 3927", ("SET 4 3927", "SET 4 3297"))]),
    ("set_flood", "valid SETs back to back at 38400 baud", set_flood,
     [("1000", 1000), ("500", 500)]),
    ("bypass_stop", "the pump too weak: the bypass at its closed stop", bypass_stop,
     [("pump 30 % (162 rpm)", 162), ("pump 36 % (192 rpm)", 192)]),
    ("sav_loop", "SAV sent in a loop for 120 s", sav_loop,
     [("every 0.5 s", 0.5), ("every 1 s", 1.0)]),
    ("raven_cr", "$R,CR with a long wheel calibration", raven_cr,
     [("30000 (3 m)", 30000), ("15000 (1.5 m)", 15000)]),
]


def step_value(timeline, t, default):
    v = default
    for t0, x in timeline:
        if t >= t0:
            v = x
    return v


def silent_dose(csv_path, spec):
    """The dose error while the operator was not told (module doc), % (None: nothing expected),
    and the litres sprayed meanwhile at a standstill."""
    applied = expected = still = 0.0
    start = spec["start"]
    with open(csv_path) as f:
        for r in csv.DictReader(f):
            t = float(r["t_s"])
            if t < start or int(r["alarms"], 16) != 0 or int(r["open_nozzles"]) == 0:
                continue
            v = float(r["v_true_kmh"])
            rate = step_value(spec.get("rate", []), t, RATE)
            width = (int(r["open_nozzles"]) - step_value(spec.get("clogs", []), t, 0)) * SPACING_M
            spray = int(r["spray_on"])
            if spray and v < 0.5:
                still += float(r["boom_lpm"]) * 0.1 / 60.0
            elif spray or v >= 2.0:
                applied += float(r["boom_lpm"]) if spray else 0.0
                expected += rate * v * max(width, 0.0) / 600.0
    return (None if expected <= 0 else (applied / expected - 1.0) * 100.0), still


def tank_share(csv_path, start, t_alarm, tank_l):
    """The share of the tank sprayed from `start` to `t_alarm`, %: the true volume at the first
    0.1 s trace row at or after each instant, their difference over the tank's size."""
    v0 = v1 = None
    with open(csv_path) as f:
        for r in csv.DictReader(f):
            t = float(r["t_s"])
            if v0 is None and t >= start - 1e-9:
                v0 = float(r["tank_l"])
            if t >= t_alarm - 1e-9:
                v1 = float(r["tank_l"])
                break
    return None if v0 is None or v1 is None else (v0 - v1) / tank_l * 100.0


def balance_note(share):
    if share is None:
        return "no %s in the run: the %g %% bound is not met" % (BALANCE_CODE, BALANCE_MAX_PCT)
    return "%s after %.1f %% of the tank sprayed: %s the %g %% bound" % (
        BALANCE_CODE, share, "within" if share < BALANCE_MAX_PCT else "over", BALANCE_MAX_PCT)


def note_of(spec, serial_path, still_l, share=None):
    if spec.get("tank_l"):
        return balance_note(share)
    if still_l >= 0.1:
        return "%.1f L sprayed at a standstill, untold" % still_l
    if spec.get("note"):
        return spec["note"]
    lines = open(serial_path, errors="replace").read().splitlines() if os.path.exists(serial_path) else []
    if spec.get("count"):
        ok = sum(1 for x in lines if x.startswith("OK") and spec["count"] in x)
        return "%s answered OK %d times" % (spec["count"], ok) if ok else "%s: no OK answer" % spec["count"]
    if spec.get("c1"):
        c1 = [x for x in lines if ",C1," in x]
        return "C1 line: `%s`" % c1[0] if c1 else "no C1 line"
    return ""


def run_one(job):
    sim, ctl, out, name, label, spec = job
    base = os.path.join(out, "%s_%s" % (name, "".join(c if c.isalnum() else "_" for c in label)))
    with open(base + ".scn", "w") as f:
        f.write(spec["text"])
    cmd = [sim, "--scenario", base + ".scn", "--controller", ctl, "--csv", base + ".csv",
           "--serial", base + ".serial"]
    p = subprocess.run(cmd, capture_output=True, text=True)
    refused = re.search(r"the firmware refuses this set of values: (.*)", p.stderr or "")
    if p.returncode != 0 and refused:
        # the settings' cross-checks refuse the machine, naming why: nothing is sprayed wrong
        return {"fault": name, "size": label, "start_s": spec["start"], "alarm": "REFUSED",
                "alarm_text": refused.group(1).strip(), "delay_s": 0.0, "later": [],
                "silent_dose_pct": None, "standstill_untold_l": 0.0, "silent_wrong_s": 0.0,
                "silent_wrong_total_s": 0.0, "dose_error_all_pct": None,
                "note": "the settings refuse this machine", "scenario": base + ".scn"}
    if p.returncode != 0:
        return {"fault": name, "size": label, "error": (p.stderr or p.stdout).strip()[-300:]}
    m = json.loads(p.stdout.strip().splitlines()[-1])
    told = [a for a in m["alarms"] if a["t_s"] >= spec["start"] - 1e-9]
    first = told[0] if told else None
    dose, still = silent_dose(base + ".csv", spec)
    share = t_cal = None
    if spec.get("tank_l"):
        cal = [a["t_s"] for a in told if a["code"] == BALANCE_CODE]
        t_cal = cal[0] if cal else None
        share = None if t_cal is None else tank_share(base + ".csv", spec["start"], t_cal, spec["tank_l"])
    return {"fault": name, "size": label, "start_s": spec["start"],
            "alarm": None if first is None else first["code"],
            "alarm_text": None if first is None else first.get("text", ""),
            "delay_s": None if first is None else round(first["t_s"] - spec["start"], 1),
            "later": [a["code"] for a in told[1:]],
            "silent_dose_pct": dose, "standstill_untold_l": still,
            "silent_wrong_s": m["silent_wrong_s"], "silent_wrong_total_s": m["silent_wrong_total_s"],
            "dose_error_all_pct": m["dose_error_all_pct"], "balance_t_s": t_cal, "tank_share_pct": share,
            "note": note_of(spec, base + ".serial", still, share),
            "scenario": base + ".scn"}


def fmt(x, f="%.1f"):
    return "-" if x is None else f % x


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("sim")
    ap.add_argument("--out", default="build/faults")
    ap.add_argument("--controller", default="ffmap")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 2)
    ap.add_argument("--only", default="", help="these faults only (names, comma-separated)")
    ap.add_argument("--tank-l", type=int, default=TANK_L, help="the meter rows' tank and Tank size, L")
    a = ap.parse_args()
    if not os.access(a.sim, os.X_OK):
        sys.exit("faults: %s: not an executable simulator (make sim-progs)" % a.sim)
    only = [x for x in a.only.split(",") if x]
    unknown = [x for x in only if x not in [f[0] for f in FAULTS]]
    if unknown:
        sys.exit("faults: unknown fault %s (one of: %s)" % (", ".join(unknown), ", ".join(f[0] for f in FAULTS)))
    os.makedirs(a.out, exist_ok=True)
    jobs = [(a.sim, a.controller, a.out, name, label, build(arg, a.tank_l) if build is meter_k else build(arg))
            for name, _, build, sizes in FAULTS if not only or name in only for label, arg in sizes]
    with Pool(max(1, a.jobs)) as pool:
        rows = progress.pool_map(pool, run_one, jobs, "faults")
    bad = [r for r in rows if "error" in r]
    if bad:
        sys.exit("faults: %s %s: %s" % (bad[0]["fault"], bad[0]["size"], bad[0]["error"]))
    what = {f[0]: f[1] for f in FAULTS}
    head = ["fault", "size", "alarm or warning (code: text)", "delay s", "dose while silent %",
            "silent_wrong_s", "note"]
    md = ["| " + " | ".join(head) + " |", "|---" * len(head) + "|"]
    print("faults: %s, %d runs; the first alarm at or after the fault's start" % (a.controller, len(rows)))
    print("%-14s %-26s %-34s %8s %10s %9s" % ("fault", "size", "alarm (code: text)", "delay s", "silent %",
                                              "silent s"))
    for r in rows:
        alarm = "none" if r["alarm"] is None else "%s: %s" % (r["alarm"], r["alarm_text"])
        print("%-14s %-26s %-34s %8s %10s %9s%s" % (r["fault"], r["size"], alarm, fmt(r["delay_s"]),
                                                     fmt(r["silent_dose_pct"]), fmt(r["silent_wrong_s"]),
                                                     "  " + r["note"] if r["note"] else ""))
        later = sorted(set(r["later"]) - {r["alarm"]})
        md.append("| %s | %s | %s | %s | %s | %s | %s |" % (
            what[r["fault"]], r["size"], "none" if r["alarm"] is None else "`%s`: %s%s" % (
                r["alarm"], r["alarm_text"], "; later %s" % ", ".join("`%s`" % c for c in later) if later else ""),
            fmt(r["delay_s"]), fmt(r["silent_dose_pct"]), fmt(r["silent_wrong_s"]), r["note"].replace("|", "/")))
    with open(os.path.join(a.out, "table.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    with open(os.path.join(a.out, "summary.json"), "w") as f:
        json.dump({"controller": a.controller, "t0_s": T0, "rows": rows}, f, indent=1)
    print("wrote %s and %s" % (os.path.join(a.out, "table.md"), os.path.join(a.out, "summary.json")))


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""gen_scenarios.py: write the project's scenarios/*.scn (speed profiles drawn from a fixed seed, so the files are reproducible).

Usage: tools/gen_scenarios.py [outdir]   (default: scenarios)
The files are committed; rerun only to change them on purpose.
"""
import math
import os
import random
import sys

OUT = sys.argv[1] if len(sys.argv) > 1 else "scenarios"
RATES = (100, 125, 150)


def write(name, text):
    path = os.path.join(OUT, name)
    with open(path, "w") as f:
        f.write(text)
    print("wrote", path)


def dynamic_profile(seed=2020, duration=300.0):
    """Speed varied at random between 4 and 11 km/h with the throttle, as in the paper's 5.1:
    start from rest, then a new speed every 12-25 s reached by moving the throttle over 1-3 s."""
    rnd = random.Random(seed)
    rows = [(0.0, 0.0), (3.0, 0.0)]
    t, v = 8.0, 6.0
    rows.append((t, v))
    while True:
        hold = rnd.uniform(12.0, 25.0)
        t += hold
        if t > duration - 5:
            break
        rows.append((round(t, 1), v))
        nv = v
        while abs(nv - v) < 1.5:            # a change the operator means (>= 1.5 km/h)
            nv = round(rnd.uniform(4.0, 11.0), 1)
        t += rnd.uniform(1.0, 3.0)
        v = nv
        rows.append((round(t, 1), v))
    rows.append((duration, v))
    return rows


def drive_table(rows):
    return "".join("%-7g %g\n" % (t, v) for t, v in rows)


def dynamic(rate, coupled):
    rows = dynamic_profile()
    pto = ("pto_coupled = 1                  # the throttle sets speed and PTO together (paper 5.1)\n"
           if coupled else
           "pto_coupled = 0                  # PTO held at 540 rpm: the bypass valve does all the work\n"
           "pto_rpm = 540\n")
    return ("# Paper 5.1 dynamic flow following: %d L/ha, speed changed at random between 4 and 11 km/h\n"
            "# with the engine throttle, 36 AIXR11003 nozzles at 50 cm (18 m boom). Made by\n"
            "# tools/gen_scenarios.py (seeded).\n"
            "[run]\nduration_s = 300\nseed = 7\n"
            "[config]\nrate_l_ha = %d\nnozzles = 36\nspacing_cm = 50\nmeter_cal_ppl = 380\n"
            "wheel_m_per_pulse = 0.3927\nmin_flow_speed_kmh = 4\n"
            "[plant]\n%s"
            "[drive]                          # time_s  commanded speed km/h\n%s"
            "[events]\n") % (rate, rate, pto, drive_table(rows))


def target_step(rate):
    """Given-speed bench test (paper Table 3): the speed sensor masked, the tractor stands, the
    PTO at 540 rpm; the given speed steps 6 -> 8 -> 7 -> 6 -> 8 km/h: true steps of the target."""
    ev = "".join("%-5d given_speed_kmh %g\n" % (t, v) for t, v in ((40, 8), (80, 7), (120, 6), (160, 8)))
    return ("# Target steps, given-speed bench test at %d L/ha (paper Table 3 speeds 6/7/8 km/h): the\n"
            "# firmware takes the given speed, the tractor stands with the PTO at 540 rpm.\n"
            "# Made by tools/gen_scenarios.py.\n"
            "[run]\nduration_s = 200\nseed = 11\n"
            "[config]\nrate_l_ha = %d\nnozzles = 36\nspacing_cm = 50\ngiven_speed_kmh = 6\n"
            "[plant]\npto_coupled = 0\npto_rpm = 540\n"
            "[drive]\n0 0\n"
            "[events]\n%s") % (rate, rate, ev)


def tractor_distance(rows, end, dt=0.001, lag=1.0, amax=0.5):
    """Distance the plant's tractor (1st-order lag, acceleration limit) covers on a drive table."""
    def cmd(t):
        if t < rows[0][0]:
            return rows[0][1]
        for i in range(len(rows) - 1):
            (t0, v0), (t1, v1) = rows[i], rows[i + 1]
            if t0 <= t < t1:
                return v0 + (v1 - v0) * (t - t0) / (t1 - t0)
        return rows[-1][1]
    v = x = 0.0
    n = int(end / dt)
    for k in range(n):
        a = (cmd((k + 1) * dt) / 3.6 - v) / lag
        a = max(-amax, min(amax, a))
        v = max(0.0, v + a * dt)
        x += v * dt
    return x


def field_rows(pass_s):
    """8 passes of the field at 7-9 km/h, headland slow-downs to 3 km/h between them, then stop."""
    rnd = random.Random(3220)
    speeds = [round(rnd.uniform(7.0, 9.0), 1) for _ in range(8)]
    rows = [(0.0, 0.0), (2.0, 0.0), (14.0, speeds[0])]
    t = 14.0
    for i, v in enumerate(speeds):
        t += pass_s
        rows.append((round(t, 2), v))
        if i < len(speeds) - 1:
            rows += [(round(t + 6, 2), 3.0), (round(t + 16, 2), 3.0), (round(t + 22, 2), speeds[i + 1])]
            t += 22
    rows += [(round(t + 10, 2), 0.0)]
    return rows


def field(rate):
    # find the pass time that makes the run 3220 m (bisection on the tractor model)
    lo, hi = 60.0, 300.0
    for _ in range(30):
        mid = 0.5 * (lo + hi)
        rows = field_rows(mid)
        if tractor_distance(rows, rows[-1][0] + 20, dt=0.01) < 3220.0:
            lo = mid
        else:
            hi = mid
    rows = field_rows(round(hi, 2))
    end = math.ceil(rows[-1][0] + 15)
    dist = tractor_distance(rows, end, dt=0.001)
    return ("# A 3220 m field run at %d L/ha (paper Table 4): start from rest, 8 passes at 7-9 km/h,\n"
            "# headland slow-downs to 3 km/h between them, stop at the end (%.0f m by the tractor\n"
            "# model). PTO coupled to the throttle. Made by tools/gen_scenarios.py.\n"
            "[run]\nduration_s = %d\nseed = 5\n"
            "[config]\nrate_l_ha = %d\nnozzles = 36\nspacing_cm = 50\n"
            "[plant]\npto_coupled = 1\n"
            "[drive]\n%s"
            "[events]\n") % (rate, dist, end, rate, drive_table(rows))


def faults(rate):
    """Every fault of docs/SCENARIOS.md once, at a steady 8 km/h: what the alarms must catch."""
    ev = [(60, "leak_lpm 12"), (90, "leak_lpm 0"), (120, "clog_nozzles 6"), (150, "clog_nozzles 0"),
          (180, "pressure_sensor_open"), (200, "pressure_sensor_restore"), (220, "valve_stuck"),
          (230, "rate_l_ha %d" % (rate - 25)), (250, "valve_free"), (260, "speed_sensor_fail"),
          (280, "speed_sensor_restore"), (300, "speed_bounce_pct 30"), (320, "speed_bounce_pct 0"),
          (340, "meter_fail"), (360, "meter_restore"), (380, "tank_l 20")]
    return ("# Faults at %d L/ha, 8 km/h, PTO coupled: a leak after the meter, clogged nozzles, the\n"
            "# pressure sensor open, the valve stuck (with a rate change), the wheel sensor lost and\n"
            "# bouncing, the meter lost, the tank nearly empty. Made by tools/gen_scenarios.py.\n"
            "[run]\nduration_s = 420\nseed = 3\n"
            "[config]\nrate_l_ha = %d\nnozzles = 36\nspacing_cm = 50\n"
            "[plant]\npto_coupled = 1\n"
            "[drive]\n0 0\n2 0\n12 8\n"
            "[events]\n%s") % (rate, rate, "".join("%-5d %s\n" % e for e in ev))


def main():
    os.makedirs(OUT, exist_ok=True)
    for r in RATES:
        write("paper_dynamic_%d.scn" % r, dynamic(r, True))
        write("paper_dynamic_%d_fixed_pto.scn" % r, dynamic(r, False))
        write("target_step_%d.scn" % r, target_step(r))
        write("field_3220m_%d.scn" % r, field(r))
    write("faults_150.scn", faults(150))


if __name__ == "__main__":
    main()

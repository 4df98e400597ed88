#!/usr/bin/env python3
"""demo_report.py: the simulator's summary (what `sim` prints before its JSON line) with the paper's figures
(PAPER.md 5.1, Table 4) beside its table.

  demo_report.py SIM_OUTPUT     SIM_OUTPUT: the whole standard output of one `sim` run
"""
import json
import sys

# the paper's figures by the start of the summary's row label: (BP-PID, fuzzy PID)
PAPER = [
    ("mean overshoot, %", "2.1", "17.6"),
    ("mean settling time, s", "0.72", "2.54"),
    ("applied dose, L/ha", "151.9", "142.1"),
    ("dose error, % (v >= 4 km/h)", "1.3", "5.9"),
    ("dose error, % (whole run)", "-", "-"),
    ("CV of 5 m zones, % (v >= 4 km/h)", "4.2-5.9", "6.9-9.2"),
    ("CV of 5 m zones, % (whole run)", "5.1-7.4", "-"),
    ("zone error min, %", "-5", "-9.9"),
    ("zone error max, %", "+5", "+9.8"),
]
COLS = "%13s %12s"


def beside(lines):
    """The summary's lines, its table's rows with the paper's columns; exits naming a missing row."""
    out, found, rules = [], set(), 0
    for ln in lines:
        if ln.startswith("figure ") and ln.rstrip().endswith("this run"):
            ln = ln + COLS % ("paper BP-PID", "paper fuzzy")
        elif ln and set(ln) == {"-"} and rules < 2:
            rules += 1
            ln = ln + "-" * 26
        else:
            for label, bp, fz in PAPER:
                if ln.startswith(label) and label not in found:
                    found.add(label)
                    ln = ln + COLS % (bp, fz)
                    break
        out.append(ln)
    missing = [label for label, _, _ in PAPER if label not in found]
    if missing:
        sys.exit("demo_report.py: the simulator's summary has no row '%s'" % missing[0])
    return out


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: demo_report.py SIM_OUTPUT")
    try:
        with open(sys.argv[1]) as f:
            lines = f.read().rstrip("\n").splitlines()
        json.loads(lines[-1])
    except (OSError, ValueError, IndexError) as e:
        sys.exit("demo_report.py: %s: no metrics JSON line last (%s)" % (sys.argv[1], e))
    table = beside(lines[:-1])
    print()
    print("\n".join(table))
    print("paper: field test of section 5.1 (150 L/ha, 4-11 km/h, throttle) and Table 4 (3220 m run);")
    print("here the sprayer is the model of docs/SCENARIOS.md, so the figures compare control, not the field.")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Writes firmware/control/ffmap_gain_tab.c: the tables of ffmap's gain schedule.

How much boom flow one stroke of the bypass valve moves (the loop's gain) changes about
threefold over a sprayer's range: with an equal-percentage valve, dQ_boom/dtheta =
ln(R) * hm(Q_v, Q_b P / (P - Pc)), hm(a, b) = a b / (a + b), Q_v = Cv(theta) sqrt(P) the
bypass flow, Q_b the boom flow, Pc the nozzles' check valves. ffmap scales its feedback by
g = K_GS (1 / Q_v + (1 - Pc / P) / Q_b), a gain of 1 at 80 L/min a stroke, clamped to
[0.7, 1.6]; no divide in the step: the reciprocals come from these tables (linear between
nodes), for the valve of docs/SCENARIOS.md (Cv 120 L/min/sqrt(bar) open, rangeability 30) and check
valves at 0.3 bar.

  ffmap_inv_cv[17]   4096 / Cv(o), o = opening 0 .. 1 in 16 steps (capped at 32767)
  ffmap_inv_sqp[26]  4096 / sqrt(P), P = 0 .. 1600 kPa in 64 kPa steps (capped)
  ffmap_pc_p[26]     32767 * (1 - Pc / P), same P nodes (0 below Pc)
  ffmap_inv_q[33]    65536 / Q, Q = 0 .. 81.92 L/min in 2.56 L/min steps (capped)
"""
import math
import sys

CV_OPEN, R, PC_KPA = 120.0, 30.0, 30.0


def cv(o):
    return CV_OPEN * (R ** (o - 1.0) - 1.0 / R) / (1.0 - 1.0 / R) if o > 0 else 0.0


def cap(x):
    return int(min(32767, math.floor(x + 0.5)))


def main(path):
    inv_cv = [cap(4096.0 / cv(k / 16.0)) if cv(k / 16.0) > 0 else 32767 for k in range(17)]
    inv_sqp = [cap(4096.0 / math.sqrt(k * 0.64)) if k else 32767 for k in range(26)]
    pc_p = [cap(32767.0 * (1.0 - PC_KPA / (k * 64.0))) if k * 64.0 > PC_KPA else 0 for k in range(26)]
    inv_q = [cap(65536.0 / (k * 2.56)) if k else 32767 for k in range(33)]

    def table(name, vals):
        rows = ["    " + ", ".join("%d" % v for v in vals[i:i + 11]) + "," for i in range(0, len(vals), 11)]
        return "const FX_CODE int16_t %s[%d] = {\n%s\n};\n" % (name, len(vals), "\n".join(rows))

    with open(path, "w") as f:
        f.write("/* ffmap_gain_tab.c: reciprocal tables of ffmap's gain schedule; written by tools/gen_ffmap_gain.py, do not edit. */\n")
        f.write('#include "ctl_int.h"\n\n')
        f.write("/* 4096 / Cv(o), o = k / 16 (valve open 120 L/min/sqrt(bar), rangeability 30) */\n")
        f.write(table("ffmap_inv_cv", inv_cv))
        f.write("/* 4096 / sqrt(P), P = 64 k kPa */\n")
        f.write(table("ffmap_inv_sqp", inv_sqp))
        f.write("/* 32767 (1 - Pc / P), Pc = 30 kPa (the nozzles' check valves), P = 64 k kPa */\n")
        f.write(table("ffmap_pc_p", pc_p))
        f.write("/* 65536 / Q, Q = 2.56 k L/min */\n")
        f.write(table("ffmap_inv_q", inv_q))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "firmware/control/ffmap_gain_tab.c")

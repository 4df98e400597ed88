#!/usr/bin/env python3
"""plot.py: PNG plots of the simulator's output (matplotlib, Agg backend).

  plot.py flow  TRACE.csv OUT.png [--title T]   speed, target and actual flow over time (paper Fig. 9),
                                                with pressure and valve position below
  plot.py zones ZONES.csv OUT.png [--rate L_HA] [--title T]
                                                volume per 5 m zone against the set rate (paper Table 4)
TRACE.csv is `sim --csv`, ZONES.csv is `sim --zones`.
"""
import argparse
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_csv(path, need):
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        sys.exit("plot.py: cannot read %s: %s" % (path, e.strerror))
    if not rows:
        sys.exit("plot.py: %s has no rows" % path)
    missing = [k for k in need if k not in rows[0]]
    if missing:
        sys.exit("plot.py: %s lacks the column(s) %s" % (path, ", ".join(missing)))
    cols = {}
    for k in rows[0]:
        vals = []
        for i, r in enumerate(rows):
            v = r[k]
            try:
                vals.append(float(v) if v != "" else float("nan"))
            except ValueError:
                try:
                    vals.append(float(int(v, 16)))
                except ValueError:
                    if k in need:
                        sys.exit("plot.py: %s line %d: %s = '%s' is not a number" % (path, i + 2, k, v))
                    vals.append(float("nan"))
        cols[k] = vals
    return cols


def plot_flow(args):
    need = ["t_s", "v_true_kmh", "v_meas_kmh", "target_lpm", "flow_meas_lpm", "flow_true_lpm", "p_bar", "valve_pos"]
    c = read_csv(args.input, need)
    t = c["t_s"]
    fig, ax = plt.subplots(3, 1, figsize=(12, 9), sharex=True,
                           gridspec_kw={"height_ratios": [1, 2, 1]})
    ax[0].plot(t, c["v_true_kmh"], color="0.3", lw=1.2, label="true speed")
    ax[0].plot(t, c["v_meas_kmh"], color="tab:orange", lw=0.8, ls="--", label="measured speed")
    ax[0].set_ylabel("speed, km/h")
    ax[0].legend(loc="upper right", fontsize=8)
    ax[0].grid(alpha=0.3)
    ax[1].plot(t, c["target_lpm"], color="tab:blue", lw=1.4, label="target flow")
    ax[1].plot(t, c["flow_meas_lpm"], color="tab:red", lw=0.8, label="measured flow (firmware)")
    ax[1].plot(t, c["flow_true_lpm"], color="tab:green", lw=0.8, alpha=0.8, label="true flow (plant)")
    ax[1].set_ylabel("boom flow, L/min")
    ax[1].legend(loc="upper right", fontsize=8)
    ax[1].grid(alpha=0.3)
    ax[2].plot(t, c["p_bar"], color="tab:purple", lw=0.8, label="pressure, bar")
    ax[2].set_ylabel("pressure, bar")
    ax[2].grid(alpha=0.3)
    a2 = ax[2].twinx()
    a2.plot(t, c["valve_pos"], color="tab:brown", lw=0.8, label="bypass valve position")
    a2.set_ylabel("valve 0 shut .. 1 open")
    a2.set_ylim(-0.05, 1.05)
    ax[2].legend(loc="upper left", fontsize=8)
    a2.legend(loc="upper right", fontsize=8)
    ax[2].set_xlabel("time, s")
    fig.suptitle(args.title or "flow following")
    fig.tight_layout()
    fig.savefig(args.output, dpi=110)
    print("plot.py: wrote", args.output)


def plot_zones(args):
    need = ["zone", "start_m", "vol_l", "expect_l", "mean_kmh"]
    c = read_csv(args.input, need)
    x = c["start_m"]
    vol = c["vol_l"]
    slow = [v < 4.0 for v in c["mean_kmh"]]
    fig, ax = plt.subplots(2, 1, figsize=(12, 7), sharex=True, gridspec_kw={"height_ratios": [2, 1]})
    ax[0].bar([xi for xi, s in zip(x, slow) if not s], [v for v, s in zip(vol, slow) if not s], width=4.2,
              align="edge", color="tab:blue", label="zone volume, v >= 4 km/h")
    ax[0].bar([xi for xi, s in zip(x, slow) if s], [v for v, s in zip(vol, slow) if s], width=4.2,
              align="edge", color="tab:orange", label="zone volume, v < 4 km/h")
    ax[0].plot([xi + 2.5 for xi in x], c["expect_l"], color="k", lw=1, label="set rate x boom x 5 m")
    if args.rate:
        ax[0].set_title("expected %.3f L per 5 m zone at %g L/ha with an 18 m boom" % (args.rate * 18 * 5 / 1e4, args.rate),
                        fontsize=9)
    exp = sorted(e for e in c["expect_l"] if e == e and e > 0)
    if exp:                         # zoom on the spread: from half the expected volume up
        top = max([v for v in vol if v == v] + [exp[-1]])
        ax[0].set_ylim(0.5 * exp[len(exp) // 2], 1.05 * top)
    ax[0].set_ylabel("volume per 5 m, L")
    ax[0].legend(loc="lower right", fontsize=8)
    ax[0].grid(alpha=0.3)
    ax[1].plot(x, c["mean_kmh"], color="0.3", lw=1)
    ax[1].axhline(4.0, color="tab:orange", ls="--", lw=0.8)
    ax[1].set_ylabel("zone speed, km/h")
    ax[1].set_xlabel("distance travelled, m")
    ax[1].grid(alpha=0.3)
    fig.suptitle(args.title or "volume per 5 m zone")
    fig.tight_layout()
    fig.savefig(args.output, dpi=110)
    print("plot.py: wrote", args.output)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("kind", choices=["flow", "zones"])
    p.add_argument("input")
    p.add_argument("output")
    p.add_argument("--title")
    p.add_argument("--rate", type=float, help="set rate, L/ha (zones: for the title)")
    args = p.parse_args()
    if args.kind == "flow":
        plot_flow(args)
    else:
        plot_zones(args)


if __name__ == "__main__":
    main()

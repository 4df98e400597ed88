#!/usr/bin/env python3
"""plot.py: PNG plots of the simulator's output (matplotlib, Agg backend).

  plot.py flow  TRACE.csv OUT.png [--title T]   speed, target and actual flow over time (paper Fig. 9),
                                                with pressure and valve position below; the alarms
                                                raised and the section switches changed are marked
  plot.py zones ZONES.csv OUT.png [--rate L_HA] [--title T]
                                                volume per 5 m zone against the set rate (paper Table 4)
                                                and each zone's error
TRACE.csv is `sim --csv`, ZONES.csv is `sim --zones`. Legends sit above the plots, never on the data;
a volume's axis starts at zero. `flow` prints the marks it drew ("plot.py: marks: ...").
"""
import argparse
import csv
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

DIAG_H = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "firmware", "ops", "diag.h")


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


def alarm_names():
    """The alarm codes by bit, from the firmware's one table (DIAG_ALARMS in firmware/ops/diag.h,
    a row X(bit, code, text) an alarm, in bit order); [] when not found."""
    try:
        with open(DIAG_H) as f:
            m = re.search(r"#define DIAG_ALARMS\(X\)(.*?)\n\n", f.read(), re.S)
    except OSError:
        return []
    return re.findall(r'X\(\s*AL_\w+\s*,\s*"([^"]*)"', m.group(1)) if m else []


def section_list(bits):
    """Switch bits as a person reads them: '1-4, 6' (sections numbered from 1), 'none'."""
    on = [i + 1 for i in range(16) if bits >> i & 1]
    runs, k = [], 0
    while k < len(on):
        j = k
        while j + 1 < len(on) and on[j + 1] == on[j] + 1:
            j += 1
        runs.append(str(on[k]) if j == k else "%d-%d" % (on[k], on[j]))
        k = j + 1
    return ", ".join(runs) or "none"


def marks(c):
    """(t_s, kind, label) of every alarm raised (a bit of the alarms column rising) and every change
    of the section switches (the sections column), in time order."""
    names = alarm_names()
    out = []
    t = c["t_s"]
    al = [int(a) if a == a else 0 for a in c.get("alarms", [0] * len(t))]
    sec = c.get("sections")
    noz = c.get("open_nozzles")
    for i in range(1, len(t)):
        rise = al[i] & ~al[i - 1]
        for b in range(16):
            if rise >> b & 1:
                out.append((t[i], "alarm", names[b] if b < len(names) else "alarm bit %d" % b))
        if sec and sec[i] == sec[i] and sec[i - 1] == sec[i - 1] and sec[i] != sec[i - 1]:
            label = "sections %s" % section_list(int(sec[i]))
            if noz and noz[i] == noz[i]:
                label += " (%d nozzles)" % noz[i]
            out.append((t[i], "sections", label))
    return out


def legend_above(ax, ncol):
    ax.legend(loc="lower left", bbox_to_anchor=(0, 1.0), ncol=ncol, fontsize=8, frameon=False,
              borderaxespad=0.2)


def plot_flow(args):
    need = ["t_s", "v_true_kmh", "v_meas_kmh", "target_lpm", "flow_meas_lpm", "flow_true_lpm", "p_bar", "valve_pos"]
    c = read_csv(args.input, need)
    t = c["t_s"]
    fig, ax = plt.subplots(3, 1, figsize=(12, 9.5), sharex=True, gridspec_kw={"height_ratios": [1, 2, 1]})
    ax[0].plot(t, c["v_true_kmh"], color="0.3", lw=1.2, label="true speed")
    ax[0].plot(t, c["v_meas_kmh"], color="tab:orange", lw=0.9, ls="--", label="measured speed (firmware)")
    ax[0].set_ylabel("speed, km/h")
    ax[0].set_ylim(bottom=0)
    # the target as a wide pale band under the flows, so that a flow on it stays visible
    ax[1].plot(t, c["target_lpm"], color="tab:blue", lw=4.5, alpha=0.3, solid_capstyle="butt",
               label="target flow (firmware)", zorder=1)
    ax[1].plot(t, c["flow_true_lpm"], color="tab:green", lw=0.9, label="true flow (plant)", zorder=2)
    ax[1].plot(t, c["flow_meas_lpm"], color="tab:red", lw=0.8, ls=(0, (4, 2)), label="measured flow (firmware)",
               zorder=3)
    ax[1].set_ylabel("boom flow, L/min")
    ax[1].set_ylim(bottom=0)
    ax[2].plot(t, c["p_bar"], color="tab:purple", lw=0.8, label="pressure, bar (left)")
    ax[2].set_ylabel("pressure, bar")
    ax[2].set_ylim(bottom=0)
    a2 = ax[2].twinx()
    a2.plot(t, c["valve_pos"], color="tab:brown", lw=0.8, label="bypass valve position (right)")
    a2.set_ylabel("valve 0 shut .. 1 open")
    a2.set_ylim(-0.05, 1.05)
    h1, l1 = ax[2].get_legend_handles_labels()
    h2, l2 = a2.get_legend_handles_labels()
    ax[2].legend(h1 + h2, l1 + l2, loc="lower left", bbox_to_anchor=(0, 1.0), ncol=2, fontsize=8, frameon=False,
                 borderaxespad=0.2)
    ax[2].set_xlabel("time, s")
    ms = marks(c)
    colour = {"alarm": "tab:red", "sections": "0.35"}
    for kind, ls, text in (("alarm", ":", "alarm raised"), ("sections", "--", "section switches changed")):
        if any(k == kind for _, k, _ in ms):
            ax[1].plot([], [], color=colour[kind], lw=0.8, ls=ls, label=text)
    legend_above(ax[0], 2)
    legend_above(ax[1], 5)
    span = (t[-1] - t[0]) or 1.0
    last, shift = None, 0
    for tm, kind, label in ms:
        for a in ax:
            a.axvline(tm, color=colour[kind], lw=0.8, ls=":" if kind == "alarm" else "--", zorder=0)
        # labels of marks closer than about a label's width stand side by side
        shift = shift + 1 if last is not None and tm - last < 0.012 * span else 0
        last = tm
        ax[1].annotate(label, xy=(tm, 1.0), xycoords=("data", "axes fraction"), xytext=(2 + 9 * shift, -4),
                       textcoords="offset points", rotation=90, va="top", ha="left", fontsize=7,
                       color=colour[kind])
    for a in ax:
        a.grid(alpha=0.3)
    fig.suptitle(args.title or "flow following")
    fig.tight_layout()
    fig.savefig(args.output, dpi=110)
    plt.close(fig)
    print("plot.py: marks: %s" % ("; ".join("%s at %.1f s" % (lb, tm) for tm, _, lb in ms) or "none"))
    print("plot.py: wrote", args.output)


def plot_zones(args):
    need = ["zone", "start_m", "vol_l", "expect_l", "mean_kmh"]
    c = read_csv(args.input, need)
    x = c["start_m"]
    vol = c["vol_l"]
    exp = c["expect_l"]
    slow = [v < 4.0 for v in c["mean_kmh"]]
    err = c.get("error_pct") or [(v / e - 1) * 100 if e > 0 else float("nan") for v, e in zip(vol, exp)]
    fig, ax = plt.subplots(3, 1, figsize=(12, 9), sharex=True, gridspec_kw={"height_ratios": [2, 1.3, 1]})
    fast_x = [xi for xi, s in zip(x, slow) if not s]
    slow_x = [xi for xi, s in zip(x, slow) if s]
    ax[0].bar(fast_x, [v for v, s in zip(vol, slow) if not s], width=4.2, align="edge", color="tab:blue",
              label="zone volume, v >= 4 km/h")
    ax[0].bar(slow_x, [v for v, s in zip(vol, slow) if s], width=4.2, align="edge", color="tab:orange",
              label="zone volume, v < 4 km/h")
    ax[0].plot([xi + 2.5 for xi in x], exp, color="k", lw=1, label="set rate x boom x 5 m")
    known = sorted(e for e in exp if e == e and e > 0)
    if args.rate and known:         # the boom's width from what the zones expect at the set rate
        e = known[len(known) // 2]
        ax[0].set_title("expected %.3f L per 5 m zone at %g L/ha with a %.1f m boom"
                        % (e, args.rate, e * 1e4 / (args.rate * 5)), fontsize=9, pad=22)
    top = max([v for v in vol + exp if v == v] + [0.0])
    ax[0].set_ylim(0, 1.1 * top if top > 0 else 1)
    ax[0].set_ylabel("volume per 5 m, L")
    legend_above(ax[0], 3)
    # the spread the volume axis from zero cannot show: each zone's error against the set rate
    ax[1].bar(fast_x, [e for e, s in zip(err, slow) if not s], width=4.2, align="edge", color="tab:blue")
    ax[1].bar(slow_x, [e for e, s in zip(err, slow) if s], width=4.2, align="edge", color="tab:orange")
    ax[1].axhline(0, color="k", lw=0.8)
    fast_err = [abs(e) for e, s in zip(err, slow) if not s and e == e]
    if fast_err:                    # the v >= 4 km/h zones' spread; a slow zone's bar may leave the frame
        lim = max(2.0, 1.2 * max(fast_err))
        ax[1].set_ylim(-lim, lim)
    ax[1].set_ylabel("zone error, %")
    ax[2].plot(x, c["mean_kmh"], color="0.3", lw=1, label="zone speed")
    ax[2].axhline(4.0, color="tab:orange", ls="--", lw=0.8, label="4 km/h")
    ax[2].set_ylim(bottom=0)
    ax[2].set_ylabel("zone speed, km/h")
    ax[2].set_xlabel("distance travelled, m")
    legend_above(ax[2], 2)
    for a in ax:
        a.grid(alpha=0.3)
    fig.suptitle(args.title or "volume per 5 m zone")
    fig.tight_layout()
    fig.savefig(args.output, dpi=110)
    plt.close(fig)
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

#!/usr/bin/env python3
"""monitor.py: the live monitor of a sprayer controller (the paper's LabVIEW screen): values in the terminal,
a live plot, the run recorded to CSV.

    monitor.py --port /dev/ttyUSB0 [--baud 38400] [--csv run.csv] [--seconds N] [--send "ACK" ...] [--no-plot]
    monitor.py --replay captured.txt [--csv run.csv] [--no-plot]

Reads the controller's checked lines (firmware/link/serial.h): LOG once a second (speed, pressure,
target and measured flow, alarms), ALM / CLR / OK / ERR. A simulated board (`sim --pty`, the
simulator's pseudo-terminal) also sends SIM lines every 0.1 s with its truth beside the
firmware's view (true speed and flow, reference target, valve drive...); then the rows come from
them and the CSV carries both. tools/report.py scores the CSV with the simulator's metrics.
Every problem is one line on stderr and exit status 1 (2 for bad arguments), never a traceback.
"""
import argparse
import csv
import os
import sys
import time

import serial_log

# the recording's columns: the firmware's view (every board), then the simulator's truth (SIM lines)
BOARD_COLS = ["t_s", "speed_kmh", "pressure_kpa", "target_lpm", "flow_lpm", "alarms"]
SIM_COLS = ["t_s", "v_true_kmh", "speed_kmh", "target_lpm", "ref_lpm", "flow_lpm", "flow_true_lpm", "boom_lpm",
            "p_bar", "pressure_kpa", "valve_drive", "spray_on", "width_m", "rate_l_ha", "alarms"]


class MonitorError(Exception):
    """A problem the user can fix: printed as one line."""


def parse(line):
    """(kind, dict) of a checked line, or (None, reason)."""
    kind, fields = serial_log.parse_line(line)
    if kind == "LOG":
        t, speed, p_mpa, target, flow, alarms = fields
        return "LOG", {"t_s": t, "speed_kmh": speed, "pressure_kpa": round(p_mpa * 1000), "target_lpm": target,
                       "flow_lpm": flow, "alarms": alarms}
    if kind is None and fields == "unknown line SIM":
        body = line.strip("\r\n").rpartition("*")[0]
        w = body.split(" ")
        if len(w) != 16:
            return None, "SIM with %d fields" % (len(w) - 1)
        try:
            v = [float(x) for x in w[1:15]]
            alarms = "%04X" % int(w[15], 16)
        except ValueError:
            return None, "SIM with a bad number"
        d = dict(zip(["t_s", "v_true_kmh", "speed_kmh", "target_lpm", "ref_lpm", "flow_lpm", "flow_true_lpm",
                      "boom_lpm", "p_bar", "pressure_kpa", "valve_drive", "spray_on", "width_m", "rate_l_ha"], v))
        d["spray_on"] = int(d["spray_on"])
        d["alarms"] = alarms
        return "SIM", d
    return kind, fields


class LivePlot:
    """speed, target and actual flow, pressure and valve drive over the last minutes (matplotlib)."""

    def __init__(self, window_s):
        import matplotlib
        import matplotlib.pyplot as plt
        self.plt = plt
        self.window = window_s
        plt.ion()
        self.fig, self.ax = plt.subplots(3, 1, figsize=(10, 7), sharex=True)
        self.fig.canvas.manager.set_window_title("sprayer monitor")
        self.lines = {}
        spec = [(0, "speed_kmh", "speed km/h", "0.3"), (1, "target_lpm", "target L/min", "tab:blue"),
                (1, "flow_lpm", "flow L/min", "tab:red"), (2, "pressure_bar", "pressure bar", "tab:purple"),
                (2, "valve_drive", "valve drive (+ opens the bypass)", "tab:brown")]
        for ax_i, key, label, color in spec:
            (self.lines[key],) = self.ax[ax_i].plot([], [], color=color, lw=1, label=label)
        for a in self.ax:
            a.grid(alpha=0.3)
            a.legend(loc="upper left", fontsize=8)
        self.ax[2].set_xlabel("time, s")
        self.data = {k: [] for k in self.lines}
        self.t = []
        self.last_draw = 0.0
        self.matplotlib = matplotlib

    def add(self, row):
        self.t.append(row["t_s"])
        for k in self.data:
            if k == "pressure_bar":
                self.data[k].append(row["pressure_kpa"] / 100.0)
            else:
                self.data[k].append(row.get(k, float("nan")))

    def draw(self, force=False):
        now = time.time()
        if not self.t or (not force and now - self.last_draw < 0.5):
            return
        self.last_draw = now
        t0 = self.t[-1] - self.window
        i = next((k for k, t in enumerate(self.t) if t >= t0), 0)
        for k, ln in self.lines.items():
            ln.set_data(self.t[i:], self.data[k][i:])
        for a in self.ax:
            a.relim()
            a.autoscale_view()
        self.plt.pause(0.001)


class Monitor:
    def __init__(self, csv_path, plot, out=sys.stdout):
        self.out = out
        self.csv_path = csv_path
        self.f = None
        self.w = None
        self.cols = None
        self.rows = 0
        self.dropped = 0
        self.other = 0              # data lines of the kind the rows do not come from
        self.plot = plot
        self.last_status = 0.0
        self.last_row = None

    def _row(self, kind, d):
        if self.cols is None:
            self.cols = SIM_COLS if kind == "SIM" else BOARD_COLS
            self.kind = kind
            if self.csv_path:
                try:
                    self.f = open(self.csv_path, "w", newline="")
                except OSError as e:
                    raise MonitorError("cannot write %s: %s" % (self.csv_path, e.strerror))
                self.w = csv.writer(self.f)
                self.w.writerow(self.cols)
        if kind != self.kind:
            self.other += 1
            return
        self.rows += 1
        if self.w:
            self.w.writerow([d[c] for c in self.cols])
        if self.plot:
            self.plot.add(d)
        self.last_row = d
        self._status(d)

    def _status(self, d, force=False):
        now = time.time()
        if not force and now - self.last_status < 0.25:
            return
        self.last_status = now
        s = "t %7.1f s  speed %5.2f km/h  target %6.2f  flow %6.2f L/min  pressure %4.2f bar  alarms %s" % (
            d["t_s"], d["speed_kmh"], d["target_lpm"], d["flow_lpm"], d["pressure_kpa"] / 100.0, d["alarms"])
        if "valve_drive" in d:
            s += "  valve %+5.2f" % d["valve_drive"]
        if self.out.isatty():
            print("\r" + s, end="", file=self.out, flush=True)
        else:
            print(s, file=self.out)

    def feed(self, line):
        if not line.strip():
            return
        kind, d = parse(line)
        if kind is None:
            self.dropped += 1
            if self.dropped <= 10:
                print("\ndropped (%s): %r" % (d, line.strip()[:80]), file=self.out)
            elif self.dropped == 11:
                print("\n(more dropped lines are counted, not shown)", file=self.out)
        elif kind in ("LOG", "SIM"):
            self._row(kind, d)
        else:
            print("\n%s %s" % (kind, " ".join(d)), file=self.out)

    def close(self):
        if self.last_row:
            self._status(self.last_row, force=True)   # the last values, whatever the rate limit hid
        if self.f:
            self.f.close()
        if self.plot:
            self.plot.draw(force=True)
        print("\nmonitor: %d rows%s, %d lines dropped%s" % (
            self.rows, (" to " + self.csv_path) if self.csv_path and self.rows else "", self.dropped,
            (", %d LOG lines shown only (rows from the SIM lines)" % self.other) if self.other else ""),
            file=self.out)


def open_port(name, baud):
    try:
        import serial  # pyserial, from the .venv
    except ImportError:
        raise MonitorError("pyserial is missing: run `make deps` (or use .venv/bin/python)")
    if "://" not in name and not os.path.exists(name):
        raise MonitorError("no such port %s (is the adapter plugged in? ls /dev/ttyUSB* /dev/ttyACM*)" % name)
    try:
        if "://" in name:
            return serial.serial_for_url(name, baudrate=baud, timeout=0.2)
        return serial.Serial(name, baudrate=baud, timeout=0.2, exclusive=True)
    except serial.SerialException as e:
        msg = str(e)
        if "lock" in msg.lower() or "busy" in msg.lower() or getattr(e, "errno", None) == 16:
            raise MonitorError("%s is busy: another program has it open" % name)
        if getattr(e, "errno", None) == 13 or "ermission" in msg:
            raise MonitorError("no permission to open %s (add yourself to the dialout group)" % name)
        raise MonitorError("cannot open %s: %s" % (name, msg))
    except (OSError, ValueError) as e:
        raise MonitorError("cannot open %s: %s" % (name, e))


def make_plot(want, window):
    if not want:
        return None
    if not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")) and sys.platform.startswith("linux"):
        print("monitor: no display: live plot off (values here, CSV recorded)", file=sys.stderr)
        return None
    try:
        return LivePlot(window)
    except Exception as e:  # a GUI backend that cannot start is not a reason to lose the run
        print("monitor: live plot off: %s" % str(e).splitlines()[0], file=sys.stderr)
        return None


def run(a):
    # the source first: a missing port or file is reported before anything else happens
    if a.replay:
        try:
            src = open(a.replay, "rb")
        except OSError as e:
            raise MonitorError("cannot read %s: %s" % (a.replay, e.strerror))
    else:
        src = open_port(a.port, a.baud)
    mon = Monitor(a.csv, make_plot(not a.no_plot, a.window))
    try:
        if a.replay:
            with src:
                for raw in src:
                    mon.feed(raw.decode("ascii", "replace"))
                    if mon.plot:
                        mon.plot.draw()
            if mon.rows == 0:
                raise MonitorError("%s holds no controller log lines (%d lines dropped)" % (a.replay, mon.dropped))
            return 0
        try:
            for cmd in a.send:
                src.write((serial_log.with_checksum(cmd) + "\r\n").encode("ascii"))
            end = time.time() + a.seconds if a.seconds else None
            buf = b""
            while end is None or time.time() < end:
                try:
                    chunk = src.read(512)
                except Exception as e:  # the port went away (unplugged, the simulator ended)
                    print("\nmonitor: the port closed: %s" % str(e).splitlines()[0], file=sys.stderr)
                    break
                buf += chunk
                while b"\n" in buf:
                    raw, _, buf = buf.partition(b"\n")
                    mon.feed(raw.decode("ascii", "replace"))
                if mon.plot:
                    mon.plot.draw()
        finally:
            src.close()
        return 0
    except KeyboardInterrupt:
        return 0
    finally:
        mon.close()


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                 epilog="records to CSV (--csv); tools/report.py RUN.csv scores it")
    src = ap.add_mutually_exclusive_group(required=True)
    src.add_argument("--port", help="serial port (/dev/ttyUSB0), a pseudo-terminal from `sim --pty`, or a pyserial URL")
    src.add_argument("--replay", help="lines captured earlier (sim --serial, a terminal log)")
    ap.add_argument("--baud", type=int, default=38400)
    ap.add_argument("--csv", help="record the rows here")
    ap.add_argument("--seconds", type=float, default=0, help="stop after this long (0: until ^C or the port closes)")
    ap.add_argument("--send", action="append", default=[], help="a command to send first (checksum added)")
    ap.add_argument("--no-plot", action="store_true", help="no live plot window")
    ap.add_argument("--window", type=float, default=120, help="seconds shown in the live plot")
    a = ap.parse_args(argv)
    try:
        return run(a)
    except MonitorError as e:
        print("monitor: %s" % e, file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())

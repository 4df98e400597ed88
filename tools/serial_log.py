#!/usr/bin/env python3
"""serial_log.py: the PC side of the RS232 link: log the controller's run to CSV, send commands.

    serial_log.py --port /dev/ttyUSB0 [--baud 38400] [--csv run.csv] [--seconds N] [--send "GET 0" ...]
    serial_log.py --replay captured.txt [--csv run.csv]        (lines captured earlier, or from the simulator)

Every line the controller sends ends in "*HH", the CRC-8 of the bytes before '*' (polynomial 0x65,
initial 0, most significant bit first: firmware/link/serial.h, docs/PC.md); a line whose check is
wrong is counted and dropped, never logged. Commands go out with the same check. LOG lines (one a
second, like the paper's PC monitor) become CSV rows; BOOT (the reset cause) / EE (settings that are
not the newest saved) / ALM / CLR / OK / ERR lines are printed.
"""
import argparse
import csv
import sys
import time

CSV_HEADER = ["t_s", "speed_kmh", "pressure_mpa", "target_lpm", "flow_lpm", "alarms_hex"]


def checksum(body):
    """CRC-8 of a line's body: polynomial 0x65, initial 0, MSB first, bit by bit."""
    c = 0
    for ch in body.encode("ascii", "replace"):
        c ^= ch
        for _ in range(8):
            c = ((c << 1) ^ 0x65) & 0xFF if c & 0x80 else (c << 1) & 0xFF
    return c


def with_checksum(body):
    return "%s*%02X" % (body, checksum(body))


def parse_line(line):
    """(kind, fields) of a checked line, or (None, reason) when it must be dropped."""
    line = line.strip("\r\n")
    if "*" not in line:
        return None, "no checksum"
    body, _, cs = line.rpartition("*")
    try:
        if int(cs, 16) != checksum(body) or len(cs) != 2:
            return None, "bad checksum"
    except ValueError:
        return None, "bad checksum"
    words = body.split(" ")
    kind = words[0]
    if kind == "LOG":
        if len(words) != 7:
            return None, "LOG with %d fields" % (len(words) - 1)
        try:
            t_ms, speed, p_kpa, target, flow = (int(w) for w in words[1:6])
            alarms = int(words[6], 16)
        except ValueError:
            return None, "LOG with a bad number"
        return "LOG", [t_ms / 1000.0, speed / 100.0, p_kpa / 1000.0, target / 100.0, flow / 100.0,
                       "%04X" % alarms]
    if kind in ("ALM", "CLR", "OK", "ERR", "BOOT", "EE"):
        return kind, words[1:]
    return None, "unknown line " + kind


class Logger:
    def __init__(self, csv_path, out=sys.stdout):
        self.rows = 0
        self.dropped = 0
        self.out = out
        self.f = open(csv_path, "w", newline="") if csv_path else None
        self.w = csv.writer(self.f) if self.f else None
        if self.w:
            self.w.writerow(CSV_HEADER)

    def feed(self, line):
        if not line.strip():
            return
        kind, fields = parse_line(line)
        if kind is None:
            self.dropped += 1
            print("dropped (%s): %r" % (fields, line.strip()), file=self.out)
        elif kind == "LOG":
            self.rows += 1
            if self.w:
                self.w.writerow(fields)
        else:
            print(kind, " ".join(fields), file=self.out)

    def close(self):
        if self.f:
            self.f.close()
        print("serial_log: %d log rows, %d lines dropped" % (self.rows, self.dropped), file=self.out)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--port", help="serial port, or a pyserial URL such as loop://")
    ap.add_argument("--baud", type=int, default=38400)
    ap.add_argument("--replay", help="parse captured lines from this file instead of a port")
    ap.add_argument("--csv", help="write the LOG lines here")
    ap.add_argument("--seconds", type=float, default=0, help="stop after this long (0: until ^C)")
    ap.add_argument("--send", action="append", default=[], help="a command to send first (checksum added)")
    a = ap.parse_args(argv)
    if not a.port and not a.replay:
        ap.error("give --port or --replay")
    if a.replay:
        try:
            f = open(a.replay, errors="replace")
        except OSError as e:
            print("serial_log: cannot read %s: %s" % (a.replay, e.strerror), file=sys.stderr)
            return 1
    else:
        import monitor
        try:
            port = monitor.open_port(a.port, a.baud)
        except monitor.MonitorError as e:
            print("serial_log: %s" % e, file=sys.stderr)
            return 1
    try:
        log = Logger(a.csv)
    except OSError as e:
        print("serial_log: cannot write %s: %s" % (a.csv, e.strerror), file=sys.stderr)
        return 1
    try:
        if a.replay:
            with f:
                for line in f:
                    log.feed(line)
            return 0 if log.dropped == 0 else 2
        for cmd in a.send:
            port.write((with_checksum(cmd) + "\r\n").encode("ascii"))
        end = time.time() + a.seconds if a.seconds else None
        buf = b""
        while end is None or time.time() < end:
            buf += port.read(256)
            while b"\n" in buf:
                raw, _, buf = buf.partition(b"\n")
                log.feed(raw.decode("ascii", "replace"))
            if a.seconds == 0 and a.port.startswith("loop://") and not buf and port.in_waiting == 0:
                break
    except KeyboardInterrupt:
        pass
    finally:
        log.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())

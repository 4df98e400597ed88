#!/usr/bin/env python3
"""rc_bridge.py: the controller as one of RateControl's modules, over its serial link.

SK21's RateControl app talks UDP to its modules: a module listens on port 28888 and sends to the
app's port 29999. This bridge runs on the PC beside the app and stands for the module: every UDP
datagram that is a whole, checked RateControl frame the controller takes (PGN 32500 rate
settings, 32501 relays, 32502 valve settings) goes to the serial port as it is; every frame the
controller sends back (32400 rate info, 32401 module info) goes to the app as one datagram. The
controller's own text lines (LOG, ALM ..., docs/PC.md) are skipped (--lines prints them).

The frames (docs/PGN.md): the PGN as u16 little-endian first, the CRC last, the low byte of the
sum of every byte before it. The controller needs `Remote` = AgOpenGPS (SET 30 3) and its
`RC module` set to the app's module id.

    .venv/bin/python tools/rc_bridge.py --port /dev/ttyUSB0
    .venv/bin/python tools/rc_bridge.py --port /dev/pts/5 --listen 127.0.0.1:28888 --app 127.0.0.1:29999
"""
import argparse
import select
import socket
import sys
import time

import serial

TAKEN = {32500: 14, 32501: 11, 32502: 24}       # frames to the controller: PGN -> length
REPLIES = {32400: 15, 32401: 15}                # frames from it


def crc_ok(f):
    return len(f) >= 3 and (sum(f[:-1]) & 0xFF) == f[-1]


def pgn_of(f):
    return f[0] | f[1] << 8 if len(f) >= 2 else -1


class ReplyParser:
    """The controller's byte stream: 32400 / 32401 frames out of it, text lines aside."""

    def __init__(self):
        self.buf = bytearray()

    def feed(self, data):
        """The frames the bytes complete (checked), and the text lines."""
        self.buf += data
        frames, lines = [], []
        while self.buf:
            b = self.buf
            if b[0] in (0x90, 0x91):
                if len(b) < 2:
                    break
                n = REPLIES.get(pgn_of(b))
                if n:
                    if len(b) < n:
                        break
                    if crc_ok(b[:n]):
                        frames.append(bytes(b[:n]))
                        del b[:n]
                        continue
                del b[:1]               # not a whole frame: resync on the next byte
                continue
            if b[0] == 0x80:            # AgOpenGPS's 237 (the machine answer): 14 bytes, not the app's
                if len(b) < 14:
                    break
                del b[:14 if b[1] == 0x81 else 1]
                continue
            end = b.find(b"\n")
            start = next((i for i, c in enumerate(b) if c in (0x90, 0x91, 0x80)), len(b))
            if end < 0 or start < end:
                if start == len(b):
                    break
                lines.append(bytes(b[:start]))
                del b[:start]
                continue
            lines.append(bytes(b[:end + 1]))
            del b[:end + 1]
        return frames, lines


def hostport(s):
    h, _, p = s.rpartition(":")
    return (h or "0.0.0.0", int(p))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--port", required=True, help="the controller's serial port (or a sim --pty)")
    ap.add_argument("--baud", type=int, default=38400)
    ap.add_argument("--listen", default="0.0.0.0:28888", help="where the app's frames come (a module's port)")
    ap.add_argument("--app", default="127.0.0.1:29999", help="where the replies go (the app's port)")
    ap.add_argument("--seconds", type=float, default=0, help="stop after this long (0: never)")
    ap.add_argument("--lines", action="store_true", help="print the controller's text lines")
    a = ap.parse_args(argv)

    ser = serial.Serial(a.port, a.baud, timeout=0)
    udp = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    udp.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    udp.bind(hostport(a.listen))
    app = hostport(a.app)
    parser = ReplyParser()
    counts = {"to_board": 0, "refused": 0, "to_app": 0}
    t_end = time.monotonic() + a.seconds if a.seconds else None
    try:
        while t_end is None or time.monotonic() < t_end:
            r, _, _ = select.select([udp, ser.fileno()], [], [], 0.05)
            if udp in r:
                f, _ = udp.recvfrom(512)
                n = TAKEN.get(pgn_of(f))
                if n and len(f) >= n and crc_ok(f[:n]):
                    ser.write(f[:n])
                    counts["to_board"] += 1
                else:
                    counts["refused"] += 1
            if ser.fileno() in r:
                try:
                    data = ser.read(4096)
                except serial.SerialException:
                    print("rc_bridge: the serial port closed", file=sys.stderr)
                    break
                frames, lines = parser.feed(data)
                for f in frames:
                    udp.sendto(f, app)
                    counts["to_app"] += 1
                if a.lines:
                    for ln in lines:
                        sys.stdout.write(ln.decode("ascii", "replace"))
    except KeyboardInterrupt:
        pass
    print("rc_bridge: %(to_board)d frames to the controller, %(refused)d datagrams refused, "
          "%(to_app)d frames to the app" % counts, file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())

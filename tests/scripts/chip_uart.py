#!/usr/bin/env python3
"""chip_uart.py S51 IHX SEND_BAUD SEND_STOP EXPECT_BAUD EXPECT_STOP: bytes into the STC12C5A60S2
model's RXD (sim/ucsim/stc12_link.h's frames, no plant) framed at SEND_BAUD with SEND_STOP stop
bits, the frames its UART sends read at EXPECT_BAUD; prints one line: each reply decoded, its
bit time and data + stop bits, and "echo ok" when every reply is its byte plus one with the
expected bit time and framing. tests/chip/uart_echo.c is the image. Stdlib only."""
import os
import struct
import subprocess
import sys
import tempfile

SYSCLK = 11059200
SLOT = 11059                        # about a millisecond of clocks a slot


def decode(byte, fb, hb):
    """the frame's byte as a receiver with bit time hb samples it (None: framing error)"""
    v = 0
    for i in range(9):
        k = (2 * i + 3) * hb // (2 * fb)
        level = 0 if k == 0 else (byte >> (k - 1)) & 1 if k <= 8 else 1
        if i < 8:
            v |= level << i
        elif not level:
            return None
    return v


def main(argv):
    s51, ihx = argv[1], argv[2]
    send_baud, send_stop, exp_baud, exp_stop = int(argv[3]), int(argv[4]), int(argv[5]), int(argv[6])
    d = tempfile.mkdtemp(prefix="chipuart.")
    fin, fout = os.path.join(d, "in"), os.path.join(d, "out")
    os.mkfifo(fin)
    os.mkfifo(fout)
    env = dict(os.environ, STC12_LINK_IN=fin, STC12_LINK_OUT=fout)
    p = subprocess.Popen([s51, "-t", "STC12", "-X", "11.0592M", ihx], stdin=subprocess.PIPE,
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
    to_m = open(fin, "wb")
    from_m = open(fout, "rb")
    p.stdin.write(b"run\n")
    p.stdin.flush()
    to_m.write(b"C" + b"\xff" * 1024 + struct.pack("<HB", 0xFFFF, 0))
    sb = SYSCLK // send_baud
    msg = b"8N2 ok"
    start = 5 * SLOT                 # after the program has set the UART up
    events = [(start + i * (10 + send_stop) * sb, b) for i, b in enumerate(msg)]
    replies, end, t = [], events[-1][0] + 40 * sb, 0
    while t < end:
        t += SLOT
        ev = [(c, b) for c, b in events if t - SLOT <= c < t]
        frame = b"S" + struct.pack("<QH", t, len(ev))
        for c, b in ev:
            frame += struct.pack("<QBI", c, 3, b | sb << 8 | send_stop << 24)
        to_m.write(frame)
        to_m.flush()
        r = from_m.read(28)
        if len(r) != 28 or r[0:1] != b"R":
            print("chip_uart: the model did not answer")
            return 1
        for _ in range(r[27]):
            clock, byte, fb, bits = struct.unpack("<QBHB", from_m.read(12))
            replies.append((byte, fb, bits))
    to_m.write(b"Q")
    to_m.flush()
    from_m.read()
    p.wait()
    hb = SYSCLK // exp_baud
    got = [decode(b, fb, hb) for b, fb, _ in replies]
    framing = {(fb, bits) for _, fb, bits in replies}
    good = (got == [(b + 1) & 0xFF for b in msg] and framing == {(SYSCLK // exp_baud, 8 + exp_stop)})
    print("replies %s, bit time and data+stop bits %s: %s" %
          (" ".join("--" if g is None else "%02x" % g for g in got) or "none", sorted(framing),
           "echo ok" if good else "echo WRONG"))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

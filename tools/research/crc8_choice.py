#!/usr/bin/env python3
"""crc8_choice.py: why the serial link's check is the CRC-8 with polynomial 0x65 (docs/PC.md).

A command line is "<body>*HH\\r\\n", HH the CRC-8 of the body in hex (either case). A 2-bit error
is missed when two flips in the body cancel in the CRC (the syndromes of two bit positions are
equal), or one flip in the body is cancelled by one flip in a hex digit (the syndrome equals the
change of the digit's value: a flip that keeps a byte a hex digit changes its value by one of a
few amounts, 1-8 in a nibble and 3, 6, 7 among them). For each of the 128 CRC-8 polynomials this
prints how long a body may be with every 1- and 2-bit error caught, strongest first, and for the
chosen one the share of two-byte substitutions (any printable bytes at any two places of a
command) it misses: no 8-bit check catches them all (65,025 changes a pair of places, 256
check values).

    .venv/bin/python tools/research/crc8_choice.py [--top N]
"""
import argparse
import itertools

HEX = "0123456789ABCDEFabcdef"
CHOSEN = 0x65


def crc8(data, poly):
    c = 0
    for b in data:
        c ^= b
        for _ in range(8):
            c = ((c << 1) ^ poly) & 0xFF if c & 0x80 else (c << 1) & 0xFF
    return c


def hex_deltas():
    """The changes of a check nibble's value a single flipped bit can make, in either nibble."""
    d = set()
    for c in HEX:
        for b in range(8):
            c2 = chr(ord(c) ^ (1 << b))
            if c2 in HEX and int(c2, 16) != int(c, 16):
                v = int(c, 16) ^ int(c2, 16)
                d.update((v, v << 4))
    return d


def longest_body(poly, deltas, limit=64):
    """Bytes of body up to which every 1- and 2-bit error of body and check is caught."""
    seen = set(1 << j for j in range(8))      # a flip of the check's own bits (in binary)
    r, n = 1, 0
    for k in range(limit * 8):
        for _ in range(8 if k == 0 else 1):   # syndrome of a flip k bits from the body's end: x^(k+8) mod P
            r <<= 1
            if r & 0x100:
                r ^= 0x100 | poly
        if r == 0 or r in seen or r in deltas:
            break
        seen.add(r)
        n = k + 1
    return n // 8


def missed_substitutions(body, poly):
    """Of all changes of two bytes of body to other printable bytes, the share whose check is
    the same (the line would pass)."""
    data = body.encode()
    want = crc8(data, poly)
    missed = total = 0
    for i, j in itertools.combinations(range(len(data)), 2):
        for a in range(0x20, 0x7F):
            if a == data[i]:
                continue
            for b in range(0x20, 0x7F):
                if b == data[j]:
                    continue
                m = bytearray(data)
                m[i], m[j] = a, b
                total += 1
                missed += crc8(m, poly) == want
    return missed, total


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--top", type=int, default=8)
    args = ap.parse_args()
    deltas = hex_deltas()
    ranks = sorted(((longest_body(p, deltas), p) for p in range(1, 256, 2)), reverse=True)
    print("hex-digit flips change a check by: %s" % ", ".join("0x%02X" % d for d in sorted(deltas)))
    print("polynomial  every 1- and 2-bit error caught up to a body of")
    for n, p in ranks[:args.top]:
        print("  0x%02X      %2d bytes%s" % (p, n, "   <- chosen" if p == CHOSEN else ""))
    for name in (0x07, 0x1D, 0x2F, 0x31, 0x9B):
        print("  0x%02X      %2d bytes (a catalogued CRC-8)" % (name, longest_body(name, deltas)))
    missed, total = missed_substitutions("SET 4 110", CHOSEN)
    print("two bytes of 'SET 4 110' changed to any printable bytes: %d of %d pass the check (%.2f %%, 1/256 = 0.39 %%)"
          % (missed, total, 100.0 * missed / total))


if __name__ == "__main__":
    main()

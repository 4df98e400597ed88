#!/usr/bin/env python3
"""Writes firmware/math/fx_tanh_tab.c: tanh(x) in Q15 at x = i/64, i = 0..N-1, in two tables:
fx_tanh_tab (int16) for i = 0..J, fx_tanh_tail (one byte: 32767 - tanh) for i = J..N-1. From
i = N-1 on tanh is 32767 in Q15 (fx_tanh returns 32767 there without a table); from i = J on it
is within 255 of 32767. N and J must match fixed.h's FX_TANH_N and FX_TANH_J."""
import math, sys

FULL = 385  # 6 * 64 + 1: x in [0, 6]


def q15(i):
    return min(32767, int(math.floor(math.tanh(i / 64.0) * 32768 + 0.5)))


def main(path):
    vals = [q15(i) for i in range(FULL)]
    n = max(i for i in range(FULL) if vals[i] != 32767) + 2     # the first of the 32767s is the last point
    j = min(i for i in range(n) if 32767 - vals[i] < 256)
    head = vals[:j + 1]
    tail = [32767 - v for v in vals[j:n]]

    def rows(v, per):
        return "\n".join("    " + ", ".join("%d" % x for x in v[i:i + per]) + "," for i in range(0, len(v), per))
    with open(path, "w") as f:
        f.write("/* fx_tanh_tab.c: tanh(i/64) in Q15 for i = 0..%d; written by tools/gen_tanh.py, do not edit. */\n" % (n - 1))
        f.write('#include "fixed.h"\n\n')
        f.write("#if FX_TANH_N != %d || FX_TANH_J != %d\n#error FX_TANH_N and FX_TANH_J (fixed.h) do not match: run tools/gen_tanh.py\n#endif\n\n" % (n, j))
        f.write("/* i = 0..%d */\n" % j)
        f.write("const FX_CODE q15_t fx_tanh_tab[FX_TANH_J + 1] = {\n")
        f.write(rows(head, 12) + "\n};\n")
        f.write("/* 32767 - tanh, i = %d..%d */\n" % (j, n - 1))
        f.write("const FX_CODE uint8_t fx_tanh_tail[FX_TANH_N - FX_TANH_J] = {\n")
        f.write(rows(tail, 16) + "\n};\n")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "firmware/math/fx_tanh_tab.c")

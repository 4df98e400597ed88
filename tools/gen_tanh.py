#!/usr/bin/env python3
"""Writes firmware/math/fx_tanh_tab.c: tanh(x) in Q15 at x = i/64, i = 0..384 (x in [0, 6])."""
import math, sys

N = 385  # 6 * 64 + 1: the last interval ends at x = 6, where tanh is 32767 in Q15


def main(path):
    vals = [min(32767, int(math.floor(math.tanh(i / 64.0) * 32768 + 0.5))) for i in range(N)]
    rows = ["    " + ", ".join("%d" % v for v in vals[i:i + 12]) + "," for i in range(0, N, 12)]
    with open(path, "w") as f:
        f.write("/* fx_tanh_tab.c: tanh(i/64) in Q15 for i = 0..%d; written by tools/gen_tanh.py, do not edit. */\n" % (N - 1))
        f.write('#include "fixed.h"\n\n')
        f.write("const FX_CODE q15_t fx_tanh_tab[FX_TANH_N] = {\n")
        f.write("\n".join(rows) + "\n};\n")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "firmware/math/fx_tanh_tab.c")

#!/usr/bin/env python3
"""memuse.py BASE --code MAX --iram MAX --xram MAX [--code-free PCT] [--xram-free B] [--stack-margin B]

Prints the linked image's use of each memory region from SDCC's BASE.mem (and the static stack
depth, tools/stackdepth.py over BASE's folder) and fails (exit 1) when a region exceeds the chip
or leaves less than its headroom floor:
  code:   at least PCT % of the flash free;
  xdata:  at least B bytes of the XRAM free (on-chip XRAM holds __xdata and __pdata);
  stack:  the internal RAM left for the stack at least B bytes more than the static worst case
          (main's deepest call chain plus the deepest interrupt of each priority).
"""
import argparse
import os
import re
import subprocess
import sys


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("base")
    ap.add_argument("--code", type=int, required=True)
    ap.add_argument("--iram", type=int, required=True)
    ap.add_argument("--xram", type=int, required=True)
    ap.add_argument("--code-free", type=float, default=0.0)
    ap.add_argument("--xram-free", type=int, default=0)
    ap.add_argument("--stack-margin", type=int, default=0)
    a = ap.parse_args()
    t = open(a.base + ".mem").read()
    size = {}
    for line in t.splitlines():
        m = re.match(r"\s*(ROM/EPROM/FLASH|EXTERNAL RAM|PAGED EXT\. RAM)\s.*?(\d+)\s+(\d+)\s*$", line)
        if m:
            size[m.group(1)] = int(m.group(2))
    code = size.get("ROM/EPROM/FLASH", 0)
    pdata = size.get("PAGED EXT. RAM", 0)
    xram = size.get("EXTERNAL RAM", 0) + pdata
    # internal RAM: the cells of the layout map that hold registers, data, bits, overlays, idata
    cells = {}
    for line in t.splitlines():
        m = re.match(r"0x[0-9a-f]+:\|(.*)\|\s*$", line)
        if m:
            for ch in m.group(1).split("|"):
                ch = ch.strip()
                if ch and ch != "S":
                    kind = ("registers" if ch in "0123" else "bits" if ch in "BT" else "overlay" if ch == "Q"
                            else "idata" if ch == "I" else "absolute" if ch == "A" else "data")
                    cells[kind] = cells.get(kind, 0) + 1
    iram = sum(cells.values())
    st = re.search(r"with (\d+) bytes available", t)
    stack_free = int(st.group(1)) if st else 0
    out = subprocess.run([sys.executable, os.path.join(os.path.dirname(os.path.abspath(__file__)), "stackdepth.py"),
                          os.path.dirname(a.base)], capture_output=True, text=True)
    if out.returncode != 0:
        print(out.stdout + out.stderr, end="")
        return 1
    worst = int(re.search(r"worst case (\d+) B", out.stdout).group(1))
    margin = stack_free - worst

    code_free_pct = 100.0 * (a.code - code) / a.code
    print("memory: code  %5d / %5d B, %5d B free (%.1f %%; floor %g %%)"
          % (code, a.code, a.code - code, code_free_pct, a.code_free))
    print("memory: xdata %5d / %5d B, %5d B free (floor %d B; pdata %d B of it)"
          % (xram, a.xram, a.xram - xram, a.xram_free, pdata))
    print("memory: idata %5d / %5d B (%s), %d B left for the stack"
          % (iram, a.iram, ", ".join("%s %d" % kv for kv in sorted(cells.items())), stack_free))
    print(out.stdout.strip().replace("stack: worst case", "stack: static worst case"))
    print("stack: margin %d B (floor %d B)" % (margin, a.stack_margin))
    bad = []
    if code > a.code:
        bad.append("code %d > %d B" % (code, a.code))
    if xram > a.xram:
        bad.append("xdata %d > %d B" % (xram, a.xram))
    if iram > a.iram:
        bad.append("idata %d > %d B" % (iram, a.iram))
    if code_free_pct < a.code_free:
        bad.append("code %.1f %% free, floor %g %%" % (code_free_pct, a.code_free))
    if a.xram - xram < a.xram_free:
        bad.append("xdata %d B free, floor %d B" % (a.xram - xram, a.xram_free))
    if margin < a.stack_margin:
        bad.append("stack margin %d B, floor %d B" % (margin, a.stack_margin))
    if bad:
        print("memory: BELOW THE FLOOR: " + "; ".join(bad))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())

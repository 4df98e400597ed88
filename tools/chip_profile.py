#!/usr/bin/env python3
"""chip_profile.py PROFILE DIR [DEPTH] [N]: where the longest passes of a make chip run spend their clocks.

PROFILE is the file the STC12C5A60S2 model writes when STC12_PROFILE names it (sim/ucsim/stc12.cc):
the longest main-loop pass and the longest control step (8 conversions), each instruction as its
PC, SP and start clock. DIR is the image's build folder (build/stc12): its .map, the .lst and .rel
of every module it links (static functions too) and its .ihx (the opcodes, to see the calls).
The call stack is rebuilt from the SP: a frame begins at an LCALL/ACALL's target (or an interrupt's
vector) and ends when the SP falls below where the call left it; a call through a pointer
(__sdcc_call_dptr) takes the name of the function it reaches. Prints, for each pass, the call
tree to DEPTH (3) levels with each node's clocks, calls and microseconds at 11.0592 MHz, then the
N (15) functions with the most clocks of their own.
"""
import bisect
import glob
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import memmap  # noqa: E402

MHZ = 11.0592
LABEL = re.compile(r"^\s*([0-9A-F]{6})\s+\d+\s+([A-Za-z_][\w.]*)::?\s*$")
AREA = re.compile(r"^\s*(?:[0-9A-F]{6})?\s*\d+\s+\.area\s+(\w+)")
TRAMPOLINE = "__sdcc_call_dptr"


def code_labels(d):
    """Sorted [(address, name)] of the image's code: the map's symbols, and every module's own
    CSEG labels placed by one of its symbols the map gives."""
    mp = glob.glob(os.path.join(d, "*.map"))[0]
    glob_sym = {}
    labels = {}
    for line in open(mp, errors="replace"):
        m = re.match(r"^C:\s+([0-9A-F]{8})\s+(\S+)\s*(\S*)", line)
        if m and not m.group(2).startswith(("s_", "l_")):
            a, n = int(m.group(1), 16), m.group(2)
            glob_sym[n] = a
            labels[a] = n
    linked = memmap.linked_modules(d)
    for lst in glob.glob(os.path.join(d, "**", "*.lst"), recursive=True):
        mod = os.path.splitext(os.path.basename(lst))[0]
        if linked is not None and mod not in linked:
            continue
        area, own = None, []
        for line in open(lst, errors="replace"):
            m = AREA.match(line)
            if m:
                area = m.group(1)
                continue
            m = LABEL.match(line)
            if m and area == "CSEG" and "$" not in m.group(2):
                own.append((int(m.group(1), 16), m.group(2)))
        base = next((glob_sym[n] - off for off, n in own if n in glob_sym), None)
        if base is not None:
            for off, n in own:
                labels.setdefault(base + off, n)
    return sorted(labels.items())


def read_ihx(path):
    code = bytearray(65536)
    for line in open(path):
        line = line.strip()
        if not line.startswith(":") or int(line[7:9], 16) != 0:
            continue
        n, a = int(line[1:3], 16), int(line[3:7], 16)
        code[a:a + n] = bytes.fromhex(line[9:9 + 2 * n])
    return code


def read_profile(path):
    passes, cur = [], None
    for line in open(path):
        if line.startswith("pass "):
            f = line.split()
            cur = {"kind": f[1], "start": int(f[3]), "clocks": int(f[5]), "adc": int(f[7]), "rec": []}
            passes.append(cur)
        else:
            pc, sp, t = line.split()
            cur["rec"].append((int(pc, 16), int(sp, 16), int(t, 16)))
    return passes


def analyse(p, labels, code, depth):
    addrs = [a for a, _ in labels]

    def fn(pc):
        i = bisect.bisect_right(addrs, pc) - 1
        return labels[i][1].lstrip("_") if i >= 0 else "0x%04x" % pc

    rec = p["rec"]
    own, tree = {}, {}
    frames = []                     # [name, sp at entry (after the call's push)]
    for i, (pc, sp, t) in enumerate(rec):
        clk = (rec[i + 1][2] if i + 1 < len(rec) else p["clocks"]) - t
        while frames and sp < frames[-1][1]:
            frames.pop()
        if i > 0:
            ppc, psp = rec[i - 1][0], rec[i - 1][1]
            op = code[ppc]
            if sp == psp + 2 and (op == 0x12 or (op & 0x1F) == 0x11):
                frames.append([fn(pc), sp])
            elif sp == psp + 2 and pc < 0x43 and pc % 8 == 3:
                frames.append(["interrupt 0x%02x" % pc, sp])
        if not frames:
            frames.append([fn(pc), -1])
        if frames[-1][0] == TRAMPOLINE.lstrip("_") and fn(pc) != frames[-1][0]:
            frames[-1][0] = fn(pc)
        name = fn(pc)
        own[name] = own.get(name, 0) + clk
        path = tuple(f[0] for f in frames[:depth])
        for k in range(1, len(path) + 1):
            node = tree.setdefault(path[:k], [0, 0, len(tree)])
            node[0] += clk
        # a call counted at its first instruction
        if len(frames) <= depth and frames[-1][1] == sp and (i == 0 or sp == rec[i - 1][1] + 2):
            tree[path][1] += 1
    return own, tree


def main():
    prof, d = sys.argv[1], sys.argv[2]
    depth = int(sys.argv[3]) if len(sys.argv) > 3 else 3
    n = int(sys.argv[4]) if len(sys.argv) > 4 else 15
    labels = code_labels(d)
    code = read_ihx(glob.glob(os.path.join(d, "*.ihx"))[0])
    for p in read_profile(prof):
        if not p["rec"]:
            continue
        print("%s pass: %d clocks = %.3f ms at %.3f s, %d conversions, %d instructions"
              % (p["kind"], p["clocks"], p["clocks"] / MHZ / 1000, p["start"] / MHZ / 1e6, p["adc"],
                 len(p["rec"])))
        own, tree = analyse(p, labels, code, depth)
        print("  call tree (clocks with what they call and the interrupts inside, calls, us):")
        for path, (clk, calls, _) in sorted(tree.items(), key=lambda kv: kv[1][2]):
            if clk * 100 < p["clocks"]:
                continue            # under 1 % of the pass
            print("  %s%-*s %8d %5s %9.1f" % ("  " * (len(path) - 1), 40 - 2 * (len(path) - 1), path[-1],
                                            clk, calls or "", clk / MHZ))
        print("  own clocks, the largest %d:" % n)
        for name, clk in sorted(own.items(), key=lambda kv: -kv[1])[:n]:
            print("    %-36s %8d %9.1f us %5.1f %%" % (name, clk, clk / MHZ, 100.0 * clk / p["clocks"]))
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""memmap.py DIR [N]: the N (20) largest users of each memory region of the SDCC image built in DIR.

Reads the assembler listings (.lst) of every module under DIR that the image links (the map's
"Files Linked" and the members of fw.lib it pulled): each label's share of its area is
the distance to the next label of the same area in the same module (or to the area's end, from
the .rel). Regions: code (CSEG, CONST, HOME, GSINIT*, the initial values XINIT), xdata (XSEG,
XISEG), pdata (PSEG), data (DSEG, OSEG, REG_BANK_*, BSEG as bytes), idata (ISEG). Library routines
linked from SDCC's own library are not in DIR and show as one line from the map's area totals.
"""
import glob
import os
import re
import sys

REGION = {
    "CSEG": "code", "CONST": "code", "HOME": "code", "GSINIT": "code", "GSINIT0": "code",
    "GSINIT1": "code", "GSINIT2": "code", "GSINIT3": "code", "GSINIT4": "code", "GSINIT5": "code",
    "GSFINAL": "code", "XINIT": "code", "CABS": "code",
    "XSEG": "xdata", "XISEG": "xdata", "PSEG": "pdata",
    "DSEG": "data", "OSEG": "data", "ISEG": "idata",
}
AREA = re.compile(r"^\s*(?:[0-9A-F]{6})?\s*\d+\s+\.area\s+(\w+)")
LABEL = re.compile(r"^\s*([0-9A-F]{6})\s+\d+\s+([A-Za-z_][\w.]*)::?\s*$")
DS = re.compile(r"^\s*[0-9A-F]{6}\s+\d+\s+\.ds\s+(\d+)")


def module_users(lst, rel):
    """{(region, name): bytes} of one module."""
    sizes = {}
    for line in open(rel, errors="replace"):
        m = re.match(r"A (\w+) size ([0-9A-Fa-f]+)", line)
        if m:
            sizes[m.group(1)] = sizes.get(m.group(1), 0) + int(m.group(2), 16)
    labels = {}
    area = None
    for line in open(lst, errors="replace"):
        m = AREA.match(line)
        if m:
            area = m.group(1)
            continue
        m = LABEL.match(line)
        if m and area in REGION and "$" not in m.group(2):
            labels.setdefault(area, []).append((int(m.group(1), 16), m.group(2)))
    users = {}
    mod = os.path.splitext(os.path.basename(lst))[0]
    for area, labs in labels.items():
        labs.sort()
        end = sizes.get(area, 0)
        for i, (addr, name) in enumerate(labs):
            nxt = labs[i + 1][0] if i + 1 < len(labs) else end
            if nxt > addr:
                key = (REGION[area], "%s %s" % (mod, name.lstrip("_")))
                users[key] = users.get(key, 0) + nxt - addr
        covered = sum(users.get((REGION[area], "%s %s" % (mod, n.lstrip("_"))), 0) for _, n in labs)
        if labs and labs[0][0] > 0:
            key = (REGION[area], "%s (%s start)" % (mod, area))
            users[key] = users.get(key, 0) + labs[0][0]
    for area, size in sizes.items():
        if area in REGION and area not in labels and size > 0:
            key = (REGION[area], "%s (%s)" % (mod, area))
            users[key] = users.get(key, 0) + size
    return users


def linked_modules(d):
    """Names of the project's modules the image linked (the map's files and fw.lib members)."""
    maps = glob.glob(os.path.join(d, "*.map"))
    if not maps:
        return None
    names, lib = set(), None
    for line in open(maps[0], errors="replace"):
        m = re.match(r"^(\S+)\.(rel|lib)\b\s*(?:\[ (\S+)\.rel \])?", line)
        if m:
            if m.group(2) == "rel":
                names.add(os.path.basename(m.group(1)))
            else:
                lib = m.group(1)
                if m.group(3) and lib.endswith("fw"):
                    names.add(m.group(3))
            continue
        m = re.match(r"^\s+\[ (\S+)\.rel \]", line)
        if m and lib and lib.endswith("fw"):
            names.add(m.group(1))
    return names


def main():
    d = sys.argv[1]
    n = int(sys.argv[2]) if len(sys.argv) > 2 else 20
    users = {}
    linked = linked_modules(d)
    for lst in glob.glob(os.path.join(d, "**", "*.lst"), recursive=True):
        rel = lst[:-4] + ".rel"
        if linked is not None and os.path.splitext(os.path.basename(lst))[0] not in linked:
            continue
        if os.path.exists(rel):
            for k, v in module_users(lst, rel).items():
                users[k] = users.get(k, 0) + v
    for region in ("code", "xdata", "pdata", "data", "idata"):
        rows = sorted(((v, k[1]) for k, v in users.items() if k[0] == region), reverse=True)
        if not rows:
            continue
        print("%s: %d B in %d users from the project's modules; the largest %d:" % (region, sum(v for v, _ in rows), len(rows), min(n, len(rows))))
        for v, name in rows[:n]:
            print("  %6d  %s" % (v, name))
    return 0


if __name__ == "__main__":
    sys.exit(main())

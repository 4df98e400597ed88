#!/usr/bin/env bash
# memuse.sh BASE CODE_MAX IRAM_MAX XRAM_MAX: print the linked image's code / RAM / stack use from
# SDCC's .mem summary, and fail when any of them exceeds the chip.
set -euo pipefail
mem=$1.mem
[ -f "$mem" ] || { echo "memuse: $mem missing" >&2; exit 1; }
python3 - "$mem" "$2" "$3" "$4" <<'PY'
import re, sys
mem, code_max, iram_max, xram_max = sys.argv[1], *map(int, sys.argv[2:])
t = open(mem).read()
size = {}
for line in t.splitlines():
    m = re.match(r"\s*(ROM/EPROM/FLASH|EXTERNAL RAM|PAGED EXT\. RAM)\s.*?(\d+)\s+(\d+)\s*$", line)
    if m:
        size[m.group(1)] = int(m.group(2))
code = size.get("ROM/EPROM/FLASH", 0)
xram = size.get("EXTERNAL RAM", 0) + size.get("PAGED EXT. RAM", 0)
# internal RAM: cells of the layout map that hold registers, data, bits, overlays or idata
used_iram = 0
for line in t.splitlines():
    m = re.match(r"0x[0-9a-f]+:\|(.*)\|\s*$", line)
    if m:
        used_iram += sum(1 for ch in m.group(1).split("|") if ch.strip() not in ("", "S"))
stack = re.search(r"Stack starts at: (0x[0-9a-fA-F]+).*?with (\d+) bytes available", t)
stack_free = int(stack.group(2)) if stack else 0
print("memory: code %d / %d B (%.1f %%), idata %d / %d B, stack %d B free, xdata %d / %d B (%.1f %%)"
      % (code, code_max, 100.0 * code / code_max, used_iram, iram_max, stack_free,
         xram, xram_max, 100.0 * xram / xram_max))
bad = []
if code > code_max: bad.append("code %d > %d B" % (code, code_max))
if xram > xram_max: bad.append("xdata %d > %d B" % (xram, xram_max))
if used_iram > iram_max: bad.append("idata %d > %d B" % (used_iram, iram_max))
if stack_free < 32: bad.append("only %d B of stack (32 needed)" % stack_free)
if bad:
    print("memory: OVERFLOW: " + ", ".join(bad))
    sys.exit(1)
PY

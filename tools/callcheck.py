#!/usr/bin/env python3
"""callcheck.py [--tree] DIR: every call in the SDCC assembly under DIR passes its arguments the way the
callee takes them.

A non-reentrant function of the large model takes its second and later parameters in XRAM
(`_f_PARM_2` ...), a reentrant one on the stack. SDCC makes every prototype a module compiled
`#pragma stackauto` sees reentrant, so such a module calls a non-reentrant function with more
than one parameter by pushing, and the callee reads a parameter nobody wrote; the linker cannot
see it. Here: each function that has a `_f_PARM_n` must have it written by every module that
calls it (the SDCC runtime's own routines are not in DIR and are left out). Exit 1 on a
mismatch, naming the caller and the callee."""
import glob
import os
import re
import sys


def main():
    tree = len(sys.argv) == 3 and sys.argv[1] == "--tree"
    if tree:
        del sys.argv[1]
    if len(sys.argv) != 2 or not os.path.isdir(sys.argv[1]):
        sys.exit("usage: callcheck.py [--tree] DIR (a build folder with SDCC .asm files)")
    files = sorted(glob.glob(os.path.join(sys.argv[1], "**", "*.asm"), recursive=True))
    if tree:
        # only those whose source is still in the tree (DIR/a/b.asm from a/b.c, run from the
        # repository's top): a build folder keeps the objects of files moved or removed since
        files = [f for f in files if os.path.exists(os.path.splitext(os.path.relpath(f, sys.argv[1]))[0] + ".c")]
    if not files:
        sys.exit("callcheck: no .asm files under %s" % sys.argv[1])
    text = {f: open(f, encoding="latin-1").read() for f in files}
    parms = {}                      # function -> its PARM symbols (defined in its module)
    for t in text.values():
        for m in re.finditer(r"^(_\w+?)_PARM_(\d+):", t, re.M):
            parms.setdefault(m.group(1), set()).add("%s_PARM_%s" % (m.group(1), m.group(2)))
    bad = 0
    calls = 0
    for f, t in text.items():
        for fn, ps in parms.items():
            if not re.search(r"\b(?:lcall|ljmp|acall|ajmp)\s+%s\b" % fn, t):
                continue
            calls += 1
            missing = [p for p in sorted(ps) if not re.search(r"#\(?%s\b" % p, t)]
            if missing:
                bad += 1
                print("callcheck: %s calls %s without writing %s (a reentrant prototype "
                      "there? declare it __reentrant)" % (os.path.relpath(f, sys.argv[1]),
                                                          fn[1:], ", ".join(missing)))
    print("callcheck: %d functions with parameters in XRAM, %d calling modules, %d mismatched"
          % (len(parms), calls, bad))
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()

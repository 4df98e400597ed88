#!/usr/bin/env python3
"""symgraph.py [ROOT] [--allow FILE] [--cc CC] [--keep DIR]: firmware/'s layering at the symbol level.

incgraph.py checks what a module includes; this checks what its object code uses. Each source
of ROOT (firmware/) is compiled for the host (cc -O0, HAL_HOST, as the host build's headers
say); `nm` gives the symbols each object defines, `objdump -dr` every use of a symbol with the
instruction that makes it. A symbol belongs to the folder (layer) of the object that defines
it; symbols defined outside ROOT (the HAL, the C library) are the platform's. Fails (exit 1) on
  - an upward use: an object that calls a function, or reads or writes a global, of a higher
    layer or of another folder of its own rank (incgraph.LAYERS, bottom first);
  - a foreign write: an object that stores into a global of another folder (a value a layer
    owns is written only by it). A store through a pointer (an indexed array, a field through
    &global) cannot be told from a read here: those uses count as reads.
Uses named in the allow file ("folder/module.c -> symbol", one a line, # comments) are
reported, not failed. x86-64 objects (the relocations are read from gcc's -O0 code, where a
global's access is one instruction with the global's relocation).
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from incgraph import LAYERS, rank  # noqa: E402  (one layer order for both checks)

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# the host build's include path outside firmware/ (Makefile HOST_INC)
HOST_INC = ["hal", "hal/host", "hal/pil", "sim", "tests/target"]
# instructions whose memory operand, last in AT&T order, is only read
READ_ONLY = re.compile(r"^(cmp|test|push|bt|ucomis|comis|call|jmp)")
RELOC = re.compile(r"^\s*[0-9a-f]+:\s+R_X86_64_(\w+)\s+([^+\-\s]+)")
INSN = re.compile(r"^\s*[0-9a-f]+:\s+(\S+)\s*(.*?)\s*(#.*)?$")


def compile_all(root, cc, out):
    """{object: source relative to root} of every .c under root, compiled into out."""
    dirs = sorted({os.path.dirname(os.path.join(d, f)) for d, _, fs in os.walk(root)
                   for f in fs if f.endswith(".c")})
    inc = ["-I" + d for d in dirs] + ["-I" + os.path.join(REPO, d) for d in HOST_INC]
    objs, procs = {}, []
    for d in dirs:
        for f in sorted(os.listdir(d)):
            if not f.endswith(".c"):
                continue
            src = os.path.join(d, f)
            rel = os.path.relpath(src, root)
            obj = os.path.join(out, rel.replace(os.sep, "__") + ".o")
            objs[obj] = rel
            procs.append((rel, subprocess.Popen(
                [cc, "-std=c99", "-D_DEFAULT_SOURCE", "-DHAL_HOST", "-O0", "-fno-common", "-w"]
                + inc + ["-c", src, "-o", obj], stderr=subprocess.PIPE, text=True)))
    bad = [(rel, p.communicate()[1]) for rel, p in procs if p.wait() != 0]
    for rel, err in bad:
        print("symgraph: %s does not compile:\n%s" % (rel, err))
    return objs, not bad


def defined(obj):
    """{symbol: kind} an object defines for others: T code, D/B/C data, R read-only data."""
    out = subprocess.run(["nm", "--defined-only", "-g", obj], capture_output=True, text=True,
                         check=True).stdout
    syms = {}
    for line in out.splitlines():
        parts = line.split()
        if len(parts) == 3:
            syms[parts[2]] = parts[1].upper()
    return syms


def uses(obj):
    """[(symbol, how)] of every relocation in the object's code: call, write or read."""
    out = subprocess.run(["objdump", "-dr", "--no-show-raw-insn", obj], capture_output=True,
                         text=True, check=True).stdout
    found, insn = [], None
    for line in out.splitlines():
        m = RELOC.match(line)
        if m:
            sym = m.group(2)
            if insn is None or sym.startswith("."):
                continue
            op, args = insn
            if op.startswith(("call", "jmp")) or m.group(1) == "PLT32":
                how = "call"
            elif op.startswith("lea"):
                how = "read"            # an address taken (an indexed access, a pointer)
            else:
                last = re.split(r",(?![^(]*\))", args)[-1] if args else ""
                how = "write" if "(%rip)" in last and not READ_ONLY.match(op) else "read"
            found.append((sym, how))
            continue
        m = INSN.match(line)
        if m:
            insn = (m.group(1), m.group(2))
    return found


def main():
    args = sys.argv[1:]
    allow = set()
    opts = {"--allow": None, "--cc": os.environ.get("CC", "cc"), "--keep": None}
    for k in list(opts):
        if k in args:
            i = args.index(k)
            opts[k] = args[i + 1]
            del args[i:i + 2]
    if opts["--allow"]:
        for line in open(opts["--allow"]):
            line = line.split("#")[0].strip()
            if line:
                a, b = [s.strip() for s in line.split("->")]
                allow.add((a, b))
    root = args[0] if args else os.path.join(REPO, "firmware")
    out = opts["--keep"] or tempfile.mkdtemp(prefix="symgraph")
    os.makedirs(out, exist_ok=True)
    try:
        objs, ok = compile_all(root, opts["--cc"], out)
        if not ok:
            return 1
        owner = {}                      # symbol -> (source, nm kind)
        for obj, rel in objs.items():
            for sym, kind in defined(obj).items():
                owner[sym] = (rel, kind)
        bad = allowed = n_uses = 0
        seen = set()
        for obj, rel in sorted(objs.items(), key=lambda x: x[1]):
            folder = rel.split(os.sep)[0]
            for sym, how in uses(obj):
                if sym not in owner or owner[sym][0] == rel:
                    continue
                n_uses += 1
                src, kind = owner[sym]
                to = src.split(os.sep)[0]
                rf, rt = rank(folder), rank(to)
                if rf is None or rt is None:
                    what = "folder %s in no layer" % (folder if rf is None else to)
                elif rt > rf or (rt == rf and to != folder):
                    what = "upward " + how
                elif to != folder and how == "write":
                    what = "foreign write"
                else:
                    continue
                key = (rel, sym, what)
                if key in seen:
                    continue
                seen.add(key)
                ok = (rel, sym) in allow
                print("symgraph: %s%s: %s -> %s (%s)" % ("allowed, " if ok else "", what,
                                                         rel, sym, src))
                if ok:
                    allowed += 1
                else:
                    bad += 1
        print("symgraph: %d objects, %d uses across modules, %s%s" % (
            len(objs), n_uses, "%d problems" % bad if bad else
            "every call and read points down, every write stays in its layer",
            " but %d allowed by the allow file" % allowed if allowed and not bad else ""))
        return 1 if bad else 0
    finally:
        if not opts["--keep"]:
            shutil.rmtree(out, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""stackdepth.py DIR: worst-case depth of the 8051 hardware stack of the SDCC image built in DIR.

Reads every SDCC .asm under DIR, walks each function linearly keeping the bytes it has on the
stack (push/pop, `mov a,sp / add a,#n / mov sp,a` frames of reentrant functions, the 2-byte
return address of every lcall/acall) and takes the call graph's deepest path. Interrupt handlers
add their own deepest path on top of the main program's: low-priority handlers cannot nest, the
high-priority PCA handler can preempt one of them. Library routines (mul/div support, generic
pointer access) are not in DIR: each is counted as LIB_BYTES. Recursion is reported as an error.
Prints the depth in bytes; with --free N exits 1 when the depth exceeds N.
"""
import glob
import os
import re
import sys

LIB_BYTES = 8           # a support routine: return address plus a few pushes (generous)
HIGH_PRIORITY = {"_stc12_pca_isr"}
# calls through a function pointer (SDCC: lcall to a local label that pushes the pointer and
# `ret`s into it), by the function that makes them: every function the pointer may hold
INDIRECT = {"_store_learnt_now": ["_diag_learnt_byte"]}   # learnt.c: store_learnt_from's


def parse(dirname):
    funcs = {}
    for path in glob.glob(os.path.join(dirname, "**", "*.asm"), recursive=True):
        cur = None
        pending_sp = False
        frame_a = None
        for line in open(path, errors="replace"):
            s = line.split(";")[0].strip()
            if line.startswith(";\t function ") or line.startswith(";\tfunction "):
                name = "_" + line.split("function", 1)[1].strip()
                cur = {"depth": 0, "max": 0, "calls": []}
                funcs[name] = cur
                continue
            if cur is None or not s:
                continue
            op = s.split()[0]
            a = re.match(r"mov\s+a,#(0x[0-9a-fA-F]+|\d+)$", s)
            if a:
                frame_a = int(a.group(1), 0)     # A's value for a _mv_enter_a that follows
            if op == "push":
                cur["depth"] += 1
                cur["max"] = max(cur["max"], cur["depth"])
            elif op == "pop" or s.replace(" ", "").replace("\t", "") == "decsp":
                cur["depth"] = max(0, cur["depth"] - 1)
            elif s.replace(" ", "").replace("\t", "") == "incsp":
                cur["depth"] += 1
                cur["max"] = max(cur["max"], cur["depth"])
            elif s.replace(" ", "").replace("\t", "") == "mova,sp":
                pending_sp = True
                continue
            elif pending_sp and s.replace(" ", "").replace("\t", "") == "mov_bp,a":
                cur["bp"] = cur["depth"]     # the frame pointer set between (mov a,sp / mov _bp,a / add a,#n)
                continue
            elif pending_sp and re.match(r"add\s+a,#(0x[0-9a-fA-F]+|\d+)", s):
                n = int(re.match(r"add\s+a,#(0x[0-9a-fA-F]+|\d+)", s).group(1), 0)
                if n < 0x80:             # a frame being made (negative adds release it)
                    cur["frame"] = cur.get("frame", 0) + n
                    cur["depth"] += n
                    cur["max"] = max(cur["max"], cur["depth"])
                else:
                    cur["depth"] = max(0, cur["depth"] - (256 - n))
            elif op == "lcall" and s.split()[1] in ("_mv_enter", "_mv_enter_a", "_mv_enter_2", "_mv_enter_dptr"):
                # a function's entry (tools/share_moves.py ENTRIES): _bp pushed, then the frame
                # of A's bytes (enter_a) or 2 bytes (enter_2, enter_dptr), the routine's return
                # address pushed back above them
                cur["depth"] += 1
                cur["bp"] = cur["depth"]
                if s.split()[1] == "_mv_enter_a":
                    cur["frame"] = cur.get("frame", 0) + frame_a
                    cur["depth"] += frame_a
                elif s.split()[1] != "_mv_enter":
                    cur["depth"] += 2
                cur["max"] = max(cur["max"], cur["depth"] + 2)
            elif op in ("lcall", "acall", "ljmp", "sjmp", "ajmp"):
                target = s.split()[1].strip()
                if op == "lcall" and target.endswith("$"):
                    if name not in INDIRECT:    # a callee this walk cannot see: no figure
                        raise SystemExit("stackdepth: %s calls through a function pointer: name "
                                         "what it may call in INDIRECT (tools/stackdepth.py)" % name)
                    cur["calls"] += [(t, cur["depth"] + 2) for t in INDIRECT[name]]
                    cur["trampoline"] = True
                elif target.startswith("_") or target.startswith("__"):
                    tail = op.endswith("jmp")
                    cur["calls"].append((target, cur["depth"] + (0 if tail else 2)))
            elif s.replace(" ", "").replace("\t", "") == "mov_bp,sp":
                cur["bp"] = cur["depth"]
            elif s.replace(" ", "").replace("\t", "") == "movsp,_bp":
                cur["depth"] = cur.get("bp", cur["depth"])
            elif op == "ret" and cur.pop("trampoline", False):
                cur["depth"] = max(0, cur["depth"] - 2)     # the pointer's 2 pushes, not a return
            elif op in ("ret", "reti"):
                cur["depth"] = 0
            pending_sp = False
    return funcs


def deepest(funcs, name, memo, path, via=None):
    """Deepest stack use from name down; via[name] = the callee on that path."""
    if name in memo:
        return memo[name]
    if name in path:
        raise SystemExit("stackdepth: recursion through " + " -> ".join(path + [name]))
    f = funcs.get(name)
    if f is None:
        return LIB_BYTES if name.startswith("__") or name not in funcs else 0
    most = f["max"]
    for callee, at in f["calls"]:
        if callee == name or not (callee in funcs or callee.startswith("__")):
            continue                  # a jump to a local label of the same function
        d = at + deepest(funcs, callee, memo, path + [name], via)
        if d > most:
            most = d
            if via is not None:
                via[name] = callee
    memo[name] = most
    return most


def path_of(via, name):
    out = [name]
    while out[-1] in via and len(out) < 64:
        out.append(via[out[-1]])
    return " > ".join(n.lstrip("_") for n in out)


def main():
    args = sys.argv[1:]
    limit = None
    if "--free" in args:
        i = args.index("--free")
        limit = int(args[i + 1])
        del args[i:i + 2]
    show_path = "--path" in args
    args = [a for a in args if a != "--path"]
    funcs = parse(args[0])
    memo, via = {}, {}
    main_depth = 2 + deepest(funcs, "_main", memo, [], via)   # the reset's call into main
    isrs = [n for n in funcs if n.endswith("_isr")]
    low = [2 + deepest(funcs, n, memo, [], via) for n in isrs if n not in HIGH_PRIORITY]
    high = [2 + deepest(funcs, n, memo, [], via) for n in isrs if n in HIGH_PRIORITY]
    total = main_depth + max(low or [0]) + max(high or [0])
    print("stack: worst case %d B (main %d, deepest low-priority interrupt %d, high-priority %d)"
          % (total, main_depth, max(low or [0]), max(high or [0])))
    if show_path:
        print("stack: deepest path: " + path_of(via, "_main"))
    if limit is not None and total > limit:
        print("stack: OVERFLOW: %d B needed, %d B free" % (total, limit))
        sys.exit(1)


if __name__ == "__main__":
    main()

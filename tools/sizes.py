#!/usr/bin/env python3
"""sizes.py [ROOT ...] [--file-max N] [--func-max N]: files and functions over their size.

A C file or header under a ROOT (default firmware/; tests/scripts/structure.sh gives firmware,
hal and sim) over FILE_MAX lines, or a function over FUNC_MAX lines (from the line of its name
to its closing brace, the project's style: a definition's `{` and `}` in column 0), is listed
and the exit status is 1. An assembly routine (a __naked function: one __asm block) is
instructions, not C, and is not counted; nor is a class, struct, union or enum body (a C++
header's). --list prints the longest functions as well.
"""
import os
import re
import sys

FILE_MAX = 500
FUNC_MAX = 80
TYPE_BODY = re.compile(r"^\s*(typedef\s+)?(class|struct|union|enum)\b")


def functions(path):
    """(name, first line, lines) of each function defined in path."""
    lines = open(path, errors="replace").read().split("\n")
    out = []
    i = 0
    while i < len(lines):
        if lines[i].startswith("{"):
            # the name: the nearest line above that opens a parameter list (a type's body: none)
            j = i - 1
            while j > 0 and "(" not in lines[j] and not TYPE_BODY.match(lines[j]):
                j -= 1
            if TYPE_BODY.match(lines[j]):
                k = i + 1
                while k < len(lines) and not lines[k].startswith("}"):
                    k += 1
                i = k + 1
                continue
            m = re.search(r"(\w+)\s*\(", lines[j])
            k = i + 1
            while k < len(lines) and not lines[k].startswith("}"):
                k += 1
            naked = "__naked" in lines[j] or "__naked" in lines[i - 1]
            if m and not naked and not lines[j].lstrip().startswith(("#", "/*", "*")):
                out.append((m.group(1), j + 1, k - j + 1))
            i = k
        i += 1
    return out


def main():
    args = sys.argv[1:]
    file_max, func_max, show = FILE_MAX, FUNC_MAX, "--list" in args
    args = [a for a in args if a != "--list"]
    if "--file-max" in args:
        i = args.index("--file-max")
        file_max = int(args[i + 1])
        del args[i:i + 2]
    if "--func-max" in args:
        i = args.index("--func-max")
        func_max = int(args[i + 1])
        del args[i:i + 2]
    roots = args or ["firmware"]
    bad, longest, nfiles, nfuncs = 0, [], 0, 0
    for folder, _, files in sorted(w for root in roots for w in os.walk(root)):
        for f in sorted(files):
            if not f.endswith((".c", ".h")):
                continue
            path = os.path.join(folder, f)
            nfiles += 1
            n = open(path, errors="replace").read().count("\n")
            if n > file_max:
                print("sizes: %s: %d lines (at most %d)" % (path, n, file_max))
                bad += 1
            for name, line, length in functions(path):
                nfuncs += 1
                longest.append((length, "%s:%d %s" % (path, line, name)))
                if length > func_max:
                    print("sizes: %s:%d: %s is %d lines (at most %d)" % (path, line, name, length, func_max))
                    bad += 1
    if show:
        for length, where in sorted(longest, reverse=True)[:15]:
            print("%5d  %s" % (length, where))
    print("sizes: %d files, %d functions, %s" % (nfiles, nfuncs,
                                                "%d too long" % bad if bad else
                                                "none over %d lines a file or %d a function" % (file_max, func_max)))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())

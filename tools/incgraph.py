#!/usr/bin/env python3
"""incgraph.py [ROOT] [--allow FILE] [--dot]: the include graph of firmware/'s modules.

A module is a source's or header's name without its extension and _int (ctl.c, ctl.h and
ctl_int.h are `ctl`);
module A uses module B when a file of A includes B's header. Fails (exit 1) on
  - a circle: modules that use each other, directly or through others;
  - a module that includes a header from a higher layer (LAYERS, bottom first: data flows one
    way, the layers above call down, never back up).
Edges named in the allow file ("a -> b", one a line, # comments) are reported, not failed.
--dot prints the graph for Graphviz instead.
"""
import os
import re
import sys

# bottom first; folders of one rank may not use each other either way unless listed together
LAYERS = [("math",), ("store",), ("measure",), ("control",), ("ops",), ("console", "link"), ("app",)]
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def scan(root):
    """module -> (folder, set of included modules); only headers that are firmware modules count."""
    mods = {}
    for folder, _, files in os.walk(root):
        for f in files:
            if not f.endswith((".c", ".h")):
                continue
            mod = re.sub(r"_int$", "", os.path.splitext(f)[0])   # x_int.h: x's internals
            rel = os.path.relpath(folder, root).split(os.sep)[0]
            entry = mods.setdefault(mod, [rel, set()])
            for inc in INCLUDE.findall(open(os.path.join(folder, f), errors="replace").read()):
                entry[1].add(re.sub(r"_int$", "", os.path.splitext(os.path.basename(inc))[0]))
    return {m: (d, {i for i in incs if i in mods and i != m}) for m, (d, incs) in mods.items()}


def rank(folder):
    for i, names in enumerate(LAYERS):
        if folder in names:
            return i
    return None


def circles(graph):
    """Strongly connected components of more than one module (Tarjan)."""
    index, low, stack, on, out = {}, {}, [], set(), []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    sys.setrecursionlimit(10000)
    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def main():
    args = sys.argv[1:]
    allow = set()
    if "--allow" in args:
        i = args.index("--allow")
        for line in open(args[i + 1]):
            line = line.split("#")[0].strip()
            if line:
                a, b = [s.strip() for s in line.split("->")]
                allow.add((a, b))
        del args[i:i + 2]
    dot = "--dot" in args
    args = [a for a in args if a != "--dot"]
    root = args[0] if args else "firmware"
    mods = scan(root)
    if dot:
        print("digraph firmware {")
        for m, (d, uses) in sorted(mods.items()):
            for u in sorted(uses):
                print('  "%s/%s" -> "%s/%s";' % (d, m, mods[u][0], u))
        print("}")
        return 0
    graph = {m: {u for u in uses if (m, u) not in allow} for m, (_, uses) in mods.items()}
    bad = 0
    for comp in circles(graph):
        print("incgraph: circle: " + " <-> ".join(comp))
        bad += 1
    for m, (d, uses) in sorted(mods.items()):
        for u in sorted(uses):
            rm, ru = rank(d), rank(mods[u][0])
            if rm is None or ru is None:
                if rm is None and d != ".":
                    print("incgraph: %s/%s: folder %s is in no layer" % (d, m, d))
                    bad += 1
                continue
            if ru > rm or (ru == rm and mods[u][0] != d):
                what = "allowed for now" if (m, u) in allow else "upward"
                print("incgraph: %s: %s/%s includes %s/%s.h" % (what, d, m, mods[u][0], u))
                if (m, u) not in allow:
                    bad += 1
    n_edges = sum(len(u) for _, u in mods.values())
    allowed = sum(1 for m, (_, uses) in mods.items() for u in uses if (m, u) in allow)
    print("incgraph: %d modules, %d include edges, %s%s" % (
        len(mods), n_edges, "%d problems" % bad if bad else "no circle, every include points down",
        " but %d allowed for now" % allowed if allowed and not bad else ""))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env bash
# include_graph.sh: firmware/'s modules include no circle and only headers of lower layers
# (tools/incgraph.py); and the check fails on each defect planted alone in a copy of the tree: a
# circle of two modules of one layer (no include points up), and an upward include (no circle).
set -uo pipefail
cd "$(dirname "$0")/../.."
if out=$(python3 tools/incgraph.py firmware 2>&1); then
    echo "ok - include graph: $(echo "$out" | tail -1 | sed 's/^incgraph: //')"
else
    echo "not ok - include graph"; echo "$out" | sed 's/^/#   /'
fi
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
# plant NAME WANT NOT [HEADER FILE]...: each HEADER included first in FILE of a fresh copy; the
# check must fail, naming WANT and never NOT
plant() {
    local name=$1 want=$2 not=$3
    shift 3
    rm -rf "$tmp/firmware" && cp -r firmware "$tmp/"
    while [ $# -ge 2 ]; do
        sed -i "0,/#include/s//#include \"$1\"\n#include/" "$tmp/firmware/$2"; shift 2
    done
    if python3 tools/incgraph.py "$tmp/firmware" > "$tmp/out" 2>&1; then
        echo "not ok - include graph check catches $name"
    elif ! grep -q "$want" "$tmp/out" || grep -q "$not" "$tmp/out"; then
        echo "not ok - include graph check catches $name: not as $want alone"; sed 's/^/#   /' "$tmp/out"
    else
        echo "ok - include graph check catches $name: $(grep -c "$want" "$tmp/out") $want"
    fi
}
# control/valve.h <-> control/target.h: a circle inside one layer, every include level
plant "a planted circle (valve.h <-> target.h, one layer)" circle upward target.h control/valve.h valve.h control/target.h
# math/umath.h -> link/linebuf.h (which includes no firmware header): upward, no circle
plant "a planted upward include (umath.h -> linebuf.h)" upward circle linebuf.h math/umath.h

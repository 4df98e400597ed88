#!/usr/bin/env bash
# include_graph.sh: firmware/'s modules include no circle and only headers of lower layers
# (tools/incgraph.py); and the check fails on a circle planted in a copy of the tree.
set -uo pipefail
cd "$(dirname "$0")/../.."
if out=$(python3 tools/incgraph.py firmware 2>&1); then
    echo "ok - include graph: $(echo "$out" | tail -1 | sed 's/^incgraph: //')"
else
    echo "not ok - include graph"; echo "$out" | sed 's/^/#   /'
fi
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
cp -r firmware "$tmp/"
sed -i '0,/#include/s//#include "valve.h"\n#include/' "$tmp/firmware/math/fixed.h"
if python3 tools/incgraph.py "$tmp/firmware" > "$tmp/out" 2>&1; then
    echo "not ok - include graph check catches a planted circle (fixed.h -> valve.h)"
else
    echo "ok - include graph check catches a planted circle: $(grep -c 'circle\|upward' "$tmp/out") problems"
fi

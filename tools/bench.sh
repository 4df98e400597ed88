#!/usr/bin/env bash
# bench.sh UCDIR: run every target test in s51 and print the machine cycles it measured
# (classic 12-clock 8051 at 11.0592 MHz: 921600 machine cycles a second).
set -uo pipefail
cd "$(dirname "$0")/.."
dir=${1:-build/ucsim}
host=$(dirname "$dir")/host-test/target    # the host twins of the same BUILD
printf '%-40s %10s %10s\n' "s51 benchmark (machine cycles)" cycles "ms@12T"
for ihx in "$dir"/tt_*.ihx; do
    name=$(basename "$ihx" .ihx)
    tools/run_target.sh "$ihx" "$host/$name" "$dir" > /dev/null || echo "($name: s51 and host differ)"
    while read -r _ what n; do
        awk -v w="$name/$what" -v n="$n" 'BEGIN { printf "%-40s %10d %10.3f\n", w, n, n / 921.6 }'
    done < "$dir/$name.bench"
done

#!/usr/bin/env bash
# run_target.sh IHX HOSTBIN [OUTDIR]: run a target test in s51 and its host twin; same text or fail.
# Lines starting with '#' (cycle counts) are kept apart in OUTDIR/<name>.bench, not compared.
set -uo pipefail
ihx=$1 host=$2 out=${3:-$(dirname "$ihx")}
name=$(basename "$ihx" .ihx)
S51_TIMEOUT=${S51_TIMEOUT:-1200}
mkdir -p "$out"
between() { sed -n '/^TT-BEGIN$/,/^TT-END$/p'; }
# commands on stdin: run until the program stops itself through simif, print the state, quit
printf 'set opt selfjump_stop 1\nrun\nstate\nquit\n' |
    timeout "$S51_TIMEOUT" s51 -t C52 -X 11.0592M -I if=xram[0xffff] -b "$ihx" > "$out/$name.s51.raw" 2>&1
between < "$out/$name.s51.raw" > "$out/$name.s51.all"
grep '^#' "$out/$name.s51.all" > "$out/$name.bench" || true
grep -v '^#' "$out/$name.s51.all" > "$out/$name.s51.txt"
"$host" > "$out/$name.host.raw" 2>&1
between < "$out/$name.host.raw" | grep -v '^#' > "$out/$name.host.txt"
if ! grep -q '^TT-END$' "$out/$name.s51.txt"; then
    echo "not ok - target $name: s51 run did not finish (see $out/$name.s51.raw)"
    exit 1
fi
if ! grep -q '^TT-END$' "$out/$name.host.txt"; then
    echo "not ok - target $name: host twin did not finish (see $out/$name.host.raw)"
    exit 1
fi
lines=$(wc -l < "$out/$name.host.txt")
if cmp -s "$out/$name.s51.txt" "$out/$name.host.txt"; then
    echo "ok - target $name: s51 and host agree bit for bit on $((lines - 2)) result lines"
else
    first=$(diff "$out/$name.s51.txt" "$out/$name.host.txt" | head -3 | tr '\n' ' ')
    echo "not ok - target $name: s51 and host differ: $first"
    exit 1
fi

#!/usr/bin/env bash
# fuzz.sh DIR SECONDS TARGET...: run each libFuzzer target of DIR/bin for SECONDS from its kept corpus
# (tests/fuzz/corpus/<t>, read only) and a working corpus DIR/<t>/corpus; one summary line each
# (executions, the time it ran, coverage, corpus, findings) on stdout and in DIR/summary.txt; exit 1
# on a finding. libFuzzer stops a target at its first finding: its line then says so, with the
# time it ran, not the time asked.
set -uo pipefail
cd "$(dirname "$0")/.."
dir=$1 secs=$2; shift 2
found=0
: > "$dir/summary.txt"
for t in "$@"; do
    bin=$dir/bin/fuzz_$t
    work=$dir/$t
    mkdir -p "$work/corpus" "tests/fuzz/corpus/$t"
    rm -f "$work"/crash-* "$work"/leak-* "$work"/timeout-* "$work"/oom-*
    echo "fuzz: $t for ${secs} s ..."
    start=$SECONDS
    "$bin" -max_total_time="$secs" -print_final_stats=1 -timeout=10 -rss_limit_mb=2048 \
        -artifact_prefix="$work/" "$work/corpus" "tests/fuzz/corpus/$t" > "$work/log.txt" 2>&1
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$work/log.txt" | tail -1)
    took=$((SECONDS - start))      # wall time: libFuzzer's "Done ... in N second(s)" is not there after a finding
    cov=$(grep -o 'cov: [0-9]*' "$work/log.txt" | tail -1 | cut -d' ' -f2)
    ft=$(grep -o 'ft: [0-9]*' "$work/log.txt" | tail -1 | cut -d' ' -f2)
    corp=$(grep -o 'corp: [0-9]*' "$work/log.txt" | tail -1 | cut -d' ' -f2)
    finds=$(ls "$work"/crash-* "$work"/leak-* "$work"/timeout-* "$work"/oom-* 2>/dev/null | wc -l)
    line=$(printf '%-9s %10s execs in %4s s, cov %5s edges, ft %5s, corpus %4s, findings %s%s' \
        "$t" "${execs:-?}" "$took" "${cov:-?}" "${ft:-?}" "${corp:-?}" "$finds" \
        "$([ "$finds" -gt 0 ] && echo " (stopped at the first)")")
    echo "$line" | tee -a "$dir/summary.txt"
    if [ "$finds" -gt 0 ]; then
        found=1
        grep -m3 -E 'ERROR|invariant broken|runtime error' "$work/log.txt" | sed 's/^/    /'
        ls "$work"/crash-* "$work"/leak-* "$work"/timeout-* "$work"/oom-* 2>/dev/null | sed 's/^/    input: /'
    fi
done
[ $found = 0 ] || { echo "fuzz: findings above (logs in $dir/<target>/log.txt)"; exit 1; }

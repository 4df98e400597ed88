#!/usr/bin/env bash
# bench.sh UCDIR: run every target test in s51 and print the machine cycles it measured
# (classic 12-clock 8051 at 11.0592 MHz: 921600 machine cycles a second), and each controller's
# worst control step against the budget (firmware/control/ctl.h CTL_STEP_BUDGET_CYCLES).
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
budget=$(sed -n 's/^#define CTL_STEP_BUDGET_CYCLES \([0-9]*\).*/\1/p' firmware/control/ctl.h)
echo
echo "budget: a control step of any controller (ctl_step + ctl_applied) at most $budget machine cycles"
echo "        of classic 12-clock timing (its time on the 1T chip: the last part of make bench, measured in the"
echo "        STC12C5A60S2 model, tools/bench_chip.sh)"
sed -n 's/^#cycles ctl_step_\(.*\)_max \([0-9]*\)$/\1 \2/p' "$dir"/tt_ctl.bench |
    while read -r c n; do
        awk -v c="$c" -v n="$n" -v b="$budget" 'BEGIN { printf "  %-12s %6d  %5.1f %% of the budget  %s\n", c, n, 100 * n / b, n <= b ? "ok" : "OVER" }'
    done

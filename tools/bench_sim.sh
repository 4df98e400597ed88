#!/usr/bin/env bash
# bench_sim.sh: simulated seconds per wall second of the simulator on one scenario (one core, best of 3).
#   usage: tools/bench_sim.sh SIM_BINARY SCENARIO
set -euo pipefail
bin=$1 scn=$2
[ -x "$bin" ] || { echo "bench-sim: $bin is not built" >&2; exit 1; }
pin=""
command -v taskset >/dev/null 2>&1 && pin="taskset -c 0"
best=0
for i in 1 2 3; do
    line=$($pin "$bin" --scenario "$scn" | tail -n 1)
    sim_s=$(echo "$line" | grep -o '"sim_s":[0-9.e+-]*' | cut -d: -f2)
    wall_s=$(echo "$line" | grep -o '"wall_s":[0-9.e+-]*' | cut -d: -f2)
    x=$(awk -v s="$sim_s" -v w="$wall_s" 'BEGIN { printf "%.0f", (w > 0 ? s / w : 0) }')
    echo "bench-sim: run $i: $sim_s s simulated in $wall_s s wall: ${x}x real time"
    [ "$x" -gt "$best" ] && best=$x
done
verdict="meets"
[ "$best" -lt 10000 ] && verdict="MISSES"
echo "bench-sim: $(basename "$scn"): best ${best}x real time on one core ($verdict the 10000x goal)"

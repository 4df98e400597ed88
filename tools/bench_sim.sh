#!/usr/bin/env bash
# bench_sim.sh: simulated seconds per second of the simulator on one scenario (one thread, so one
# core): the fastest of RUNS runs (9) by wall time, and by the process's CPU time (the same unless
# other load on the machine takes the core away; a shared machine's wall figure is the lower).
# PIN=N pins the runs to core N (unpinned, the scheduler may move a run off a busy core).
#   usage: tools/bench_sim.sh SIM_BINARY SCENARIO [SIM_OPTION...]
set -euo pipefail
bin=$1 scn=$2
shift 2
runs=${RUNS:-9}
[ -x "$bin" ] || { echo "bench-sim: $bin is not built" >&2; exit 1; }
[[ "$runs" =~ ^[1-9][0-9]*$ ]] || { echo "bench-sim: RUNS must be a positive count, not '$runs'" >&2; exit 1; }
pin=""
if [ -n "${PIN:-}" ]; then
    [[ "$PIN" =~ ^[0-9]+$ ]] || { echo "bench-sim: PIN must be a core number, not '$PIN'" >&2; exit 1; }
    command -v taskset >/dev/null 2>&1 || { echo "bench-sim: PIN needs taskset" >&2; exit 1; }
    pin="taskset -c $PIN"
fi
fastest=0 fastest_cpu=0
for i in $(seq "$runs"); do
    line=$($pin "$bin" --scenario "$scn" "$@" | tail -n 1)
    sim_s=$(echo "$line" | grep -o '"sim_s":[0-9.e+-]*' | cut -d: -f2)
    wall_s=$(echo "$line" | grep -o '"wall_s":[0-9.e+-]*' | cut -d: -f2)
    cpu_s=$(echo "$line" | grep -o '"cpu_s":[0-9.e+-]*' | cut -d: -f2)
    [ -n "$sim_s" ] && [ -n "$wall_s" ] && [ -n "$cpu_s" ] || { echo "bench-sim: no sim_s, wall_s, cpu_s in: $line" >&2; exit 1; }
    x=$(awk -v s="$sim_s" -v w="$wall_s" 'BEGIN { printf "%.0f", (w > 0 ? s / w : 0) }')
    xc=$(awk -v s="$sim_s" -v w="$cpu_s" 'BEGIN { printf "%.0f", (w > 0 ? s / w : 0) }')
    echo "bench-sim: run $i: $sim_s s simulated in $wall_s s wall ($cpu_s s CPU): ${x}x real time (${xc}x by CPU time)"
    [ "$x" -gt "$fastest" ] && fastest=$x
    [ "$xc" -gt "$fastest_cpu" ] && fastest_cpu=$xc
done
# a timing on a shared machine is a measurement of that machine, not a pass or a fail: the
# figure is reported with the machine it ran on
cpu=$(grep -m1 'model name' /proc/cpuinfo 2>/dev/null | sed 's/.*: //' || true)
echo "bench-sim: $(basename "$scn")${*:+ $*}: fastest ${fastest}x real time on one core, ${fastest_cpu}x by CPU time (on ${cpu:-an unknown CPU}, $(nproc 2>/dev/null || echo '?') cores, load $(cut -d' ' -f1 /proc/loadavg 2>/dev/null || echo '?'))"

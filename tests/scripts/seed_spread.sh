#!/usr/bin/env bash
# seed_spread.sh: the simulator's metrics over seeds 1-16 stay within their seed-to-seed spread of
# the reference (tests/sim/seed_spread_ref.json, written by the 1 ms model of the firmware it
# was last saved with): tools/seed_spread.py
# --check. So do those of its fast mode (sim --fast, 5 ms ticks, 10 ms while the plant is idle),
# or within 3 % of the reference's mean for figures the seed barely moves (the pressure's extremes,
# which the longer tick smooths). A deliberate change of the physics or the firmware writes the
# reference again: tools/seed_spread.py SIM --save tests/sim/seed_spread_ref.json (the firmware's
# change with the simulator's physics unchanged; a change of the simulator alone is checked against
# the reference the old simulator saved).
set -uo pipefail
cd "$(dirname "$0")/../.."
B=${BUILD:-build}
SIM=$B/host/bin/sim
if ! make -s --no-print-directory "$SIM" BUILD="$B" > /dev/null 2>&1; then
    echo "not ok - seed spread: the simulator builds"
    exit 0
fi
python3 tools/seed_spread.py "$SIM" --check tests/sim/seed_spread_ref.json
# the step scenario's overshoot and settling move with the tick (the latency it adds to a loop
# driving its valve at full duty; docs/PIL.md): printed only. So do two worst zones, a single
# zone's extreme: the fixed PTO's 100 L/ha run's (ffmap's valve rests through most of that run,
# the plant then steps at the idle tick, and the worst zone lands lower on most seeds) and the
# paper's 150 L/ha run's (ffmap waits two periods for a reversal's answer, which the 5 ms tick
# shows later: 1.8 % against 1.4 %); the 1 ms check above holds both (docs/PIL.md)
python3 tools/seed_spread.py "$SIM" --check tests/sim/seed_spread_ref.json --args --fast --rel 0.03 \
    --skip target_step_125:overshoot_mean_pct,target_step_125:settle_mean_s,paper_dynamic_100_fixed_pto:zone_error_min_pct,paper_dynamic_150:zone_error_max_pct

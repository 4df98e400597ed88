#!/usr/bin/env bash
# bench_chip.sh SIM IHX S51: the field image's passes and interrupt handlers in 1T clocks, measured
# in the STC12C5A60S2 model (make chip) over scenarios/pil_bench.scn and its .input (60 s), and
# where the longest passes spend their clocks (the model's STC12_PROFILE, tools/chip_profile.py).
set -uo pipefail
cd "$(dirname "$0")/.."
sim=$1 ihx=$2 s51=$3
echo
echo "the field image in the STC12C5A60S2 model (make chip: hal/stc12, its handlers, 1T clocks at 11.0592 MHz),"
echo "scenarios/pil_bench.scn + .input, 60 s; a pass runs from one entry of app_poll to the next"
prof=$(mktemp)
trap 'rm -f "$prof"' EXIT
# the model's pass profile (STC12_PROFILE), the second pass of the step (diag_step's) too
at=$(awk '$3 == "_diag_step" { print "0x" $2 }' "${ihx%.ihx}.map")
out=$(STC12_PROFILE=$prof STC12_PROFILE_AT=$at "$sim" --chip "$ihx" --s51 "$s51" --scenario scenarios/pil_bench.scn \
      --input scenarios/pil_bench.input --serial /dev/null 2>&1)
echo "$out" | grep '^chip: ' | sed 's/^chip: /  /'
echo "$out" | grep '^sim: ' | sed 's/^sim: /  /'
echo "  where the longest passes spend their clocks (tools/chip_profile.py: the call tree to 3 levels, over 1 %;"
echo "  \"at\": the longest pass that ran diag_step, the step's second pass)"
python3 tools/chip_profile.py "$prof" "$(dirname "$ihx")" 3 8 | sed 's/^/  /'
echo "  goal: every pass under 5 ms (the start-up's and the control step's among them); every handler's own time under 50 us"
echo "$out" | awk '
    /^chip: worst pass/ { if (match($0, /= [0-9.]+ ms/)) { ms = substr($0, RSTART + 2, RLENGTH - 5) + 0;
                                        if (ms >= 5) bad = bad " a pass " ms " ms;" } }
    /^chip: worst control step pass/ { if (match($0, /= [0-9.]+ ms/)) { ms = substr($0, RSTART + 2, RLENGTH - 5) + 0;
                                        if (ms >= 5) bad = bad " the control step " ms " ms;" } }
    /^chip: handler/ { if (match($0, /own time max [0-9]+ clocks = [0-9.]+ us/)) {
                           t = substr($0, RSTART, RLENGTH); sub(/.*= /, "", t); us = t + 0;
                           h = $0; sub(/^chip: handler +/, "", h); sub(/ +vector.*/, "", h);
                           if (us >= 50) bad = bad " " h " " us " us;" } }
    END { print "  " (bad == "" ? "within the goals" : "OVER THE GOAL:" bad) }'

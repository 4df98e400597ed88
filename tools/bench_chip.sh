#!/usr/bin/env bash
# bench_chip.sh SIM IHX S51: the field image's passes and interrupt handlers in 1T clocks, measured
# in the STC12C5A60S2 model (make chip) over scenarios/pil_bench.scn and its .input (60 s).
set -uo pipefail
cd "$(dirname "$0")/.."
sim=$1 ihx=$2 s51=$3
echo
echo "the field image in the STC12C5A60S2 model (make chip: hal/stc12, its handlers, 1T clocks at 11.0592 MHz),"
echo "scenarios/pil_bench.scn + .input, 60 s; a pass runs from one entry of app_poll to the next"
out=$("$sim" --chip "$ihx" --s51 "$s51" --scenario scenarios/pil_bench.scn --input scenarios/pil_bench.input \
      --serial /dev/null 2>&1)
echo "$out" | grep '^chip: ' | sed 's/^chip: /  /'
echo "$out" | grep '^sim: ' | sed 's/^sim: /  /'
echo "  goal: the worst control step pass under 5 ms; every handler's own time under 50 us"
echo "$out" | awk '
    /^chip: worst control step pass/ { ms = $(NF-3) + 0; if (ms >= 5) bad = bad " control step " ms " ms;" }
    /^chip: handler/ { for (i = 1; i <= NF; i++) if ($i == "us,") { us = $(i-1) + 0; if (us >= 50) bad = bad " " $3 " " us " us;" ; break } }
    END { print "  " (bad == "" ? "within the goals" : "OVER THE GOAL:" bad) }'

#!/usr/bin/env bash
# bench_pil.sh ISR_IHX SIM PIL_IHX: the chip's interrupt handlers and the whole firmware's passes in s51
# (classic 12-clock machine cycles; the 1T chip's own clocks: tools/bench_chip.sh, make chip).
set -uo pipefail
cd "$(dirname "$0")/.."
isr=$1 sim=$2 pil=$3
echo
echo "interrupt handlers of hal/stc12 (machine cycles at 12T, longest path, entry and RETI included; goal <= 300)"
printf 'set opt selfjump_stop 1\nrun\nquit\n' | timeout 120 s51 -t C52 -X 11.0592M -I if=xram[0xffff] -b "$isr" 2>&1 |
    sed -n '/^TT-BEGIN$/,/^TT-END$/p' | grep -v '^TT-' |
    awk '{ printf "  %-28s %6d cycles  %7.1f us at 12T\n", $1, $2, $2 / 0.9216 }'
echo
echo "the whole firmware in s51 (make pil), scenarios/pil_bench.scn + .input: 60 s with keys, serial"
echo "commands, a boom shut, an open pressure sensor and a lost wheel sensor; one pass a millisecond"
"$sim" --pil "$pil" --scenario scenarios/pil_bench.scn --input scenarios/pil_bench.input --serial /dev/null |
    grep '^pil:' | sed 's/^pil: /  /'
echo "  goal: worst pass <= 60000 cycles at 12T, stack high-water mark >= 40 B below the top"

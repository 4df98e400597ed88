#!/usr/bin/env bash
# pil.sh: processor in the loop: the whole firmware built by SDCC runs in s51 against the plant
# (scenarios/pil_bench.scn, 60 s, with pil_bench.input's keys and serial commands) and must drive
# the valve and the boom valve exactly as the host build does on the same scenario and seed,
# tick for tick; its serial output and its metrics JSON must be the same too.
set -uo pipefail
cd "$(dirname "$0")/../.."
B=${BUILD:-build}
SIM=$B/host/bin/sim
IHX=$B/pil/sprayer_pil.ihx
SCN=scenarios/pil_bench.scn
IN=scenarios/pil_bench.input
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
ok() { echo "ok - pil: $1"; }
nok() { echo "not ok - pil: $1"; [ -n "${2:-}" ] && echo "$2" | head -5 | sed 's/^/#   /'; }

if ! make -s --no-print-directory "$SIM" "$IHX" BUILD="$B" > "$tmp/build.log" 2>&1; then
    nok "the simulator and the s51 image build" "$(cat "$tmp/build.log")"
    exit 0
fi
ok "the simulator and the s51 image (hal/pil) build"

"$SIM" --scenario $SCN --input $IN --drive-log "$tmp/host.drive" --serial "$tmp/host.serial" > "$tmp/host.out" 2>&1
"$SIM" --pil "$IHX" --scenario $SCN --input $IN --drive-log "$tmp/pil.drive" --serial "$tmp/pil.serial" \
    > "$tmp/pil.out" 2>&1; rc=$?
if [ $rc -ne 0 ] || ! tail -n 1 "$tmp/pil.out" | grep -q '"sim_s":60'; then
    nok "a 60 s run in s51 completes" "$(tail -5 "$tmp/pil.out")"
    exit 0
fi
ok "a 60 s run of the whole firmware in s51 completes"
grep '^pil:' "$tmp/pil.out" | sed 's/^/# /'

n=$(wc -l < "$tmp/host.drive")
if [ "$n" -gt 100 ] && cmp -s "$tmp/host.drive" "$tmp/pil.drive"; then
    ok "the valve drive sequence in s51 is the host build's, tick for tick ($n changes)"
else
    nok "the valve drive sequence in s51 is the host build's" "$(diff "$tmp/host.drive" "$tmp/pil.drive" | head -5)"
fi
if [ -s "$tmp/host.serial" ] && grep -q '^OK 0 140' "$tmp/host.serial" && cmp -s "$tmp/host.serial" "$tmp/pil.serial"; then
    ok "the serial link says the same, replies to the commands and keys included ($(wc -l < "$tmp/host.serial") lines)"
else
    nok "the serial link says the same" "$(diff "$tmp/host.serial" "$tmp/pil.serial" | head -5)"
fi
strip() { tail -n 1 "$1" | sed 's/,"wall_s".*//'; }
if [ "$(strip "$tmp/host.out")" = "$(strip "$tmp/pil.out")" ]; then
    ok "make pil's metrics JSON is make sim's"
else
    nok "make pil's metrics JSON is make sim's" "$(diff <(strip "$tmp/host.out" | tr , '\n') <(strip "$tmp/pil.out" | tr , '\n') | head -6)"
fi

#!/usr/bin/env bash
# hil.sh: hardware in the loop with the host build standing in for the board (make hil-host): the
# figures equal the simulator's on the same scenario, and frames dropped or damaged on purpose are
# counted by both ends and reported, the run failing (exit 3).
set -uo pipefail
cd "$(dirname "$0")/../.."
B=${BUILD:-build}
out=$B/test-logs/hil
SCN=tests/scripts/data/short_dynamic_150.scn
mkdir -p "$out"
ok() { echo "ok - hil: $1"; }
nok() { echo "not ok - hil: $1"; }
make -s --no-print-directory -j2 $B/host/bin/sim $B/host/bin/hil $B/host/bin/hilboard > "$out/build.log" 2>&1 \
    || { nok "build: $(tail -3 "$out/build.log")"; exit 0; }

$B/host/bin/sim --scenario $SCN > "$out/sim.out"
tail -1 "$out/sim.out" > "$out/sim.json"
timeout 300 make -s --no-print-directory hil-host SCENARIO=$SCN BUILD=$B > "$out/hil.out" 2> "$out/hil.err"
rc=$?
tail -1 "$out/hil.out" > "$out/hil.json"
# stated rounding: none; the board's step sees the very inputs of the simulator's, at the same instant
.venv/bin/python - "$out/sim.json" "$out/hil.json" > "$out/compare.out" <<'PYEOF'
import json, sys
sim, hil = (json.load(open(p)) for p in sys.argv[1:3])
skip = {"wall_s", "cpu_s", "speed_x_realtime", "hil_frames", "hil_answered", "hil_lost", "hil_lost_controller"}
bad = [k for k in sim if k not in skip and sim[k] != hil.get(k)]
n = sum(1 for k in sim if k not in skip)
print("%d figures, %d differ: %s" % (n, len(bad), ", ".join("%s %s vs %s" % (k, sim[k], hil.get(k)) for k in bad[:4])))
sys.exit(1 if bad or hil.get("hil_lost") != 0 or hil.get("hil_frames") != 700 else 0)
PYEOF
crc=$?
if [ $rc -eq 0 ] && [ $crc -eq 0 ]; then
    ok "make hil-host on $SCN equals make sim ($(cat "$out/compare.out" | cut -d: -f1), 700 frames, none lost)"
else
    nok "hil-host rc $rc: $(cat "$out/compare.out") $(tail -2 "$out/hil.err")"
fi

# frames lost on purpose: every 50th not sent (14), every 77th sent damaged (9)
timeout 300 tools/hil_host.sh $B/host/bin $SCN --drop-every 50 --corrupt-every 77 --timeout 0.3 \
    > "$out/drop.out" 2> "$out/drop.err"
rc=$?
tail -1 "$out/drop.out" > "$out/drop.json"
lost=$(.venv/bin/python -c "import json,sys; d=json.load(open(sys.argv[1])); print(d['hil_lost'], d['hil_lost_controller'])" "$out/drop.json" 2>/dev/null)
# the controller counts a gap at the next frame that comes: the last frame (700, dropped) has none
if [ $rc -eq 3 ] && [ "$lost" = "23 22" ] && grep -q "FRAMES LOST" "$out/drop.out" \
   && grep -q "14 not sent, 9 sent damaged" "$out/drop.out"; then
    ok "23 frames lost on purpose (14 not sent, 9 damaged): the PC counts 23, the controller 22, the run says FRAMES LOST and exits 3"
else
    nok "dropped frames: rc $rc, lost '$lost': $(head -2 "$out/drop.out")"
fi

# a port that is not there: one line, exit 1
if ! $B/host/bin/hil --scenario $SCN --port /dev/ttyNOSUCH0 > /dev/null 2> "$out/noport.err" \
   && grep -q "no such port" "$out/noport.err" && [ "$(wc -l < "$out/noport.err")" -eq 1 ]; then
    ok "a missing port: '$(cat "$out/noport.err")'"
else
    nok "a missing port: $(cat "$out/noport.err")"
fi

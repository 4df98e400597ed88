#!/usr/bin/env bash
# serial_log.sh: the PC logger (tools/serial_log.py) against lines with good and bad checksums,
# over pyserial's loopback port, and against the firmware's own output in the simulator.
set -uo pipefail
cd "$(dirname "$0")/../.."
B=${BUILD:-build}
PY=.venv/bin/python
out=$B/test-logs/serial_log
mkdir -p "$out"
ok() { echo "ok - serial_log: $1"; }
nok() { echo "not ok - serial_log: $1"; }

# checksums worked out by hand: "OK ACK" = 0x4F^0x4B^0x20^0x41^0x43^0x4B = 0x6D; the second LOG
# differs from the first by '2'^'1' = 0x03, so 0x4C^0x03 = 0x4F is right and 0x4E (sent) is wrong
cat > "$out/lines.txt" <<'L'
LOG 1000 700 250 3150 3148 0000*4C
OK ACK*6D
LOG 2000 700 250 3150 3148 0000*4E
ALM TANK_LOW Tank low*00
L
$PY tools/serial_log.py --replay "$out/lines.txt" --csv "$out/lines.csv" > "$out/lines.out"; rc=$?
rows=$(($(wc -l < "$out/lines.csv") - 1))
if [ $rc -eq 2 ] && [ "$rows" -eq 1 ] && grep -q "1 log rows, 2 lines dropped" "$out/lines.out"; then
    ok "a line with a wrong checksum is dropped, never logged (1 row kept, 2 dropped)"
else
    nok "checksum check: rc $rc, $rows rows: $(tail -1 "$out/lines.out")"
fi
if grep -q "^1.0,7.0,0.25,31.5,31.48,0000" "$out/lines.csv"; then
    ok "LOG fields scaled to s, km/h, MPa, L/min"
else
    nok "LOG scaling: $(sed -n 2p "$out/lines.csv")"
fi
if grep -q "^OK ACK" "$out/lines.out"; then ok "replies are shown"; else nok "replies are shown"; fi

# loopback: what --send writes comes back and must carry a valid checksum
$PY tools/serial_log.py --port loop:// --send ACK > "$out/loop.out" 2>&1
if grep -q "dropped (unknown line ACK)" "$out/loop.out"; then
    ok "--send frames a command with its checksum (read back over loop://)"
else
    nok "--send over loop://: $(cat "$out/loop.out")"
fi

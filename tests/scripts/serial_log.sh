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

# the CRC-8 of each body worked out a second way, as the remainder of the body's bits times x^8
# divided by x^8+x^6+x^5+x^2+1 (long division, not the tool's shift register): the first LOG
# 0x95, OK ACK 0xA9, the second LOG 0x10 (sent: 0x95, its first line's, wrong), the ALM 0x28
# (sent: 0x00, wrong); the second LOG also carries the XOR of its bytes, 0x4F, as before
cat > "$out/lines.txt" <<'L'
LOG 1000 700 250 3150 3148 0000*95
OK ACK*A9
LOG 2000 700 250 3150 3148 0000*95
ALM TANK_LOW Tank low*00
LOG 2000 700 250 3150 3148 0000*4F
L
$PY tools/serial_log.py --replay "$out/lines.txt" --csv "$out/lines.csv" > "$out/lines.out"; rc=$?
rows=$(($(wc -l < "$out/lines.csv") - 1))
if [ $rc -eq 2 ] && [ "$rows" -eq 1 ] && grep -q "1 log rows, 3 lines dropped" "$out/lines.out"; then
    ok "a line with a wrong checksum is dropped, never logged (1 row kept, 3 dropped, the XOR's too)"
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

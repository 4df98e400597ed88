#!/usr/bin/env bash
# pgn_bridge.sh: tools/rc_bridge.py makes the simulated board (sim --pty) one of RateControl's
# modules: a UDP client on the loopback address sends PGN 32500 frames built byte for byte as
# RateControl's PGN32500.Send builds them (to the module port 28888, here 28988) for 120 L/ha
# over the boom at 7 km/h; the board's 32400 frames come back to the app's port (29999, here
# 30099) and their applied rate reaches the frames' target. A damaged datagram is refused.
source "$(dirname "$0")/tap.sh" pgn_bridge
out=$B/test-logs/pgn_bridge
SCN=tests/scripts/data/rc_bridge_150.scn
mkdir -p "$out"
rm -rf "${out:?}"/*
make -s --no-print-directory -j2 $B/host/bin/sim > "$out/build.log" 2>&1 || { nok "build: $(tail -3 "$out/build.log")"; exit 0; }

# the board at 4 x real time: 60 s of the run in 15 s (the bridge stops after 11 s)
$B/host/bin/sim --scenario $SCN --pty --pace 4 --wait 20 > "$out/sim.out" 2> "$out/sim.err" &
sim=$!
for _ in $(seq 100); do grep -q "serial link on" "$out/sim.err" && break; sleep 0.1; done
port=$(sed -n 's/.*serial link on \([^ ]*\).*/\1/p' "$out/sim.err")
$PY tools/rc_bridge.py --port "$port" --listen 127.0.0.1:28988 --app 127.0.0.1:30099 --seconds 11 \
    > "$out/bridge.out" 2> "$out/bridge.err" &
bridge=$!
$PY - "$out" <<'PY' > "$out/client.out" 2>&1
import socket, sys, time
out = sys.argv[1]

def crc(d):                       # RateControl's Tls.CRC: the low byte of the sum from byte 0
    return sum(d) & 0xFF

def pgn32500(module, sensor, upm, meter_cal, command, manual_pwm=0):
    # PGN32500.Send: 244 126, Mod/Sen ID, rate set x1000 (3 bytes LE), flow cal x1000 (3 bytes),
    # command, manual PWM (2 bytes), -, CRC
    d = bytearray(14)
    d[0], d[1] = 244, 126
    d[2] = (module << 4) | (sensor & 0x0F)
    rs = int(upm * 1000.0)
    d[3], d[4], d[5] = rs & 0xFF, (rs >> 8) & 0xFF, (rs >> 16) & 0xFF
    mc = int(meter_cal * 1000.0)
    d[6], d[7], d[8] = mc & 0xFF, (mc >> 8) & 0xFF, (mc >> 16) & 0xFF
    d[9] = command
    d[10], d[11] = manual_pwm & 0xFF, (manual_pwm >> 8) & 0xFF
    d[13] = crc(d[:13])
    return bytes(d)

app = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
app.bind(("127.0.0.1", 30099))
app.settimeout(0.05)
upm = 120 * 7 * 18 / 600.0                  # 120 L/ha x 7 km/h x 18 m / 600 = 25.2 L/min
frame = pgn32500(0, 0, upm, 380.0, 16 | 64)  # MasterOnMode, AutoOn
bad = bytearray(frame); bad[4] ^= 0x01       # one bit of the rate
applied, seen, t0 = [], 0, time.monotonic()
while time.monotonic() - t0 < 10.0:
    app.sendto(frame if seen != 5 else bytes(bad), ("127.0.0.1", 28988))
    seen += 1
    end = time.monotonic() + 0.05
    while time.monotonic() < end:
        try:
            r, _ = app.recvfrom(64)
        except socket.timeout:
            continue
        if len(r) == 15 and r[0] == 144 and r[1] == 126 and crc(r[:14]) == r[14]:
            applied.append((time.monotonic() - t0, (r[3] | r[4] << 8 | r[5] << 16) / 1000.0, r[2], r[11]))
print("sent", seen, "frames; 32400 received:", len(applied))
for a in applied[-5:]:
    print("t %.1f s applied %.3f UPM module/sensor %d status %d" % a)
last = [a[1] for a in applied if a[0] > 8.0]
ok = len(applied) > 20 and last and all(abs(x - upm) <= 0.05 * upm for x in last) \
    and all(a[2] == 0 and a[3] & 1 for a in applied)
print("RESULT", "ok" if ok else "bad", "%.3f" % (sum(last) / len(last) if last else 0), "%.3f" % upm)
PY
wait $bridge
brc=$?
kill $sim 2>/dev/null; wait $sim 2>/dev/null
res=$(grep RESULT "$out/client.out")
if [ $brc -eq 0 ] && [ "${res#RESULT ok}" != "$res" ]; then
    read -r _ _ got want <<< "$res"
    ok "RateControl-shaped 32500 frames set the rate through the bridge; the board's 32400 came back to the app's port with the applied rate ($got UPM for $want, within 5 %)"
else
    nok "bridge rc $brc, client: $(tail -3 "$out/client.out"), bridge: $(tail -1 "$out/bridge.err"), sim: $(tail -1 "$out/sim.err")"
fi
if grep -q "[1-9][0-9]* datagrams refused" "$out/bridge.err"; then
    ok "a damaged datagram (one bit of the rate) refused at the bridge: $(tail -1 "$out/bridge.err")"
else
    nok "no datagram refused: $(tail -1 "$out/bridge.err")"
fi

#!/usr/bin/env bash
# pil_frames.sh: the serial link flooded with PGN frames, processor in the loop: AgOpenGPS's 254
# (7.0 km/h) and 239 back to back for 9 s, a GET line among every ten frames
# (tests/scripts/data/frame_flood.scn) into the whole firmware in s51: every control step still
# runs within its period and the watchdog is kicked after each (one frame a pass, as one line a
# pass); every GET is answered; the speed used is the frames'; they are never lost.
source "$(dirname "$0")/tap.sh" pil_frames
IHX=$B/pil/sprayer_pil.ihx
SCN=tests/scripts/data/frame_flood.scn

if ! make -s --no-print-directory "$SIM" "$IHX" BUILD="$B" > "$tmp/build.log" 2>&1; then
    nok "the simulator and the s51 image build" "$(cat "$tmp/build.log")"
    exit 0
fi
# a 14-byte frame at 38400 baud takes 3.65 ms: one every 3.65 ms keeps the wire busy
$PY - > "$tmp/flood.input" <<'P'
def aog(pgn, data):
    f = [0x80, 0x81, 0x7F, pgn, len(data)] + data
    return f + [sum(f[2:]) & 0xFF]
t, k, gets = 3.0, 0, 0
while t < 11.5:
    f = aog(254, [70, 0, 1, 0, 0, 0x7D, 0x3F, 0]) if k % 2 == 0 else aog(239, [0, 70, 0, 0, 0, 0, 0x3F, 0])
    print("%.5f frame %s" % (t, " ".join("%02X" % b for b in f)))
    t += 0.00365
    k += 1
    if k % 10 == 0:
        print("%.5f serial GET 0" % t)
        t += 0.0021
        gets += 1
P
gets=$(grep -c " serial GET 0" "$tmp/flood.input")
frames=$(grep -c " frame " "$tmp/flood.input")
"$SIM" --pil "$IHX" --scenario $SCN --input "$tmp/flood.input" --serial "$tmp/pil.serial" > "$tmp/pil.out" 2>&1; rc=$?
if [ $rc -ne 0 ] || ! tail -n 1 "$tmp/pil.out" | grep -q '"sim_s":12'; then
    nok "a 12 s run flooded with frames in s51 completes" "$(tail -5 "$tmp/pil.out")"
    exit 0
fi
grep '^pil:' "$tmp/pil.out" | sed 's/^/# /'
read -r n g k h < <(sed -n 's/^pil: \([0-9]*\) control steps, the longest time between two \([0-9]*\) ms.*; \([0-9]*\) watchdog kicks, the longest time between two \([0-9]*\) ms.*/\1 \2 \3 \4/p' "$tmp/pil.out")
# the bound as pil_flood.sh's: twice the 5 ms a step may wait for the modules' constants
if [ "${n:-0}" -ge 119 ] && [ "${g:-999}" -le 110 ] && [ "${k:-0}" -ge 119 ] && [ "${h:-999}" -le 110 ]; then
    ok "every control step within its period and the watchdog kicked under $frames frames ($n steps, the longest gap $g ms; $k kicks, $h ms)"
else
    nok "every step within its period under the frames" "$n steps, longest gap $g ms; $k kicks, longest $h ms"
fi
oks=$(grep -a -c 'OK 0 1500\*' "$tmp/pil.serial")
if [ "$oks" -eq "$gets" ]; then
    ok "every GET among the frames answered ($oks of $gets)"
else
    nok "every GET among the frames answered" "$oks of $gets"
fi
# the LOG lines after 4 s: the speed the frames carry (7.0 km/h: 700), no alarm but MIN_FLOW's
# start (none: SPEED_LOST would say the frames were lost)
bad=$(grep -a -o 'LOG [0-9]* [0-9]* [0-9]* [0-9-]* [0-9-]* [0-9A-F]*' "$tmp/pil.serial" | awk '$2 >= 4000 && ($3 != 700 || $7 != "0000")' | head -3)
if [ -z "$bad" ] && grep -a -q 'LOG 1[01][0-9]* 700 ' "$tmp/pil.serial"; then
    ok "the speed used is the frames' 7.0 km/h throughout, no alarm (no frame lost for Frames lost)"
else
    nok "the frames' speed, no alarm" "$bad"
fi

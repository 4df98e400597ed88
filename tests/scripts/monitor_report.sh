#!/usr/bin/env bash
# monitor_report.sh: the live monitor records a simulated run through a pseudo-terminal (sim --pty),
# tools/report.py scores the recording with the simulator's metrics and must agree with the
# simulator's own JSON within the rounding below; the monitor and the report refuse bad input
# with one line and no traceback.
set -uo pipefail
cd "$(dirname "$0")/../.."
B=${BUILD:-build}
PY=.venv/bin/python
out=$B/test-logs/monitor_report
SCN=tests/scripts/data/short_dynamic_150.scn
mkdir -p "$out"
rm -rf "${out:?}"/*
ok() { echo "ok - monitor_report: $1"; }
nok() { echo "not ok - monitor_report: $1"; }
make -s --no-print-directory -j2 $B/host/bin/sim $B/host/bin/score > "$out/build.log" 2>&1 || { nok "build: $(tail -3 "$out/build.log")"; exit 0; }

# the simulated board on a pseudo-terminal, as fast as the monitor reads
$B/host/bin/sim --scenario $SCN --pty --pace 0 --wait 20 > "$out/sim.out" 2> "$out/sim.err" &
sim=$!
for _ in $(seq 100); do grep -q "serial link on" "$out/sim.err" && break; sleep 0.1; done
port=$(sed -n 's/.*serial link on \([^ ]*\).*/\1/p' "$out/sim.err")
timeout 120 $PY tools/monitor.py --port "$port" --csv "$out/run.csv" --no-plot > "$out/monitor.out" 2>&1
mrc=$?
wait $sim
src=$?
rows=$(($(wc -l < "$out/run.csv" 2>/dev/null || echo 1) - 1))
if [ $mrc -eq 0 ] && [ $src -eq 0 ] && [ "$rows" -eq 700 ]; then
    ok "the monitor recorded the whole simulated run through $port (700 rows of 0.1 s)"
else
    nok "recording: monitor rc $mrc, sim rc $src, $rows rows: $(tail -2 "$out/monitor.out")"
fi
tail -1 "$out/sim.out" > "$out/sim.json"

$PY tools/report.py "$out/run.csv" --out "$out/report" --rate 150 > "$out/report.out" 2> "$out/report.err"
rrc=$?
if [ $rrc -eq 0 ] && [ -s "$out/report/flow.png" ] && [ -s "$out/report/zones.png" ] && [ -s "$out/report/metrics.json" ]; then
    ok "report.py wrote the metrics, the flow plot (Figs. 8-9) and the zone plot (Table 4)"
else
    nok "report.py rc $rrc: $(cat "$out/report.err")"
fi

# the stated rounding: what 0.1 s rows of printed values change against the simulator's 1 ms
$PY - "$out/sim.json" "$out/report/metrics.json" > "$out/compare.out" <<'PYEOF'
import json, sys
sim = json.load(open(sys.argv[1]))
rep = json.load(open(sys.argv[2]))
TOL = {"applied_l_ha": 0.05, "dose_error_pct": 0.01, "dose_error_all_pct": 0.01, "cv_pct": 0.02,
       "cv_all_pct": 0.05, "zone_error_min_pct": 0.1, "zone_error_max_pct": 0.1, "volume_l": 0.01,
       "area_ha": 0.0005, "overshoot_mean_pct": 0.01, "overshoot_max_pct": 0.01, "settle_mean_s": 0.01,
       "settle_max_s": 0.01, "start_s": 0.001, "pressure_min_bar": 0.1, "pressure_max_bar": 0.1}
bad = []
for k, tol in TOL.items():
    a, b = sim.get(k), rep.get(k)
    if a is None or b is None or abs(a - b) > tol:
        bad.append("%s %s vs %s (tolerance %g)" % (k, a, b, tol))
    print("%-20s sim %12.6g  report %12.6g" % (k, a if a is not None else float("nan"), b if b is not None else float("nan")))
if sim["zones"] != rep["zones"] or sim["steps_scored"] != rep["steps_scored"] or sim["steps_scored"] < 2:
    bad.append("zones %s/%s, steps %s/%s" % (sim["zones"], rep["zones"], sim["steps_scored"], rep["steps_scored"]))
for s, r in zip(sim["steps"], rep["steps"]):
    for k in ("t_s", "rise_s", "overshoot_pct", "settle_5pct_s", "settle_2pct_s", "sse_pct"):
        if (s[k] is None) != (r[k] is None) or (s[k] is not None and abs(s[k] - r[k]) > 0.01):
            bad.append("step at %s: %s %s vs %s" % (s["t_s"], k, s[k], r[k]))
if [a["code"] for a in sim["alarms"]] != [a["code"] for a in rep["alarms"]]:
    bad.append("alarms %s vs %s" % (sim["alarms"], rep["alarms"]))
print("; ".join(bad) if bad else "all within the stated rounding")
sys.exit(1 if bad else 0)
PYEOF
if [ $? -eq 0 ]; then
    ok "report.py on the recording gives the simulator's metrics within the stated rounding ($(grep -c '^' "$out/compare.out") figures)"
else
    nok "report vs sim: $(tail -1 "$out/compare.out")"
fi

# a real board's log (LOG lines, once a second, the firmware's measured values) is scored too
$B/host/bin/sim --scenario $SCN --serial "$out/link.txt" > /dev/null
$PY tools/monitor.py --replay "$out/link.txt" --csv "$out/log.csv" --no-plot > /dev/null 2>&1
if $PY tools/report.py "$out/log.csv" --no-plots --out "$out/report_log" 2>&1 | grep -q '"score_source": "measured"'; then
    ok "a board's once-a-second log is scored on its measured values, and says so"
else
    nok "the log's report: $(tail -1 "$out/report_log/metrics.json" 2>/dev/null)"
fi

# the live plot's code on a display-less backend (the window itself needs a screen)
DISPLAY=${DISPLAY:-:99} MPLBACKEND=Agg $PY tools/monitor.py --replay "$out/link.txt" > "$out/plot.out" 2>&1
if [ $? -eq 0 ] && grep -q "monitor: 69 rows" "$out/plot.out" && ! grep -q -e Traceback -e "plot off" "$out/plot.out"; then
    ok "the live plot draws speed, target and actual flow, pressure and valve drive from the rows"
else
    nok "live plot: $(tail -3 "$out/plot.out")"
fi

# bad input: one line on stderr, exit status 1, no traceback
one_line() {  # one_line NAME EXPECTED-TEXT COMMAND...
    local name=$1 want=$2; shift 2
    "$@" > "$out/err.out" 2> "$out/err.txt"
    local rc=$?
    if [ $rc -eq 1 ] && grep -q "$want" "$out/err.txt" && ! grep -q Traceback "$out/err.txt" "$out/err.out"; then
        ok "$name: '$(grep "$want" "$out/err.txt")'"
    else
        nok "$name: rc $rc, $(cat "$out/err.txt" "$out/err.out" | head -3)"
    fi
}
one_line "a missing port" "no such port" $PY tools/monitor.py --port /dev/ttyNOSUCH0 --no-plot
one_line "a missing replay file" "cannot read" $PY tools/monitor.py --replay /nonexistent --no-plot
one_line "a replay file without controller lines" "holds no controller log lines" $PY tools/monitor.py --replay README.md --no-plot
one_line "serial_log.py: a missing replay file" "cannot read" $PY tools/serial_log.py --replay /nonexistent
one_line "serial_log.py: a missing port" "no such port" $PY tools/serial_log.py --port /dev/ttyNOSUCH0
one_line "report.py: a missing file" "cannot read" $PY tools/report.py /nonexistent
one_line "report.py: not a recording" "not a recorded run" $PY tools/report.py README.md --out "$out/bad"
# a busy port: another program holds the pseudo-terminal open exclusively
$PY - > "$out/holder.txt" <<'PYEOF' &
import os, pty, time, serial
m, s = pty.openpty()
p = serial.Serial(os.ttyname(s), exclusive=True)
print(os.ttyname(s), flush=True)
time.sleep(5)
PYEOF
holder=$!
for _ in $(seq 50); do [ -s "$out/holder.txt" ] && break; sleep 0.1; done
one_line "a busy port" "is busy" $PY tools/monitor.py --port "$(cat "$out/holder.txt")" --no-plot
kill $holder 2>/dev/null; wait $holder 2>/dev/null
exit 0

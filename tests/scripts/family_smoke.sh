#!/usr/bin/env bash
# family_smoke.sh: tools/family.py (and tools/research/redraw.py) on a few plants: the same seed gives the same table, every run scored, the files written.
. "$(dirname "$0")/tap.sh" family

make -s --no-print-directory "$SIM" BUILD="$B" > "$tmp/build.log" 2>&1 || { nok "the simulator builds" "$(cat "$tmp/build.log")"; exit 0; }
if $PY tools/family.py "$SIM" --n 6 --controllers ffmap,pid --out "$tmp/a" > "$tmp/a.out" 2>&1 \
   && $PY tools/family.py "$SIM" --n 6 --controllers ffmap,pid --out "$tmp/b" > "$tmp/b.out" 2>&1; then
    ok "6 plants x 2 controllers run"
else
    nok "6 plants x 2 controllers run" "$(tail -3 "$tmp/a.out" "$tmp/b.out")"; exit 0
fi
cmp -s "$tmp/a/summary.json" "$tmp/b/summary.json" && cmp -s "$tmp/a/runs.csv" "$tmp/b/runs.csv" \
    && ok "the same seed gives the same table and runs" || nok "the same seed gives the same table and runs"
n=$(($(wc -l < "$tmp/a/runs.csv") - 1))
[ "$n" -eq 24 ] && ok "runs.csv has every run, each plant told and untold (24)" || nok "runs.csv has every run ($n of 24)"
# told and untold: the same sprayer, the firmware's stroke time the only difference
d=$(diff "$tmp/a/scn/plant_003_told.scn" "$tmp/a/scn/plant_003_untold.scn" | grep '^[<>]' | grep -v '^[<>] # plant')
if [ "$(echo "$d" | grep -c '^< valve_travel_s = ')" -eq 1 ] && [ "$(echo "$d" | wc -l)" -eq 1 ] \
   && [ "$(awk -F, 'NR > 1 && $2 == "ffmap" { c[$4]++ } END { print c[0] "/" c[1] }' "$tmp/a/runs.csv")" = "6/6" ]; then
    ok "each plant runs told and untold, the scenarios differing only in the told stroke time"
else
    nok "each plant runs told and untold, the scenarios differing only in the told stroke time" "$d"
fi
if $PY tools/family.py "$SIM" --n 6 --controllers ffmap --told drawn --out "$tmp/d" > "$tmp/d.out" 2>&1 \
   && [ "$(($(wc -l < "$tmp/d/runs.csv") - 1))" -eq 6 ] && [ -f "$tmp/d/scn/plant_005.scn" ]; then
    ok "--told drawn runs each plant once, told by its draw"
else
    nok "--told drawn runs each plant once, told by its draw" "$(tail -3 "$tmp/d.out")"
fi
if $PY - "$tmp/a/summary.json" <<'PYEOF'
import json, sys
s = json.load(open(sys.argv[1]))
assert s["told"] == "both" and s["controllers"]["ffmap"]["cv_untold_over_told"] > 0
for c in ("ffmap", "pid"):
    for k in ("dose_abs_pct", "dose_ctl_abs_pct", "cv_pct", "zone_worst_pct", "reversals_per_min", "settle_mean_s"):
        assert s["controllers"][c][k]["median"] is not None, (c, k)
        assert s["controllers"][c][k]["p95"] >= s["controllers"][c][k]["median"], (c, k)
    assert isinstance(s["controllers"][c]["alarm_runs"], int)
PYEOF
then ok "summary.json has the median and 95th percentile of every figure"; else nok "summary.json has the median and 95th percentile of every figure"; fi
# told or not and the hunt: the summary's max and counts over the bounds are runs.csv's, counted here
if $PY - "$tmp/a/summary.json" "$tmp/a/runs.csv" <<'PYEOF'
import csv, json, sys
s = json.load(open(sys.argv[1]))
rows = list(csv.DictReader(open(sys.argv[2])))
for c in ("ffmap", "pid"):
    for col, bound in (("silent_wrong_s", 10.0), ("ripple_p95_pct", 5.0)):
        j = s["controllers"][c][col]
        v = [float(r[col]) for r in rows if r["controller"] == c and r[col] != ""]
        assert len(v) == j["runs"] and j["runs"] > 0, (c, col)
        assert j["max"] == max(v) and j["over"] == sum(1 for x in v if x > bound), (c, col, j)
        assert j["median"] <= j["p95"] <= j["max"], (c, col, j)
        n = j["worst_plant"].split("/")
        assert n[0] == "1" and any(int(r["plant"]) == int(n[1]) and float(r[col]) == j["max"] for r in rows)
PYEOF
then ok "summary.json has silent_wrong_s and ripple_p95_pct: median, p95, max, its plant, runs over 10 s / 5 %"
else nok "summary.json has silent_wrong_s and ripple_p95_pct: median, p95, max, its plant, runs over 10 s / 5 %"; fi
grep -q "plant family: 6 plants" "$tmp/a.out" && ok "the table is printed" || nok "the table is printed" "$(cat "$tmp/a.out")"
# the loop's share in the start (the simulator's) is a part of it: in most runs neither none nor all
if $PY - "$tmp/a/runs.csv" <<'PYEOF'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
part = sum(1 for r in rows if float(r["dose_ctl_start_pct"]) != 0
           and abs(abs(float(r["dose_ctl_start_pct"])) - float(r["dose_ctl_abs_pct"])) > 1e-4)
assert part > len(rows) // 2, (part, len(rows))
PYEOF
then ok "runs.csv splits the loop's share into the start's and the rest"; else nok "runs.csv splits the loop's share into the start's and the rest"; fi
if $PY tools/research/ctl_tail.py "$tmp/a" "$tmp/b" > "$tmp/t.out" 2>&1 \
   && grep -Eq "^ffmap: 24 runs; 95th percentile of abs\(dose_ctl_pct\) [0-9.]+ %, past the start [0-9.]+ %$" "$tmp/t.out" \
   && grep -Eq "^the start over half of the run's share: [0-9]+ of 2 " "$tmp/t.out"; then
    ok "ctl_tail sorts the runs above the 95th percentile of the loop's share by their start"
else
    nok "ctl_tail sorts the runs above the 95th percentile of the loop's share by their start" "$(cat "$tmp/t.out")"
fi
$PY tools/research/ctl_tail.py "$tmp/nonexistent" > /dev/null 2> "$tmp/err" && nok "ctl_tail refuses a directory without runs.csv" \
    || { grep -q "^ctl_tail: .*runs.csv: No such file" "$tmp/err" && ok "ctl_tail refuses a directory without runs.csv in one line" \
         || nok "ctl_tail refuses a directory without runs.csv in one line" "$(cat "$tmp/err")"; }
$PY tools/family.py /nonexistent --n 1 > /dev/null 2> "$tmp/err" && nok "a missing simulator is refused" \
    || { grep -q "not an executable" "$tmp/err" && ok "a missing simulator is refused in one line" || nok "a missing simulator is refused in one line" "$(cat "$tmp/err")"; }
# redraw.py: a plant of the family again with more noise draws, the scenario the family wrote
if $PY tools/research/redraw.py "$SIM" 1/3/told 1/3/untold --draws 2 --out "$tmp/r" > "$tmp/r.out" 2>&1 \
   && diff -q "$tmp/a/scn/plant_003_told.scn" "$tmp/r/scn/seed1_plant_003_told.scn" > /dev/null \
   && diff -q "$tmp/a/scn/plant_003_untold.scn" "$tmp/r/scn/seed1_plant_003_untold.scn" > /dev/null \
   && grep -Eq "^1/3/told +[0-9]+ of 2 +median CV [0-9.]+ %" "$tmp/r.out" && grep -q "^alarm runs: [0-9]* of 4$" "$tmp/r.out"; then
    ok "redraw runs a family plant (the same scenario) with more noise draws and counts the alarm runs"
else
    nok "redraw runs a family plant (the same scenario) with more noise draws and counts the alarm runs" "$(tail -3 "$tmp/r.out")"
fi
$PY tools/research/redraw.py "$SIM" 28/35 > /dev/null 2> "$tmp/err" && nok "redraw refuses a plant without told/untold" \
    || { grep -q "a plant is SEED/NUMBER/told" "$tmp/err" && ok "redraw refuses a bad plant name in one line" || nok "redraw refuses a bad plant name in one line" "$(cat "$tmp/err")"; }
$PY tools/research/redraw.py "$SIM" --select fast-high --seeds 1-1 > "$tmp/r1.out" 2> "$tmp/err" && nok "redraw refuses a class with no plant" \
    || { grep -q "no plant of seeds 1-1 is fast-high" "$tmp/err" && ! grep -q "alarm runs" "$tmp/r1.out" \
         && ok "redraw refuses a class with no plant, rather than run the default plants" \
         || nok "redraw refuses a class with no plant, rather than run the default plants" "$(cat "$tmp/err")"; }
if $PY - <<'PYEOF'
import sys
sys.path[:0] = ["tools", "tools/research"]
import family, redraw
sel = redraw.select("fast-high", 1, 2)
assert sel and all(n.split("/")[2] in ("told", "untold") for n in sel)
for n in sel:
    s, i, _ = n.split("/")
    d = family.draw(int(s), int(i), "both")
    vmax = max(v for _, v in d["drive"])
    assert d["plant"]["valve_travel_s"] < 3.0
    assert family.nozzle_bar(d["rate"], vmax, d["plant"]["nozzle_wear_pct"], d["plant"]["check_valve_bar"]) >= 4.0
st = redraw.select("fast-stiff", 1, 1)
assert st and all(family.draw(1, int(n.split("/")[1]), "both")["plant"]["valve_stiction_duty"] >= 0.25 for n in st)
assert "36/28/told" in redraw.select("fast-stiff", 36, 36)    # breaks away at 0.281 and crept
PYEOF
then ok "redraw --select picks the fast valves near P max, and the fast stiff ones"; else nok "redraw --select picks the fast valves near P max, and the fast stiff ones"; fi
# an alarm's cause, by hand: a drive 0 -> 8 km/h over 0-10 s, held to 100 s, stopping by 110 s
# (under 4 km/h from 105 s); nozzles worn 10.5 % or 9.9 %
if $PY - <<'PYEOF'
import sys
sys.path.insert(0, "tools")
import family
d = {"drive": [(0, 0), (10, 8), (100, 8), (110, 0)], "plant": {"nozzle_wear_pct": 10.5}}
assert family.drive_kmh(d["drive"], 5) == 4 and family.drive_kmh(d["drive"], 105) == 4
def a(*cs):
    return [{"code": c, "t_s": t} for c, t in cs]
assert family.uncaused(d, a(("NOZZLE_WEAR", 50), ("MIN_FLOW", 8.9), ("MIN_FLOW", 106)), False) == []
assert family.uncaused(d, a(("MIN_FLOW", 9.1)), False) == ["MIN_FLOW"]     # 4 km/h at 5 s: 4.1 s before
assert family.uncaused(d, a(("MIN_FLOW", 50), ("OFF_RATE", 60)), False) == ["MIN_FLOW", "OFF_RATE"]
assert family.uncaused(d, a(("OFF_RATE", 60)), True) == []                 # an operator's change
d["plant"]["nozzle_wear_pct"] = 9.9
assert family.uncaused(d, a(("NOZZLE_WEAR", 50), ("LEAK", 70)), True) == ["LEAK", "NOZZLE_WEAR"]
PYEOF
then ok "an alarm's cause: worn nozzles over 10 %, the drive under 4 km/h within 4 s; any other without"
else nok "an alarm's cause: worn nozzles over 10 %, the drive under 4 km/h within 4 s; any other without"; fi
if $PY - "$tmp/a/summary.json" "$tmp/a/runs.csv" <<'PYEOF'
import csv, json, sys
s = json.load(open(sys.argv[1]))
rows = list(csv.DictReader(open(sys.argv[2])))
for c in ("ffmap", "pid"):
    assert s["controllers"][c]["uncaused_runs"] == sum(1 for r in rows if r["controller"] == c and r["uncaused"])
    assert all(set(r["uncaused"].split()) <= set(r["alarms"].split()) for r in rows)
PYEOF
then ok "summary.json counts the runs with an alarm without cause, runs.csv's"
else nok "summary.json counts the runs with an alarm without cause, runs.csv's"; fi
# the corners: plant i's valve at the ends its bits pick, every noise at its top, the rest drawn
if $PY tools/family.py "$SIM" --n 2 --corners --controllers ffmap --out "$tmp/c" > "$tmp/c.out" 2>&1 \
   && grep -q "^valve_travel_s = 1.5$" "$tmp/c/scn/plant_000_untold.scn" && grep -q "^valve_travel_s = 12.0$" "$tmp/c/scn/plant_001_untold.scn" \
   && grep -q "^pump_pulsation_pct = 10.0$" "$tmp/c/scn/plant_001_told.scn" && grep -q "^speed_bounce_pct = 3.0$" "$tmp/c/scn/plant_000_told.scn" \
   && [ "$(($(wc -l < "$tmp/c/runs.csv") - 1))" -eq 4 ] && $PY - <<'PYEOF'
import sys
sys.path.insert(0, "tools")
import family
for i in range(64):
    d = family.corner(1, i)
    p = d["plant"]
    assert p["valve_travel_s"] == (12.0 if i & 1 else 1.5) and p["valve_stiction_duty"] == (0.35 if i & 2 else 0.10)
    assert abs(p["valve_running_duty"] / p["valve_stiction_duty"] - (0.8 if i & 4 else 0.5)) < 0.01
    assert p["valve_backlash"] == (0.04 if i & 8 else 0.005) and p["valve_motor_tau_s"] == (0.15 if i & 16 else 0.02)
    assert d["kind"] == ("field" if i & 32 else "dynamic") and p["pressure_noise_lsb"] == 3.0
    assert family.corner(1, i + 64)["plant"]["valve_travel_s"] == p["valve_travel_s"]
PYEOF
then ok "--corners: the valve's ends by the plant's bits, every noise at its top"
else nok "--corners: the valve's ends by the plant's bits, every noise at its top" "$(tail -3 "$tmp/c.out")"; fi
# the peers tuned for each plant's valve: a second scenario per plant with their settings, scored apart
if $PY tools/family.py "$SIM" --n 2 --controllers raven,raven_tuned,aog_tuned --out "$tmp/t" > "$tmp/t.out" 2>&1 \
   && grep -q "^raven_valve_cal = [1-9][0-9][0-9][1-9]$" "$tmp/t/scn/plant_000_told_tuned.scn" \
   && grep -q "^aog_min_pwm = " "$tmp/t/scn/plant_000_untold_tuned.scn" \
   && ! grep -q "raven_valve_cal" "$tmp/t/scn/plant_000_told.scn" \
   && [ "$(grep -c ',raven_tuned,' "$tmp/t/runs.csv")" -eq 4 ] && grep -q "| raven_tuned |" "$tmp/t/table.md"; then
    ok "raven_tuned and aog_tuned run each plant with settings for its valve"
else
    nok "raven_tuned and aog_tuned run each plant with settings for its valve" "$(tail -3 "$tmp/t.out")"
fi

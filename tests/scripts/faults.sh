#!/usr/bin/env bash
# faults.sh: tools/faults.py (make faults): the dose while silent on a hand-made trace, the faults' scenarios, a table that is the simulator's figures, one-line refusals.
. "$(dirname "$0")/tap.sh" faults

make -s --no-print-directory "$SIM" BUILD="$B" > "$tmp/build.log" 2>&1 || { nok "the simulator builds" "$(cat "$tmp/build.log")"; exit 0; }
# By hand, 150 L/ha over 36 nozzles at 50 cm (18 m) at 8 km/h asks 150 x 8 x 18 / 600 = 36 L/min:
# 10 rows at 36 and 10 at 27 L/min, 5 rows with an alarm (not counted), 5 rows with the boom
# shut at 8 km/h (nothing applied), 3 rows spraying 6 L/min at a standstill (0.03 L apart):
# 630 of 900 asked, -30 %; with 6 nozzles clogged the width is 15 m, 750 asked: -16 %.
if $PY - "$tmp/t.csv" > "$tmp/hand.out" 2>&1 <<'PYEOF'
import sys
sys.path.insert(0, "tools")
import faults
rows = [(36, 8, 1, 0)] * 10 + [(27, 8, 1, 0)] * 10 + [(0, 8, 1, 1)] * 5 + [(0, 8, 0, 0)] * 5 + [(6, 0, 1, 0)] * 3
with open(sys.argv[1], "w") as f:
    f.write("t_s,v_true_kmh,boom_lpm,spray_on,open_nozzles,alarms\n")
    for k, (q, v, s, a) in enumerate(rows):
        f.write("%.1f,%g,%g,%d,36,0x%04x\n" % (100 + 0.1 * k, v, q, s, a))
d, still = faults.silent_dose(sys.argv[1], {"start": 100.0})
assert abs(d + 30.0) < 1e-9 and abs(still - 0.03) < 1e-12, (d, still)
d, _ = faults.silent_dose(sys.argv[1], {"start": 100.0, "clogs": [(0, 6)]})
assert abs(d + 16.0) < 1e-9, d
d, _ = faults.silent_dose(sys.argv[1], {"start": 100.0, "rate": [(0, 150), (100.95, 100)]})
# from row 10 on the operator asks 100 L/ha (24 L/min): 360 + 270 of 360 + 15 x 24 = 720: -12.5 %
assert abs(d + 12.5) < 1e-9, d
sc = faults.leak_growing(10)["text"]
leaks = [l.split() for l in sc.splitlines() if "leak_lpm" in l]
assert [(float(t), int(v)) for t, _, v in leaks] == [(90 + 20 * k, k + 1) for k in range(10)], leaks
assert faults.csum("SET 0 100") == "SET 0 100*EA"          # the CRC-8 (poly 0x65) of docs/SCENARIOS.md's example line
assert faults.xor_check("SET 0 150") == "46"                # the issue's collision: 'SET 4 110*46'
assert all(len(s) == 2 for _, _, _, s in faults.FAULTS) and len(faults.FAULTS) == 17
# the tank's share: 990 L at the fault's start (100.0 s), 877.5 L at 100.3 s, of 750 L: 15 %, over
with open(sys.argv[1], "w") as f:
    f.write("t_s,tank_l\n99.9,995\n100.0,990\n100.1,950\n100.2,900\n100.3,877.5\n100.4,870\n")
share = faults.tank_share(sys.argv[1], 100.0, 100.25, 750)
assert abs(share - 15.0) < 1e-9, share
assert faults.balance_note(share).endswith("over the 15 % bound"), faults.balance_note(share)
assert faults.balance_note(14.9).endswith("within the 15 % bound")
assert "not met" in faults.balance_note(None)
PYEOF
then ok "the dose while silent of a hand-made trace: -30 %, -16 % with 6 clogged, -12.5 % at a SET rate; the leak's steps; the tank's share"
else nok "the dose while silent of a hand-made trace: -30 %, -16 % with 6 clogged, -12.5 % at a SET rate; the leak's steps; the tank's share" "$(cat "$tmp/hand.out")"; fi

# a meter reading low: the share of the tank sprayed before METER_CAL, again as the nozzles' volume
# from the fault's start to the alarm (the trace's boom flow, no leak: what left the tank)
if $PY tools/faults.py "$SIM" --only meter_low --out "$tmp/m" > "$tmp/m.out" 2>&1 && $PY - "$tmp/m/summary.json" <<'PYEOF'
import csv, json, sys
rows = json.load(open(sys.argv[1]))["rows"]
assert len(rows) == 2
for r in rows:
    trace = list(csv.DictReader(open(r["scenario"][:-4] + ".csv")))
    assert "tank_l = 1000" in open(r["scenario"]).read() and r["balance_t_s"] is not None, r
    sprayed = sum(float(x["boom_lpm"]) * 0.1 / 60.0 for x in trace
                  if r["start_s"] <= float(x["t_s"]) < r["balance_t_s"])
    assert abs(sprayed / 10.0 - r["tank_share_pct"]) < 0.05, (r["size"], sprayed, r["tank_share_pct"])
    assert ("within" in r["note"]) == (r["tank_share_pct"] < 15), r["note"]
PYEOF
then ok "a meter reading low: the tank's share before METER_CAL is the nozzles' volume to the alarm"
else nok "a meter reading low: the tank's share before METER_CAL is the nozzles' volume to the alarm" "$(tail -3 "$tmp/m.out")"; fi

# a smaller sprayer's tank: 400 L (the level's resolution m = 400 / 256 + 1 = 2 L, half a 1000 L
# tank's 4 L, over a tank 2.5 times smaller): a meter 10 or 20 % off is still told before 15 %
if $PY tools/faults.py "$SIM" --only meter_low,meter_high --tank-l 400 --out "$tmp/s" > "$tmp/s.out" 2>&1 && $PY - "$tmp/s/summary.json" <<'PYEOF'
import json, sys
rows = json.load(open(sys.argv[1]))["rows"]
assert len(rows) == 4
for r in rows:
    assert "tank_l = 400" in open(r["scenario"]).read() and "tank_size_l = 400" in open(r["scenario"]).read(), r
    assert r["tank_share_pct"] is not None and r["tank_share_pct"] < 15.0, (r["size"], r["tank_share_pct"])
PYEOF
then ok "a 400 L tank: a meter 10 or 20 % off told by METER_CAL before 15 % of the tank is sprayed"
else nok "a 400 L tank: a meter 10 or 20 % off told by METER_CAL before 15 % of the tank is sprayed" "$(tail -3 "$tmp/s.out")"; fi

if $PY tools/faults.py "$SIM" --only leak_growing,set_then_cut --out "$tmp/f" > "$tmp/f.out" 2>&1; then
    ok "two faults at two sizes run"
else
    nok "two faults at two sizes run" "$(tail -3 "$tmp/f.out")"; exit 0
fi
[ "$(grep -c "^| " "$tmp/f/table.md")" -eq 5 ] && grep -q "^| a leak after the meter growing 1 L/min every 20 s | to 10 L/min | " "$tmp/f/table.md" \
    && ok "table.md has a header and four rows" || nok "table.md has a header and four rows" "$(cat "$tmp/f/table.md")"
# every row's figures are the simulator's own on the scenario the tool wrote
if $PY - "$tmp/f/summary.json" "$SIM" <<'PYEOF'
import json, subprocess, sys
s = json.load(open(sys.argv[1]))
assert len(s["rows"]) == 4
for r in s["rows"]:
    out = subprocess.run([sys.argv[2], "--scenario", r["scenario"], "--controller", "ffmap"], capture_output=True, text=True)
    m = json.loads(out.stdout.strip().splitlines()[-1])
    assert m["silent_wrong_s"] == r["silent_wrong_s"], (r["fault"], r["size"])
    after = [a for a in m["alarms"] if a["t_s"] >= r["start_s"]]
    assert (after[0]["code"] if after else None) == r["alarm"], (r["fault"], r["size"])
    assert r["delay_s"] is None or abs(after[0]["t_s"] - r["start_s"] - r["delay_s"]) < 0.051
    assert r["silent_dose_pct"] is not None
PYEOF
then ok "each row's alarm, delay and silent_wrong_s are the simulator's on the scenario written"
else nok "each row's alarm, delay and silent_wrong_s are the simulator's on the scenario written"; fi
# silent_wrong_s again from the 0.1 s trace (the nozzles' mean flow, the true speed, the width less
# the clogged nozzles, the boom valve, the alarms), apart from the simulator's metrics code
if $PY - "$SIM" "$tmp" <<'PYEOF'
import csv, json, subprocess, sys
sys.path.insert(0, "tools")
import faults
sim, tmp = sys.argv[1:3]
for size in (10, 5):
    spec = faults.clog_growing(size)
    path = "%s/clog%d.scn" % (tmp, size)
    open(path, "w").write(spec["text"])
    out = subprocess.run([sim, "--scenario", path, "--csv", path + ".csv"], capture_output=True, text=True)
    m = json.loads(out.stdout.strip().splitlines()[-1])
    run = longest = total = 0.0
    n_wrong = 0
    for r in csv.DictReader(open(path + ".csv")):
        t, v, q = float(r["t_s"]), float(r["v_true_kmh"]), float(r["boom_lpm"])
        width = (int(r["open_nozzles"]) - faults.step_value(spec["clogs"], t, 0)) * 0.5
        spray, told = int(r["spray_on"]), int(r["alarms"], 16) != 0
        if not spray:
            wrong = v >= 2.0
        elif v < 0.5:
            wrong = q > 0
        else:
            wrong = width <= 0 or abs(q * 600 / (v * width) / float(r["rate_l_ha"]) - 1) > 0.10
        n_wrong += wrong
        if wrong and not told:
            run += 0.1
        else:
            if run >= 5 - 1e-9:
                longest, total = max(longest, run), total + run
            run = 0.0
    if run >= 5 - 1e-9:
        longest, total = max(longest, run), total + run
    assert abs(longest - m["silent_wrong_s"]) < 0.01 and abs(total - m["silent_wrong_total_s"]) < 0.01, \
        (size, longest, total, m["silent_wrong_s"], m["silent_wrong_total_s"])
    # by hand: from the 4th clogged nozzle (150 s) the open strips get 36 / 32 = +12.5 % or more, to 300 s: 1500 samples
    assert n_wrong > 1400, n_wrong
PYEOF
then ok "silent_wrong_s and its total counted again from the trace of a clogging boom: the simulator's"
else nok "silent_wrong_s and its total counted again from the trace of a clogging boom: the simulator's"; fi
$PY tools/faults.py "$SIM" --only no_such_fault --out "$tmp/g" > /dev/null 2> "$tmp/err" && nok "an unknown fault is refused" \
    || { grep -q "^faults: unknown fault no_such_fault (one of: leak_growing" "$tmp/err" && ok "an unknown fault is refused in one line" \
         || nok "an unknown fault is refused in one line" "$(cat "$tmp/err")"; }
$PY tools/faults.py /nonexistent > /dev/null 2> "$tmp/err" && nok "a missing simulator is refused" \
    || { grep -q "not an executable simulator" "$tmp/err" && ok "a missing simulator is refused in one line" \
         || nok "a missing simulator is refused in one line" "$(cat "$tmp/err")"; }

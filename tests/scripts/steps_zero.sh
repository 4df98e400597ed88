#!/usr/bin/env bash
# steps_zero.sh: on every scenario in scenarios/, a flow equal to the firmware's target scores 0 % overshoot and 0 s settling, and a late flow scores worse the later it is.
. "$(dirname "$0")/tap.sh" steps_zero
STEPS=$B/host/bin/steps

if ! make -s --no-print-directory "$SIM" "$STEPS" BUILD="$B" > "$tmp/build.log" 2>&1; then
    nok "the simulator and steps build" "$(cat "$tmp/build.log")"
    exit 0
fi
total=0
for scn in scenarios/*.scn; do
    name=$(basename "$scn" .scn)
    if ! "$SIM" --scenario "$scn" --samples "$tmp/$name.csv" > "$tmp/$name.out" 2>&1; then
        nok "$name runs" "$(tail -3 "$tmp/$name.out")"
        continue
    fi
    # the simulator's own figures and steps' on the same series agree; the target as the flow scores 0
    sim_json=$(tail -n 1 "$tmp/$name.out")
    got=$("$STEPS" "$tmp/$name.csv") && zero=$("$STEPS" "$tmp/$name.csv" --flow target_lpm) || { nok "$name: steps reads the series"; continue; }
    if res=$($PY - "$sim_json" "$got" "$zero" <<'PYEOF'
import json, sys
sim, got, zero = (json.loads(a) for a in sys.argv[1:4])
for k in ("steps_scored", "overshoot_mean_pct", "settle_mean_s", "start_s"):
    assert sim[k] == got[k] or abs(sim[k] - got[k]) < 1e-9, (k, sim[k], got[k])
assert zero["steps_scored"] == sim["steps_scored"], (zero["steps_scored"], sim["steps_scored"])
for s in zero["steps"]:
    assert s["overshoot_pct"] == 0 and s["settle_5pct_s"] == 0 and s["settle_2pct_s"] == 0, s
    assert s["settled_5pct"] and s["settled_2pct"], s
assert zero["start_s"] in (0, None), zero["start_s"]
print(zero["steps_scored"])
PYEOF
    ); then
        total=$((total + res))
        ok "$name: the target as the flow scores 0 % / 0 s on its $res steps; sim and steps agree"
    else
        nok "$name: the target as the flow scores 0 % / 0 s" "$res"
    fi
done
[ "$total" -gt 20 ] && ok "the scenarios have $total scored steps in all" || nok "the scenarios have scored steps ($total)"

# a late flow: the target 0.5 s and 1 s late settles later than on time, on the paper's run
d0=$("$STEPS" "$tmp/paper_dynamic_150.csv" --flow target_lpm --delay-samples 5 | $PY -c "import json,sys; print(json.load(sys.stdin)['settle_mean_s'])")
d1=$("$STEPS" "$tmp/paper_dynamic_150.csv" --flow target_lpm --delay-samples 10 | $PY -c "import json,sys; print(json.load(sys.stdin)['settle_mean_s'])")
if $PY -c "import sys; a, b = float(sys.argv[1]), float(sys.argv[2]); sys.exit(0 if 0 < a < b else 1)" "$d0" "$d1"; then
    ok "a flow 0.5 s / 1 s late settles in $d0 / $d1 s on the paper's run (0 s on time)"
else
    nok "a late flow settles later the later it is ($d0, $d1)"
fi
"$STEPS" /nonexistent.csv > /dev/null 2> "$tmp/err" && nok "steps refuses a missing file" || { grep -q "cannot open" "$tmp/err" && ok "steps refuses a missing file with one line" || nok "steps refuses a missing file with one line" "$(cat "$tmp/err")"; }

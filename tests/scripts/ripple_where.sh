#!/usr/bin/env bash
# ripple_where.sh: tools/ripple_where.py takes ripple_p95_pct's samples as the simulator does (its 95th percentile is each run's in runs.csv) and splits them by time.
. "$(dirname "$0")/tap.sh" ripple_where

make -s --no-print-directory "$SIM" BUILD="$B" > "$tmp/build.log" 2>&1 || { nok "the simulator builds" "$(cat "$tmp/build.log")"; exit 0; }
$PY tools/family.py "$SIM" --n 4 --corners --controllers ffmap --out "$tmp/f" > "$tmp/f.out" 2>&1 \
    || { nok "4 corners run" "$(tail -3 "$tmp/f.out")"; exit 0; }
# --bound 0: every run listed, each checked against the simulator's own figure
if $PY tools/ripple_where.py "$SIM" --family "$tmp/f" --bound 0 > "$tmp/w.out" 2>&1 \
   && [ "$(($(wc -l < "$tmp/w.out") - 1))" -eq 8 ]; then
    ok "every run's 95th percentile is the simulator's (8 runs)"
else
    nok "every run's 95th percentile is the simulator's (8 runs)" "$(tail -3 "$tmp/w.out")"
fi
# the split adds up: the samples over 0 % in the three stretches are at most all of them
if awk 'NR > 1 && $5 + $6 + $7 > $4 { bad = 1 } END { exit bad }' "$tmp/w.out"; then
    ok "the stretches' samples add up to at most the run's"
else
    nok "the stretches' samples add up to at most the run's" "$(cat "$tmp/w.out")"
fi
# a runs.csv that disagrees with the simulator is found
awk -F, 'BEGIN { OFS = "," } NR == 1 { for (i = 1; i <= NF; i++) if ($i == "ripple_p95_pct") c = i }
         NR > 1 { $c = $c + 0.5 } { print }' "$tmp/f/runs.csv" > "$tmp/r.csv" && mv "$tmp/r.csv" "$tmp/f/runs.csv"
if ! $PY tools/ripple_where.py "$SIM" --family "$tmp/f" --bound 0 > "$tmp/x.out" 2>&1 \
   && grep -q "differs from runs.csv" "$tmp/x.out"; then
    ok "a 95th percentile that differs from runs.csv fails"
else
    nok "a 95th percentile that differs from runs.csv fails" "$(tail -3 "$tmp/x.out")"
fi

#!/usr/bin/env bash
# alarm_table.sh: the README's alarm table is firmware/ops/diag.h's DIAG_ALARMS: every code with its LCD text (at most 15 characters, after the '!'), a cause and what to do; no row for an alarm the firmware does not have.
. "$(dirname "$0")/tap.sh" alarm_table

# the firmware's: "CODE|text" a line, from X(AL_.., "CODE", "text")
sed -n 's/^ *X(AL_[A-Z_]*, *"\([A-Z_]*\)", *"\([^"]*\)").*/\1|\2/p' firmware/ops/diag.h > "$tmp/fw"
# a README's: the rows of the table under "| code | LCD |", "A / B" rows split into two
readme_rows() {
    awk -F'|' '/^\| code \| LCD \|/ { on = 1; next } on && !/^\|/ { exit }
               on && !/^\|---/ { gsub(/^ +| +$/, "", $2); gsub(/^ +| +$/, "", $3); gsub(/^ +| +$/, "", $4)
                                 nc = split($2, c, / \/ /); nt = split($3, t, / \/ /)
                                 for (i = 1; i <= nc; i++) print c[i] "|" (nc == nt ? t[i] : $3) "|" length($4) }' "$1"
}
check() {  # check README: what disagrees with diag.h, one a line
    readme_rows "$1" > "$tmp/rd"
    while IFS='|' read -r code text; do
        row=$(grep "^$code|" "$tmp/rd") || { echo "$code: no row"; continue; }
        [ "$(echo "$row" | cut -d'|' -f2)" = "$text" ] || echo "$code: LCD '$(echo "$row" | cut -d'|' -f2)' in the README, '$text' in diag.h"
        [ "$(echo "$row" | cut -d'|' -f3)" -ge 20 ] || echo "$code: no cause or action"
        [ "${#text}" -le 15 ] || echo "$code: '$text' is ${#text} characters"
    done < "$tmp/fw"
    cut -d'|' -f1 "$tmp/rd" | while read -r code; do
        grep -q "^$code|" "$tmp/fw" || echo "$code: a row for no alarm of diag.h"
    done
}
n=$(wc -l < "$tmp/fw")
bad=$(check README.md)
if [ "$n" -ge 10 ] && [ -z "$bad" ]; then ok "the README's table has the $n alarms of diag.h, their LCD texts (15 characters at most) and what to do"
else nok "the README's table has the alarms of diag.h ($n found)" "$bad"; fi
# planted: a text changed, a row gone, a row for an alarm that is not there
sed 's/^| METER_CAL | Meter\/tank cal\. |/| METER_CAL | Meter cal. |/; /^| LEAK |/d' README.md \
    | awk '/^\| INTERNAL \|/ { print; print "| VALVE_STOP | Valve at stop | the valve driven against its stop |"; next } { print }' > "$tmp/README.md"
bad=$(check "$tmp/README.md")
if echo "$bad" | grep -q "^METER_CAL: LCD 'Meter cal.'" && echo "$bad" | grep -q "^LEAK: no row" \
   && echo "$bad" | grep -q "^VALVE_STOP: a row for no alarm"; then
    ok "the check catches a changed text, a missing row and a row for no alarm"
else nok "the check catches a changed text, a missing row and a row for no alarm" "$bad"; fi

#!/usr/bin/env bash
# panel_everyday.sh: `make panel` under tmux: the rate nudge and its return, Rate 2 on its key (the target and Raven's C1 line), US units on the run screen, a rate typed in gal/acre and Raven's C3 line in the units.
set -u
cd "$(dirname "$0")/../.."
B=${BUILD:-build}
export BUILD=$B
PY=.venv/bin/python
[ -x "$PY" ] || PY=python3
tmp=$(mktemp -d)
sock="panel-everyday-$$"
T="tmux -L $sock"
cleanup() { $T kill-server 2>/dev/null; rm -rf "$tmp"; }
trap cleanup EXIT
ok() { echo "ok - panel_everyday: $1"; }
nok() { echo "not ok - panel_everyday: $1"; [ -n "${2:-}" ] && echo "$2" | sed 's/^/#   /'; }

if ! out=$(make --no-print-directory "$B/host/bin/panel" 2>&1); then
    nok "builds" "$(echo "$out" | tail -5)"; exit 0
fi
command -v tmux >/dev/null || { nok "tmux is installed (tools/deps.sh)"; exit 0; }

# 8 km/h, Rate step 10 %; Remote on (SET 30 1, Raven's strings) and a field computer asking
# for the calibration ($R,CR) every 2 s: the C1 line carries the preset in use
signed() { $PY -c "
import sys
c = 0
for b in sys.argv[1].encode():
    c ^= b
    for _ in range(8):
        c = ((c << 1) ^ 0x65) & 0xFF if c & 0x80 else (c << 1) & 0xFF
print('%s*%02X' % (sys.argv[1], c))" "$1"; }
{
    printf '[run]\nduration_s = 3600\n[config]\nrate_step_pct = 10\n[drive]\n0 8\n3600 8\n[events]\n'
    printf '1 serial %s\n' "$(signed 'SET 30 1')"
    for ((t = 4; t < 1800; t += 2)); do printf '%d serial $R,CR\n' $t; done
} > "$tmp/field.scn"

lcd_line() { $T capture-pane -p -t panel 2>/dev/null | grep -E '^    \|.{16}\|$' | sed -n "$1p" | cut -c6-21; }
until_ok() {
    local i n=$1; shift
    for ((i = 0; i < n * 10; i++)); do "$@" && return 0; sleep 0.1; done
    return 1
}
line_is() { [ "$(lcd_line "$1")" = "$2" ]; }
line_has() { lcd_line "$1" | grep -qE "$2"; }
keys() { local k; for k in "$@"; do $T send-keys -t panel -l "$k"; sleep 0.3; done; }
target() { lcd_line 2 | sed -nE 's/^Q *([0-9.]+)>.*/\1/p'; }
ratio_in() { local a; a=$(target); [ -n "$a" ] && awk "BEGIN{r = $a / $1; exit !(r > $2 && r < $3)}"; }
# switch byte 2 of the newest C1 line the controller sent
c1_sw2() { grep -a '^\$R124F,C1,' "$tmp/link.txt" 2>/dev/null | tail -n 1 | cut -d, -f4; }
c1_is() { [ "$(c1_sw2)" = "$1" ]; }

$T new-session -d -s panel -x 120 -y 50 \
    "make --no-print-directory panel PANEL_SCENARIO=$tmp/field.scn PANEL_ARGS='--speed 2 --serial $tmp/link.txt'; sleep 30"
if until_ok 30 line_has 1 'km/h'; then ok "runs under tmux"; else
    nok "runs under tmux" "$($T capture-pane -p -t panel | tail -20)"; exit 0; fi
keys '*' '*'                          # the first boot's notice shown, then acknowledged
sleep 20                              # 40 s simulated: up to speed, the flow settled
before=$(target)
if [ -n "$before" ] && awk "BEGIN{exit !($before > 34 && $before < 38)}"; then
    ok "target at 150 L/ha and 8 km/h: $before L/min (36 by hand: 150 x 8 x 18 / 600)"
else
    nok "target at 150 L/ha and 8 km/h (got '$before', 36 expected)" "$($T capture-pane -p -t panel | tail -14)"
fi
if until_ok 10 c1_is 136; then ok "C1's switch byte 2 in auto with Rate 1: 136 (bit 3)"; else nok "C1 with Rate 1" "$(c1_sw2)"; fi

# two presses of 2 at a 10 % step: the target 20 % up at the next redraw, the rate and its offset shown
$T send-keys -t panel -l 2; sleep 0.15; $T send-keys -t panel -l 2
if until_ok 2 ratio_in "$before" 1.19 1.21 && until_ok 2 line_is 4 "180.0L/ha   +20%"; then
    ok "2 2 nudges the rate 20 %: target $before -> $(target) L/min, '$(lcd_line 4)'"
else
    nok "2 2 nudges the rate 20 % (target $before -> '$(target)')" "$($T capture-pane -p -t panel | tail -14)"
fi
keys 5
if until_ok 2 ratio_in "$before" 0.99 1.01 && until_ok 2 line_has 4 '^T +[0-9]+L +ffmap$'; then
    ok "5 returns to the preset: target $(target) L/min, '$(lcd_line 4)'"
else
    nok "5 returns to the preset (target '$(target)')" "$($T capture-pane -p -t panel | tail -14)"
fi

# Rate 2 (200 L/ha) on its key: the target x 4/3, the bottom line and the C1 line say so
keys 0
if until_ok 3 ratio_in "$before" 1.32 1.35 && until_ok 5 line_has 4 'Rate 2$'; then
    ok "0 takes Rate 2: target $before -> $(target) L/min (x 200/150), '$(lcd_line 4)'"
else
    nok "0 takes Rate 2 (target $before -> '$(target)')" "$($T capture-pane -p -t panel | tail -14)"
fi
if until_ok 10 c1_is 144; then ok "C1's switch byte 2 with Rate 2: 144 (bit 4)"; else nok "C1 with Rate 2" "$(c1_sw2)"; fi
keys 0
until_ok 3 ratio_in "$before" 0.99 1.01

# US units from the menu: A opens it, then A steps up (from the first, round to the last) until
# Units is shown; at most once round the table
keys A
for ((i = 0; i < 60; i++)); do line_is 2 "Units           " && break; keys A; done
if until_ok 5 line_is 2 "Units           "; then ok "the menu has Units"; else nok "the menu has Units" "$($T capture-pane -p -t panel | tail -14)"; fi
keys D A D C
if until_ok 5 line_has 1 '^ *[0-9.]+mph +[0-9.]+PSI *$' && until_ok 5 line_has 3 '^[0-9.]+gal/ac +AUTO *$' &&
   until_ok 5 line_has 2 '^Q *[0-9.]+> *[0-9.]+gpm'; then
    ok "US units: '$(lcd_line 1)' '$(lcd_line 2)' '$(lcd_line 3)'"
else
    nok "US units on the run screen" "$($T capture-pane -p -t panel | tail -14)"
fi
# the speed in mph from its definition (1 mile = 1609.344 m): 8 km/h is 4.97 mph
mph=$(lcd_line 1 | sed -nE 's/^ *([0-9.]+)mph.*/\1/p')
if [ -n "$mph" ] && awk "BEGIN{e = $mph - 8 / 1.609344; exit !(e > -0.25 && e < 0.25)}"; then
    ok "the speed in mph: $mph (8 km/h = 4.97 mph)"; else nok "the speed in mph ('$mph')"; fi

# 15.0 gal/acre typed for Rate 1 reads back unchanged, and is 140.3 L/ha in metric
keys A D 1 5 '#' 0 D
if until_ok 5 line_is 4 "Saved           " && until_ok 5 line_is 3 "     15.0 gal/ac"; then
    ok "15.0 gal/acre typed for Rate 1 reads back as 15.0 gal/ac"
else
    nok "15.0 gal/acre reads back" "$($T capture-pane -p -t panel | tail -14)"
fi
# the field computer's C3 line carries it in the console's units too (docs/REMOTE.md)
c3_rate() { grep -a '^\$R124F,C3,' "$tmp/link.txt" 2>/dev/null | tail -n 1 | cut -d, -f4; }
c3_is() { [ "$(c3_rate)" = "$1" ]; }
if until_ok 10 c3_is 15.0; then ok "Raven's C3 line in US units: rate 15.0 (gal/acre)"; else nok "C3 in US units" "$(c3_rate)"; fi
want=$(awk 'BEGIN{printf "%.1f L/ha", 15.0 * 3.785411784 / (4046.8564224 / 10000)}')
for ((i = 0; i < 60; i++)); do line_is 2 "Units           " && break; keys A; done
keys D B D
until_ok 5 line_is 4 "Saved           "
for ((i = 0; i < 60; i++)); do line_is 2 "Rate 1          " && break; keys B; done
if until_ok 5 line_is 2 "Rate 1          " && until_ok 5 line_has 3 "^ +$want$"; then
    ok "in metric it is $(lcd_line 3 | sed 's/^ *//') ($want from the definitions)"
else
    nok "in metric it is $want" "$($T capture-pane -p -t panel | tail -14)"
fi
if until_ok 10 c3_is 140.3; then ok "Raven's C3 line in metric: rate 140.3 (L/ha)"; else nok "C3 in metric" "$(c3_rate)"; fi
keys q

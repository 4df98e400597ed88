#!/usr/bin/env bash
# panel_tmux.sh: `make panel` under tmux: the run screen's rate against the plant's truth, the boom and section switches, Rate 1 through the menus, an alarm over the notice; the PNG screenshot decodes.
set -u
cd "$(dirname "$0")/../.."
B=${BUILD:-build}
export BUILD=$B
tmp=$(mktemp -d)
sock="panel-test-$$"
T="tmux -L $sock"
cleanup() { $T kill-server 2>/dev/null; rm -rf "$tmp"; }
trap cleanup EXIT
ok() { echo "ok - panel: $1"; }
nok() { echo "not ok - panel: $1"; [ -n "${2:-}" ] && echo "$2" | sed 's/^/#   /'; }

# a field at a constant 8 km/h: 150 L/ha x 8 km/h x 18 m / 600 = 36 L/min at the default dose
cat > "$tmp/const8.scn" <<'EOF'
[run]
duration_s = 3600
[drive]
0    8
3600 8
EOF

if ! out=$(make --no-print-directory "$B/host/bin/panel" 2>&1); then
    nok "builds" "$(echo "$out" | tail -5)"; exit 0
fi
ok "builds"
command -v tmux >/dev/null || { nok "tmux is installed (tools/deps.sh)"; exit 0; }

# the LCD's text box, one line: "|...16 chars...|"
lcd_line() { $T capture-pane -p -t panel 2>/dev/null | grep -E '^    \|.{16}\|$' | sed -n "$1p" | cut -c6-21; }
wait_for() {  # wait_for REGEX SECONDS: until the pane shows it
    local i
    for ((i = 0; i < $2 * 10; i++)); do
        $T capture-pane -p -t panel 2>/dev/null | grep -qE "$1" && return 0
        sleep 0.1
    done
    return 1
}
# until_ok SECONDS COMMAND...: until the command succeeds (the panel runs in real time, and a
# loaded machine may lag behind it)
until_ok() {
    local i n=$1; shift
    for ((i = 0; i < n * 10; i++)); do "$@" && return 0; sleep 0.1; done
    return 1
}
line_is() { [ "$(lcd_line "$1")" = "$2" ]; }
ratio_in() { local a b; a=$(target); b=$1; [ -n "$a" ] && [ -n "$b" ] && awk "BEGIN{r = $a / $b; exit !(r > $2 && r < $3)}"; }
follows() { local m a; m=$(measured); a=$(target); [ -n "$m" ] && [ -n "$a" ] && awk "BEGIN{e = ($m - $a) / $a; exit !(e > -0.1 && e < 0.1)}"; }
keys() { local k; for k in "$@"; do $T send-keys -t panel -l "$k"; sleep 0.3; done; }
target() { lcd_line 2 | sed -nE 's/^Q *([0-9.]+)>.*/\1/p'; }
measured() { lcd_line 2 | sed -nE 's/^Q *[0-9.]+> *([0-9.]+)L\/mn$/\1/p'; }

$T new-session -d -s panel -x 120 -y 50 \
    "make --no-print-directory panel PANEL_SCENARIO=$tmp/const8.scn PANEL_ARGS='--speed 2'; sleep 30"
if wait_for 'km/h' 30; then ok "runs under tmux and shows the run screen"; else
    nok "runs under tmux and shows the run screen" "$($T capture-pane -p -t panel | tail -20)"; exit 0; fi
# the pixel image is drawn too (braille or half blocks above the text box)
if $T capture-pane -p -t panel | LC_ALL=C grep -q $'\xe2[\xa0-\xa3\x96]'; then ok "draws the 128x64 pixels"; else nok "draws the 128x64 pixels"; fi

# the first-boot notice stays on the bottom line until * (acknowledged in the alarm part below)
if until_ok 10 line_is 4 "!EE: defaults   "; then ok "the first-boot notice shows"; else nok "the first-boot notice shows" "$(lcd_line 4)"; fi
sleep 20                              # 40 s simulated: up to speed, the wheel learnt, flow settled

# the applied rate now against the plant's truth: boom flow over true speed times the open width
truth_rate() { $T capture-pane -p -t panel | sed -nE 's/.*truth: *([0-9.]+) km\/h +boom +([0-9.]+) L\/min +width +([0-9.]+) m.*/\1 \2 \3/p' | head -1 |
               awk '$1 > 0 && $3 > 0 {printf "%.1f", $2 * 600 / ($1 * $3)}'; }
shown_rate() { lcd_line 3 | sed -nE 's/^Now *([0-9]+)L\/ha.*/\1/p'; }
rate_close() { local a b; b=$(truth_rate); a=$(shown_rate); [ -n "$a" ] && [ -n "$b" ] && awk "BEGIN{e = ($a - $b) / $b; exit !(e > -0.05 && e < 0.05)}"; }
if until_ok 10 rate_close; then ok "the run screen's rate now, $(shown_rate) L/ha, within 5 % of the truth, $(truth_rate) L/ha"; else
    nok "the run screen's rate now within 5 % of the truth ('$(shown_rate)' for '$(truth_rate)')" "$($T capture-pane -p -t panel | tail -12)"; fi

before=$(target)
if [ -n "$before" ] && awk "BEGIN{exit !($before > 30 && $before < 42)}"; then
    ok "target flow at 150 L/ha and 8 km/h is $before L/min (36 expected)"
else
    nok "target flow at 150 L/ha and 8 km/h (got '$before', 36 expected)" "$($T capture-pane -p -t panel)"
fi

# a section switch: section 3 of 6 off takes its 6 of the 36 nozzles' share off the target
switches() { $T capture-pane -p -t panel | sed -nE 's/^switches: boom (ON|OFF) +sections ([-0-9]+) +relay (on|off).*/\1 \2 \3/p' | head -1; }
keys s 3
share=$(awk 'BEGIN{print (36 - 36 / 6) / 36}')
if until_ok 10 ratio_in "$before" "$(awk "BEGIN{print $share * 0.98}")" "$(awk "BEGIN{print $share * 1.02}")" &&
   [ "$(switches)" = "ON 12-456 on" ]; then
    ok "s3 closes section 3: target $before -> $(target) L/min ($share of it)"
else
    nok "s3 closes section 3 (target $before -> '$(target)', $share of it; switches '$(switches)')" "$($T capture-pane -p -t panel | tail -12)"
fi
keys s 3
if until_ok 10 ratio_in "$before" 0.98 1.02 && [ "$(switches)" = "ON 123456 on" ]; then ok "s3 opens it again"; else nok "s3 opens it again" "$(switches) $(target)"; fi

# the master boom switch: the relay drops, the target goes to nothing, the nozzles stop
boom_flow() { $T capture-pane -p -t panel | sed -nE 's/.*boom +([0-9.]+) L\/min.*/\1/p' | head -1; }
boom_dry() { local f; f=$(boom_flow); [ -n "$f" ] && awk "BEGIN{exit !($f < 0.2)}"; }
keys m
if until_ok 10 boom_dry && [ "$(target)" = "0.0" ] && [ "$(switches)" = "OFF 123456 off" ]; then
    ok "m closes the boom: relay off, target 0, the nozzles' flow $(boom_flow) L/min"
else
    nok "m closes the boom (switches '$(switches)', target '$(target)', flow '$(boom_flow)')" "$($T capture-pane -p -t panel | tail -12)"
fi
keys m
if until_ok 20 follows && ratio_in "$before" 0.98 1.02 && [ "$(switches)" = "ON 123456 on" ]; then
    ok "m opens it again: target $(target), measured $(measured) L/min"
else
    nok "m opens the boom again (switches '$(switches)', target '$(target)', measured '$(measured)')" "$($T capture-pane -p -t panel | tail -12)"
fi

keys A                                # menu, entry 1: Rate 1
if until_ok 5 line_is 2 "Rate 1          "; then ok "A opens the menu at Rate 1"; else nok "A opens the menu at Rate 1" "$($T capture-pane -p -t panel)"; fi
keys D 1 5 0 0 D                      # out of range: refused
if until_ok 5 line_is 4 "Range 10..1000  "; then ok "1500 L/ha is refused with 'Range 10..1000'"; else nok "1500 L/ha is refused" "$(lcd_line 4)"; fi
keys 2 0 0 D                          # 200 L/ha: 48 L/min, 3.8 bar at the nozzles (the relief opens at 5)
if until_ok 5 line_is 4 "Saved           " && lcd_line 3 | grep -q '200.0 L/ha'; then ok "200 L/ha is accepted and saved"; else
    nok "200 L/ha is accepted and saved" "$($T capture-pane -p -t panel | tail -12)"; fi
keys C                                # back to the run screen
until_ok 10 ratio_in "$before" 1.31 1.36
after=$(target)
if [ -n "$after" ] && [ -n "$before" ] && awk "BEGIN{r = $after / $before; exit !(r > 1.31 && r < 1.36)}"; then
    ok "the flow target follows the dose: $before -> $after L/min (x 4/3)"
else
    nok "the flow target follows the dose ($before -> '$after', 4/3 of it expected)" "$($T capture-pane -p -t panel | tail -12)"
fi
until_ok 45 follows                   # 30 s simulated or so for the valve and the controller
sleep 2                               # and still there 4 s simulated later
m=$(measured); a2=$(target)
if [ -n "$m" ] && [ -n "$a2" ] && awk "BEGIN{e = ($m - $a2) / $a2; exit !(e > -0.1 && e < 0.1)}"; then
    ok "the measured flow follows: $m L/min for $a2"
else
    nok "the measured flow follows within 10 % ('$m' for '$a2')" "$($T capture-pane -p -t panel | tail -12)"
fi

# the rate now follows the new dose (the job's average, still near 150, would not)
if until_ok 10 rate_close && [ "$(shown_rate)" -gt 185 ]; then ok "the rate now follows: $(shown_rate) L/ha for the truth's $(truth_rate) L/ha"; else
    nok "the rate now follows the new dose within 5 % ('$(shown_rate)' for '$(truth_rate)')" "$($T capture-pane -p -t panel | tail -12)"; fi

keys q
sleep 1
if $T capture-pane -p -t panel | grep -q 'km/h' && ! pgrep -f "$B/host/bin/panel --scenario $tmp" >/dev/null; then
    ok "q quits"
else
    nok "q quits"
fi

# an alarm raised while the first-boot notice shows takes the line; * acknowledges the alarm
# shown and says so; the notice is shown, then acknowledged, by presses of its own
cat > "$tmp/psens.scn" <<'EOF2'
[run]
duration_s = 600
[drive]
0   8
600 8
[events]
30  pressure_sensor_open
EOF2
$T new-session -d -s alarm -x 160 -y 50 \
    "$B/host/bin/panel --scenario $tmp/psens.scn --time 15 --speed 2; sleep 30"
$T kill-session -t panel 2>/dev/null    # (the new session first: the server stays up)
$T rename-session -t alarm panel
if until_ok 20 line_is 4 "!EE: defaults   "; then ok "the notice shows before the alarm"; else nok "the notice shows before the alarm" "$(lcd_line 4)"; fi
if until_ok 30 line_is 4 "!P sensor fault "; then ok "the alarm takes the line from the notice"; else
    nok "the alarm takes the line from the notice" "$($T capture-pane -p -t panel | tail -12)"; fi
keys '*'
if until_ok 5 line_is 3 "Acknowledged:   " && line_is 4 " P sensor fault "; then ok "* acknowledges the alarm shown and says which"; else
    nok "* acknowledges the alarm shown and says which" "$(lcd_line 3)/$(lcd_line 4)"; fi
sleep 3
if line_is 4 " P sensor fault "; then ok "the acknowledged alarm keeps the line over the notice"; else nok "the acknowledged alarm keeps the line" "$(lcd_line 4)"; fi
keys '*'
if until_ok 5 line_is 4 "!EE: defaults   "; then ok "* shows the notice before acknowledging it"; else nok "* shows the notice first" "$(lcd_line 4)"; fi
keys '*'
if until_ok 5 line_is 4 "EE: seen        "; then ok "* then acknowledges the notice"; else nok "* then acknowledges the notice" "$(lcd_line 4)"; fi
keys q

# the screenshot for the README: a PNG that decodes to the LCD image
if out=$("$B/host/bin/panel" --scenario "$tmp/const8.scn" --time 5 --keys 'A' --screenshot "$tmp/menu.png" 2>&1) &&
   echo "$out" | head -1 | grep -q '^Menu ' &&
   .venv/bin/python - "$tmp/menu.png" <<'EOF'
import sys
from PIL import Image
im = Image.open(sys.argv[1]).convert("RGB")
assert im.size == ((128 + 8) * 3, (64 + 8) * 3), im.size
colours = dict((c, n) for n, c in im.getcolors())
assert len(colours) == 2, colours
dark = colours.get((0x1E, 0x2A, 0x14), 0)
assert dark > 500, dark
EOF
then ok "--screenshot writes a PNG of the LCD that decodes"; else nok "--screenshot writes a PNG of the LCD that decodes" "$out"; fi

# `make screenshots`: each picture shows what the README's caption says (run in a scratch folder)
shots=$(make -n --no-print-directory screenshots 2>/dev/null | grep -- '--screenshot docs/panel_' | sed "s|docs/|$tmp/|")
want_run='^ *[0-9.]+km/h.*bar$|^Q .*L/mn$|^Now +[0-9]+L/ha AUTO$|^T +[0-9]+L +ffmap$'
want_menu='^Menu +[0-9]+/[0-9]+$|^Wheel cal *$'
want_refused='^Rate 1 *$|^Range 10\.\.1000 *$'
want_iotest='^P *[0-9]+ +[0-9.]+mA R1$|^L *[0-9]+ +[0-9.]+mA B0$|^W *[0-9]+ +[0-9]+Hz V.$|^M *[0-9]+ +[1-9][0-9]*Hz *$'
for name in run menu refused iotest; do
    cmd=$(echo "$shots" | grep -- "$tmp/panel_$name.png")
    eval "want=\$want_$name"
    n_want=$(echo "$want" | tr '|' '\n' | wc -l)
    if [ -n "$cmd" ] && text=$(cd . && eval "$cmd" 2>&1) && [ "$(echo "$text" | grep -cE "$want")" -ge "$n_want" ]; then
        ok "make screenshots: panel_$name.png shows its caption's screen"
    else
        nok "make screenshots: panel_$name.png shows its caption's screen" "$cmd"$'\n'"$text"
    fi
done

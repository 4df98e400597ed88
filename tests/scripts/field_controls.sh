#!/usr/bin/env bash
# field_controls.sh: the field image carries ffmap alone (params.h P_CTL_MIN/MAX, FW_PEERS): in its
# s51 build (hal/pil, the same sources as the chip's) the console's Control choice offers no
# controller the image lacks (the emulated LCD, sim --lcd), and the link refuses them; the host
# build, which carries all six, steps on to the next.
source "$(dirname "$0")/tap.sh" field_controls
IHX=$B/pil/sprayer_pil.ihx
SCN=tests/scripts/data/chip_short.scn
IN=tests/scripts/data/field_controls.input

if ! make -s --no-print-directory "$SIM" "$IHX" BUILD="$B" > "$tmp/build.log" 2>&1; then
    nok "the simulator and the s51 image build" "$(cat "$tmp/build.log")"
    exit 0
fi

# the choice after A, before D: the field image's stays ffmap; the host's goes on to aog
"$SIM" --pil "$IHX" --scenario $SCN --input $IN --lcd "$tmp/pil.lcd" --duration 2.6 > /dev/null 2>&1
"$SIM" --scenario $SCN --input $IN --lcd "$tmp/host.lcd" --duration 2.6 > /dev/null 2>&1
if [ "$(sed -n 1p "$tmp/pil.lcd")" = "Control         " ] && [ "$(sed -n 3p "$tmp/pil.lcd")" = "new        ffmap" ] \
   && [ "$(sed -n 3p "$tmp/host.lcd")" = "new          aog" ]; then
    ok "the field image's Control choice stays on ffmap (the host's, with six, goes on to aog)"
else
    nok "the field image's Control choice stays on ffmap (the host's, with six, goes on to aog)" \
        "$(cat "$tmp/pil.lcd" "$tmp/host.lcd")"
fi

# the link: SET 8 2 and 8 4 refused (RANGE), 8 3 taken, GET 8 answers 3
"$SIM" --pil "$IHX" --scenario $SCN --input $IN --serial "$tmp/pil.serial" --duration 4 > /dev/null 2>&1
got=$(grep -v '^LOG\|^BOOT\|^EE ' "$tmp/pil.serial" | tr -d '\r' | sed 's/\*..$//' | tr '\n' '|')
if [ "$got" = "ERR RANGE|ERR RANGE|OK 8 3|OK 8 3|" ]; then
    ok "the field image's link refuses Control 2 and 4 and takes 3"
else
    nok "the field image's link refuses Control 2 and 4 and takes 3" "$got"
fi

# --lcd refuses a file it cannot write, in one line
if "$SIM" --scenario $SCN --lcd /nonexistent/x.lcd --duration 0.5 > /dev/null 2> "$tmp/err"; then
    nok "--lcd refuses a file it cannot write"
else
    grep -q "^sim: --lcd: /nonexistent/x.lcd: " "$tmp/err" && ok "--lcd refuses a file it cannot write, in one line" \
        || nok "--lcd refuses a file it cannot write, in one line" "$(cat "$tmp/err")"
fi
"$SIM" --scenario $SCN --chip "$B/stc12/sprayer.ihx" --lcd "$tmp/c.lcd" > /dev/null 2> "$tmp/err"
rc=$?
[ $rc -eq 2 ] && grep -q "^sim: --lcd and --chip: " "$tmp/err" && [ ! -e "$tmp/c.lcd" ] \
    && ok "--lcd with --chip is refused in one line, before any run (the model does not decode the LCD)" \
    || nok "--lcd with --chip is refused in one line, before any run" "rc $rc: $(cat "$tmp/err")"

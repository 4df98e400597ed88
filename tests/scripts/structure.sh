#!/usr/bin/env bash
# structure.sh: no file in firmware/, hal/ or sim/ over 500 lines and no function over 80
# (tools/sizes.py); and the check fails on a function made too long in a copy of the tree.
set -uo pipefail
cd "$(dirname "$0")/../.."
for dir in firmware hal sim; do
    if out=$(python3 tools/sizes.py $dir 2>&1); then
        echo "ok - sizes of $dir/: $(echo "$out" | tail -1 | sed 's/^sizes: //')"
    else
        echo "not ok - sizes of $dir/"; echo "$out" | sed 's/^/#   /'
    fi
done
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
cp -r firmware "$tmp/"
{ echo "void too_long(void)"; echo "{"; for i in $(seq 90); do echo "    hal_wdt_kick();"; done; echo "}"; } >> "$tmp/firmware/math/fixed.c"
if python3 tools/sizes.py "$tmp/firmware" > "$tmp/out" 2>&1; then
    echo "not ok - sizes check catches a 92-line function"
else
    echo "ok - sizes check catches a 92-line function: $(grep -c 'too_long' "$tmp/out") found"
fi

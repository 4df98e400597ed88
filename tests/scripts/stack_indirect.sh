#!/usr/bin/env bash
# stack_indirect.sh: tools/stackdepth.py follows the one call through a function pointer (learnt.c's
# store_learnt_now calls what store_learnt_from registered: INDIRECT), so the image's static stack
# figure includes that callee's depth; and it refuses an indirect call it is not told about (the
# function renamed in a copy of the image's assembly) rather than print a figure that misses it.
. "$(dirname "$0")/tap.sh" "stack depth"
[ -f "$B/stc12/firmware/store/learnt.asm" ] || make --no-print-directory -j2 firmware BUILD="$B" > /dev/null 2>&1
if out=$(python3 - "$B/stc12" <<'PY' 2>&1
import sys
sys.path.insert(0, "tools")
import stackdepth as s
f = s.parse(sys.argv[1])
memo = {}
outer, inner = s.deepest(f, "_store_learnt_now", memo, []), s.deepest(f, "_diag_learnt_byte", memo, [])
print("store_learnt_now %d B, diag_learnt_byte %d B" % (outer, inner))
sys.exit(0 if outer >= inner + 2 else 1)
PY
); then
    ok "it follows the learnt figures' pointer: $out"
else
    nok "it follows the learnt figures' pointer" "$out"
fi
(cd "$B/stc12" && find . -name '*.asm' -exec cp --parents {} "$tmp/" \;)
sed -i 's/^;\t function store_learnt_now$/;\t function store_learnt_now_renamed/' "$tmp/firmware/store/learnt.asm"
if python3 tools/stackdepth.py "$tmp" > "$tmp/out" 2>&1; then
    nok "it refuses an indirect call it does not know" "$(cat "$tmp/out")"
elif grep -q "store_learnt_now_renamed calls through a function pointer" "$tmp/out"; then
    ok "it refuses an indirect call it does not know: $(cat "$tmp/out")"
else
    nok "it refuses an indirect call it does not know: not as itself" "$(cat "$tmp/out")"
fi

#!/usr/bin/env bash
# symbol_graph.sh: firmware/'s objects call and read only down the layers and write only their
# own layer's globals (tools/symgraph.py over the host objects, its allow file); and the check
# fails on each defect planted alone in a copy of the tree, where no include shows it: an upward
# call (store -> ops, the prototype written in place) and foreign writes (control -> store; app
# -> the status block ops owns).
. "$(dirname "$0")/tap.sh" "symbol graph"
allow=tools/symgraph_allow.txt
if out=$(python3 tools/symgraph.py firmware --allow $allow 2>&1); then
    ok "$(echo "$out" | tail -1 | sed 's/^symgraph: //')"
else
    nok "the firmware's objects" "$out"
fi
# plant NAME WANT FILE TEXT: TEXT appended to FILE of a fresh copy; the check must fail on WANT
# alone (one problem, naming WANT)
plant() {
    local name=$1 want=$2
    rm -rf "$tmp/firmware" && cp -r firmware "$tmp/"
    printf '%s\n' "$4" >> "$tmp/firmware/$3"
    if python3 tools/symgraph.py "$tmp/firmware" --allow $allow > "$tmp/out" 2>&1; then
        nok "the check catches $name" "$(cat "$tmp/out")"
    elif ! grep -q "^symgraph: $want" "$tmp/out" || ! grep -q " 1 problems$" "$tmp/out"; then
        nok "the check catches $name: not as $want alone" "$(cat "$tmp/out")"
    else
        ok "the check catches $name: $(grep "^symgraph: $want" "$tmp/out" | sed 's/^symgraph: //')"
    fi
}
plant "a planted upward call (learnt.c -> diag_learnt_byte)" "upward call: store/learnt.c -> diag_learnt_byte" \
    store/learnt.c 'uint8_t diag_learnt_byte(uint8_t i); uint8_t store_planted(void) { return diag_learnt_byte(0); }'
plant "a planted foreign write (target.c -> totals)" "foreign write: control/target.c -> totals" \
    control/target.c '#include "totals.h"
void target_planted(void) { totals.life_m2 = 0; }'
plant "a planted write of the status from above (app.c -> app_status)" "foreign write: app/app.c -> app_status" \
    app/app.c 'void app_planted(void) { app_status.tank_l = 0; }'

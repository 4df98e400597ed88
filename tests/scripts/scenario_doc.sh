#!/usr/bin/env bash
# scenario_doc.sh: docs/SCENARIOS.md lists every key and event the scenario reader accepts (the repository documents itself).
set -uo pipefail
cd "$(dirname "$0")/../.."
doc=docs/SCENARIOS.md
ok() { echo "ok - scenario_doc: $1"; }
nok() { echo "not ok - scenario_doc: $1"; }
plant=$(sed -n 's/^ *X(\([a-z0-9_]*\), .*/\1/p' sim/plant.h)
config=$(sed -n 's/^ *{"\([a-z0-9_]*\)", P_.*/\1/p' sim/scenario_keys.c)
events=$(sed -n 's/^ *X(EV_[A-Z_]*, *"\([a-z_]*\)".*/\1/p' sim/scenario.h)
for kind in plant config events; do
    list=${!kind}
    n=$(echo "$list" | wc -w)
    missing=""
    for k in $list; do grep -q "\`$k\`" "$doc" || missing="$missing $k"; done
    if [ "$n" -gt 5 ] && [ -z "$missing" ]; then ok "every $kind key ($n) is in $doc"; else nok "every $kind key is in $doc (of $n, missing:$missing)"; fi
done
grep -rq "PLANT\.md" README.md sim tools docs hal firmware Makefile $(ls tests/*/*.[ch] 2>/dev/null) 2>/dev/null && nok "nothing points outside the repository (../shared/PLANT.md)" || ok "nothing points outside the repository (../shared/PLANT.md)"

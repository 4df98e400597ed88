#!/usr/bin/env bash
# targets.sh: every target the README names (its two commands and its table of targets) is a target
# of the Makefile and is listed by `make help`; the check fails on a name planted in a copy of the README.
set -uo pipefail
cd "$(dirname "$0")/../.."
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
ok() { echo "ok - targets: $1"; }
nok() { echo "not ok - targets: $1"; [ -n "${2:-}" ] && echo "$2" | head -5 | sed 's/^/#   /'; }

make -qp 2>/dev/null | grep -E '^[a-z][a-z-]*:' | cut -d: -f1 | sort -u > "$tmp/made"
make --no-print-directory help > "$tmp/help"
# readme_targets FILE: the X of `make X` in the two commands' block and in the first cell of the table rows
readme_targets() {
    { sed -n '/^## Two commands/,/^## /p' "$1" | grep -oE '^make [a-z][a-z-]*' | cut -d' ' -f2
      grep -E '^\| `make' "$1" | cut -d'|' -f2 | grep -oE '`make [a-z][a-z-]*' | cut -d' ' -f2
    } | sort -u
}
check() {  # check README: the names missing from the Makefile or from make help, one a line
    local t
    for t in $(readme_targets "$1"); do
        grep -qx "$t" "$tmp/made" || echo "$t: no such Makefile target"
        grep -qE "^ *make $t( |$)" "$tmp/help" || echo "$t: not in make help"
    done
}
n=$(readme_targets README.md | wc -l)
bad=$(check README.md)
if [ "$n" -ge 18 ] && [ -z "$bad" ]; then
    ok "the README's $n targets are the Makefile's and make help lists each"
else
    nok "the README's targets are the Makefile's and make help lists each ($n found)" "$bad"
fi
sed 's/^| `make bench-sim` |/| `make bench-fast` |/' README.md > "$tmp/README.md"
bad=$(check "$tmp/README.md")
if echo "$bad" | grep -q "^bench-fast: no such Makefile target" && echo "$bad" | grep -q "^bench-fast: not in make help"; then
    ok "the check catches a target the README names and the Makefile does not have"
else
    nok "the check catches a target the README names and the Makefile does not have" "$bad"
fi

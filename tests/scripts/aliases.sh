#!/usr/bin/env bash
# aliases.sh: no macro in firmware/, hal/ or sim/ names a variable's member or element (one name,
# one meaning: tools/aliases.py); the check catches planted aliases and passes real expressions.
set -uo pipefail
cd "$(dirname "$0")/../.."
if out=$(python3 tools/aliases.py firmware hal sim 2>&1); then
    echo "ok - no aliases: $(echo "$out" | tail -1)"
else
    echo "not ok - no aliases"; echo "$out" | sed 's/^/#   /'
fi
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
cat > "$tmp/a.h" <<'HEOF'
#define con_io (con.u.io)
#define M (&ctl_st.fm)
#define first_q   q_tab[0]   /* a comment */
#define N_OK (sizeof(con.u.io))
#define SUM_OK (a.b + 1)
#define CALL_OK (f(x).y)
#define NUM_OK 42u
HEOF
if python3 tools/aliases.py "$tmp" > "$tmp/out" 2>&1; then
    echo "not ok - the check catches planted aliases"; sed 's/^/#   /' "$tmp/out"
else
    names=$(grep -o ': [A-Za-z_]* ->' "$tmp/out" | tr -d ':>-' | tr -s ' ' | xargs)
    [ "$names" = "con_io M first_q" ] && echo "ok - the check catches planted aliases ($names), not expressions" \
        || { echo "not ok - the check catches planted aliases, not expressions"; sed 's/^/#   /' "$tmp/out"; }
fi

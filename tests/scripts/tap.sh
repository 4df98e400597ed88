# tap.sh NAME, sourced by a script of tests/scripts: the repository's root as the working folder,
# B (the build folder), SIM and PY, a temporary folder $tmp removed on exit, and ok / nok printing
# the TAP lines "ok - NAME: ..." (nok's second argument: up to five lines of detail).
set -uo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
TAP_NAME=$1
B=${BUILD:-build}
SIM=$B/host/bin/sim
PY=.venv/bin/python
[ -x "$PY" ] || PY=python3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
ok() { echo "ok - $TAP_NAME: $1"; }
nok() { echo "not ok - $TAP_NAME: $1"; [ -n "${2:-}" ] && echo "$2" | head -5 | sed 's/^/#   /'; }

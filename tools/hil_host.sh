#!/usr/bin/env bash
# hil_host.sh BIN_DIR SCENARIO [hil options...]: hardware in the loop without hardware: the host build
# stands in for the board (BIN_DIR/hilboard on a pseudo-terminal) and BIN_DIR/hil runs SCENARIO
# against it as against a flashed board; prints what hil prints (the metrics JSON last), exits as hil.
set -uo pipefail
bin=$1 scn=$2; shift 2
tmp=$(mktemp -d)
trap 'kill $board 2>/dev/null; rm -rf "$tmp"' EXIT
"$bin/hilboard" --wait 30 2> "$tmp/board.err" &
board=$!
for _ in $(seq 100); do grep -qs "serial link on" "$tmp/board.err" && break; sleep 0.05; done
port=$(sed -n 's/.*serial link on \([^ ]*\).*/\1/p' "$tmp/board.err")
if [ -z "$port" ]; then
    echo "hil-host: the stand-in board did not start: $(cat "$tmp/board.err")" >&2
    exit 1
fi
"$bin/hil" --scenario "$scn" --port "$port" --pace 0 "$@"
rc=$?
kill $board 2>/dev/null     # it ends by itself when hil closes the port; not when hil never opened it
wait $board 2>/dev/null
exit $rc

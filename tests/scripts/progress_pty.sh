#!/usr/bin/env bash
# progress_pty.sh: the progress line of long host commands (sim/progress.c, tools/progress.py) shows on a terminal (a pty), never in a pipe, a log or CI.
source "$(dirname "$0")/tap.sh" progress

if ! make -s --no-print-directory "$SIM" BUILD="$B" > "$tmp/build.log" 2>&1; then
    nok "the simulator builds" "$(cat "$tmp/build.log")"
    exit 0
fi
printf '[run]\nduration_s = 3600\n[drive]\n0 8\n3600 8\n' > "$tmp/long.scn"

# on_pty OUT ENV... -- CMD...: CMD with its stderr (and stdin) on a pseudo-terminal, stdout to a
# file; what the terminal received into OUT
cat > "$tmp/on_pty.py" <<'PYEOF'
import os, pty, select, subprocess, sys
out_path = sys.argv[1]
i = sys.argv.index("--")
env = dict(os.environ)
env.pop("CI", None)
for kv in sys.argv[2:i]:
    k, v = kv.split("=", 1)
    env[k] = v
m, s = pty.openpty()
with open(out_path + ".stdout", "w") as so:
    p = subprocess.Popen(sys.argv[i + 1:], stdin=s, stdout=so, stderr=s, env=env)
os.close(s)
got = b""
while True:
    r, _, _ = select.select([m], [], [], 0.2)
    if r:
        try:
            d = os.read(m, 65536)
        except OSError:
            d = b""
        if not d:
            break
        got += d
    elif p.poll() is not None:
        break
sys.exit(p.wait() or open(out_path, "wb").write(got) * 0)
PYEOF

# the simulator on a terminal: the line shows (done / total, elapsed, estimate), is cleared at
# the end, and the JSON on stdout is untouched
if $PY "$tmp/on_pty.py" "$tmp/tty.txt" PROGRESS_AFTER_S=0 -- "$SIM" --scenario "$tmp/long.scn" &&
   grep -aqE 'sim: [0-9]+ / 3600 s simulated, [0-9]+:[0-9]{2} elapsed, about [0-9]+:[0-9]{2} left' "$tmp/tty.txt" &&
   [ "$(tail -c 4 "$tmp/tty.txt" | od -An -c | tr -d ' ')" = '\r033[K' ] &&
   tail -n 1 "$tmp/tty.txt.stdout" | $PY -c 'import json, sys; assert json.loads(sys.stdin.read())["sim_s"] == 3600'; then
    ok "sim on a terminal: '$(tr '\r' '\n' < "$tmp/tty.txt" | grep -a 'simulated' | tail -n 1 | sed 's/\x1b\[K//')'"
else
    nok "sim on a terminal shows its progress" "$(od -c "$tmp/tty.txt" | tail -5)"
fi
# ... and nothing in a pipe (make test's log), nor on a terminal with CI set
err=$(PROGRESS_AFTER_S=0 "$SIM" --scenario "$tmp/long.scn" 2>&1 >/dev/null)
if [ -z "$err" ]; then ok "sim in a pipe: nothing on stderr"; else nok "sim in a pipe: nothing on stderr" "$err"; fi
if $PY "$tmp/on_pty.py" "$tmp/ci.txt" PROGRESS_AFTER_S=0 CI=1 -- "$SIM" --scenario "$tmp/long.scn" && [ ! -s "$tmp/ci.txt" ]; then
    ok "sim on a terminal under CI: nothing"
else
    nok "sim on a terminal under CI: nothing" "$(od -c "$tmp/ci.txt" | head -3)"
fi
# ... and nothing on a terminal for a run shorter than the few seconds it waits
if $PY "$tmp/on_pty.py" "$tmp/short.txt" -- "$SIM" --scenario "$tmp/long.scn" --duration 60 && [ ! -s "$tmp/short.txt" ]; then
    ok "a short sim run on a terminal: nothing"
else
    nok "a short sim run on a terminal: nothing" "$(od -c "$tmp/short.txt" | head -3)"
fi

# the tools' pool (make faults here, one fault: two runs) on a terminal, then in a pipe
if $PY "$tmp/on_pty.py" "$tmp/faults.txt" PROGRESS_AFTER_S=0 -- $PY tools/faults.py "$SIM" --only leak_growing --jobs 1 --out "$tmp/f1" &&
   grep -aqE 'faults: [12] / 2 runs, [0-9]+:[0-9]{2} elapsed, about [0-9]+:[0-9]{2} left' "$tmp/faults.txt" &&
   grep -q 'Leak past meter' "$tmp/f1/table.md"; then
    ok "make faults on a terminal: '$(tr '\r' '\n' < "$tmp/faults.txt" | grep -a ' runs, ' | tail -n 1 | sed 's/\x1b\[K//')'"
else
    nok "make faults on a terminal shows its progress" "$(od -c "$tmp/faults.txt" | tail -5)"
fi
err=$(PROGRESS_AFTER_S=0 $PY tools/faults.py "$SIM" --only leak_growing --jobs 1 --out "$tmp/f2" 2>&1 >/dev/null)
if [ -z "$err" ]; then ok "make faults in a pipe: nothing on stderr"; else nok "make faults in a pipe: nothing on stderr" "$err"; fi

#!/usr/bin/env bash
# deps.sh: install what the build needs on a Debian machine; quick and silent when all is there.
#   apt: sdcc (with stc12.h), sdcc-ucsim (s51), libcmocka-dev, tmux; with --fuzz also clang (libFuzzer);
#   Python: .venv from tools/requirements.txt
set -euo pipefail
cd "$(dirname "$0")/.."
quiet=0 fuzz=0
for a in "$@"; do
    case "$a" in
        --quiet) quiet=1 ;;
        --fuzz) fuzz=1 ;;   # make fuzz: clang with libFuzzer and the sanitizers' runtimes
        *) echo "deps: unknown option $a (--quiet, --fuzz)" >&2; exit 2 ;;
    esac
done
say() { [ $quiet = 1 ] || echo "deps: $*"; }

missing=()
command -v sdcc >/dev/null 2>&1 || missing+=(sdcc)
command -v s51 >/dev/null 2>&1 || missing+=(sdcc-ucsim)
[ -f /usr/include/cmocka.h ] || missing+=(libcmocka-dev)
command -v tmux >/dev/null 2>&1 || missing+=(tmux)
if [ $fuzz = 1 ]; then
    # Debian's clang carries libFuzzer (libclang-rt-*-dev, a dependency of clang-14)
    command -v clang >/dev/null 2>&1 || missing+=(clang)
fi
if [ ${#missing[@]} -gt 0 ]; then
    echo "deps: installing ${missing[*]} (apt)"
    sudo=""
    if [ "$(id -u)" != 0 ]; then sudo="sudo"; fi
    export DEBIAN_FRONTEND=noninteractive
    $sudo apt-get update -qq
    $sudo apt-get install -y -qq "${missing[@]}" >/dev/null
fi

stamp=.venv/.requirements
if [ ! -f "$stamp" ] || ! cmp -s tools/requirements.txt "$stamp"; then
    echo "deps: creating .venv from tools/requirements.txt"
    python3 -m venv .venv
    .venv/bin/pip install -q --disable-pip-version-check -r tools/requirements.txt
    cp tools/requirements.txt "$stamp"
fi
say "sdcc $(sdcc --version 2>/dev/null | head -1 | grep -o '[0-9]\.[0-9]\.[0-9]' | head -1), s51, cmocka,$([ $fuzz = 1 ] && echo " clang,") .venv: ready"

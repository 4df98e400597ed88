#!/usr/bin/env bash
# run_tests.sh: every test of the project; TAP lines, then one line "N passed, N failed".
#   host unit tests (cmocka, ASan+UBSan), target tests (s51 vs host, bit for bit), the firmware
#   build and its memory check, the fuzz corpus replayed (tests/fuzz/), and the script tests in
#   tests/scripts/*.sh (they print TAP lines).
set -uo pipefail
cd "$(dirname "$0")/.."
export MAKEFLAGS="${MAKEFLAGS:-} --no-print-directory"
JOBS=${JOBS:-$(nproc 2>/dev/null || echo 2)}
pass=0 fail=0
B=${BUILD:-build}
export BUILD=$B
log=$B/test-logs
mkdir -p "$log"

tap() {  # count the "ok" / "not ok" lines of a stream, echoing them
    local line
    while IFS= read -r line; do
        case "$line" in
            "ok "*) pass=$((pass + 1)); echo "$line" ;;
            "not ok "*) fail=$((fail + 1)); echo "$line" ;;
            "#"*) echo "$line" ;;
        esac
    done
}
check() {  # check NAME COMMAND...: one test from a command's exit status
    local name=$1; shift
    if "$@" > "$log/$name.log" 2>&1; then
        pass=$((pass + 1)); echo "ok - $name"
    else
        fail=$((fail + 1)); echo "not ok - $name (see $log/$name.log)"; tail -5 "$log/$name.log" | sed 's/^/#   /'
    fi
}

echo "# building host tests, target tests and the firmware"
check build-host-tests make -j"$JOBS" host-tests
check build-target-tests make -j"$JOBS" target-tests
check firmware-builds-within-memory make -j"$JOBS" firmware
grep -E '^(memory|stack):' "$log/firmware-builds-within-memory.log" | sed 's/^/# /'
check bench-image-fits-the-chip make -j"$JOBS" firmware HIL=1
check research-image-fits-the-chip make -j"$JOBS" firmware FW_PEERS=1

echo "# host unit tests"
for t in $B/host-test/test_*; do
    [ -x "$t" ] || continue
    name=$(basename "$t")
    out=$(CMOCKA_MESSAGE_OUTPUT=TAP timeout 1800 "$t" 2>&1); rc=$?
    echo "$out" > "$log/$name.log"
    before=$((pass + fail))
    tap < <(echo "$out" | sed -E "s/^(not ok|ok) [0-9]+ - /\1 - $name: /" | grep -E '^(ok|not ok) - ')
    if [ $rc -ne 0 ] && [ $((pass + fail)) -eq $before ]; then
        fail=$((fail + 1)); echo "not ok - $name crashed (rc $rc, see $log/$name.log)"
    elif [ $rc -ne 0 ] && ! echo "$out" | grep -q '^not ok [0-9]'; then
        fail=$((fail + 1)); echo "not ok - $name exited $rc (see $log/$name.log)"
    fi
done

echo "# fuzz corpus replay: every kept input of tests/fuzz/corpus/<t> through its harness (gcc, ASan, UBSan)"
for r in $B/host-test/fuzz/replay_*; do
    [ -x "$r" ] || continue
    t=${r##*/replay_}
    check "fuzz-corpus-$t-($(ls tests/fuzz/corpus/$t | wc -l)-inputs)" timeout 600 "$r" "tests/fuzz/corpus/$t"
done

echo "# target tests: the SDCC build in s51 against the host build"
for ihx in $B/ucsim/tt_*.ihx; do
    [ -f "$ihx" ] || continue
    name=$(basename "$ihx" .ihx)
    tap < <(tools/run_target.sh "$ihx" "$B/host-test/target/$name" $B/ucsim)
done

echo "# the checks can fail"
overflow_fails() {  # a code size smaller than the image must stop the build
    if make firmware BUILD=$B/overflow-check CODE_SIZE=4096; then return 1; fi
    return 0
}
check firmware-overflow-fails-the-build overflow_fails
stack_check_fails() {  # the static stack-depth check must refuse an image given too little stack
    ! python3 tools/stackdepth.py $B/stc12 --free 16
}
check stack-depth-check-refuses-too-little-stack stack_check_fails
floor_fails() {  # floor_fails VAR=VALUE: the same image under a floor it does not meet must fail the build
    make firmware "$1" > "$log/floor.out" 2>&1 && return 1
    grep -q 'BELOW THE FLOOR' "$log/floor.out"
}
check firmware-below-the-code-floor-fails floor_fails CODE_FREE_PCT=50
check firmware-below-the-xdata-floor-fails floor_fails XRAM_FREE_MIN=900
check firmware-below-the-stack-margin-floor-fails floor_fails STACK_MARGIN_MIN=200
calls_match() {  # every call passes its arguments the way the callee takes them (s51 builds too)
    python3 tools/callcheck.py --tree $B/ucsim
}
check calls-pass-arguments-as-the-callee-takes-them calls_match
callcheck_catches() {  # a caller pushing the second argument of a callee that reads it from XRAM
    local d=$B/callcheck-check
    rm -rf "$d" && mkdir -p "$d"
    printf '_f:\n\tmov dptr,#_f_PARM_2\n\tret\n_f_PARM_2:\n\t.ds 1\n' > "$d/callee.asm"
    printf '_g:\n\tpush acc\n\tlcall _f\n\tdec sp\n\tret\n' > "$d/caller.asm"
    ! python3 tools/callcheck.py "$d"
}
check callcheck-catches-a-pushed-argument-read-from-xram callcheck_catches
sabotage_is_caught() {  # sabotage_is_caught N: routine N of mul.h's FX_SABOTAGE list wrong on the target only must break the comparison
    make sabotage SAB="$1" || return 1
    ! tools/run_target.sh $B/ucsim/sabotage-$1/tt_ops.ihx $B/host-test/target/tt_ops $B/ucsim/sabotage-$1
}
n=0
for r in mul_ab mac_ab dot_ab upd_ab umul_ab mul_r15 mul_r12 acc_shr15 acc_shr12 fx_sat16 fx_tanh \
         um_mul32x16_shr16 um_muldiv um_scaled_div; do
    n=$((n + 1))
    check "target-comparison-catches-$r-wrong" sabotage_is_caught $n
done

echo "# mutation sample: 5 mutants of the safety rules (tools/mutate.py; make mutate runs them all)"
mutate_seed=${MUTATE_SEED:-$((RANDOM % 10000))}
echo "# mutation sample seed $mutate_seed (MUTATE_SEED=$mutate_seed repeats it)"
check "mutation-sample-seed-$mutate_seed-no-survivor" make mutate MUTATE_ARGS="--sample 5 --seed $mutate_seed"
grep -E '^(killed|SURVIVED)' "$log/mutation-sample-seed-$mutate_seed-no-survivor.log" | sed 's/^/# /'

for s in tests/scripts/*.sh; do
    [ -x "$s" ] || continue
    echo "# $(basename "$s")"
    tap < <(timeout 1800 "$s" 2>&1 | tee "$log/$(basename "$s").log"; echo "# rc ${PIPESTATUS[0]}" > "$log/$(basename "$s").rc")
    # a script that breaks itself (a shell error, a crash) has skipped its later checks: a failure
    if grep -qE '^[^ ]+\.sh: line [0-9]+: |unbound variable|syntax error' "$log/$(basename "$s").log" \
       || { ! grep -q '^# rc 0$' "$log/$(basename "$s").rc" && ! grep -q '^not ok' "$log/$(basename "$s").log"; }; then
        fail=$((fail + 1)); echo "not ok - $(basename "$s") broke off: $(cat "$log/$(basename "$s").rc") (see $log/$(basename "$s").log)"
        grep -E '\.sh: line [0-9]+: ' "$log/$(basename "$s").log" | head -3 | sed 's/^/#   /'
    fi
done

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]

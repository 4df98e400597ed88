#!/usr/bin/env bash
# chip_reverts.sh [NAME..]: each HAL fix of tests/scripts/data/chip_revert_NAME.patch undone in a
# copy of the tree (build/reverts/NAME), the field image built there (CODE_FREE_PCT=0: a revert
# may cross a floor) and tests/scripts/chip.sh run on it: the chip test that guards the fix must
# fail. Prints each revert's TAP lines and "caught" or "NOT CAUGHT". Minutes a revert.
set -uo pipefail
cd "$(dirname "$0")/.."
root=$PWD
names=("$@")
[ ${#names[@]} -gt 0 ] || names=(pca_race port_modes stackauto_save)
declare -A guard=([pca_race]="wheel edges swept" [port_modes]="after init the H-bridge" [stackauto_save]="saved by the field image")
status=0
for n in "${names[@]}"; do
    d=build/reverts/$n
    rm -rf "$d" && mkdir -p "$d"
    git ls-files | tar cf - -T - | tar xf - -C "$d"
    ln -s "$root/.venv" "$d/.venv"
    patch -s -p1 -d "$d" < tests/scripts/data/chip_revert_$n.patch || { echo "$n: the patch does not apply"; status=1; continue; }
    make -C "$d" -s --no-print-directory firmware CODE_FREE_PCT=0 > "$d/firmware.log" 2>&1
    if [ ! -f "$d/build/stc12/sprayer.ihx" ]; then
        echo "$n: the reverted image does not build ($d/firmware.log)"; status=1; continue
    fi
    out=$(CHIP_IHX="$d/build/stc12/sprayer.ihx" bash tests/scripts/chip.sh 2>&1)
    echo "# $n"
    echo "$out" | grep -E '^(ok|not ok)' | sed 's/^/  /'
    if echo "$out" | grep -q "^not ok - chip: .*${guard[$n]}"; then
        echo "$n: caught"
    else
        echo "$n: NOT CAUGHT"; status=1
    fi
done
exit $status

#!/usr/bin/env bash
# share_moves.sh: tools/share_moves.py replaces exactly its sequences by calls of routines that
# hold exactly those instructions (firmware/math/moves*.c), and leaves alone a sequence with a
# label inside (a jump into its middle) or one cut short.
set -uo pipefail
cd "$(dirname "$0")/../.."
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# every MOVES entry has a routine in moves.c, moves_short.c, moves_arith.c, moves_more.c or
# moves_late.c with
# the same instructions, then RET, and no other
if out=$(python3 - <<'EOF' 2>&1
import re, sys
sys.path.insert(0, "tools")
from share_moves import MOVES, norm
asm = "".join(re.search(r"__asm(.*?)__endasm;", open(f).read(), re.S).group(1)
              for f in ("firmware/math/moves.c", "firmware/math/moves_short.c",
                        "firmware/math/moves_arith.c", "firmware/math/moves_more.c",
                        "firmware/math/moves_late.c"))
found, cur = {}, None
for line in asm.splitlines():
    m = re.match(r"\s*_mv_(\w+)::\s*$", line)
    if m:
        cur = found.setdefault(m.group(1), [])
    elif cur is not None and norm(line) is not None:
        cur.append(norm(line))
bad = [n for n in MOVES if found.get(n) != MOVES[n] + ["ret"]]
bad += [n for n in found if n not in MOVES]
if bad:
    sys.exit("routines that differ from MOVES: " + ", ".join(sorted(bad)))
print("%d routines" % len(found))
EOF
); then
    echo "ok - share_moves: moves.c, moves_short.c, moves_arith.c, moves_more.c and moves_late.c hold each sequence exactly, then RET ($out)"
else
    echo "not ok - share_moves: moves.c, moves_short.c, moves_arith.c, moves_more.c and moves_late.c hold each sequence exactly"; echo "$out" | sed 's/^/#   /'
fi

# a whole sequence (a C line comment inside it kept) is replaced; one with a label inside, or
# cut short, is not (the sets before the later round: its shorter z_ld_r5a would take the rest)
cat > "$tmp/a.asm" <<'EOF'
_f:
	mov	dptr,#_x
	movx	a,@dptr
	mov	r4,a
	inc	dptr
;	a.c:3: the comment stays
	movx	a,@dptr
	mov	r5,a
	inc	dptr
	movx	a,@dptr
	mov	r6,a
	inc	dptr
	movx	a,@dptr
	mov	r7,a
	mov	dptr,#_y
	movx	a,@dptr
	mov	r4,a
	inc	dptr
00101$:
	movx	a,@dptr
	mov	r5,a
	inc	dptr
	movx	a,@dptr
	mov	r7,a
	inc	dptr
	movx	a,@dptr
	mov	r3,a
	mov	dpl,r4
	mov	b,r6
	ret
EOF
python3 tools/share_moves.py --skip=z_ "$tmp/a.asm"
calls=$(grep -c 'lcall' "$tmp/a.asm")
if [ "$calls" -eq 1 ] && grep -q 'lcall	_mv_ld_r4567' "$tmp/a.asm" && grep -q 'the comment stays' "$tmp/a.asm" \
    && grep -q '^00101\$:' "$tmp/a.asm" && [ "$(grep -c 'movx	a,@dptr' "$tmp/a.asm")" -eq 4 ]; then
    echo "ok - share_moves: a whole sequence becomes one call; one a label cuts, or one cut short, stays"
else
    echo "not ok - share_moves: replacement"; sed 's/^/#   /' "$tmp/a.asm"
fi

# the later round (z_) is a second pass: the sets before share first (ld_r56, not z_ld_r5a and
# a move left), and it takes what they left (z_ld_r5a before a move of its own)
seq=$'\tmovx\ta,@dptr\n\tmov\tr5,a\n\tinc\tdptr\n\tmovx\ta,@dptr\n'
printf '_g:\n%s\tmov\tr6,a\n\tret\n_h:\n%s\tmov\tr2,a\n\tret\n' "$seq" "$seq" > "$tmp/c.asm"
python3 tools/share_moves.py "$tmp/c.asm"
if [ "$(grep -c 'lcall' "$tmp/c.asm")" -eq 2 ] \
    && [ "$(sed -n '/^_g:/,/^_h:/p' "$tmp/c.asm" | grep -c 'lcall	_mv_ld_r56')" -eq 1 ] \
    && [ "$(sed -n '/^_h:/,$p' "$tmp/c.asm" | grep -c 'lcall	_mv_z_ld_r5a')" -eq 1 ]; then
    echo "ok - share_moves: the later round's sequences share after the sets before"
else
    echo "not ok - share_moves: the later round"; sed 's/^/#   /' "$tmp/c.asm"
fi

# --skip-func=NAME leaves that function alone (a controller's step) and shares in the others
seq=$'\tmovx\ta,@dptr\n\tmov\tr6,a\n\tinc\tdptr\n\tmovx\ta,@dptr\n\tmov\tr7,a\n'
printf '_step:\n%s\tret\n_derive:\n%s\tret\n' "$seq" "$seq" > "$tmp/b.asm"
python3 tools/share_moves.py --skip-func=step "$tmp/b.asm"
if [ "$(grep -c 'lcall' "$tmp/b.asm")" -eq 1 ] \
    && [ "$(sed -n '/^_derive:/,$p' "$tmp/b.asm" | grep -c 'lcall	_mv_ld_r67')" -eq 1 ]; then
    echo "ok - share_moves: --skip-func leaves the named function alone, the next one shares"
else
    echo "not ok - share_moves: --skip-func"; sed 's/^/#   /' "$tmp/b.asm"
fi

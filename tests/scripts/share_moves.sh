#!/usr/bin/env bash
# share_moves.sh: tools/share_moves.py generates from its one table routines that hold exactly
# its sequences, then RET (assembled by sdas to the bytes its size model counts); it replaces a
# whole sequence by a call, leaves alone one with a label inside (a jump into its middle) or one
# cut short, covers overlapping candidates at the fewest bytes, jumps where the function returns
# right after, and uses only the hot routines in the functions --hot names.
set -uo pipefail
cd "$(dirname "$0")/../.."
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
SDAS=${SDAS:-sdas8051}

# the generated modules: one a routine, each exactly its table entry then RET, assembled to
# the size share_moves.py counts (its choice of cover rests on those sizes)
python3 tools/share_moves.py --gen "$tmp/gen"
for f in "$tmp"/gen/*.asm; do "$SDAS" -plosgffw "${f%.asm}.rel" "$f" || echo "sdas failed: $f"; done > "$tmp/sdas.log" 2>&1
if out=$(python3 - "$tmp/gen" <<'EOF' 2>&1
import glob, os, re, sys
sys.path.insert(0, "tools")
from share_moves import ROUTINES, ENTRIES, norm, body_size, tails
gen = sys.argv[1]
bad = []
table = dict(ROUTINES)
table.update({k: (False, v) for k, v in ENTRIES.items()})
into = tails()
heads = set(table) - set(into.values())
body = {}                           # each label's instructions to the RET that ends its module
for asm in glob.glob(os.path.join(gen, "*.asm")):
    cur = []
    for line in open(asm):
        m = re.match(r"_mv_(\w+)::\s*$", line)
        if m:
            cur.append(m.group(1))
            body[m.group(1)] = []
        elif norm(line) is not None:
            for c in cur:
                body[c].append(norm(line))
for name, (_, seq) in table.items():
    if body.get(name) != seq + ["ret"]:
        bad.append(name + " (instructions)")
for name in heads:                  # a chain's module: its first routine's size, then RET
    rel = open(os.path.join(gen, "mv_%s.rel" % name)).read()
    m = re.search(r"^A CSEG size (\w+)", rel, re.M)
    if not m or int(m.group(1), 16) != body_size(table[name][1]) + 1:
        bad.append(name + " (size)")
if len(glob.glob(os.path.join(gen, "*.asm"))) != len(heads) or not into:
    bad.append("stray modules, or no chain")
if bad:
    sys.exit("differ from the table: " + ", ".join(sorted(bad)))
print("%d routines in %d modules" % (len(table), len(heads)))
EOF
); then
    echo "ok - share_moves: --gen makes one module a routine (a chain where one ends with another), each label exactly its sequence then RET, of the size counted ($out)"
else
    echo "not ok - share_moves: --gen"; echo "$out" | sed 's/^/#   /'; sed 's/^/#   /' "$tmp/sdas.log"
fi

# a whole sequence (a C line comment inside it kept) is replaced; one with a label inside, or
# cut short, is not (after the label only what follows it whole: xld_r5a)
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
python3 tools/share_moves.py "$tmp/a.asm"
if [ "$(grep -c 'lcall' "$tmp/a.asm")" -eq 2 ] && grep -q 'lcall	_mv_xld_r4567' "$tmp/a.asm" \
    && grep -q 'lcall	_mv_xld_r5a' "$tmp/a.asm" && grep -q 'the comment stays' "$tmp/a.asm" \
    && grep -q '^00101\$:' "$tmp/a.asm" && [ "$(grep -c 'movx	a,@dptr' "$tmp/a.asm")" -eq 2 ] \
    && [ "$(sed -n '/^_f:/,/^00101/p' "$tmp/a.asm" | grep -c 'mov	r4,a')" -eq 1 ]; then
    echo "ok - share_moves: a whole sequence becomes one call; one a label cuts stays"
else
    echo "not ok - share_moves: replacement"; sed 's/^/#   /' "$tmp/a.asm"
fi

# overlapping candidates: the cover with the fewest bytes, not the first or longest match.
# "mov r7,a / mov r0,_bp / inc r0 / mov dpl,@r0 / inc r0 / mov dph,@r0": fp1_after_r7a would
# take the first three (a call and 5 B kept: 8 B), fp1_dptr the last five (mov r7,a kept, 1 B,
# and a call: 4 B); written out they are 9 B
printf '_g:\n\tmov\tr7,a\n\tmov\tr0,_bp\n\tinc\tr0\n\tmov\tdpl,@r0\n\tinc\tr0\n\tmov\tdph,@r0\n\tret\n' > "$tmp/c.asm"
python3 tools/share_moves.py "$tmp/c.asm"
if [ "$(grep -c '_mv_' "$tmp/c.asm")" -eq 1 ] && grep -q 'l[a-z]*	_mv_fp1_dptr' "$tmp/c.asm" \
    && grep -q 'mov	r7,a' "$tmp/c.asm"; then
    echo "ok - share_moves: overlapping sequences covered at the fewest bytes"
else
    echo "not ok - share_moves: cover"; sed 's/^/#   /' "$tmp/c.asm"
fi

# --hot=NAME: only the hot routines in that function (a controller's step), all in the others
seq=$'\tmov\tr6,dpl\n\tmov\tr7,dph\n\tmov\tr5,dpl\n\tmov\tr6,dph\n'
printf '_step:\n%s\tret\n_derive:\n%s\tret\n' "$seq" "$seq" > "$tmp/b.asm"
python3 tools/share_moves.py '--hot=ste?' "$tmp/b.asm"
if [ "$(sed -n '/^_step:/,/^_derive:/p' "$tmp/b.asm" | grep -c '_mv_')" -eq 1 ] \
    && sed -n '/^_step:/,/^_derive:/p' "$tmp/b.asm" | grep -q 'lcall	_mv_res_r67' \
    && [ "$(sed -n '/^_derive:/,$p' "$tmp/b.asm" | grep -c '_mv_')" -eq 2 ] \
    && sed -n '/^_derive:/,$p' "$tmp/b.asm" | grep -q 'ljmp	_mv_res_r56'; then
    echo "ok - share_moves: --hot keeps a step's function to the hot routines, the next one shares all"
else
    echo "not ok - share_moves: --hot"; sed 's/^/#   /' "$tmp/b.asm"
fi

# a sequence the function returns right after: LJMP, the routine's RET returns for it; not
# where a label stands before the RET (something jumps to it)
printf '_f:\n\tmov\tr6,dpl\n\tmov\tr7,dph\n;\tc.c:9: }\n\tret\n_g:\n\tmov\tr6,dpl\n\tmov\tr7,dph\n00105$:\n\tret\n' > "$tmp/d.asm"
python3 tools/share_moves.py "$tmp/d.asm"
if [ "$(sed -n '/^_f:/,/^_g:/p' "$tmp/d.asm" | grep -c 'ret')" -eq 0 ] \
    && sed -n '/^_f:/,/^_g:/p' "$tmp/d.asm" | grep -q 'ljmp	_mv_res_r67' \
    && sed -n '/^_g:/,$p' "$tmp/d.asm" | grep -q 'lcall	_mv_res_r67' \
    && [ "$(sed -n '/^_g:/,$p' "$tmp/d.asm" | grep -c 'ret')" -eq 1 ]; then
    echo "ok - share_moves: a call the function returns after becomes a jump, not across a label"
else
    echo "not ok - share_moves: tail jump"; sed 's/^/#   /' "$tmp/d.asm"
fi

# a reentrant function's end (SP back to the frame pointer, the caller's popped, RET): a jump to
# ret_frame, whose RET returns for the function; never a call (the return address would be
# popped into _bp), so not where a label stands before the RET or something else follows
printf '_f:\n\tmov\tsp,_bp\n\tpop\t_bp\n\tret\n_g:\n\tmov\tsp,_bp\n\tpop\t_bp\n00107$:\n\tret\n_h:\n\tmov\tsp,_bp\n\tpop\t_bp\n\tmov\tr7,a\n\tret\n' > "$tmp/e.asm"
python3 tools/share_moves.py "$tmp/e.asm"
if sed -n '/^_f:/,/^_g:/p' "$tmp/e.asm" | grep -q 'ljmp	_mv_ret_frame' \
    && [ "$(sed -n '/^_f:/,/^_g:/p' "$tmp/e.asm" | grep -c 'ret$')" -eq 0 ] \
    && ! sed -n '/^_g:/,$p' "$tmp/e.asm" | grep -q '_mv_ret_frame' \
    && [ "$(sed -n '/^_g:/,$p' "$tmp/e.asm" | grep -c 'pop	_bp')" -eq 2 ]; then
    echo "ok - share_moves: a frame's end becomes a jump to ret_frame, never a call"
else
    echo "not ok - share_moves: ret_frame"; sed 's/^/#   /' "$tmp/e.asm"
fi

# --relax, from sdas's listing: a long jump within reach of its label (the same function's: a
# local label reused by the next is another place) becomes SJMP; "J<c> skip / LJMP far / skip:"
# becomes "J<not c> far" where far is within reach; one out of reach stays long, and so do a
# switch's jump table's (JMP @A+DPTR into LJMPs 3 bytes apart)
{
    printf '\t.area CSEG (CODE)\n_f:\n\tjz\t00101$\n\tljmp\t00102$\n00101$:\n\tinc\ta\n\tljmp\t00102$\n'
    printf '\tjb\tacc.0,00103$\n\tljmp\t00104$\n00103$:\n\tinc\ta\n00102$:\n\tljmp\t00104$\n'
    for i in $(seq 140); do printf '\tnop\n'; done
    printf '00104$:\n\tret\n_g:\n\tljmp\t00101$\n00101$:\n\tret\n'
    printf '_t:\n\tmov\tdptr,#00110$\n\tjmp\t@a+dptr\n00110$:\n\tljmp\t00111$\n\tljmp\t00112$\n00111$:\n\tret\n00112$:\n\tret\n'
} > "$tmp/r.asm"
cp "$tmp/r.asm" "$tmp/r0.asm"
"$SDAS" -plosgffw "$tmp/r.rel" "$tmp/r.asm" && n=$(python3 tools/share_moves.py --relax "$tmp/r.asm") \
    && "$SDAS" -plosgffw "$tmp/r.rel" "$tmp/r.asm"
size() { grep "^A CSEG size" "$1" | awk '{print $4}'; }
"$SDAS" -plosgffw "$tmp/r0.rel" "$tmp/r0.asm"
if [ "$n" = 5 ] && sed -n '/^_f:/,/^00101/p' "$tmp/r.asm" | grep -q 'jnz	00102\$' \
    && [ "$(sed -n '/^_f:/,/^_g:/p' "$tmp/r.asm" | grep -c 'ljmp')" -eq 2 ] && grep -q 'jb	acc.0,00103\$' "$tmp/r.asm" \
    && [ "$(sed -n '/^_g:/,/^_t:/p' "$tmp/r.asm" | grep -c 'sjmp	00101\$')" -eq 1 ] \
    && [ "$(sed -n '/^_t:/,$p' "$tmp/r.asm" | grep -c 'ljmp')" -eq 2 ] \
    && [ $((16#$(size "$tmp/r0.rel") - 16#$(size "$tmp/r.rel"))) -eq 5 ]; then
    echo "ok - share_moves: --relax shortens the long jumps within reach, 5 B here, not the others"
else
    echo "not ok - share_moves: --relax ($n)"; sed 's/^/#   /' "$tmp/r.asm" | grep -v nop
fi

# a reentrant function's entry: "push _bp / mov _bp,sp" a call of enter, "push _bp / mov a,sp /
# mov _bp,a / add a,#N / mov sp,a" A = N and a call of enter_a (comments between kept); only at
# the function's first instructions, not in a --hot function, not past a label
printf '_f:\n\tpush\t_bp\n;\tc.c:2: x\n\tmov\t_bp,sp\n\tmov\tr7,dpl\n\tret\n_g:\n\tpush\t_bp\n\tmov\ta,sp\n\tmov\t_bp,a\n\tadd\ta,#0x05\n\tmov\tsp,a\n\tret\n_h:\n\tpush\t_bp\n\tmov\t_bp,sp\n\tret\n_k:\n\tmov\tr7,dpl\n\tpush\t_bp\n\tmov\t_bp,sp\n\tret\n_m:\n00101$:\n\tpush\t_bp\n\tmov\t_bp,sp\n\tret\n' > "$tmp/n.asm"
python3 tools/share_moves.py --hot=h "$tmp/n.asm"
if sed -n '/^_f:/,/^_g:/p' "$tmp/n.asm" | grep -q 'lcall	_mv_enter$' \
    && sed -n '/^_f:/,/^_g:/p' "$tmp/n.asm" | grep -q 'c.c:2: x' \
    && [ "$(sed -n '/^_f:/,/^_g:/p' "$tmp/n.asm" | grep -c '_bp')" -eq 0 ] \
    && [ "$(sed -n '/^_g:/,/^_h:/p' "$tmp/n.asm" | tr '\n' ' ')" = "$(printf '_g:\n\tmov\ta,#0x05\n\tlcall\t_mv_enter_a\n\tret\n_h:\n' | tr '\n' ' ')" ] \
    && [ "$(sed -n '/^_h:/,$p' "$tmp/n.asm" | grep -c '_mv_enter')" -eq 0 ]; then
    echo "ok - share_moves: a function's entry a call of enter or enter_a, only at its start"
else
    echo "not ok - share_moves: entries"; sed 's/^/#   /' "$tmp/n.asm"
fi

# tools/stackdepth.py counts an entry routine's frame as the sequence's it stands for, and the
# return address the routine pushes back above it: the reset's call 2 B, main's _bp, 5 B of frame,
# f's call 2 B, f's _bp and its routine's return address 2 B
mkdir -p "$tmp/sd"
printf ';\t function main\n_main:\n\tmov\ta,#0x05\n\tlcall\t_mv_enter_a\n\tlcall\t_f\n\tmov\tsp,_bp\n\tpop\t_bp\n\tret\n;\t function f\n_f:\n\tlcall\t_mv_enter\n\tpush\tar7\n\tpop\tar7\n\tpop\t_bp\n\tret\n' > "$tmp/sd/a.asm"
if python3 tools/stackdepth.py "$tmp/sd" | grep -q "worst case 13 B"; then
    echo "ok - share_moves: stackdepth counts the entry routines' frames (13 B here)"
else
    echo "not ok - share_moves: stackdepth of the entries"; python3 tools/stackdepth.py "$tmp/sd" | sed 's/^/#   /'
fi

# ... and the entries that make 2 bytes of frame (inc sp twice, or the first argument's DPL, DPH
# pushed): one call each, counted by stackdepth as the pushes they stand for
printf ';\t function main\n_main:\n\tpush\t_bp\n\tmov\t_bp,sp\n\tinc\tsp\n\tinc\tsp\n\tlcall\t_f\n\tmov\tsp,_bp\n\tpop\t_bp\n\tret\n;\t function f\n_f:\n\tpush\t_bp\n\tmov\t_bp,sp\n\tpush\tdpl\n\tpush\tdph\n\tmov\tsp,_bp\n\tpop\t_bp\n\tret\n' > "$tmp/sd/a.asm"
python3 tools/share_moves.py "$tmp/sd/a.asm"
if grep -q 'lcall	_mv_enter_2' "$tmp/sd/a.asm" && grep -q 'lcall	_mv_enter_dptr' "$tmp/sd/a.asm" \
    && [ "$(grep -c 'push	_bp\|inc	sp\|push	dp' "$tmp/sd/a.asm")" -eq 0 ] \
    && python3 tools/stackdepth.py "$tmp/sd" | grep -q "worst case 12 B"; then
    echo "ok - share_moves: enter_2 and enter_dptr, their frames counted (12 B here)"
else
    echo "not ok - share_moves: enter_2, enter_dptr"; sed 's/^/#   /' "$tmp/sd/a.asm"; python3 tools/stackdepth.py "$tmp/sd" | sed 's/^/#   /'
fi

#!/usr/bin/env python3
"""share_moves.py: the 8051 port's shared instruction sequences, from one table.

SDCC's large model writes the same short sequences out again and again: a 32-bit value from
XRAM into R4-R7 is 11 bytes wherever such a value is read. ROUTINES below is the one list of
those sequences; the build makes from it

  --gen DIR          one assembly module DIR/mv_NAME.asm a routine: the sequence, then RET, so
                     that the linker takes from the firmware's archive only the routines called
                     (where a routine ends with another's whole sequence, one module runs on into
                     the other's label: tails());
  --relax FILE.asm   after sdas assembled it: the long jumps within reach made short (from its
                     listing FILE.lst);
  [--hot=F,..] FILE.asm..
                     the modules' assembly rewritten in place: each sequence found whole (no
                     label inside it, so nothing jumps into its middle) becomes LCALL _mv_NAME
                     (LJMP, the RET dropped, where the function returns right after it).

A call leaves the registers, DPTR, A, the flags and the memory as the sequence did; the stack
holds two bytes more for the moment and the sequence takes 4 machine cycles longer. This runs on
SDCC's output after its own optimiser (whose register analysis takes a call to leave R0-R7
unread and would drop the moves feeding one) and before the assembler.

Where several sequences could start or overlap, each function's instructions are covered at
the fewest bytes (a shortest path over the instructions: an instruction kept costs its size, a
call 3 bytes; a tie keeps the instructions, fewer calls). The one exception mechanism: --hot
names the functions whose cycles count (a controller's step; `*` every function of the file);
in them only the routines marked hot (the plain loads, stores and frame addresses) are used.

--stats: what each routine saves over the files given, SDCC's output or a build's rewritten
assembly (its calls there count): uses x (its size - 3), less its own size and RET; nothing
changed. Names say what a routine does (the key below ROUTINES)."""
import os
import re
import sys
from fnmatch import fnmatch

# Names:  xld_/xst_ load from / store to the XRAM at DPTR (through DPTR, incremented);
#         cld_ load from the code at DPTR;  ild_/ist_ load from / store to the internal RAM at
#         R0 (R1 where named);  res_ the result of a call (DPL, DPH, B, A) into registers;
#         arg_ registers into DPL, DPH, B, A;  fp_rN_XX RN = the frame pointer _bp + XX (a
#         reentrant function's local);  add_/sub_ sums and differences, sbc_ a subtraction's
#         later bytes (the borrow in C), cmp_ an unsigned compare (C the result), scmp_ SDCC's
#         signed compare (sign bits flipped), neg_scmp_ that of 0 - x;  shl/shr shifts.
#         Operand letters: r4567 the registers low byte first, i4 four bytes at @R0, a the
#         accumulator, 0/1 those constants.
# name: (hot, instructions) - normalised: mnemonic, one space, operands without spaces


def _xld(regs, last_a=False):
    """XRAM at DPTR into the registers (low byte first); last_a: the last byte left in A"""
    out = []
    for k, r in enumerate(regs):
        out += (["inc dptr"] if k else []) + ["movx a,@dptr", "mov r%s,a" % r]
    return out + (["inc dptr", "movx a,@dptr"] if last_a else [])


def _xst(regs):
    out = []
    for k, r in enumerate(regs):
        out += ["mov a,r%s" % r] + (["inc dptr"] if k else []) + ["movx @dptr,a"]
    return out


def _cld(regs, last_a=False):
    out = []
    for k, r in enumerate(regs):
        out += (["inc dptr"] if k else []) + ["clr a", "movc a,@a+dptr", "mov r%s,a" % r]
    return out + (["inc dptr", "clr a", "movc a,@a+dptr"] if last_a else [])


def _ild(regs, ptr="r0"):
    out = []
    for k, r in enumerate(regs):
        out += (["inc %s" % ptr] if k else []) + ["mov ar%s,@%s" % (r, ptr)]
    return out


def _ist(regs):
    out = []
    for k, r in enumerate(regs):
        out += (["inc r0"] if k else []) + ["mov @r0,ar%s" % r]
    return out


def _res(regs):
    return ["mov r%s,%s" % (r, s) for r, s in zip(regs, ("dpl", "dph", "b", "a"))]


def _arg(regs):
    return ["mov %s,r%s" % (s, r) for r, s in zip(regs, ("dpl", "dph", "b", "a"))]


def _fp(reg, off):
    return ["mov a,_bp", "add a,#0x%02x" % off, "mov %s,a" % reg]


ROUTINES = {
    # loads and stores of 16- and 32-bit values (the hot set: a controller's step may use them)
    "xld_r4567": (True, _xld("4567")),
    "xld_r2367": (True, _xld("2367")),
    "xld_r2345": (True, _xld("2345")),
    "xld_r67": (True, _xld("67")),
    "xld_r45": (True, _xld("45")),
    "xld_r23": (True, _xld("23")),
    "xld_r56": (True, _xld("56")),
    "xld_r34": (False, _xld("34")),
    "xld_r47": (False, _xld("47")),
    "xld_r6a": (False, _xld("6", True)),
    "xld_r2a": (False, _xld("2", True)),
    "xld_r5a": (False, _xld("5", True)),
    "xld_dptr": (True, ["movx a,@dptr", "mov r6,a", "inc dptr", "movx a,@dptr", "mov dpl,r6",
                        "mov dph,a"]),
    "xst_r4567": (True, _xst("4567")),
    "xst_r2367": (True, _xst("2367")),
    "xst_r2345": (True, _xst("2345")),
    "xst_r67": (True, _xst("67")),
    "xst_r45": (True, _xst("45")),
    "xst_r23": (True, _xst("23")),
    "xst_r56": (False, _xst("56")),
    "xst_r34": (False, _xst("34")),
    "xst_00": (True, ["clr a", "movx @dptr,a", "inc dptr", "movx @dptr,a"]),
    "xst_a000": (True, ["movx @dptr,a", "clr a", "inc dptr", "movx @dptr,a", "inc dptr",
                        "movx @dptr,a", "inc dptr", "movx @dptr,a"]),
    "xst_next_a00": (True, ["inc dptr", "movx @dptr,a", "clr a", "inc dptr", "movx @dptr,a",
                            "inc dptr", "movx @dptr,a"]),
    "xst_next_a10": (False, ["inc dptr", "movx @dptr,a", "mov a,#0x01", "inc dptr",
                             "movx @dptr,a", "clr a", "inc dptr", "movx @dptr,a"]),
    "xst_aaaa": (True, ["movx @dptr,a", "inc dptr", "movx @dptr,a", "inc dptr", "movx @dptr,a",
                        "inc dptr", "movx @dptr,a"]),
    "xst_a_r56": (False, ["movx @dptr,a", "mov a,r5", "inc dptr", "movx @dptr,a", "mov a,r6",
                          "inc dptr", "movx @dptr,a"]),
    "xld_i4": (True, ["movx a,@dptr", "mov @r0,a", "inc dptr", "movx a,@dptr", "inc r0",
                      "mov @r0,a", "inc dptr", "movx a,@dptr", "inc r0", "mov @r0,a",
                      "inc dptr", "movx a,@dptr", "inc r0", "mov @r0,a"]),
    "xld_i2": (False, ["movx a,@dptr", "mov @r0,a", "inc dptr", "movx a,@dptr", "inc r0",
                       "mov @r0,a"]),
    "xst_i4": (True, ["mov a,@r0", "movx @dptr,a", "inc r0", "mov a,@r0", "inc dptr",
                      "movx @dptr,a", "inc r0", "mov a,@r0", "inc dptr", "movx @dptr,a",
                      "inc r0", "mov a,@r0", "inc dptr", "movx @dptr,a"]),
    "xst_i2": (True, ["mov a,@r0", "movx @dptr,a", "inc r0", "mov a,@r0", "inc dptr",
                      "movx @dptr,a"]),
    "cld_r67": (True, _cld("67")),
    "cld_r45": (False, _cld("45")),
    "cld_r3a": (False, _cld("3", True)),
    "ild_r23": (True, _ild("23")),
    "ild_r45": (True, _ild("45")),
    "ild_r67": (True, _ild("67")),
    "ild_r4567_r1": (False, _ild("4567", "r1")),
    "ist_r4567": (True, _ist("4567")),
    "ist_r3456": (True, _ist("3456")),
    "ist_r23": (True, _ist("23")),
    "ist_r45": (False, _ist("45")),
    "ist_r67": (True, _ist("67")),
    "ist_00": (False, ["inc r0", "mov @r0,#0x00", "inc r0", "mov @r0,#0x00"]),
    "copy_i4_r0_r1": (False, ["mov a,@r0", "mov @r1,a", "inc r0", "mov a,@r0", "inc r1", "mov @r1,a",
                              "inc r0", "mov a,@r0", "inc r1", "mov @r1,a", "inc r0", "mov a,@r0",
                              "inc r1", "mov @r1,a"]),
    "copy_i2_r0_r1": (True, ["mov @r1,a", "inc r0", "mov a,@r0", "inc r1", "mov @r1,a"]),
    "ild_dptr": (False, ["mov dpl,@r0", "inc r0", "mov dph,@r0"]),
    # a call's result and arguments (DPL, DPH, B, A)
    "res_r4567": (True, _res("4567")),
    "res_r3456": (True, _res("3456")),
    "res_r3467": (False, _res("3467")),
    "res_r67": (True, _res("67")),
    "res_r45": (True, _res("45")),
    "res_r23": (True, _res("23")),
    "res_r56": (False, _res("56")),
    "res_hi_r567": (False, ["mov r5,dph", "mov r6,b", "mov r7,a"]),
    "res_i4": (True, ["mov @r0,dpl", "inc r0", "mov @r0,dph", "inc r0", "mov @r0,b", "inc r0",
                      "mov @r0,a"]),
    "arg_r4567": (True, _arg("4567")),
    "arg_r67": (True, _arg("67")),
    "arg_r45": (True, _arg("45")),
    "arg_r23": (True, _arg("23")),
    "arg_r34": (False, _arg("34")),
    "arg_r56": (False, _arg("56")),
    "arg_r76": (False, _arg("76")),
    "arg_r564": (False, _arg("564")),
    "arg_r6754": (False, _arg("6754")),
    "arg_r67_dptr2": (False, _arg("67") + ["inc dptr", "inc dptr"]),     # DPTR = R6:R7 + 2
    "arg_r2345": (False, _arg("2345")),
    "arg_r2367": (False, _arg("2367")),
    "param_at_a": (False, ["mov b,#0x02", "mul ab", "add a,#_param_v", "mov dpl,a",
                           "mov a,#(_param_v>>8)", "addc a,b", "mov dph,a"]),    # DPTR = &param_v[A]
    "arg_r456": (False, _arg("456")),
    "xld_arg_r456a": (False, _xld("456", True) + _arg("456")),     # XRAM at DPTR to DPL, DPH, B, A
    "xld_arg_r67": (False, _xld("67") + _arg("67")),
    "res_r2345": (False, _res("2345")),
    "res_r236": (False, _res("23") + ["mov r6,b"]),
    "xst_r23_sext": (False, _xst("23") + ["mov a,r3", "rlc a", "subb a,acc", "inc dptr", "movx @dptr,a",
                                          "inc dptr", "movx @dptr,a"]),
    "arg_i4": (True, ["mov dpl,@r0", "inc r0", "mov dph,@r0", "inc r0", "mov b,@r0", "inc r0",
                      "mov a,@r0"]),
    "ctl_in_dptr": (False, ["mov dpl,_ctl_in", "mov dph,(_ctl_in+1)"]),   # the step's inputs (ctl.h)
    "dptr_a_r67": (False, ["add a,r6", "mov dpl,a", "clr a", "addc a,r7", "mov dph,a"]),
    "dptr_a_plus_i2": (False, ["add a,@r0", "mov dpl,a", "clr a", "inc r0", "addc a,@r0",
                               "mov dph,a"]),
    "addc_b_dph": (False, ["addc a,b", "mov dph,a"]),
    # a reentrant function's locals: R0 (R1) at the frame pointer plus an offset
    "fp_r0_02": (False, ["mov r0,_bp", "inc r0", "inc r0"]),
    "fp_r0_05_keep_a": (False, ["xch a,r0", "mov a,_bp", "add a,#0x05", "xch a,r0"]),
    "fp1_dptr": (True, ["mov r0,_bp", "inc r0", "mov dpl,@r0", "inc r0", "mov dph,@r0"]),
    "fp1_a": (True, ["mov r0,_bp", "inc r0", "mov a,@r0"]),
    "fp1_res_i4": (False, ["mov r0,_bp", "inc r0", "mov @r0,dpl", "inc r0", "mov @r0,dph", "inc r0",
                           "mov @r0,b", "inc r0", "mov @r0,a"]),
    "fp_r0_fc_a": (False, _fp("r0", 0xfc) + ["mov a,@r0"]),
    "fp_r0_fd_a": (False, _fp("r0", 0xfd) + ["mov a,@r0"]),
    "fp_r0_03_dptr": (False, _fp("r0", 0x03) + ["mov dpl,@r0", "inc r0", "mov dph,@r0"]),
    "fp1_st00": (False, ["mov r0,_bp", "inc r0", "clr a", "mov @r0,a", "inc r0", "mov @r0,a"]),
    "fp1_after_r7a": (False, ["mov r7,a", "mov r0,_bp", "inc r0"]),
    # sums, differences and compares
    "addc_i_r67": (True, ["mov a,r6", "inc r0", "addc a,@r0", "mov r6,a", "mov a,r7", "inc r0",
                          "addc a,@r0", "mov r7,a"]),
    "add_i_r4567": (True, ["mov a,@r0", "add a,r4", "mov r4,a", "inc r0", "mov a,@r0",
                           "addc a,r5", "mov r5,a", "inc r0", "mov a,@r0", "addc a,r6",
                           "mov r6,a", "inc r0", "mov a,@r0", "addc a,r7"]),
    "add_i_r23": (False, ["mov a,r2", "add a,@r0", "mov r2,a", "mov a,r3", "inc r0",
                          "addc a,@r0", "mov r3,a"]),
    "add_fp1_r45": (False, ["mov r0,_bp", "inc r0", "mov a,r4", "add a,@r0", "mov r4,a",
                            "mov a,r5", "inc r0", "addc a,@r0", "mov r5,a"]),
    "add_a_r67": (False, ["add a,r6", "mov r6,a", "clr a", "addc a,r7", "mov r7,a"]),
    "add_a_r45": (False, ["add a,r4", "mov r4,a", "clr a", "addc a,r5", "mov r5,a"]),
    "adc_r67": (True, ["clr a", "addc a,r6", "mov r6,a", "clr a", "addc a,r7", "mov r7,a"]),
    "xld_r45_add_3ff0": (False, ["movx a,@dptr", "mov r6,a", "inc dptr", "movx a,@dptr",
                                 "mov r4,a", "mov ar5,r6", "clr a", "mov r6,a", "mov r7,a",
                                 "mov a,#0xf0", "add a,r6", "mov r6,a", "mov a,#0x3f",
                                 "addc a,r7", "mov r7,a", "clr a", "addc a,r5", "mov r5,a",
                                 "clr a", "addc a,r4", "mov r4,a"]),
    "sub_i_r2367": (True, ["mov a,@r0", "clr c", "subb a,r2", "mov r2,a", "inc r0", "mov a,@r0",
                           "subb a,r3", "mov r3,a", "inc r0", "mov a,@r0", "subb a,r6",
                           "mov r6,a", "inc r0", "mov a,@r0", "subb a,r7"]),
    "sub_i_r4763": (False, ["mov a,@r0", "clr c", "subb a,r4", "mov r4,a", "inc r0",
                            "mov a,@r0", "subb a,r7", "mov r7,a", "inc r0", "mov a,@r0",
                            "subb a,r6", "mov r6,a", "inc r0", "mov a,@r0", "subb a,r3",
                            "mov r3,a"]),
    "sub_r4567_to_i": (False, ["clr c", "subb a,r4", "mov @r0,a", "inc r0", "mov a,@r0",
                               "subb a,r5", "mov @r0,a", "inc r0", "mov a,@r0", "subb a,r6",
                               "mov @r0,a", "inc r0", "mov a,@r0", "subb a,r7", "mov @r0,a"]),
    "sub_r67_r45": (False, ["mov a,r6", "clr c", "subb a,r4", "mov r4,a", "mov a,r7",
                            "subb a,r5", "mov r5,a"]),
    "sub_ii_r67": (False, ["inc r1", "mov @r1,a", "inc r0", "mov a,@r0", "subb a,r6", "inc r1",
                           "mov @r1,a", "inc r0", "mov a,@r0", "subb a,r7", "inc r1",
                           "mov @r1,a"]),
    "sbc_ii3": (False, ["subb a,@r0", "inc r1", "mov a,@r1", "inc r0", "subb a,@r0", "inc r1",
                        "mov a,@r1", "inc r0", "subb a,@r0"]),
    "sbc_r45_i": (False, ["subb a,r4", "mov r4,a", "inc r0", "mov a,@r0", "subb a,r5",
                          "mov r5,a", "inc r0", "mov a,@r0"]),
    "sbc_r67_i": (False, ["subb a,r6", "mov r6,a", "inc r0", "mov a,@r0", "subb a,r7",
                          "mov r7,a"]),
    "sbc_i3_0": (False, ["subb a,@r0", "clr a", "inc r0", "subb a,@r0", "clr a", "inc r0",
                         "subb a,@r0"]),
    "sbc_i3_r67": (False, ["inc r0", "subb a,@r0", "mov a,r6", "inc r0", "subb a,@r0",
                           "mov a,r7", "inc r0", "subb a,@r0"]),
    "sbc_0_r567": (False, ["subb a,r5", "clr a", "subb a,r6", "clr a", "subb a,r7"]),
    "cmp_r4567_i": (False, ["clr c", "mov a,r4", "subb a,@r0", "mov a,r5", "inc r0",
                            "subb a,@r0", "mov a,r6", "inc r0", "subb a,@r0", "mov a,r7",
                            "inc r0", "subb a,@r0"]),
    "cmp_i_r2367": (False, ["clr c", "mov a,@r0", "subb a,r2", "inc r0", "mov a,@r0",
                            "subb a,r3", "inc r0", "mov a,@r0", "subb a,r6", "inc r0",
                            "mov a,@r0", "subb a,r7"]),
    "cmp_ffff_r4567": (False, ["clr c", "mov a,#0xff", "subb a,r4", "mov a,#0xff", "subb a,r5",
                               "clr a", "subb a,r6", "clr a", "subb a,r7"]),
    "cmp_ffff_r3456": (False, ["clr c", "mov a,#0xff", "subb a,r3", "mov a,#0xff", "subb a,r4",
                               "clr a", "subb a,r5", "clr a", "subb a,r6"]),
    "cmp_r67_100": (False, ["clr c", "mov a,r6", "subb a,#0x64", "mov a,r7", "subb a,#0x00"]),
    "cmp_r67_r45": (False, ["clr c", "mov a,r6", "subb a,r4", "mov a,r7", "subb a,r5"]),
    "scmp_b": (True, ["xrl b,#0x80", "subb a,b"]),
    "scmp_next_i": (False, ["inc r0", "mov b,@r0", "xrl b,#0x80", "subb a,b"]),
    "neg_scmp_b_r45": (False, ["clr c", "clr a", "subb a,r4", "mov a,#(0x00^0x80)", "mov b,r5",
                               "xrl b,#0x80", "subb a,b"]),
    "cmp_r45_r67": (False, ["clr c", "mov a,r4", "subb a,r6", "mov a,r5", "subb a,r7"]),
    "ist_r23_sext": (False, _ist("23") + ["mov a,r3", "rlc a", "subb a,acc", "inc r0", "mov @r0,a",
                                          "inc r0", "mov @r0,a"]),
    "scmp_b_r7": (False, ["mov b,r7", "xrl b,#0x80", "subb a,b"]),
    "scmp_r7": (False, ["xrl a,#0x80", "mov b,r7", "xrl b,#0x80", "subb a,b"]),
    "scmp_0_r2": (False, ["clr c", "mov a,#(0x00^0x80)", "mov b,r2"]),
    "neg_scmp_r23": (False, ["clr c", "clr a", "subb a,r2", "mov a,#(0x00^0x80)", "mov b,r3"]),
    "neg_scmp_r45": (False, ["clr c", "clr a", "subb a,r4", "mov a,#(0x00^0x80)", "mov b,r5"]),
    "neg_scmp_r67": (False, ["clr c", "clr a", "subb a,r6", "mov a,#(0x00^0x80)", "mov b,r7"]),
    "mov_r45_r67": (False, ["mov ar4,r6", "mov ar5,r7"]),
    "orl_i3": (False, ["inc r0", "orl a,@r0", "inc r0", "orl a,@r0", "inc r0", "orl a,@r0"]),
    "i3_a_clr_c": (False, ["inc r0", "inc r0", "inc r0", "mov a,@r0", "clr c"]),
    "carry_dpl": (False, ["clr a", "rlc a", "mov dpl,a"]),
    "mul_b2": (False, ["mov b,#0x02", "mul ab"]),
    "r67_0": (True, ["mov r6,#0x00", "mov r7,#0x00"]),
    # a reentrant function's end: SP back to its frame pointer, the caller's frame pointer
    # popped; then the routine's RET returns for the function (TAIL_ONLY: jumped to, never called)
    "ret_frame": (False, ["mov sp,_bp", "pop _bp"]),
    "inc_dptr5": (True, ["inc dptr"] * 5),
    "sext_r67": (True, ["rlc a", "subb a,acc", "mov r6,a", "mov r7,a"]),
    # shifts
    "shr1_i4": (False, ["inc r0", "inc r0", "inc r0", "mov a,@r0", "clr c", "rrc a", "mov @r0,a",
                        "dec r0", "mov a,@r0", "rrc a", "mov @r0,a", "dec r0", "mov a,@r0", "rrc a",
                        "mov @r0,a", "dec r0", "mov a,@r0", "rrc a", "mov @r0,a"]),
    "rrc_i3": (True, ["rrc a", "mov @r0,a", "dec r0", "mov a,@r0", "rrc a", "mov @r0,a",
                      "dec r0", "mov a,@r0", "rrc a", "mov @r0,a"]),
    "rrc_r67": (False, ["rrc a", "xch a,r6", "rrc a", "xch a,r6", "mov r7,a"]),
    "shr4_r4": (True, ["swap a", "xch a,r4", "swap a", "anl a,#0x0f", "xrl a,r4", "xch a,r4",
                       "anl a,#0x0f", "xch a,r4", "xrl a,r4", "xch a,r4"]),
    "shr4_r6": (True, ["swap a", "xch a,r6", "swap a", "anl a,#0x0f", "xrl a,r6", "xch a,r6",
                       "anl a,#0x0f", "xch a,r6", "xrl a,r6", "xch a,r6"]),
    "shl4_r45": (False, ["swap a", "anl a,#0xf0", "xch a,r4", "swap a", "xch a,r4", "xrl a,r4",
                         "xch a,r4", "anl a,#0xf0", "xch a,r4", "xrl a,r4", "mov r5,a"]),
    "shl4_r67_to_i": (False, ["mov @r0,ar5", "mov a,r6", "swap a", "xch a,@r0", "swap a",
                              "anl a,#0x0f", "xrl a,@r0", "xch a,@r0", "anl a,#0x0f",
                              "xch a,@r0", "xrl a,@r0", "xch a,@r0", "inc r0", "mov @r0,a",
                              "mov a,r7", "swap a", "anl a,#0xf0", "orl a,@r0", "mov @r0,a",
                              "mov a,r7", "swap a", "anl a,#0x0f", "inc r0", "mov @r0,a",
                              "inc r0"]),
    "shl1_r4567": (False, ["mov a,r4", "add a,r4", "mov r4,a", "mov a,r5", "rlc a", "mov r5,a",
                           "mov a,r6", "rlc a", "mov r6,a", "mov a,r7", "rlc a", "mov r7,a"]),
    "shl1_r56": (False, ["mov a,r5", "add a,r5", "mov r5,a", "mov a,r6", "rlc a", "mov r6,a"]),
    "shl1_r23": (False, ["mov a,r2", "add a,r2", "mov r2,a", "mov a,r3", "rlc a", "mov r3,a"]),
    "shl2_r45": (False, ["mov c,acc.7", "xch a,r4", "rlc a", "xch a,r4", "rlc a", "mov c,acc.7",
                         "xch a,r4", "rlc a", "xch a,r4", "rlc a", "xch a,r4", "anl a,#0x03",
                         "mov r5,a"]),
    "shl2_r67": (False, ["mov c,acc.7", "xch a,r6", "rlc a", "xch a,r6", "rlc a", "mov c,acc.7",
                         "xch a,r6", "rlc a", "xch a,r6", "rlc a", "xch a,r6", "anl a,#0x03",
                         "mov r7,a"]),
    "shl2_r2a": (False, ["mov c,acc.7", "xch a,r2", "rlc a", "xch a,r2", "rlc a", "mov c,acc.7",
                         "xch a,r2", "rlc a", "xch a,r2", "rlc a", "xch a,r2", "anl a,#0x03"]),
    "shr5_r2": (False, ["swap a", "rl a", "xch a,r2", "swap a", "rl a", "anl a,#0x1f", "xrl a,r2",
                        "xch a,r2", "anl a,#0x1f", "xch a,r2", "xrl a,r2", "xch a,r2"]),
    "shr1_r4567": (False, ["clr c", "rrc a", "mov r7,a", "mov a,r6", "rrc a", "mov r6,a",
                           "mov a,r5", "rrc a", "mov r5,a", "mov a,r4", "rrc a"]),
    "shr1_r4": (False, ["clr c", "rrc a", "xch a,r4", "rrc a", "xch a,r4"]),
    "shr1_i4_r67": (False, ["inc r0", "inc r0", "inc r0", "mov a,@r0", "clr c", "rrc a",
                            "mov r7,a", "dec r0", "mov a,@r0", "rrc a", "mov r6,a", "dec r0",
                            "mov a,@r0", "rrc a"]),
    "shr2_i": (False, ["anl a,#0x03", "mov c,acc.0", "xch a,@r0", "rrc a", "xch a,@r0", "rrc a",
                       "mov c,acc.0", "xch a,@r0", "rrc a", "xch a,@r0", "rrc a", "xch a,@r0",
                       "inc r0", "mov @r0,a"]),
    "shr2_orl_i": (False, ["mov a,r5", "rr a", "rr a", "anl a,#0x3f", "dec r0", "orl a,@r0",
                           "mov @r0,a", "dec r0", "dec r0", "mov @r0,ar4", "mov a,r5"]),
}
# the frame offsets the firmware's reentrant functions use most
for _off in (0x03, 0x04, 0x05, 0x06, 0x07, 0x09, 0x0b, 0x0d, 0x11, 0x13, 0x15, 0xfc, 0xfd):
    ROUTINES["fp_r0_%02x" % _off] = (True, _fp("r0", _off))
for _off in (0x08, 0x0a, 0x0f, 0x10, 0x1b, 0x1d, 0xf8, 0xfa):
    ROUTINES["fp_r0_%02x" % _off] = (False, _fp("r0", _off))
ROUTINES["fp_r1_05"] = (True, _fp("r1", 0x05))

# the routines only a jump may reach, where the function returns right after the sequence (a
# call's return address would sit where they pop)
TAIL_ONLY = {"ret_frame"}

# A reentrant function's entry, shared: its frame pointer pushed and set, and its locals' room
# made. At a function's entry nothing is live but the arguments in DPL, DPH, B (and A where the
# function's own code leaves it alone): R6 and R7 are the caller's to save (SDCC's calls save what
# they need), so the routines carry the return address in them around the push of _bp.
#   enter     for  push _bp / mov _bp,sp                                      (5 B -> 3 B)
#   enter_a   for  push _bp / mov a,sp / mov _bp,a / add a,#N / mov sp,a       (10 B -> 5 B:
#             mov a,#N / lcall _mv_enter_a; A = the new SP after either)
#   enter_2   for  push _bp / mov _bp,sp / inc sp / inc sp                       (9 B -> 3 B)
#   enter_dptr for push _bp / mov _bp,sp / push dpl / push dph (the first argument kept) (9 B -> 3 B)
# tools/stackdepth.py counts their frames as those of the sequences they stand for.
_CARRY_RET = (["pop ar7", "pop ar6", "push _bp", "mov _bp,sp"], ["push ar6", "push ar7"])
ENTRIES = {
    "enter": _CARRY_RET[0] + _CARRY_RET[1],
    "enter_a": _CARRY_RET[0] + ["add a,sp", "mov sp,a"] + _CARRY_RET[1],
    "enter_2": _CARRY_RET[0] + ["inc sp", "inc sp"] + _CARRY_RET[1],
    "enter_dptr": _CARRY_RET[0] + ["push dpl", "push dph"] + _CARRY_RET[1],
}
ENTRY_2 = ["push _bp", "mov _bp,sp", "inc sp", "inc sp"]
ENTRY_DPTR = ["push _bp", "mov _bp,sp", "push dpl", "push dph"]
ENTRY_A = ["push _bp", "mov a,sp", "mov _bp,a", None, "mov sp,a"]    # None: add a,#N
ENTRY = ["push _bp", "mov _bp,sp"]

CALL_BYTES = 3          # LCALL addr16


def size(ins):
    """bytes of one instruction of the table (the 8051's encodings)"""
    op, _, args = ins.partition(" ")
    a = args.split(",") if args else []
    if op in ("lcall", "ljmp"):
        return 3
    if op in ("ret", "swap", "rr", "rl", "rrc", "rlc", "mul", "movc", "movx") or \
            ins in ("clr a", "clr c", "inc dptr", "inc a", "dec a"):
        return 1
    if op in ("inc", "dec"):
        return 1 if re.match(r"@?r\d$", a[0]) else 2
    imm = [x for x in a if x.startswith("#")]
    direct = [x for x in a if not re.match(r"(a|c|@r\d|r\d|@a\+dptr|dptr|#.*)$", x)]
    if op == "mov" and a[0] == "c":
        return 2                                 # mov c,bit
    if imm and direct:
        return 3                                 # op direct,#data
    if len(direct) == 2:
        return 3                                 # mov direct,direct
    return 1 + len(imm) + len(direct)


def body_size(seq):
    return sum(size(s) for s in seq)


def norm(line):
    """an instruction line normalised, or None for anything else (label, directive, comment)"""
    s = line.split(";", 1)[0].strip()
    if not s or s.endswith(":") or s.startswith(".") or "=" in s or ":" in s:
        return None
    parts = s.split(None, 1)
    return parts[0] + (" " + re.sub(r"\s+", "", parts[1]) if len(parts) > 1 else "")


FUNC = re.compile(r"^_(\w+):\s*$")


def matches(lines, i, seq):
    """the end of seq matched whole from lines[i] and the comments inside it, or None"""
    j, k, kept = i, 0, []
    while k < len(seq) and j < len(lines):
        n = norm(lines[j])
        if n is None:
            if lines[j].strip().startswith(";"):
                kept.append(lines[j])            # a comment: kept, after the call
                j += 1
                continue
            return None                          # a label or directive: not whole
        if n != seq[k]:
            return None
        k += 1
        j += 1
    return (j, kept) if k == len(seq) else None


def returns_at(lines, j):
    """the index of the RET that follows line j with only comments between, or None"""
    while j < len(lines) and (not lines[j].strip() or lines[j].strip().startswith(";")):
        j += 1
    return j if j < len(lines) and norm(lines[j]) == "ret" else None


def entries(lines, hot=()):
    """lines with each function's entry (ENTRY, ENTRY_A) a call of its routine, and the count"""
    out, used, i = [], {}, 0
    while i < len(lines):
        out.append(lines[i])
        m = FUNC.match(lines[i])
        i += 1
        if not m or any(fnmatch(m.group(1), p) for p in hot):
            continue
        ins, at = [], i                          # the first five instructions, comments kept
        while at < len(lines) and len(ins) < 5:
            n = norm(lines[at])
            if n is None and lines[at].strip() and not lines[at].strip().startswith(";"):
                break                            # a label: nothing past it is the entry's
            if n is not None:
                ins.append((n, at))
            at += 1
        names = [n for n, _ in ins]
        add = re.match(r"add a,#(0x[0-9a-f]{2})$", names[3]) if len(names) == 5 else None
        if add and names[:3] == ENTRY_A[:3] and names[4] == ENTRY_A[4]:
            name, last, call = "enter_a", ins[4][1], "\tmov\ta,#%s\n\tlcall\t_mv_enter_a\n" % add.group(1)
        elif names[:4] == ENTRY_2:
            name, last, call = "enter_2", ins[3][1], "\tlcall\t_mv_enter_2\n"
        elif names[:4] == ENTRY_DPTR:
            name, last, call = "enter_dptr", ins[3][1], "\tlcall\t_mv_enter_dptr\n"
        elif names[:2] == ENTRY:
            name, last, call = "enter", ins[1][1], "\tlcall\t_mv_enter\n"
        else:
            continue
        out.append(call)
        out.extend(l for l in lines[i:last + 1] if norm(l) is None)     # the comments between
        used[name] = used.get(name, 0) + 1
        i = last + 1
    return out, used


def share(lines, hot=()):
    """lines rewritten: each function's instructions covered at the fewest bytes"""
    firsts = {}
    for name, (is_hot, seq) in ROUTINES.items():
        firsts.setdefault(seq[0], []).append(name)
    funcs, func = [], None
    for i, line in enumerate(lines):
        m = FUNC.match(line)
        if m:
            func = m.group(1)
        funcs.append(func)
    n = len(lines)
    # cost[i]: bytes from line i to the end; choice[i]: (routine, end, comments) or None
    cost, choice = [0] * (n + 1), [None] * (n + 1)
    for i in range(n - 1, -1, -1):
        ins = norm(lines[i])
        keep = size(ins) if ins is not None and ins.split()[0] in _KNOWN_OPS else 0
        cost[i] = keep + cost[i + 1]
        if ins is None:
            continue
        is_hot = funcs[i] is not None and any(fnmatch(funcs[i], p) for p in hot)
        for name in firsts.get(ins, ()):
            h, seq = ROUTINES[name]
            if is_hot and not h:
                continue
            m = matches(lines, i, seq)
            if m and name in TAIL_ONLY and not returns_at(lines, m[0]):
                continue
            if m and CALL_BYTES + cost[m[0]] < cost[i]:
                cost[i] = CALL_BYTES + cost[m[0]]
                choice[i] = (name, m[0], m[1])
    out, used, i = [], {}, 0
    while i < n:
        if choice[i]:
            name, j, kept = choice[i]
            k = returns_at(lines, j)             # a RET right after it, no label between: the
            if k is not None:                    # routine's own RET returns for the function
                out.append("\tljmp\t_mv_%s\n" % name)
                out.extend(kept + lines[j:k])
                j = k + 1
            else:
                out.append("\tlcall\t_mv_%s\n" % name)
                out.extend(kept)
            used[name] = used.get(name, 0) + 1
            i = j
        else:
            out.append(lines[i])
            i += 1
    return out, used


_KNOWN_OPS = {s.split()[0] for _, seq in ROUTINES.values() for s in seq}


def tails():
    """{routine: the routine whose whole sequence ends it}: its module runs on into that one's
    label (each routine the tail of one other at most, the longest tails first), so the shorter
    one's instructions and RET are there once"""
    pairs = sorted(((body_size(ss) + 1, r, t) for r, (_, rs) in ROUTINES.items()
                    for t, (_, ss) in ROUTINES.items()
                    if r != t and len(ss) < len(rs) and rs[-len(ss):] == ss), reverse=True)
    into, taken = {}, set()
    for _, r, t in pairs:
        if r not in into and t not in taken:
            into[r] = t
            taken.add(t)
    return into


def gen(folder):
    """one module a routine, DIR/mv_NAME.asm, or a chain of them where one ends with another's
    whole sequence (tails): the first's module holds each label in turn"""
    os.makedirs(folder, exist_ok=True)
    table = dict(ROUTINES)
    table.update({k: (False, v) for k, v in ENTRIES.items()})
    into = tails()
    for name in sorted(set(table) - set(into.values())):
        text = [";\tgenerated by tools/share_moves.py --gen from its ROUTINES table\n",
                "\t.module mv_%s\n" % name,
                "\tar0 = 0x00\n\tar1 = 0x01\n\tar2 = 0x02\n\tar3 = 0x03\n",
                "\tar4 = 0x04\n\tar5 = 0x05\n\tar6 = 0x06\n\tar7 = 0x07\n",
                "\t.area CSEG (CODE)\n"]
        r = name
        while r is not None:
            seq, nxt = table[r][1], into.get(r)
            text += [";\t-----------------------------------------\n",
                     ";\t function mv_%s\n" % r,
                     ";\t-----------------------------------------\n",
                     "_mv_%s::\n" % r]
            own = seq[:len(seq) - len(table[nxt][1])] if nxt else seq
            text += ["\t%s\n" % s.replace(" ", "\t", 1) for s in own]
            r = nxt
        text += ["\tret\n"]
        path = os.path.join(folder, "mv_%s.asm" % name)
        old = open(path).read() if os.path.exists(path) else None
        if old != "".join(text):
            with open(path, "w") as f:
                f.writelines(text)


INVERSE = {"jz": "jnz", "jnz": "jz", "jc": "jnc", "jnc": "jc", "jb": "jnb", "jnb": "jb"}
LOCAL = re.compile(r"\d+\$$")


def listing(path):
    """{.asm line number (1-based): (area, scope, address)} and {(scope, local label): (area,
    address)} from sdas's listing of that .asm; a scope (where a local label n$ means one place)
    runs from one ordinary label to the next"""
    at, labels, area, scope = {}, {}, None, 0
    for line in open(path, encoding="latin-1"):
        m = re.match(r"(?:\[\s*\d+\])?\s*(\d+)(?:\s|$)", line[30:])
        if not m:
            continue
        num, src, addr = int(m.group(1)), line[30 + m.end():].strip(), line[6:12].strip()
        a = re.match(r"\.area\s+(\w+)", src)
        if a:
            area = a.group(1)
        lab = re.match(r"([A-Za-z_.$][\w.$]*|\d+\$)::?(\s|$)", src)
        if lab and not LOCAL.match(lab.group(1)):
            scope += 1
        if not addr:
            continue
        at[num] = (area, scope, int(addr, 16))
        if lab and LOCAL.match(lab.group(1)):
            labels[(scope, lab.group(1))] = (area, int(addr, 16))
    return at, labels


def relax(lines, at, labels):
    """lines with each LJMP to a label of the same function in reach made short: SJMP, or a
    conditional jump over it (J<c> skip / LJMP far / skip:) turned into J<not c> far. Code only
    shrinks, so every distance measured before stays in reach after. Returns (lines, bytes)."""
    out, saved, i = list(lines), 0, 0
    prev = None                                  # the instruction line before, its index
    tables = {n.split("#", 1)[1] for n in map(norm, lines) if n and re.match(r"mov dptr,#\d+\$$", n)}
    in_table = False                             # a switch's jump table (JMP @A+DPTR): its
    for i, line in enumerate(lines):             # LJMPs are 3 bytes apart, left as they are
        ins = norm(line)
        if ins is None:
            if line.strip() and not line.strip().startswith(";"):
                prev = None                      # a label or directive between
                in_table = in_table or line.strip()[:-1] in tables
            continue
        op, _, arg = ins.partition(" ")
        in_table = in_table and op == "ljmp"
        if in_table:
            continue
        if op == "ljmp" and LOCAL.match(arg) and (i + 1) in at \
                and labels.get((at[i + 1][1], arg), (None,))[0] == at[i + 1][0]:
            area, scope, here = at[i + 1]
            target = labels[(scope, arg)][1]
            if prev is not None:
                p_ins = norm(lines[prev])
                p_op, _, p_arg = p_ins.partition(" ")
                p_args = p_arg.split(",")
                skip = p_args[-1]
                j = i + 1                        # the label right after the LJMP
                while j < len(lines) and (not lines[j].strip() or lines[j].strip().startswith(";")):
                    j += 1
                if p_op in INVERSE and j < len(lines) and lines[j].strip() == skip + ":" \
                        and (prev + 1) in at:
                    p_at = at[prev + 1][2]
                    p_size = 3 if p_op in ("jb", "jnb") else 2
                    if -128 <= target - (p_at + p_size) <= 127:
                        out[prev] = "\t%s\t%s\n" % (INVERSE[p_op], ",".join(p_args[:-1] + [arg]))
                        out[i] = ""
                        saved += 3
                        prev = None
                        continue
            if -128 <= target - (here + 2) <= 127:
                out[i] = "\tsjmp\t%s\n" % arg
                saved += 1
        prev = i if op not in ("ljmp", "sjmp", "ret", "reti") else None
    return out, saved


def main():
    args = sys.argv[1:]
    if args[:1] == ["--gen"] and len(args) == 2:
        gen(args[1])
        return
    if args[:1] == ["--relax"] and len(args) == 2:
        path = args[1]
        at, labels = listing(path[:-4] + ".lst")
        with open(path, encoding="latin-1") as f:
            lines = f.readlines()
        out, saved = relax(lines, at, labels)
        if saved:
            with open(path, "w", encoding="latin-1") as f:
                f.writelines(out)
        print(saved)
        return
    stats = "--stats" in args
    hot = [p for a in args if a.startswith("--hot=") for p in a.split("=", 1)[1].split(",") if p]
    files = [a for a in args if not a.startswith("--")]
    if not files:
        sys.exit("usage: share_moves.py --gen DIR | [--stats] [--hot=FUNC,..] FILE.asm...")
    total = {}
    for path in files:
        with open(path, encoding="latin-1") as f:
            lines = f.readlines()
        out, used = share(lines, hot)
        out, used_entries = entries(out, hot)
        used.update(used_entries)
        if stats:                                # the calls a build already made count too
            for line in lines:
                m = re.match(r"\s*l(?:call|jmp)\s+_mv_(\w+)", line)
                if m:
                    used[m.group(1)] = used.get(m.group(1), 0) + 1
        for k, v in used.items():
            total[k] = total.get(k, 0) + v
        if not stats and used:
            with open(path, "w", encoding="latin-1") as f:
                f.writelines(out)
    if stats:
        net = 0
        for k in sorted(ROUTINES, key=lambda k: -total.get(k, 0) * (body_size(ROUTINES[k][1]) - CALL_BYTES)):
            b = body_size(ROUTINES[k][1])
            gain = total.get(k, 0) * (b - CALL_BYTES) - (b + 1) if k in total else 0
            net += gain
            print("%-18s %4d uses, %2d bytes each, %5d B net" % (k, total.get(k, 0), b, gain))
        print("share_moves: %d bytes saved, the routines' own bytes counted" % net)


if __name__ == "__main__":
    main()

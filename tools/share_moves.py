#!/usr/bin/env python3
"""share_moves.py FILE.asm...: replace the long register and memory moves SDCC writes out again
and again by calls of one shared copy each (firmware/math/moves*.c), in place.

SDCC's large model moves every 32-bit value byte by byte: XRAM to R4-R7 is 11 bytes of code,
and the same 11 bytes appear wherever such a value is read. Each sequence in MOVES below is
replaced, where it stands whole (no label inside it, so nothing jumps into its middle), by an
LCALL of the routine that holds exactly those instructions and a RET: the registers, DPTR, A,
the flags and the memory end as they did; only the stack holds two bytes more for the moment,
and the sequence takes 4 machine cycles longer. This runs on the assembly SDCC wrote, after its
own optimiser (whose register analysis takes a call to leave R0-R7 unread and would drop the
moves that set them up), and before the assembler. The Makefile runs it on every firmware
module but most of the controllers' (their step's cycles count: make bench).

The later round's sequences (names z_) are a second pass over what the first left: the sets
before it share exactly as they did.

--stats: print what would be replaced, change nothing. --skip=PREFIX: not the sequences whose
name starts with PREFIX (fp_: a controller's locals, reached many times a step).
--skip-func=NAME: nothing in the function NAME (its C name; from its label to the next
function's): a controller's step, whose cycles count, in a module whose other functions
(derivations, initialisation) may share."""
import re
import sys

# name -> instructions (normalised: mnemonic, one space, operands without spaces)
MOVES = {
    "ld_r4567": ["movx a,@dptr", "mov r4,a", "inc dptr", "movx a,@dptr", "mov r5,a",
                 "inc dptr", "movx a,@dptr", "mov r6,a", "inc dptr", "movx a,@dptr", "mov r7,a"],
    "ld_r2367": ["movx a,@dptr", "mov r2,a", "inc dptr", "movx a,@dptr", "mov r3,a",
                 "inc dptr", "movx a,@dptr", "mov r6,a", "inc dptr", "movx a,@dptr", "mov r7,a"],
    "ld_r2345": ["movx a,@dptr", "mov r2,a", "inc dptr", "movx a,@dptr", "mov r3,a",
                 "inc dptr", "movx a,@dptr", "mov r4,a", "inc dptr", "movx a,@dptr", "mov r5,a"],
    "st_r4567": ["mov a,r4", "movx @dptr,a", "mov a,r5", "inc dptr", "movx @dptr,a",
                 "mov a,r6", "inc dptr", "movx @dptr,a", "mov a,r7", "inc dptr", "movx @dptr,a"],
    "st_r2367": ["mov a,r2", "movx @dptr,a", "mov a,r3", "inc dptr", "movx @dptr,a",
                 "mov a,r6", "inc dptr", "movx @dptr,a", "mov a,r7", "inc dptr", "movx @dptr,a"],
    "st_r2345": ["mov a,r2", "movx @dptr,a", "mov a,r3", "inc dptr", "movx @dptr,a",
                 "mov a,r4", "inc dptr", "movx @dptr,a", "mov a,r5", "inc dptr", "movx @dptr,a"],
    "ld_i4": ["movx a,@dptr", "mov @r0,a", "inc dptr", "movx a,@dptr", "inc r0", "mov @r0,a",
              "inc dptr", "movx a,@dptr", "inc r0", "mov @r0,a", "inc dptr", "movx a,@dptr",
              "inc r0", "mov @r0,a"],
    "st_i4": ["mov a,@r0", "movx @dptr,a", "inc r0", "mov a,@r0", "inc dptr", "movx @dptr,a",
              "inc r0", "mov a,@r0", "inc dptr", "movx @dptr,a", "inc r0", "mov a,@r0",
              "inc dptr", "movx @dptr,a"],
    "rv_i4": ["mov @r0,dpl", "inc r0", "mov @r0,dph", "inc r0", "mov @r0,b", "inc r0",
              "mov @r0,a"],
    "rv_r4567": ["mov r4,dpl", "mov r5,dph", "mov r6,b", "mov r7,a"],
    "ar_r4567": ["mov dpl,r4", "mov dph,r5", "mov b,r6", "mov a,r7"],
    "ld_r67": ["movx a,@dptr", "mov r6,a", "inc dptr", "movx a,@dptr", "mov r7,a"],
    "ld_r45": ["movx a,@dptr", "mov r4,a", "inc dptr", "movx a,@dptr", "mov r5,a"],
    "ld_r23": ["movx a,@dptr", "mov r2,a", "inc dptr", "movx a,@dptr", "mov r3,a"],
    "st_r67": ["mov a,r6", "movx @dptr,a", "mov a,r7", "inc dptr", "movx @dptr,a"],
    "st_r45": ["mov a,r4", "movx @dptr,a", "mov a,r5", "inc dptr", "movx @dptr,a"],
    "cld_r67": ["clr a", "movc a,@a+dptr", "mov r6,a", "inc dptr", "clr a", "movc a,@a+dptr",
                "mov r7,a"],
    "gp_r67": ["mov r5,#0x80", "mov dpl,r6", "mov dph,r7", "mov b,r5"],
    "rrc_i3": ["rrc a", "mov @r0,a", "dec r0", "mov a,@r0", "rrc a", "mov @r0,a", "dec r0",
               "mov a,@r0", "rrc a", "mov @r0,a"],
    "ld_fp1": ["mov r0,_bp", "inc r0", "mov dpl,@r0", "inc r0", "mov dph,@r0"],
    "ld_dptr": ["movx a,@dptr", "mov r6,a", "inc dptr", "movx a,@dptr", "mov dpl,r6", "mov dph,a"],
    "addc_i67": ["mov a,r6", "inc r0", "addc a,@r0", "mov r6,a", "mov a,r7", "inc r0",
                 "addc a,@r0", "mov r7,a"],
    "ar_i4a": ["mov r0,a", "mov dpl,@r0", "inc r0", "mov dph,@r0", "inc r0", "mov b,@r0",
               "inc r0", "mov a,@r0"],
    "ar_i4": ["mov dpl,@r0", "inc r0", "mov dph,@r0", "inc r0", "mov b,@r0", "inc r0",
              "mov a,@r0"],
    "st_ir4567": ["mov @r0,ar4", "inc r0", "mov @r0,ar5", "inc r0", "mov @r0,ar6", "inc r0",
                  "mov @r0,ar7"],
    "st_a000": ["movx @dptr,a", "clr a", "inc dptr", "movx @dptr,a", "inc dptr", "movx @dptr,a",
                "inc dptr", "movx @dptr,a"],
    "st_1a00": ["inc dptr", "movx @dptr,a", "clr a", "inc dptr", "movx @dptr,a", "inc dptr",
                "movx @dptr,a"],
    "st_aaaa": ["movx @dptr,a", "inc dptr", "movx @dptr,a", "inc dptr", "movx @dptr,a",
                "inc dptr", "movx @dptr,a"],
    # the shorter ones: a 16-bit value between DPTR and a register
    # pair, the registers a call's 24- or 32-bit result lands in, 16-bit moves through @R0 and
    # @R1, SDCC's signed compare (sign bits flipped; the carry is the result), 32-bit sums and
    # differences with a local, carries and sign extensions into R6-R7, 32-bit shifts by 4
    "ar_r67": ["mov dpl,r6", "mov dph,r7"],
    "ar_r45": ["mov dpl,r4", "mov dph,r5"],
    "ar_r23": ["mov dpl,r2", "mov dph,r3"],
    "rv_r67": ["mov r6,dpl", "mov r7,dph"],
    "rv_r45": ["mov r4,dpl", "mov r5,dph"],
    "rv_r23": ["mov r2,dpl", "mov r3,dph"],
    "rv_r3456": ["mov r3,dpl", "mov r4,dph", "mov r5,b", "mov r6,a"],
    "st_i2": ["mov a,@r0", "movx @dptr,a", "inc r0", "mov a,@r0", "inc dptr", "movx @dptr,a"],
    "cp_ii2": ["mov @r1,a", "inc r0", "mov a,@r0", "inc r1", "mov @r1,a"],
    "ld_ir23": ["mov ar2,@r0", "inc r0", "mov ar3,@r0"],
    "ld_ir45": ["mov ar4,@r0", "inc r0", "mov ar5,@r0"],
    "ld_ir67": ["mov ar6,@r0", "inc r0", "mov ar7,@r0"],
    "st_ir23": ["mov @r0,ar2", "inc r0", "mov @r0,ar3"],
    "st_ir67": ["mov @r0,ar6", "inc r0", "mov @r0,ar7"],
    "st_ir3456": ["mov @r0,ar3", "inc r0", "mov @r0,ar4", "inc r0", "mov @r0,ar5", "inc r0",
                  "mov @r0,ar6"],
    "ld_r56": ["movx a,@dptr", "mov r5,a", "inc dptr", "movx a,@dptr", "mov r6,a"],
    "st_r23": ["mov a,r2", "movx @dptr,a", "mov a,r3", "inc dptr", "movx @dptr,a"],
    "st_00": ["clr a", "movx @dptr,a", "inc dptr", "movx @dptr,a"],
    "ld_fp1a": ["mov r0,_bp", "inc r0", "mov a,@r0"],
    "r67_0": ["mov r6,#0x00", "mov r7,#0x00"],
    "inc_dptr5": ["inc dptr", "inc dptr", "inc dptr", "inc dptr", "inc dptr"],
    "scmp_b": ["xrl b,#0x80", "subb a,b"],
    "sub_i_r2367": ["mov a,@r0", "clr c", "subb a,r2", "mov r2,a", "inc r0", "mov a,@r0",
                    "subb a,r3", "mov r3,a", "inc r0", "mov a,@r0", "subb a,r6", "mov r6,a",
                    "inc r0", "mov a,@r0", "subb a,r7"],
    "add_i_r4567": ["mov a,@r0", "add a,r4", "mov r4,a", "inc r0", "mov a,@r0", "addc a,r5",
                    "mov r5,a", "inc r0", "mov a,@r0", "addc a,r6", "mov r6,a", "inc r0",
                    "mov a,@r0", "addc a,r7"],
    "adc_r67": ["clr a", "addc a,r6", "mov r6,a", "clr a", "addc a,r7", "mov r7,a"],
    "sext_r67": ["rlc a", "subb a,acc", "mov r6,a", "mov r7,a"],
    "shr4_r4": ["swap a", "xch a,r4", "swap a", "anl a,#0x0f", "xrl a,r4", "xch a,r4",
                "anl a,#0x0f", "xch a,r4", "xrl a,r4", "xch a,r4"],
    "shr4_r6": ["swap a", "xch a,r6", "swap a", "anl a,#0x0f", "xrl a,r6", "xch a,r6",
                "anl a,#0x0f", "xch a,r6", "xrl a,r6", "xch a,r6"],
    # issue 14's tenth round (x_): sequences found by counting those the firmware's modules still
    # write out after the sets above; not in the controllers' modules (--skip=x_: their steps' cycles)
    "x_sbc_ii3": ["subb a,@r0", "inc r1", "mov a,@r1", "inc r0", "subb a,@r0", "inc r1",
                  "mov a,@r1", "inc r0", "subb a,@r0"],
    "x_cmp_r4567_i": ["clr c", "mov a,r4", "subb a,@r0", "mov a,r5", "inc r0", "subb a,@r0",
                      "mov a,r6", "inc r0", "subb a,@r0", "mov a,r7", "inc r0", "subb a,@r0"],
    "x_cmp_ffff_r4567": ["clr c", "mov a,#0xff", "subb a,r4", "mov a,#0xff", "subb a,r5", "clr a",
                         "subb a,r6", "clr a", "subb a,r7"],
    "x_neg_scmp_r45": ["mov ar4,r6", "mov ar5,r7", "clr c", "clr a", "subb a,r4",
                       "mov a,#(0x00^0x80)", "mov b,r5"],
    "x_rv_r567": ["mov r5,dpl", "mov r6,dph", "mov r7,b"],
    "x_shl4_r67_i": ["mov @r0,ar5", "mov a,r6", "swap a", "xch a,@r0", "swap a", "anl a,#0x0f",
                     "xrl a,@r0", "xch a,@r0", "anl a,#0x0f", "xch a,@r0", "xrl a,@r0",
                     "xch a,@r0", "inc r0", "mov @r0,a", "mov a,r7", "swap a", "anl a,#0xf0",
                     "orl a,@r0", "mov @r0,a", "mov a,r7", "swap a", "anl a,#0x0f", "inc r0",
                     "mov @r0,a", "inc r0"],
    "x_cmp_i_r2367": ["clr c", "mov a,@r0", "subb a,r2", "inc r0", "mov a,@r0", "subb a,r3",
                      "inc r0", "mov a,@r0", "subb a,r6", "inc r0", "mov a,@r0", "subb a,r7"],
    "x_shl1_r4567": ["mov a,r4", "add a,r4", "mov r4,a", "mov a,r5", "rlc a", "mov r5,a",
                     "mov a,r6", "rlc a", "mov r6,a", "mov a,r7", "rlc a", "mov r7,a"],
    "x_ar_r564": ["mov dpl,r5", "mov dph,r6", "mov b,r4"],
    "x_sbc_r45_i": ["subb a,r4", "mov r4,a", "inc r0", "mov a,@r0", "subb a,r5", "mov r5,a",
                    "inc r0", "mov a,@r0"],
    "x_shl4_r2367": ["xch a,r6", "swap a", "anl a,#0xf0", "xch a,r6", "swap a", "xch a,r6",
                     "xrl a,r6", "xch a,r6", "anl a,#0xf0", "xch a,r6", "xrl a,r6", "mov r7,a",
                     "mov a,r2", "swap a", "anl a,#0x0f", "orl a,r6", "mov r6,a", "mov a,r2",
                     "swap a", "anl a,#0xf0", "mov r3,a", "mov r2,#0x00"],
    "x_sub_i_r4567": ["clr c", "subb a,r4", "mov @r0,a", "inc r0", "mov a,@r0", "subb a,r5",
                      "mov @r0,a", "inc r0", "mov a,@r0", "subb a,r6", "mov @r0,a", "inc r0",
                      "mov a,@r0", "subb a,r7", "mov @r0,a"],
    "x_shr1_r4567": ["clr c", "rrc a", "mov r7,a", "mov a,r6", "rrc a", "mov r6,a", "mov a,r5",
                     "rrc a", "mov r5,a", "mov a,r4", "rrc a"],
    "x_fp_r0_02": ["mov r0,_bp", "inc r0", "inc r0"],
    "x_cmp_ii4": ["mov a,_bp", "add a,#0x18", "mov r0,a", "mov a,_bp", "add a,#0x1c", "mov r1,a",
                  "clr c", "mov a,@r0", "subb a,@r1", "inc r0", "mov a,@r0", "inc r1",
                  "subb a,@r1", "inc r0", "mov a,@r0", "inc r1", "subb a,@r1", "inc r0",
                  "mov a,@r0", "inc r1", "subb a,@r1"],
    "x_shr1_i4_r67": ["inc r0", "inc r0", "inc r0", "mov a,@r0", "clr c", "rrc a", "mov r7,a",
                      "dec r0", "mov a,@r0", "rrc a", "mov r6,a", "dec r0", "mov a,@r0", "rrc a"],
    "x_ld_r45_add": ["movx a,@dptr", "mov r6,a", "inc dptr", "movx a,@dptr", "mov r4,a",
                     "mov ar5,r6", "clr a", "mov r6,a", "mov r7,a", "mov a,#0xf0", "add a,r6",
                     "mov r6,a", "mov a,#0x3f", "addc a,r7", "mov r7,a", "clr a", "addc a,r5",
                     "mov r5,a", "clr a", "addc a,r4", "mov r4,a"],
    "x_add_fp1_r45": ["mov r0,_bp", "inc r0", "mov a,r4", "add a,@r0", "mov r4,a", "mov a,r5",
                      "inc r0", "addc a,@r0", "mov r5,a"],
    "x_fp_x05": ["xch a,r0", "mov a,_bp", "add a,#0x05", "xch a,r0"],
    "x_ar_r567": ["mov dpl,r5", "mov dph,r6", "mov b,r7"],
    "x_dptr_a_r67": ["add a,r6", "mov dpl,a", "clr a", "addc a,r7", "mov dph,a"],
    "x_shl1_r56": ["mov a,r5", "add a,r5", "mov r5,a", "mov a,r6", "rlc a", "mov r6,a"],
    "x_st_i00": ["inc r0", "mov @r0,#0x00", "inc r0", "mov @r0,#0x00"],
    "x_ld_r6a": ["movx a,@dptr", "mov r6,a", "inc dptr", "movx a,@dptr"],
    "x_add_i_r23": ["mov a,r2", "add a,@r0", "mov r2,a", "mov a,r3", "inc r0", "addc a,@r0",
                    "mov r3,a"],
    "x_fp1_st00": ["mov r0,_bp", "inc r0", "clr a", "mov @r0,a", "inc r0", "mov @r0,a"],
    "x_neg_scmp_r67": ["clr c", "clr a", "subb a,r6", "mov a,#(0x00^0x80)", "mov b,r7"],
    "x_cmp_r67_100": ["clr c", "mov a,r6", "subb a,#0x64", "mov a,r7", "subb a,#0x00"],
    "x_rv_r3467": ["mov r3,dpl", "mov r4,dph", "mov r6,b", "mov r7,a"],
    "x_mv_r45_r67": ["mov ar4,r6", "mov ar5,r7"],
    "x_add_ii4_r4567": ["mov a,@r1", "add a,@r0", "mov r4,a", "inc r1", "mov a,@r1", "inc r0",
                        "addc a,@r0", "mov r5,a", "inc r1", "mov a,@r1", "inc r0", "addc a,@r0",
                        "mov r6,a", "inc r1", "mov a,@r1", "inc r0", "addc a,@r0", "mov r7,a"],
    "x_sbc_i_r67": ["mov a,r6", "inc r0", "subb a,@r0", "mov r6,a", "mov a,r7", "inc r0",
                    "subb a,@r0", "mov r7,a"],
    "x_orl_i3": ["inc r0", "orl a,@r0", "inc r0", "orl a,@r0", "inc r0", "orl a,@r0"],
    "x_sbc_r67_i": ["subb a,r6", "mov r6,a", "inc r0", "mov a,@r0", "subb a,r7", "mov r7,a"],
    "x_shr2_i": ["anl a,#0x03", "mov c,acc.0", "xch a,@r0", "rrc a", "xch a,@r0", "rrc a",
                 "mov c,acc.0", "xch a,@r0", "rrc a", "xch a,@r0", "rrc a", "xch a,@r0", "inc r0",
                 "mov @r0,a"],
    "x_sbc_r567_0": ["subb a,r5", "clr a", "subb a,r6", "clr a", "subb a,r7"],
    "x_st_r56": ["mov a,r5", "movx @dptr,a", "mov a,r6", "inc dptr", "movx @dptr,a"],
    "x_add_a_r67": ["add a,r6", "mov r6,a", "clr a", "addc a,r7", "mov r7,a"],
    "x_cmp_r67_r45": ["clr c", "mov a,r6", "subb a,r4", "mov a,r7", "subb a,r5"],
    "x_st_r34": ["mov a,r3", "movx @dptr,a", "mov a,r4", "inc dptr", "movx @dptr,a"],
    "x_ld_r2a": ["movx a,@dptr", "mov r2,a", "inc dptr", "movx a,@dptr"],
    "x_fp_r0_fa": ["mov a,_bp", "add a,#0xfa", "mov r0,a"],
    "x_addc_b_dph": ["addc a,b", "mov dph,a"],
    "x_sub_i_r4763": ["mov a,@r0", "clr c", "subb a,r4", "mov r4,a", "inc r0", "mov a,@r0",
                      "subb a,r7", "mov r7,a", "inc r0", "mov a,@r0", "subb a,r6", "mov r6,a",
                      "inc r0", "mov a,@r0", "subb a,r3", "mov r3,a"],
    "x_shl2_r45": ["mov c,acc.7", "xch a,r4", "rlc a", "xch a,r4", "rlc a", "mov c,acc.7",
                   "xch a,r4", "rlc a", "xch a,r4", "rlc a", "xch a,r4", "anl a,#0x03",
                   "mov r5,a"],
    "x_shl2_r67": ["mov c,acc.7", "xch a,r6", "rlc a", "xch a,r6", "rlc a", "mov c,acc.7",
                   "xch a,r6", "rlc a", "xch a,r6", "rlc a", "xch a,r6", "anl a,#0x03",
                   "mov r7,a"],
    "x_rv_r56": ["mov r5,dpl", "mov r6,dph"],
    "x_cmp_fp1_r3467": ["mov r0,_bp", "inc r0", "clr c", "mov a,r3", "subb a,@r0", "mov a,r4",
                        "inc r0", "subb a,@r0", "mov a,r6", "inc r0", "subb a,@r0", "mov a,r7",
                        "inc r0", "subb a,@r0"],
    "x_st_1a010": ["inc dptr", "movx @dptr,a", "mov a,#0x01", "inc dptr", "movx @dptr,a", "clr a",
                   "inc dptr", "movx @dptr,a"],
    "x_sbc_i3_0": ["subb a,@r0", "clr a", "inc r0", "subb a,@r0", "clr a", "inc r0", "subb a,@r0"],
    "x_cld_r45": ["clr a", "movc a,@a+dptr", "mov r4,a", "inc dptr", "clr a", "movc a,@a+dptr",
                  "mov r5,a"],
    "x_ld_i2": ["movx a,@dptr", "mov @r0,a", "inc dptr", "movx a,@dptr", "inc r0", "mov @r0,a"],
    "x_rlc_r67": ["mov a,r6", "rlc a", "mov r6,a", "mov a,r7", "rlc a", "mov r7,a"],
    "x_ld_r34": ["movx a,@dptr", "mov r3,a", "inc dptr", "movx a,@dptr", "mov r4,a"],
    "x_st_ir45": ["mov @r0,ar4", "inc r0", "mov @r0,ar5"],
    # a later round (z_, firmware/math/moves_late.c): the sequences still written out often enough
    # to pay for a routine, counted on the modules' assembly after every set above had been
    # shared (LATE: a second pass, so the sets above are shared exactly as before); not in the
    # controllers' modules (--skip=z_), nor any that sets _bp or SP (tools/stackdepth.py reads
    # the frames from those)
    "z_ar_i2": ["mov dpl,@r0", "inc r0", "mov dph,@r0"],
    "z_mul_b2": ["mov b,#0x02", "mul ab"],
    "z_fp_r0_14": ["mov a,_bp", "add a,#0x14", "mov r0,a"],
    "z_sbc_i3_r67": ["inc r0", "subb a,@r0", "mov a,r6", "inc r0", "subb a,@r0", "mov a,r7", "inc r0", "subb a,@r0"],
    "z_neg_scmp_r23": ["clr c", "clr a", "subb a,r2", "mov a,#(0x00^0x80)", "mov b,r3"],
    "z_st_1a1a": ["inc dptr", "movx @dptr,a", "inc dptr", "movx @dptr,a"],
    "z_ar_r34": ["mov dpl,r3", "mov dph,r4"],
    "z_c_dpl": ["clr a", "rlc a", "mov dpl,a"],
    "z_rrc_r67": ["rrc a", "xch a,r6", "rrc a", "xch a,r6", "mov r7,a"],
    "z_sbc_0_r67": ["subb a,#0x00", "mov a,r6", "subb a,#0x00", "mov a,r7", "subb a,#0x00"],
    "z_ld_fp1_r34": ["mov r0,_bp", "inc r0", "mov ar3,@r0", "inc r0", "mov ar4,@r0"],
    "z_rv_r567a": ["mov r5,dph", "mov r6,b", "mov r7,a"],
    "z_fp_r1_09": ["mov a,_bp", "add a,#0x09", "mov r1,a"],
    "z_shl4_r45": ["swap a", "anl a,#0xf0", "xch a,r4", "swap a", "xch a,r4", "xrl a,r4", "xch a,r4", "anl a,#0xf0", "xch a,r4", "xrl a,r4", "mov r5,a"],
    "z_shr2_orl_i": ["mov a,r5", "rr a", "rr a", "anl a,#0x3f", "dec r0", "orl a,@r0", "mov @r0,a", "dec r0", "dec r0", "mov @r0,ar4", "mov a,r5"],
    "z_shl1_r23": ["mov a,r2", "add a,r2", "mov r2,a", "mov a,r3", "rlc a", "mov r3,a"],
    "z_ld_r5a": ["movx a,@dptr", "mov r5,a", "inc dptr", "movx a,@dptr"],
    "z_ar_r56": ["mov dpl,r5", "mov dph,r6"],
    "z_ar_r76": ["mov dpl,r7", "mov dph,r6"],
    "z_cld_r3a": ["clr a", "movc a,@a+dptr", "mov r3,a", "inc dptr", "clr a", "movc a,@a+dptr"],
    "z_sub_ii_r67": ["inc r1", "mov @r1,a", "inc r0", "mov a,@r0", "subb a,r6", "inc r1", "mov @r1,a", "inc r0", "mov a,@r0", "subb a,r7", "inc r1", "mov @r1,a"],
    "z_add_a_r45": ["add a,r4", "mov r4,a", "clr a", "addc a,r5", "mov r5,a"],
    "z_ld_r47": ["movx a,@dptr", "mov r4,a", "inc dptr", "movx a,@dptr", "mov r7,a"],
    "z_fp1_r7a": ["mov r7,a", "mov r0,_bp", "inc r0"],
    "z_sub_r67_r45": ["mov a,r6", "clr c", "subb a,r4", "mov r4,a", "mov a,r7", "subb a,r5", "mov r5,a"],
    "z_scmp_0_r2": ["clr c", "mov a,#(0x00^0x80)", "mov b,r2"],
    "z_cmp_ffff_r3456": ["clr c", "mov a,#0xff", "subb a,r3", "mov a,#0xff", "subb a,r4", "clr a", "subb a,r5", "clr a", "subb a,r6"],
    "z_st_a_r56": ["movx @dptr,a", "mov a,r5", "inc dptr", "movx @dptr,a", "mov a,r6", "inc dptr", "movx @dptr,a"],
    "z_shr1_r4": ["clr c", "rrc a", "xch a,r4", "rrc a", "xch a,r4"],
    "z_add_a_r23": ["add a,r2", "mov r2,a", "clr a", "addc a,r3", "mov r3,a"],
    "z_ld_ir4567_r1": ["mov ar4,@r1", "inc r1", "mov ar5,@r1", "inc r1", "mov ar6,@r1", "inc r1", "mov ar7,@r1"],
    "z_i3_clr": ["inc r0", "inc r0", "inc r0", "mov a,@r0", "clr c"],
    "z_fp_r0_0a": ["mov a,_bp", "add a,#0x0a", "mov r0,a"],
}
# R0 (or R1) = the address of a reentrant function's local: the frame base _bp plus its offset
# (the offsets the firmware uses most)
for _reg, _offs in (("r0", (0x03, 0x04, 0x05, 0x06, 0x07, 0x09, 0x0b, 0x0d, 0x0f, 0x11, 0x13, 0x15,
                            0xfc, 0xfd)),
                    ("r1", (0x05,))):
    for _off in _offs:
        MOVES["fp_%s_%02x" % (_reg, _off)] = ["mov a,_bp", "add a,#0x%02x" % _off, "mov %s,a" % _reg]
ORDER = sorted((n for n in MOVES if not n.startswith("z_")), key=lambda n: -len(MOVES[n]))
LATE = sorted((n for n in MOVES if n.startswith("z_")), key=lambda n: -len(MOVES[n]))


def norm(line):
    """an instruction line normalised, or None for anything else (label, directive, comment)"""
    s = line.split(";", 1)[0].strip()
    if not s or s.endswith(":") or s.startswith(".") or "=" in s or ":" in s:
        return None
    parts = s.split(None, 1)
    return parts[0] + (" " + re.sub(r"\s+", "", parts[1]) if len(parts) > 1 else "")


FUNC = re.compile(r"^_(\w+):\s*$")


def share(lines, skip_funcs=(), order=None):
    order = ORDER if order is None else order
    out, used, i, func = [], {}, 0, None
    while i < len(lines):
        hit = None
        m = FUNC.match(lines[i])
        if m:
            func = m.group(1)
        if norm(lines[i]) is not None and func not in skip_funcs:
            for name in order:
                seq, j, k, kept = MOVES[name], i, 0, []
                while k < len(seq) and j < len(lines):
                    n = norm(lines[j])
                    if n is None:
                        if lines[j].strip().startswith(";"):
                            kept.append(lines[j])      # a comment: kept, after the call
                            j += 1
                            continue
                        break                          # a label or directive: not whole
                    if n != seq[k]:
                        break
                    k += 1
                    j += 1
                if k == len(seq):
                    hit = (name, j, kept)
                    break
        if hit:
            name, j, kept = hit
            out.append("\tlcall\t_mv_%s\n" % name)
            out.extend(kept)
            used[name] = used.get(name, 0) + 1
            i = j
        else:
            out.append(lines[i])
            i += 1
    return out, used


def main():
    global ORDER, LATE
    args = sys.argv[1:]
    stats = "--stats" in args
    skip = [a.split("=", 1)[1] for a in args if a.startswith("--skip=")]
    skip_funcs = [a.split("=", 1)[1] for a in args if a.startswith("--skip-func=")]
    ORDER = [n for n in ORDER if not any(n.startswith(p) for p in skip)]
    LATE = [n for n in LATE if not any(n.startswith(p) for p in skip)]
    files = [a for a in args if a != "--stats" and not a.startswith("--skip")]
    if not files:
        sys.exit("usage: share_moves.py [--stats] [--skip=PREFIX] [--skip-func=NAME] FILE.asm...")
    total = {}
    for path in files:
        with open(path, encoding="latin-1") as f:
            lines = f.readlines()
        out, used = share(lines, skip_funcs)
        out, late = share(out, skip_funcs, LATE)
        used.update(late)
        for k, v in used.items():
            total[k] = total.get(k, 0) + v
        if not stats and used:
            with open(path, "w", encoding="latin-1") as f:
                f.writelines(out)
    if stats:
        saved = 0
        for k in ORDER + LATE:
            if k in total:
                b = sum(1 if s.split()[0] in ("movx", "inc") or re.match(r"mov (a,r\d|r\d,a|a,@r0|@r0,a)$", s)
                        else 2 for s in MOVES[k])
                saved += total[k] * (b - 3)
                print("%-10s %4d uses, %2d bytes each" % (k, total[k], b))
        print("share_moves: about %d bytes saved before the routines" % saved)


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""mutate.py: mutation testing of the firmware's safety and integrity rules (make mutate).

No C mutation tool is packaged where this project installs from (Debian's apt and PyPI through
tools/requirements.txt: neither carries mull, dextool or universalmutator's C front end), so this
is a small harness of the project's own. It takes the functions named in SITES below, makes one
mutant a change:

  cmp     a comparison flipped (< into >=, == into !=, ...) or moved by its boundary (< into <=)
  const   an integer constant off by one (a literal, or a #defined constant written in the body)
  cond    a condition dropped: one operand of && taken as 1, of || as 0; an if's condition as 0

compiles the one mutated file with the host test flags, links it ahead of the host test
library (so that library's own object of that file is never pulled), runs the host tests that
cover the file (TESTS below, fastest first) and reports the mutants no test kills. A survivor
gets a test that kills it, or a line in EQUIVALENT below with the reason.

  tools/mutate.py                    every mutant (make mutate)
  tools/mutate.py --sample 5 --seed N   five of them drawn with seed N (make test)
  tools/mutate.py --list [--only FILE[:FUNC]]   the mutants, not run
  tools/mutate.py --only firmware/ops/diag.c:rule   the mutants of one function (or file)

Sites are keyed on function names, not lines: a rule added to a listed function joins at once;
a new function joins by a line in SITES. An EQUIVALENT line names the function, the mutated
line's text and the change, so it follows the line when the file moves around it; one that
matches no mutant any more is reported as stale.
"""
import argparse
import os
import random
import re
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor

# ---- what is mutated: file -> the functions whose bodies hold its rules ------------------------
SITES = {
    # alarms and their timing
    "firmware/ops/diag.c": ["need_periods", "rule", "diag_supply", "diag_model", "diag_offrate", "diag_speed",
                            "diag_step", "x_of"],
    "firmware/ops/diag_line.c": ["diag_period", "diag_dry_line", "diag_zero", "diag_balance"],
    "firmware/ops/diag_wheel.c": ["diag_pump"],
    # the link's checksum, layout and refusals; Raven's strings and their refusals
    "firmware/link/linecheck.c": ["line_crc8", "hexval", "line_check", "line_number"],
    "firmware/link/serial.c": ["answer", "run", "take", "serial_poll"],
    "firmware/link/remote.c": ["remote_command"],
    # the AgOpenGPS and RateControl frames: their checks and refusals, stopping, the speeds apart
    "firmware/link/pgn.c": ["pgn_byte", "pgn_drop", "take", "rc_rate", "stale", "pgn_lost", "pgn_frames",
                            "pgn_speed", "pgn_sections"],
    # the EEPROM record checks; the settings' ranges and cross-checks
    "firmware/store/record.c": ["store_ck_more"],
    "firmware/store/store.c": ["store_load", "load_newest"],
    "firmware/store/params.c": ["param_in_range", "param_put", "params_cross", "param_try"],
    # the valve's stops, dead time and reversals
    "firmware/control/valve.c": ["apply", "integrate", "valve_set"],
    # the remote window, the minimum-flow rule, working speed
    "firmware/control/target.c": ["target_rate_window", "target_remote_rate", "target_working_speed",
                                  "target_flow_x100"],
    # plausibility: the meter's impossible periods, the sensors' loop currents
    "firmware/measure/flow.c": ["flow_step"],
    "firmware/measure/analog.c": ["judge", "analog_step"],
}

# ---- which host tests cover a file (build/host-test/<name>), the fastest killers first --------
TESTS = {
    "firmware/ops/diag.c": ["test_diag_edges", "test_diag", "test_pgn", "test_plaus", "test_faults"],
    "firmware/ops/diag_line.c": ["test_diag_line", "test_diag", "test_diag_edges", "test_slow_faults"],
    "firmware/ops/diag_wheel.c": ["test_diag_wheel", "test_plaus", "test_diag", "test_faults"],
    "firmware/link/linecheck.c": ["test_serial", "test_raven", "test_hil"],
    "firmware/link/serial.c": ["test_serial", "test_raven", "test_hil", "test_pgn"],
    "firmware/link/remote.c": ["test_raven", "test_serial"],
    "firmware/link/pgn.c": ["test_pgn", "test_pgn_sim"],
    "firmware/store/record.c": ["test_store"],
    "firmware/store/store.c": ["test_store"],
    "firmware/store/params.c": ["test_store", "test_serial", "test_console"],
    "firmware/control/valve.c": ["test_valve", "test_plaus", "test_drive", "test_faults"],
    "firmware/control/target.c": ["test_target", "test_raven", "test_plaus", "test_diag_edges"],
    "firmware/measure/flow.c": ["test_measure", "test_plaus", "test_diag_edges"],
    "firmware/measure/analog.c": ["test_measure", "test_diag_edges"],
}

# ---- equivalent mutants: (file, function, the line's text, change, reason) --------------------
NP = "DIAG_METER_PERIODS, 1, 1, 1, DIAG_OVERP_PERIODS, 1, 1, 1, 0,"
NP2 = "DIAG_BAL_PERIODS, 1, DIAG_MIN_FLOW_PERIODS"
DIGIT = ("Valve cal's dead-band digit: the subtractions only take the digits apart; a bound moved by "
         "one leaves a value ending in 0 at 0 and one ending in 1-9 (or wrapped past 0) not at 0")
DIR = "dir is set to 1 or -1 just above (d > 0 ? 1 : -1): dir >= 0 is dir > 0"
AT_END = "at t == 32767 both ways leave t at 32767 with nothing added over the end"
FAR = ("the constant moved in the test only: a hi of 120 (or under) leaves with 120 either way, "
       "the assignment writes DIAG_PDEV_FAR_KPA")
SIGNED = ("JOG, NUD and HIL need their checksum (CHANGES): past the word, p[0] is a space or the '*' that "
          "line_check ended the line at, and then p[1] and p[2] are the checksum's hex digits: p[2] is "
          "not the end, refused either way")
RAVEN_ONLY = ("remote_command acts only on '$R,' with letters, digits and commas up to the line's end (each "
              "of its paths reads to the end or refuses): a line line_check refuses holds a space "
              "(LINE_E_ARG: leading, trailing, doubled) or a '*' (LINE_E_CSUM) before its end, refused there too")
RAVEN_IF = "if (c < LINE_E_ARG && se.buf[0] == '$')"
PAST_END = ("slot STORE_SLOTS starts at 2 x HAL_EEPROM_SECTOR = HAL_EEPROM_SIZE, past the EEPROM: both "
            "HALs read 0xFF there (hal.h), no magic, no record")
FLOW8 = "30001 / 8 and 30000 / 8 are both 3750 (integer division): the same bound"
COUNTED = "rule() counts the period before it compares: a count of at least 1 is at least 0"
AGE = "stale() compares an age with Frames lost, 100 periods at most: 254 and 255 alike"
RC_HEARD = ("age_rc is read only by 32400's status bit (pgn_next), and a 32400 goes out only in answer to a "
            "32500, which set age_rc to 0 that pass: the bit reads an age of 0 or 1 however it counts on")
RC_AGE = "if (pg.age_rc < 255u)"
EQUIVALENT = [
    ("firmware/link/pgn.c", "rc_rate", "if (((uint32_t)(r > last ? r - last : last - r) << 7) > last || !last) {",
     "> -> >=", "at r == last both ways give 0"),
    ("firmware/link/pgn.c", "pgn_speed", "d = wheel_x100 > gps ? wheel_x100 - gps : gps - wheel_x100;", "> -> >=",
     "at wheel_x100 == gps both ways give 0"),
    ("firmware/link/pgn.c", "pgn_speed", "if (src == SPEED_SRC_BOTH && gps >= PGN_CHECK_X100) {",
     "PGN_CHECK_X100 -> (PGN_CHECK_X100 - 1)", "the GPS's speed is whole tenths of km/h (254's x10 field "
     "times 10): 199 and 200 part them alike"),
    ("firmware/link/pgn.c", "pgn_speed", "if (pg.age_speed < 255u)", "255u -> 254u", AGE),
    ("firmware/link/pgn.c", "pgn_speed", "if (pg.age_sect < 255u)", "255u -> 254u", AGE),
    ("firmware/link/pgn.c", "pgn_speed", RC_AGE, "pg.age_rc < 255u -> 0", RC_HEARD),
    ("firmware/link/pgn.c", "pgn_speed", RC_AGE, "< -> >=", RC_HEARD),
    ("firmware/link/pgn.c", "pgn_speed", RC_AGE, "< -> <=", RC_HEARD),
    ("firmware/link/pgn.c", "pgn_speed", RC_AGE, "255u -> 256u", RC_HEARD),
    ("firmware/link/pgn.c", "pgn_speed", RC_AGE, "255u -> 254u", RC_HEARD),
    ("firmware/ops/diag.c", "need_periods", NP, "1 -> 0", COUNTED),
    ("firmware/ops/diag.c", "need_periods", NP, "1 -> 0 #2", COUNTED),
    ("firmware/ops/diag.c", "need_periods", NP, "1 -> 0 #3", COUNTED),
    ("firmware/ops/diag.c", "need_periods", NP, "1 -> 0 #4", COUNTED),
    ("firmware/ops/diag.c", "need_periods", NP, "1 -> 0 #5", COUNTED),
    ("firmware/ops/diag.c", "need_periods", NP, "1 -> 0 #6", COUNTED),
    ("firmware/ops/diag.c", "need_periods", NP, "1 -> 2 #4",
     "AL_OFFRATE's rule() call only clears it (diag_offrate counts its own raising): never read"),
    ("firmware/ops/diag.c", "need_periods", NP, "0 -> 1", "AL_INTERNAL has no rule(): never read"),
    ("firmware/ops/diag.c", "need_periods", NP2, "1 -> 0", COUNTED),
    ("firmware/ops/diag.c", "diag_offrate",
     "&& UMUL(qp < 0 ? -qp : qp, 100u) > UMUL(param_v[P_OFFRATE], target);",
     "0 -> 1", "at qp == 0, -qp and qp are both 0"),
    ("firmware/ops/diag.c", "rule", "if (*cnt < 255)", "255 -> 254",
     "a count is reset when it reaches its need (30 at most): it never nears 254"),
    ("firmware/ops/diag.c", "rule", "if (*cnt < 255)", "< -> <=",
     "a count is reset when it reaches its need (30 at most): it never reaches 255"),
    ("firmware/ops/diag.c", "diag_model", "&& target > 0 && UMUL(meter > target ? meter - target : target - meter, 20u) <= (uint16_t)target;", "0 -> 1",
     "at target 1 the meter, 500 or more while judged, is never within 5 % of it"),
    ("firmware/ops/diag.c", "diag_model", "&& target > 0 && UMUL(meter > target ? meter - target : target - meter, 20u) <= (uint16_t)target;", "> -> >=",
     "at target 0 the meter, 500 or more while judged, times 20 is never 0 or less"),
    ("firmware/ops/diag.c", "diag_model", "&& target > 0 && UMUL(meter > target ? meter - target : target - meter, 20u) <= (uint16_t)target;", "> -> >= #2", "at meter == target both ways give 0"),
    ("firmware/ops/diag.c", "diag_model", "a = UMUL(p > dg.pc_kpa ? p - dg.pc_kpa : 0, 100u);", "> -> >=",
     "at p == pc_kpa both ways give 0"),
    ("firmware/ops/diag.c", "diag_model", "lo = pexp > hi ? pexp - hi : 0;     /* p + dev < pexp */", "> -> >=",
     "at pexp == hi both ways give 0"),
    ("firmware/ops/diag.c", "diag_model", "if (hi < DIAG_PDEV_FAR_KPA)", "< -> <=", FAR),
    ("firmware/ops/diag.c", "diag_model", "if (hi < DIAG_PDEV_FAR_KPA)", "DIAG_PDEV_FAR_KPA -> (DIAG_PDEV_FAR_KPA + 1)",
     FAR),
    ("firmware/ops/diag.c", "diag_offrate", "&& UMUL(qp < 0 ? -qp : qp, 100u) > UMUL(param_v[P_OFFRATE], target);",
     "< -> <=", "at qp == 0, -qp and qp are both 0"),
    ("firmware/ops/diag.c", "diag_step", "dg.meter_noise = (uint8_t)(dg.meter_noise > 235 ? 255 : dg.meter_noise + 20);",
     "235 -> 234", "at 235 both ways give 255 (235 + 20)"),
    ("firmware/ops/diag.c", "diag_step", "dg.meter_noise = (uint8_t)(dg.meter_noise > 235 ? 255 : dg.meter_noise + 20);",
     "> -> >=", "at 235 both ways give 255 (235 + 20)"),
    ("firmware/ops/diag.c", "diag_step", "dg.wheel_noise = (uint8_t)(x > 255u ? 255u : x);", "255u -> 254u",
     "at x == 255 both ways give 255"),
    ("firmware/ops/diag.c", "diag_step", "dg.wheel_noise = (uint8_t)(x > 255u ? 255u : x);", "> -> >=",
     "at x == 255 both ways give 255"),
    ("firmware/ops/diag.c", "diag_step", "x = x > n ? x - n : 0;", "> -> >=", "at x == n both ways give 0"),
    ("firmware/ops/diag.c", "diag_step",
     "g = dg.learnt && dg.kp_kpa < DIAG_WEAR_KP_KPA && !(dg.alarms & (1u << AL_METER_CAL));", "dg.learnt -> 1",
     "with nothing learnt kp is the told 300 kPa (model_told; every path that sets learnt to 0 calls it), "
     "not under DIAG_WEAR_KP_KPA"),
    ("firmware/ops/diag.c", "diag_supply", "rule(AL_PUMP_DRY, dry || line, !line && !dry && (refill || !diag_lsens));",
     "!dry -> 1", "dry needs a working level sensor at 1 % of Tank size or less, where refill (over Tank min "
     "+ Tank size / 64) cannot hold: with dry 1 the rest of the clear is 0 either way"),
    ("firmware/link/serial.c", "answer", "if (!(p[0] == ' ' && (p[1] == '+' || p[1] == '-' || p[1] == '0')))",
     "p[0] == ' ' -> 1", SIGNED),
    ("firmware/link/serial.c", "answer", RAVEN_IF, "< -> <=", RAVEN_ONLY),
    ("firmware/link/serial.c", "answer", RAVEN_IF, "LINE_E_ARG -> (LINE_E_ARG + 1)", RAVEN_ONLY),
    ("firmware/link/serial.c", "answer", RAVEN_IF, "c < LINE_E_ARG -> 1", RAVEN_ONLY),
    ("firmware/link/serial.c", "answer", RAVEN_IF, "LINE_E_ARG -> (LINE_E_ARG - 1)",
     "a good line's value is its length (SERIAL_LINE_MAX at most) with LINE_CHECKED: 0x9F at most"),
    ("firmware/ops/diag.c", "diag_speed", "!DIAG_FRAMES(DIAG_FRAMES_LOST) && (g || x < DIAG_SPEED_PERIODS / 2u",
     "DIAG_SPEED_PERIODS -> (DIAG_SPEED_PERIODS + 1)", "21 / 2 and 20 / 2 are both 10 (integer division)"),
    ("firmware/link/serial.c", "answer", "if (!(p[0] == ' ' && p[1] == 'O' && p[2] == 'N'))", "p[0] == ' ' -> 1",
     SIGNED),
    ("firmware/store/record.c", "store_ck_more",
     "} else if (!(sv_at & 1u) && sv_at > HDR_VALUES && sv_at < LIFE_N(ck.n)) {",
     "HDR_VALUES -> (HDR_VALUES - 1)", "at sv_at == HDR_VALUES (odd) the parity test is 0: no check either way"),
    ("firmware/store/store.c", "store_load", "for (s = 0; s < STORE_SLOTS; s++) {", "< -> <=", PAST_END),
    ("firmware/store/store.c", "store_load", "for (s = 0; s < STORE_SLOTS; s++) {", "STORE_SLOTS -> (STORE_SLOTS + 1)",
     PAST_END),
    ("firmware/store/params.c", "params_cross", "> (PARAM_FLOW_MAX_X100 / 8u) * (PARAM_FLOW_MAX_X100 / 8u) * 300u / 2048u)",
     "PARAM_FLOW_MAX_X100 -> (PARAM_FLOW_MAX_X100 + 1)", FLOW8),
    ("firmware/store/params.c", "params_cross", "> (PARAM_FLOW_MAX_X100 / 8u) * (PARAM_FLOW_MAX_X100 / 8u) * 300u / 2048u)",
     "PARAM_FLOW_MAX_X100 -> (PARAM_FLOW_MAX_X100 + 1) #2", FLOW8),
    ("firmware/control/valve.c", "apply", "if (va.want_dir == HAL_VALVE_OFF || va.want_duty == 0) {",
     "va.want_dir == HAL_VALVE_OFF -> 0", "want_duty is 0 exactly when want_dir is off (valve_set)"),
    ("firmware/control/valve.c", "apply", "if (va.want_dir == HAL_VALVE_OFF || va.want_duty == 0) {",
     "va.want_duty == 0 -> 0", "want_duty is 0 exactly when want_dir is off (valve_set)"),
    ("firmware/control/valve.c", "apply", "if (va.want_dir == HAL_VALVE_OFF || va.want_duty == 0) {",
     "va.want_dir == HAL_VALVE_OFF || va.want_duty == 0 -> 0",
     "an off demand then takes the next branches: off equals off, or the bridge on is switched off"),
    ("firmware/control/valve.c", "integrate", "if (d == 0)", "d == 0 -> 0",
     "a drive of 0 is under VALVE_MOVE_Q15 and returns a few lines on"),
    ("firmware/control/valve.c", "integrate", "if (d == 0)", "0 -> 1",
     "drives of 0 and 1 are both under VALVE_MOVE_Q15 and return a few lines on"),
    ("firmware/control/valve.c", "integrate", "dir = d > 0 ? 1 : -1;                   /* + closes */", "> -> >=",
     "d is not 0 here"),
    ("firmware/control/valve.c", "integrate", "dir = d > 0 ? 1 : -1;                   /* + closes */", "0 -> 1",
     "d = 1 gets the wrong way but is under VALVE_MOVE_Q15: it returns before the way is used"),
    ("firmware/control/valve.c", "integrate", "if (d < 0)", "< -> <=", "d is not 0 here"),
    ("firmware/control/valve.c", "integrate", "if (d < 0)", "0 -> 1", "d is not 0 here: d < 1 is d < 0"),
    ("firmware/control/valve.c", "integrate",
     "step = d > va.drun ? (int16_t)MUL_R15(d - va.drun, va.rate) : 0;    /* (.. * rate + 2^14) >> 15 */",
     "> -> >=", "at d == drun the product is 0 and rounds to 0: a step of 0 either way"),
    ("firmware/control/valve.c", "integrate", "va.limit &= (uint8_t)~(dir > 0 ? CTL_AT_OPEN : CTL_AT_CLOSED);",
     "> -> >=", DIR),
    ("firmware/control/valve.c", "integrate", "if (dir > 0) {", "> -> >=", DIR),
    ("firmware/control/valve.c", "integrate", "va.limit |= dir > 0 ? CTL_AT_CLOSED : CTL_AT_OPEN;", "> -> >=", DIR),
    ("firmware/control/valve.c", "integrate", "va.pos = dir > 0 ? 0 : 32767;", "> -> >=", DIR),
    ("firmware/control/valve.c", "integrate", "if ((uint16_t)step >= t) {", ">= -> >",
     "at step == t both ways end at t = 0 with nothing added over the end"),
    ("firmware/control/valve.c", "integrate", "if (t >= 32767u) {", ">= -> >", AT_END),
    ("firmware/control/valve.c", "integrate", "if (t >= 32767u) {", "32767u -> 32768u", AT_END),
    ("firmware/control/valve.c", "valve_set", "bit = drive > 0 ? CTL_AT_CLOSED : CTL_AT_OPEN;", "> -> >=",
     "inside if (drive != 0): drive >= 0 is drive > 0"),
    ("firmware/control/valve.c", "valve_set",
     "mag = drive > 0 ? (uint16_t)drive : drive == Q15_MIN ? 32767u : (uint16_t)-drive;", "> -> >=",
     "in the drive != 0 branch: drive >= 0 is drive > 0"),
    ("firmware/control/valve.c", "valve_set", "va.want_dir = drive > 0 ? HAL_VALVE_CLOSE : HAL_VALVE_OPEN;", "> -> >=",
     "in the drive != 0 branch: drive >= 0 is drive > 0"),
    ("firmware/ops/diag_line.c", "diag_dry_line",
     "&& UMUL(meter > 0 ? meter : 0, 4u) < (uint16_t)diag_in->in.target_lpm_x100) {", "> -> >=",
     "at meter == 0 both ways give 0"),
    ("firmware/ops/diag_line.c", "diag_dry_line",
     "if (dl.dry_line && (!diag_in->open_nozzles || (!diag_in->spraying && diag_psens && p >= pmin)",
     "dl.dry_line -> 1",
     "the branch clears dry_line: clearing it when it is 0 changes nothing"),
    ("firmware/ops/diag_line.c", "diag_zero", "if (diag_in->spraying || diag_in->in.speed_kmh_x100 || !dl.p_spray",
     "!dl.p_spray -> 0", "with p_spray 0 the window's test z_hi << 1 >= p_spray holds: it returns zero_off "
     "with z_n 0 a few lines on, and z_lo, z_hi are set anew at the next window's first period"),
    ("firmware/ops/diag_line.c", "diag_zero",
     "|| !((valve_limit() & CTL_AT_OPEN) || (pos != VALVE_POS_UNKNOWN && pos >= DIAG_ZERO_OPEN_Q15))) {",
     "(valve_limit() & CTL_AT_OPEN) -> 0", "valve.c sets CTL_AT_OPEN with the position 32767 and clears it "
     "at the first step closed: while it stands the position's test holds as well"),
    ("firmware/ops/diag_line.c", "diag_zero", "if (!dl.z_n || p < dl.z_lo)", "< -> <=",
     "at p == z_lo it writes the value z_lo holds"),
    ("firmware/ops/diag_line.c", "diag_zero", "if (!dl.z_n || p > dl.z_hi)", "> -> >=",
     "at p == z_hi it writes the value z_hi holds"),
    ("firmware/ops/diag_line.c", "diag_balance", "a = v > a ? v - a : a - v;", "> -> >=",
     "at v == a both ways give 0"),
    ("firmware/ops/diag_line.c", "diag_balance",
     "f = dl.bal_n >= DIAG_BAL_STRETCH && dl.bal_s0 > l ? dl.bal_s0 - l : 0;   /* the stretch's fall */",
     "> -> >=", "at s0 == l both ways give 0"),
    ("firmware/ops/diag_line.c", "diag_balance",
     "if ((!run || f >= (m << 5)) && dl.bal_n) {     /* closed, or long: into the sums, and anew */",
     "dl.bal_n -> 1", "with no stretch open f is 0 and the branch sums nothing: it writes bal_n = f = 0, "
     "which they hold"),
    ("firmware/ops/diag_line.c", "diag_balance", "if (l < dl.bal_smin)", "< -> <=",
     "at l == bal_smin it writes the value bal_smin holds"),
    ("firmware/ops/diag_line.c", "diag_balance", "if (dl.bal_n < 255u)", "255u -> 254u",
     "bal_n is compared with DIAG_BAL_STRETCH (100) and 0 only: 254 and 255 alike"),
    ("firmware/control/target.c", "target_rate_window",
     "uint16_t job = target_preset_x10(), d = rate_x10 >= job ? rate_x10 - job : job - rate_x10;", ">= -> >",
     "at rate_x10 == job both ways give 0"),
    ("firmware/control/target.c", "target_flow_x100", "if (speed_x100 < vmin)", "< -> <=",
     "at speed_x100 == vmin both ways give vmin"),
    ("firmware/control/target.c", "target_flow_x100", "return q > 32767u ? 32767 : (int16_t)q;", "> -> >=",
     "at q == 32767 both ways give 32767"),
    ("firmware/control/target.c", "target_flow_x100", "return q > 32767u ? 32767 : (int16_t)q;",
     "32767u -> 32766u", "at q == 32767 both ways give 32767"),
    ("firmware/measure/flow.c", "flow_step", "if (c.last == fl.last_pca || q > FLOW_MAX_X100)",
     "c.last == fl.last_pca -> 0", "um_muldiv over a span of 0 gives 0xFFFFFFFF: above FLOW_MAX_X100 too"),
    ("firmware/measure/flow.c", "flow_step", "if (fl.have_edge && fl.quiet < FLOW_ZERO_PERIODS) {",
     "fl.have_edge -> 1", "no edge is held only at the start (quiet 0xFFFF) or after FLOW_STALE_PERIODS: "
     "quiet is past FLOW_ZERO_PERIODS both times"),
    ("firmware/measure/flow.c", "flow_step", "if (fl.quiet < 0xFFFF)", "0xFFFF -> 0xfffe",
     "quiet is only compared with small counts (3, 10, 100): 65534 and 65535 alike"),
    ("firmware/store/record.c", "store_ck_more",
     "} else if (!(sv_at & 1u) && sv_at > HDR_VALUES && sv_at < LIFE_N(ck.n)) {", "> -> >=",
     "at sv_at == HDR_VALUES (odd) the parity test is 0: no check either way"),
    ("firmware/store/record.c", "store_ck_more",
     "} else if (!(sv_at & 1u) && sv_at > HDR_VALUES && sv_at < LIFE_N(ck.n)) {", "< -> <=",
     "at sv_at == LIFE_N(n) = HDR_VALUES + 2n (odd) the parity test is 0: no check either way"),
    ("firmware/store/record.c", "store_ck_more", "} else if (sv_at > ck.end) {", "> -> >=",
     "sv_at == ck.end is taken by the branch before"),
    ("firmware/store/params.c", "param_in_range", "while (v >= 1000u)", ">= -> >", DIGIT),
    ("firmware/store/params.c", "param_in_range", "while (v >= 1000u)", "1000u -> 1001u", DIGIT),
    ("firmware/store/params.c", "param_in_range", "while (v >= 1000u)", "1000u -> 999u", DIGIT),
    ("firmware/store/params.c", "param_in_range", "while (v >= 100u)", ">= -> >", DIGIT),
    ("firmware/store/params.c", "param_in_range", "while (v >= 100u)", "100u -> 101u", DIGIT),
    ("firmware/store/params.c", "param_in_range", "while (v >= 100u)", "100u -> 99u", DIGIT),
    ("firmware/store/params.c", "param_in_range", "while (v >= 10u)", "10u -> 9u", DIGIT),
    ("firmware/measure/analog.c", "judge", "if (c->bad < 255)", "255 -> 254",
     "the count is compared with ANALOG_FAULT_PERIODS (3) only"),
    ("firmware/measure/analog.c", "judge", "if (c->good < 255)", "255 -> 254",
     "the count is compared with ANALOG_OK_PERIODS (10) only"),
    ("firmware/measure/analog.c", "judge", "if (!c->ok && c->good >= ANALOG_OK_PERIODS)", "!c->ok -> 1",
     "setting ok when it is already 1 changes nothing"),
    ("firmware/measure/flow.c", "flow_step", "if (q < fl.q_x100)", "< -> <=",
     "at q == q_x100 both ways leave the same value"),
    ("firmware/link/linecheck.c", "line_check", "for (i = 0; i < n && p[i] != '*'; i++)", "< -> <=",
     "p[n] is inside the buffer (n <= SERIAL_LINE_MAX); a '*' found at n fails the i < n after"),
    ("firmware/link/linecheck.c", "line_check", "for (i = 1; i < n; i++)", "< -> <=",
     "p[n] is the line's end, 0 just written: never a space"),
    ("firmware/link/linecheck.c", "hexval", "if (c >= '0' && c <= '9')", "c >= '0' -> 1",
     "a byte under '0' gives c - '0' under 0: the -1 of a refusal's test either way"),
    ("firmware/link/serial.c", "answer", "if (c >= LINE_E_ARG) {", "LINE_E_ARG -> (LINE_E_ARG - 1)",
     "a good line's value is its length (SERIAL_LINE_MAX at most) with LINE_CHECKED: 0x9F at most"),
    ("firmware/link/linecheck.c", "line_number", "if (n == 0 || (*p != sep && *p != 0))", "n == 0 -> 0",
     "with no digit *p is neither sep nor the end (serial.c: the character after a space, and line_check "
     "refuses a double or trailing space; remote.c: an empty field is not read), so the second test "
     "refuses it"),
]

# survivors recorded by the last whole run that still await a test (not equivalent): one a line,
# file TAB function TAB the line's text TAB change. make mutate reports them apart and fails only
# on others; the sample of make test does not draw them. --record rewrites the file from a run.
AWAITING_FILE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "mutate_awaiting.txt")

# a test run longer than this many times its own unmutated time (and TIMEOUT_MIN_S) is a kill
TIMEOUT_FACTOR = 10
TIMEOUT_MIN_S = 10

CMP_FLIP = {"<": ">=", ">=": "<", ">": "<=", "<=": ">", "==": "!=", "!=": "=="}
CMP_EDGE = {"<": "<=", "<=": "<", ">": ">=", ">=": ">"}
OPS3 = ("<<=", ">>=")
OPS2 = ("<=", ">=", "==", "!=", "&&", "||", "<<", ">>", "->", "++", "--", "+=", "-=", "*=", "/=",
        "%=", "&=", "|=", "^=")
ASSIGN = {"=", "+=", "-=", "*=", "/=", "%=", "&=", "|=", "^=", "<<=", ">>="}
INT_RE = re.compile(r"(0[xX][0-9a-fA-F]+|[0-9]+)([uUlL]*)$")


def tokens(text, start, end):
    """(kind, text, offset) of text[start:end]: comments, strings and characters skipped."""
    out, i = [], start
    while i < end:
        c = text[i]
        if c.isspace():
            i += 1
        elif text.startswith("/*", i):
            i = text.index("*/", i) + 2
        elif text.startswith("//", i) or (c == "#" and (i == 0 or text[i - 1] == "\n")):
            while i < end and text[i] != "\n":     # a comment, or a preprocessor line
                i += 2 if text[i] == "\\" else 1
        elif c in "\"'":
            j = i + 1
            while text[j] != c:
                j += 2 if text[j] == "\\" else 1
            out.append(("str", text[i:j + 1], i))
            i = j + 1
        elif c.isalpha() or c == "_":
            j = i
            while j < end and (text[j].isalnum() or text[j] == "_"):
                j += 1
            out.append(("id", text[i:j], i))
            i = j
        elif c.isdigit():
            j = i
            while j < end and (text[j].isalnum() or text[j] in "._"):
                j += 1
            out.append(("num", text[i:j], i))
            i = j
        else:
            for op in OPS3 + OPS2 + (c,):
                if text.startswith(op, i):
                    out.append(("op", op, i))
                    i += len(op)
                    break
    return out


def function_body(text, name):
    """(start, end) offsets of the body's braces of function `name`, or None."""
    for m in re.finditer(r"^[A-Za-z_][^;{}()]*\b%s\s*\(" % re.escape(name), text, re.M):
        toks = tokens(text, m.end() - 1, len(text))
        depth = 0
        for k, (kind, t, off) in enumerate(toks):
            if t == "(":
                depth += 1
            elif t == ")":
                depth -= 1
                if depth == 0:
                    rest = toks[k + 1:]
                    # after the parameters: attributes (__reentrant ...) then a body, or ; (a prototype)
                    j = 0
                    while j < len(rest) and rest[j][0] == "id":
                        j += 1
                    if j < len(rest) and rest[j][1] == "{":
                        return brace_span(text, rest[j][2])
                    break
    return None


def table_body(text, name):
    """(start, end) of the initializer's braces of the array `name` (a table of periods, limits)."""
    m = re.search(r"\b%s\s*\[[^\]]*\]\s*=\s*\{" % re.escape(name), text)
    return brace_span(text, m.end() - 1) if m else None


def brace_span(text, open_at):
    depth = 0
    for kind, t, off in tokens(text, open_at, len(text)):
        if t == "{":
            depth += 1
        elif t == "}":
            depth -= 1
            if depth == 0:
                return open_at, off + 1
    raise ValueError("unbalanced braces")


def numeric_defines(paths):
    """Names #defined as an integer constant in these files: the constants a body may move by one."""
    names = set()
    for p in paths:
        with open(p) as f:
            for line in f:
                m = re.match(r"\s*#\s*define\s+([A-Z][A-Z0-9_]*)\s+\(?\s*-?(0[xX][0-9a-fA-F]+|[0-9]+)[uUlL]*\s*\)?\s*(/[*/].*)?$", line)
                if m:
                    names.add(m.group(1))
    return names


def operand_span(toks, i, step, op):
    """The operand of the && or || at toks[i] on one side (step +1 right, -1 left): (first, last)
    token indices, and the token that ended it (None at the end)."""
    stops = {"||", "?", ":", ";", ",", "{", "}", "return"} | ASSIGN
    if op == "&&":
        stops |= {"&&"}
    depth, j = 0, i + step
    while 0 <= j < len(toks):
        t = toks[j][1]
        if t in "([" and len(t) == 1:
            if step < 0 and depth == 0:
                break
            depth += step
        elif t in ")]" and len(t) == 1:
            if step > 0 and depth == 0:
                break
            depth -= step
        elif depth == 0 and t in stops:
            break
        j += step
    first, last = sorted((i + step, j - step))
    return first, last, (toks[j][1] if 0 <= j < len(toks) else None)


def in_comparisons(toks):
    """Indices of the tokens inside a comparison's operands: the constants moved by one are the
    ones a rule compares against (a threshold, a count, a bound), not every 0 a reset writes."""
    stops = {"&&", "||", "?", ":", ";", ",", "{", "}", "return"} | ASSIGN | set(CMP_FLIP)
    marked = set()
    for i, (kind, t, off) in enumerate(toks):
        if kind != "op" or t not in CMP_FLIP:
            continue
        for step in (1, -1):
            depth, j = 0, i + step
            while 0 <= j < len(toks):
                u = toks[j][1]
                if u in ("(", "["):
                    if step < 0 and depth == 0:
                        break
                    depth += step
                elif u in (")", "]"):
                    if step > 0 and depth == 0:
                        break
                    depth -= step
                elif depth == 0 and u in stops:
                    break
                marked.add(j)
                j += step
    return marked


class Mutant:
    def __init__(self, path, func, kind, start, end, orig, repl, line_no, line_text):
        self.path, self.func, self.kind = path, func, kind
        self.start, self.end, self.orig, self.repl = start, end, orig, repl
        self.line_no, self.line_text = line_no, line_text
        self.equivalent = None
        self.nth = 1

    def change(self):
        """The change as EQUIVALENT names it; "#2" and on: the same change again on the same line."""
        return "%s -> %s%s" % (" ".join(self.orig.split()), self.repl, " #%d" % self.nth if self.nth > 1 else "")

    def name(self):
        return "%s:%d %s() %s: %s" % (self.path, self.line_no, self.func, self.kind, self.change())


def mutants_of(path, funcs, consts):
    with open(path) as f:
        text = f.read()
    out = []

    def add(func, kind, start, end, repl):
        line_no = text.count("\n", 0, start) + 1
        line_text = text.splitlines()[line_no - 1].strip()
        out.append(Mutant(path, func, kind, start, end, text[start:end], repl, line_no, line_text))

    for func in funcs:
        span = function_body(text, func) or table_body(text, func)
        if span is None:
            sys.exit("mutate.py: %s has no function %s (SITES is out of date)" % (path, func))
        toks = tokens(text, span[0], span[1])
        table = toks and toks[0][1] == "{" and text[span[0] - 1:span[0]] != ")" and func in text[:span[0]].rsplit("\n", 1)[-1]
        compared = set(range(len(toks))) if table else in_comparisons(toks)
        for i, (kind, t, off) in enumerate(toks):
            if kind == "op" and t in CMP_FLIP:
                add(func, "cmp", off, off + len(t), CMP_FLIP[t])
                if t in CMP_EDGE:
                    add(func, "cmp", off, off + len(t), CMP_EDGE[t])
            elif kind == "num" and i in compared:
                m = INT_RE.match(t)
                if not m or (i > 0 and toks[i - 1][1] == "case"):
                    continue                # a float, or a case label (a duplicate case, no mutant)
                v = int(m.group(1), 0)
                hexa = m.group(1)[:2].lower() == "0x"
                for w in (v + 1, v - 1):
                    if w >= 0:
                        add(func, "const", off, off + len(t), (hex(w) if hexa else str(w)) + m.group(2))
            elif kind == "id" and t in consts and i in compared and not (i > 0 and toks[i - 1][1] == "case"):
                add(func, "const", off, off + len(t), "(%s + 1)" % t)
                add(func, "const", off, off + len(t), "(%s - 1)" % t)
            elif kind == "op" and t in ("&&", "||"):
                neutral = "1" if t == "&&" else "0"
                f, l, _ = operand_span(toks, i, +1, t)
                add(func, "cond", toks[f][2], toks[l][2] + len(toks[l][1]), neutral)
                f, l, stop = operand_span(toks, i, -1, t)
                if stop != t:               # the chain's first operand (the others are right ones)
                    add(func, "cond", toks[f][2], toks[l][2] + len(toks[l][1]), neutral)
            elif kind == "id" and t == "if" and i + 1 < len(toks) and toks[i + 1][1] == "(":
                depth, j = 0, i + 1
                while True:
                    depth += {"(": 1, ")": -1}.get(toks[j][1], 0)
                    if depth == 0:
                        break
                    j += 1
                add(func, "cond", toks[i + 2][2], toks[j - 1][2] + len(toks[j - 1][1]), "0")
    seen = {}
    for m in out:
        k = (m.func, m.line_text, m.change())
        seen[k] = seen.get(k, 0) + 1
        m.nth = seen[k]
    return out, text


def key(m):
    return "\t".join((m.path, m.func, m.line_text, m.change()))


def awaiting():
    if not os.path.exists(AWAITING_FILE):
        return set()
    with open(AWAITING_FILE) as f:
        return {l.rstrip("\n") for l in f if l.strip() and not l.startswith("#")}


def mark_equivalents(muts):
    """Each EQUIVALENT line on its mutants; the lines that match none (stale) returned."""
    used = set()
    for m in muts:
        for k, (path, func, line, change, why) in enumerate(EQUIVALENT):
            if m.path == path and m.func == func and m.line_text == line and m.change() == change:
                m.equivalent = why
                used.add(k)
    return [e for k, e in enumerate(EQUIVALENT) if k not in used]


# ---- building and running ----------------------------------------------------------------------
class Runner:
    def __init__(self, args, texts):
        self.cc = args.cc
        self.cflags = [f for f in args.cflags.split() if f != "-g"]    # (no debug info: faster)
        self.ldflags = args.ldflags.split()
        self.build = args.build
        self.texts = texts
        self.work = os.path.join(self.build, "mutate")
        os.makedirs(self.work, exist_ok=True)
        self.lib = os.path.join(self.build, "host-test", "libsprayer.a")
        self.helpers = sorted(
            os.path.join(self.build, "host-test", p[:-2] + ".o")
            for p in subprocess.run(["sh", "-c", "ls tests/*/helper_*.c"], capture_output=True,
                                    text=True).stdout.split())
        self.base_s = {}
        self.tests = {}

    def test_obj(self, name):
        for layer in sorted(os.listdir("tests")):
            p = os.path.join("tests", layer, name + ".c")
            if os.path.exists(p):
                return os.path.join(self.build, "host-test", "tests", layer, name + ".o")
        return None

    def tests_for(self, path):
        """The tests of TESTS built now (taken once: a test built during the run does not join),
        the fastest first once the baseline has timed them (a kill by the first costs least)."""
        if path not in self.tests:
            self.tests[path] = [t for t in TESTS.get(path, [])
                                if self.test_obj(t) and os.path.exists(self.test_obj(t))]
        if all(t in self.base_s for t in self.tests[path]):
            self.tests[path].sort(key=lambda t: self.base_s[t])
        return self.tests[path]

    def baseline(self, names):
        """The unmutated tests must pass; their times set the timeouts."""
        for t in names:
            if t in self.base_s:
                continue
            exe = os.path.join(self.build, "host-test", t)
            t0 = time.time()
            r = subprocess.run([exe], capture_output=True)
            if r.returncode != 0:
                sys.exit("mutate.py: %s fails without a mutant: fix it first" % exe)
            self.base_s[t] = time.time() - t0

    def run(self, m, idx):
        """'killed by T', 'survived', or 'not built' (the compiler refused the mutant: a kill too)."""
        d = tempfile.mkdtemp(prefix="m%d-" % idx, dir=self.work)
        try:
            src = os.path.join(d, os.path.basename(m.path))
            text = self.texts[m.path]
            with open(src, "w") as f:
                f.write(text[:m.start] + m.repl + text[m.end:])
            obj = src[:-2] + ".o"
            # the mutated copy compiles as the file itself would: its own folder first on the path
            inc = ["-I" + os.path.dirname(m.path)]
            r = subprocess.run([self.cc] + self.cflags + inc + ["-c", src, "-o", obj], capture_output=True)
            if r.returncode != 0:
                return "not built"
            for t in self.tests_for(m.path):
                exe = os.path.join(d, t)
                r = subprocess.run([self.cc] + self.ldflags + [self.test_obj(t)] + self.helpers
                                   + [obj, self.lib, "-lcmocka", "-lm", "-o", exe], capture_output=True)
                if r.returncode != 0:
                    return "killed by link (%s)" % t
                lim = max(TIMEOUT_MIN_S, TIMEOUT_FACTOR * self.base_s[t])
                try:
                    r = subprocess.run([exe], capture_output=True, timeout=lim)
                except subprocess.TimeoutExpired:
                    return "killed by %s (over %.0f s)" % (t, lim)
                if r.returncode != 0:
                    return "killed by %s" % t
            return "survived"
        finally:
            shutil.rmtree(d, ignore_errors=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cc", default=os.environ.get("CC", "cc"))
    ap.add_argument("--cflags", default="")
    ap.add_argument("--ldflags", default="-fsanitize=address,undefined")
    ap.add_argument("--build", default=os.environ.get("BUILD", "build"))
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--sample", type=int, default=0, help="run this many mutants drawn at random")
    ap.add_argument("--seed", type=int, default=None)
    ap.add_argument("--only", action="append", default=[], help="FILE or FILE:FUNCTION")
    ap.add_argument("--list", action="store_true")
    ap.add_argument("--record", action="store_true", help="write the survivors to mutate_awaiting.txt")
    ap.add_argument("--recheck", action="store_true",
                    help="run the awaiting mutants only; those killed now leave mutate_awaiting.txt")
    ap.add_argument("--prune", action="store_true",
                    help="drop the awaiting lines that are equivalent now or match no mutant")
    args = ap.parse_args()

    t0 = time.time()
    headers = [os.path.join(dp, f) for dp, _, fs in os.walk("firmware") for f in fs if f.endswith(".h")]
    muts, texts = [], {}
    for path, funcs in SITES.items():
        consts = numeric_defines(headers + [path])
        if args.only:
            keep = [o.split(":", 1) for o in args.only if o.split(":", 1)[0] == path]
            if not keep:
                continue
            if all(len(k) == 2 for k in keep):
                funcs = [f for f in funcs if f in {k[1] for k in keep}]
        ms, texts[path] = mutants_of(path, funcs, consts)
        muts += ms
    stale = mark_equivalents(muts)
    live = [m for m in muts if not m.equivalent]
    for path, func, line, change, why in ([] if args.only else stale):
        print("stale equivalent (matches no mutant): %s %s() '%s' %s" % (path, func, line, change))
    if args.prune:
        keep = {key(m) for m in live}
        known = awaiting()
        with open(AWAITING_FILE) as f:
            head = [l for l in f if l.startswith("#")]
        with open(AWAITING_FILE, "w") as f:
            f.write("".join(head) + "".join(k + "\n" for k in sorted(known & keep)))
        print("mutate: %d awaiting kept, %d gone (equivalent now, or their line changed)"
              % (len(known & keep), len(known - keep)))
        return 0
    if args.list:
        for m in muts:
            print(m.name() + ("   [equivalent: %s]" % m.equivalent if m.equivalent else ""))
        print("%d mutants, %d listed as equivalent" % (len(muts), len(muts) - len(live)))
        return 0
    known = awaiting()
    if args.recheck:                # the awaiting ones only (of --only's files): the killed leave the file
        live = [m for m in live if key(m) in known]
        args.record = True
    elif args.record and args.only:
        sys.exit("mutate.py: --record takes a whole run (no --only)")
    if args.sample:
        live = [m for m in live if key(m) not in known]
        seed = args.seed if args.seed is not None else random.randrange(1 << 16)
        print("mutate: sample of %d, seed %d (tools/mutate.py --sample %d --seed %d repeats it)"
              % (args.sample, seed, args.sample, seed))
        live = random.Random(seed).sample(live, min(args.sample, len(live)))

    runner = Runner(args, texts)
    runner.baseline(sorted({t for m in live for t in runner.tests_for(m.path)}))
    results = [None] * len(live)

    def one(k):
        results[k] = runner.run(live[k], k)
        return k

    done = 0
    with ThreadPoolExecutor(max_workers=args.jobs) as pool:
        for k in pool.map(one, range(len(live))):
            done += 1
            if args.sample or results[k] == "survived":
                tag = "SURVIVED" if results[k] == "survived" else "killed"
                if results[k] == "survived" and key(live[k]) in known:
                    tag = "awaiting"
                print("%-9s %s" % (tag, live[k].name()), flush=True)
            elif done % 25 == 0:
                print("  %d of %d mutants run, %.0f s" % (done, len(live), time.time() - t0), flush=True)

    surv = [m for m, r in zip(live, results) if r == "survived"]
    if args.record:
        head = ("# tools/mutate.py --record: survivors of the last whole run awaiting a test (not\n"
                "# equivalent: each needs a test that kills it, then its line goes)\n")
        if args.recheck:            # only the ones run and killed now leave
            killed = {key(m) for m, r in zip(live, results) if r != "survived"}
            lines = [k for k in sorted(known) if k not in killed]
        else:
            lines = [key(m) for m in surv]
        with open(AWAITING_FILE, "w") as f:
            f.write(head + "".join(k + "\n" for k in lines))
    new_surv = [m for m in surv if key(m) not in known]
    gone = sorted(known - {key(m) for m in surv} & {key(m) for m in live})
    by = {}
    for m, r in zip(live, results):
        k = by.setdefault(m.path, [0, 0, 0])
        k[0] += 1
        k[1] += r == "survived"
    for m in muts:
        if m.equivalent and m.path in by:
            by[m.path][2] += 1
    print("mutate: per file: mutants run, survivors, listed equivalent")
    for p, (n, s, e) in by.items():
        print("  %-28s %4d %4d %4d" % (p, n, s, e))
    if known and not args.sample:
        print("mutate: %d of the survivors await a test (%s), %d new; %d recorded there are killed now"
              % (len(surv) - len(new_surv), os.path.basename(AWAITING_FILE), len(new_surv), len(gone)))
    ru = resource.getrusage(resource.RUSAGE_CHILDREN)
    print("mutate: %d mutants run, %d killed, %d survived, %d listed as equivalent (not run); %.0f s on %d jobs, "
          "%.0f s of CPU (%.0f s on 2 idle cores)"
          % (len(live), len(live) - len(surv), len(surv), sum(1 for m in muts if m.equivalent),
             time.time() - t0, args.jobs, ru.ru_utime + ru.ru_stime, (ru.ru_utime + ru.ru_stime) / 2))
    return 1 if new_surv else 0


if __name__ == "__main__":
    sys.exit(main())

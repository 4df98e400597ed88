/* test_scenario.c: the scenario reader: a good file, every kind of bad file (named by file, line and key), docs/SCENARIOS.md's example. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <stdio.h>
#include <string.h>
#include <stdlib.h>
#include <unistd.h>
#include <cmocka.h>
#include "scenario.h"
#include "ctl.h"

static scenario_t s;
static char err[512];

static const char good[] =
    "# a scenario with every section\n"
    "[run]\n"
    "duration_s = 120   # two minutes\n"
    "seed = 18446744073709551615\n"
    "\n"
    "[config]\n"
    "controller = pid\n"
    "rate_l_ha = 125\n"
    "nozzles = 24\n"
    "spacing_cm = 75\n"
    "sections = 4\n"
    "meter_cal_ppl = 372.5\n"
    "wheel_m_per_pulse = 0.4012\n"
    "min_flow_speed_kmh = 3.5\n"
    "given_speed_kmh = 6.5\n"
    "tank_size_l = 400\n"
    "[plant]\n"
    "  valve_travel_s = 12   \n"
    "pto_coupled = 0\n"
    "pto_rpm = 1000\n"
    "meter_k_ppl = 390\n"
    "wheel_slip_pct = 3.5\n"
    "tank_start_l = 400\n"
    "[drive]\n"
    "0 0\n"
    "10 8\n"
    "10 6      # a step\n"
    "20 6\n"
    "[events]\n"
    "30 sections_open 12\n"
    "40 meter_fail\n"
    "50 rate_l_ha 100\n"
    "60 leak_lpm 2.5\n";

/* Every value lands where it belongs, in the firmware's units: 372.5 p/L -> 3725 (0.1 p/L),
 * 0.4012 m -> 4012 (0.1 mm), 3.5 km/h -> 35, 6.5 km/h -> 65. */
static void test_scenario_good_file(void **state)
{
    (void)state;
    assert_int_equal(scenario_parse(&s, good, "good.scn", err, sizeof err), 0);
    assert_string_equal(err, "");
    assert_true(s.duration_s == 120.0);
    assert_true(s.seed == 18446744073709551615ull);
    assert_int_equal(s.param[P_CONTROLLER], CTL_PID);
    assert_int_equal(s.param[P_RATE], 1250);               /* 0.1 L/ha */
    assert_int_equal(s.param[P_NOZZLES], 24);
    assert_int_equal(s.param[P_SPACING], 75);
    assert_int_equal(s.param[P_SECTIONS], 4);
    assert_int_equal(s.param[P_METER_K], 3725);
    assert_int_equal(s.param[P_WHEEL], 4012);
    assert_int_equal(s.param[P_MINF_SPEED], 35);
    assert_int_equal(s.param[P_GIVEN_SPEED], 65);
    assert_int_equal(s.param[P_TANK_L], 400);               /* the firmware's Tank size, as the plant's */
    assert_true(s.plant.valve_travel_s == 12.0);
    assert_true(s.plant.pto_coupled == 0.0);
    assert_true(s.plant.pto_rpm == 1000.0);
    assert_true(s.plant.meter_k_ppl == 390.0);
    assert_true(s.plant.wheel_slip_pct == 3.5);
    assert_true(s.plant.tank_start_l == 400.0);
    assert_true(s.plant.relief_bar == 5.0);          /* untouched keys keep docs/SCENARIOS.md's default */
    assert_int_equal(s.plant.nozzles, 24);
    assert_true(s.plant.spacing_m == 0.75);
    assert_int_equal(s.n_drive, 4);
    assert_int_equal(s.n_events, 4);
    assert_int_equal(s.events[0].kind, EV_SECTIONS_OPEN);
    assert_true(s.events[0].value == 12.0);
    assert_int_equal(s.events[0].line, 30);
    assert_int_equal(s.events[1].kind, EV_METER_FAIL);
    assert_true(s.events[3].value == 2.5);
    assert_int_equal(scenario_nozzles_per_section(&s), 6);
    /* the driver: linear between rows, the second row at one time wins (a step) */
    assert_true(scenario_drive_kmh(&s, 5) == 4.0);
    assert_true(scenario_drive_kmh(&s, 9.999) > 7.99);
    assert_true(scenario_drive_kmh(&s, 10) == 6.0);
    assert_true(scenario_drive_kmh(&s, 500) == 6.0);
}

/* Windows line ends and a UTF-8 byte order mark are read like plain text. */
static void test_scenario_crlf_and_bom(void **state)
{
    (void)state;
    assert_int_equal(scenario_parse(&s, "\xEF\xBB\xBF[run]\r\nduration_s = 60\r\n[drive]\r\n0\t5\r\n",
                                    "win.scn", err, sizeof err), 0);
    assert_true(s.duration_s == 60);
    assert_int_equal(s.n_drive, 1);
    assert_true(s.drive[0].kmh == 5);
}

/* A file of one drive row is all defaults: 300 s, seed 7, the firmware's parameter defaults,
 * docs/SCENARIOS.md's plant. */
static void test_scenario_drive_alone_is_the_defaults(void **state)
{
    (void)state;
    assert_int_equal(scenario_parse(&s, "# nothing else\n[drive]\n0 8\n", "one.scn", err, sizeof err), 0);
    assert_true(s.duration_s == 300.0);
    assert_true(s.seed == 7);
    assert_int_equal(s.param[P_RATE], 1500);
    assert_int_equal(s.param[P_CONTROLLER], CTL_FFMAP);
    assert_true(s.plant.pump_lpm_at_540 == 120.0);
    assert_true(s.plant.valve_travel_s == 4.0);
    assert_true(s.plant.nozzle_lpm_at_3bar == 1.18);
    assert_int_equal(s.n_drive, 1);
    assert_true(scenario_drive_kmh(&s, 10) == 8.0);
}

/* One bad file: refused, the message names file, line and key, and the scenario is untouched. */
static void bad(const char *text, const char *where)
{
    s.duration_s = 12345;                       /* a marker: nothing may be written on a refusal */
    if (scenario_parse(&s, text, "bad.scn", err, sizeof err) != -1)
        fail_msg("accepted: %s", text);
    if (!strstr(err, where))
        fail_msg("message '%s' does not contain '%s'", err, where);
    for (const char *p = err; *p; p++)
        if ((unsigned char)*p < 0x20 || (unsigned char)*p >= 0x7F)
            fail_msg("message '%s' holds byte 0x%02X", err, (unsigned char)*p);
    assert_true(s.duration_s == 12345);
}

/* Nothing to run: an empty file, one of comments and settings only, a [drive] without rows. The
 * reader used to run these 300 s at 0 km/h and report null metrics. */
static void test_scenario_refuses_a_file_without_drive_rows(void **state)
{
    (void)state;
    bad("", "bad.scn: key '[drive]': missing: a run needs a [drive] section with at least one 'time_s speed_kmh' row");
    bad("# nothing\n\n", "bad.scn: key '[drive]': missing");
    bad("[run]\nduration_s = 60\n[config]\nrate_l_ha = 100\n", "bad.scn: key '[drive]': missing");
    bad("[run]\nduration_s = 60\n\n[drive]\n# later\n\n[events]\n10 meter_fail\n",
        "bad.scn:4: key '[drive]': no rows: a run needs at least one 'time_s speed_kmh'");
    /* the errors of the rest of the file come first */
    bad("[config]\nrate_l_ha = 5\n", "bad.scn:2: key 'rate_l_ha': 5 out of the firmware's range");
}

/* Bytes that do not print are written \xHH in the message: control codes, an escape sequence a
 * terminal would obey, bytes past ASCII (binary input without NUL bytes). */
static void test_scenario_messages_escape_what_does_not_print(void **state)
{
    (void)state;
    bad("[plant]\n\x01\x7f\xff\xfe = 3\n", "bad.scn:2: key '\\x01\\x7F\\xFF\\xFE': unknown key in [plant]");
    bad("[config]\nrate_l_ha = \x1b[2J150\n", "bad.scn:2: key 'rate_l_ha': '\\x1B[2J150' is not a number");
    bad("[events]\n10 m\xc3\xa9ter_fail\n", "bad.scn:2: key 'm\\xC3\\xA9ter_fail': unknown event");
    bad("\x7f\x45\x4c\x46\x02\x01\x01\x03\n", "bad.scn:1: key '\\x7FELF\\x02\\x01\\x01\\x03': comes before any [section]");
    /* the name too, and a long message is cut at a whole escape */
    char small[16];
    assert_int_equal(scenario_parse(&s, "x", "a\x01" "b.scn", small, sizeof small), -1);
    assert_string_equal(small, "a\\x01b.scn:1: k");    /* 15 characters and the end */
    assert_int_equal(scenario_parse(&s, "x", "abcdefghijkl\x01", small, sizeof small), -1);
    assert_string_equal(small, "abcdefghijkl");
    assert_int_equal(scenario_set_controller(&s, "\x1b]0;pwned\x07", err, sizeof err), -1);
    assert_non_null(strstr(err, "unknown controller '\\x1B]0;pwned\\x07'"));
}

/* A value the firmware's cross-checks refuse with the others is named by the latest line that
 * gave one of the values compared. */
static void test_scenario_cross_checks_name_their_line(void **state)
{
    (void)state;
    /* Tank min at the firmware's tank size, 1000 L */
    bad("[config]\nrate_l_ha = 100\ntank_min_l = 1000\n[drive]\n0 5\n",
        "bad.scn:3: key 'tank_min_l': the firmware refuses this value with the others: Tank min>=size");
    bad("[config]\ntank_min_l = 30\ntank_size_l = 30\n[drive]\n0 5\n",
        "bad.scn:3: key 'tank_size_l': the firmware refuses this value with the others: Tank min>=size");
    /* the meter's pulses with every nozzle open at P max (480 kPa): 2000 p/L x 96 x 2 L/min
     * / 60 = 6400 Hz at 3 bar, over the 5 kHz budget; named by the last of its three lines */
    bad("[config]\nmeter_cal_ppl = 2000\nnozzles = 96\nnozzle_lpm_at_3bar = 2\nrate_l_ha = 100\n[drive]\n0 5\n",
        "bad.scn:4: key 'nozzle_lpm_at_3bar': the firmware refuses this value with the others: Meter K:too fast");
    bad("[config]\nnozzle_lpm_at_3bar = 2\nnozzles = 96\nmeter_cal_ppl = 2000\n[drive]\n0 5\n",
        "bad.scn:4: key 'meter_cal_ppl': the firmware refuses");
    /* the plant's tank: the later of tank_l and tank_start_l, by its own name */
    bad("[plant]\ntank_start_l = 800\ntank_l = 500\n[drive]\n0 5\n",
        "bad.scn:3: key 'tank_l': tank_start_l 800 L is more than the tank holds (tank_l 500)");
    bad("[plant]\ntank_l = 500\ntank_start_l = 800\n[drive]\n0 5\n",
        "bad.scn:3: key 'tank_start_l': tank_start_l 800 L is more than the tank holds");
}

static void test_scenario_unknown_keys_and_sections(void **state)
{
    (void)state;
    bad("[plant]\npump_lpm = 100\n", "bad.scn:2: key 'pump_lpm': unknown key in [plant]");
    bad("[config]\nrate = 100\n", "bad.scn:2: key 'rate': unknown key in [config]");
    bad("[run]\nduration = 100\n", "bad.scn:2: key 'duration': unknown key in [run]");
    bad("[run]\n[sprayer]\n", "bad.scn:2: key 'sprayer': unknown section");
    bad("duration_s = 10\n[run]\n", "bad.scn:1: key 'duration_s = 10': comes before any [section]");
    bad("[run]\n[plant]\n[run]\n", "bad.scn:3: key 'run': section given twice");
    bad("[run\n", "bad.scn:1: key '[run': a section header");
    bad("[plant]\nvalve_travel_s 4\n", "bad.scn:2: key 'valve_travel_s 4': expected 'key = value'");
    bad("[config]\ncontroller = magic\n", "bad.scn:2: key 'controller': unknown controller 'magic'");
}

static void test_scenario_missing_and_bad_numbers(void **state)
{
    (void)state;
    bad("[config]\nrate_l_ha =\n", "bad.scn:2: key 'rate_l_ha': missing value");
    bad("[config]\nrate_l_ha = # none\n", "bad.scn:2: key 'rate_l_ha': missing value");
    bad("[config]\n = 5\n", "bad.scn:2: key '': a value without a key");
    bad("[config]\nrate_l_ha = 15O\n", "bad.scn:2: key 'rate_l_ha': '15O' is not a number");
    bad("[plant]\n\nvalve_travel_s = nan\n", "bad.scn:3: key 'valve_travel_s': 'nan' is not a number");
    bad("[plant]\nvalve_travel_s = 0x10\n", "key 'valve_travel_s': '0x10' is not a number");
    bad("[plant]\nvalve_travel_s = 1e999\n", "key 'valve_travel_s': '1e999' is not a number");
    bad("[plant]\nvalve_travel_s = 4 s\n", "key 'valve_travel_s': '4 s' is not a number");
    bad("[run]\nseed = -1\n", "bad.scn:2: key 'seed': '-1' is not a whole number");
    bad("[run]\nseed = 18446744073709551616\n", "key 'seed'");
    bad("[plant]\nwheel_elements = 12.5\n", "key 'wheel_elements': 12.5 is not a whole number");
}

static void test_scenario_values_out_of_range(void **state)
{
    (void)state;
    bad("[config]\nrate_l_ha = 5000\n", "bad.scn:2: key 'rate_l_ha': 5000 out of the firmware's range 10..1000 L/ha");
    bad("[config]\nnozzles = 0\n", "key 'nozzles': 0 out of the firmware's range");
    bad("[config]\ngiven_speed_kmh = 31\n", "key 'given_speed_kmh': 31 out of the firmware's range 0..30 km/h");
    bad("[config]\nmeter_cal_ppl = 380.05\n", "key 'meter_cal_ppl': 380.05 has more decimals than the firmware keeps");
    bad("[plant]\nvalve_travel_s = -1\n", "bad.scn:2: key 'valve_travel_s': -1 out of range");
    bad("[plant]\npto_coupled = 2\n", "key 'pto_coupled': 2 out of range 0..1");
    bad("[run]\nduration_s = 0\n", "key 'duration_s': 0 out of range");
    bad("[config]\nrate_l_ha = 100\nrate_l_ha = 120\n", "bad.scn:3: key 'rate_l_ha': given twice in [config]");
    bad("[config]\nnozzles = 35\n", "bad.scn:2: key 'nozzles': 35 nozzles do not split evenly over 6 sections");
    bad("[plant]\ntank_l = 500\n", "bad.scn:2: key 'tank_l': tank_start_l 1000 L is more than the tank holds (tank_l 500)");
    bad("[plant]\nvalve_stiction_duty = 0.1\n", "bad.scn:2: key 'valve_stiction_duty': running duty 0.12 is above the break-away duty 0.1");
    bad("[plant]\nvalve_running_duty = 0.25\n", "bad.scn:2: key 'valve_running_duty': running duty 0.25 is above");
    bad("[plant]\nmeter_blades = 0\n", "key 'meter_blades': 0 out of range");
    bad("[config]\nraven_valve_cal = 2120\n", "bad.scn:2: key 'raven_valve_cal': 2120 refused by the firmware");
    bad("[config]\naog_brake_pct = 10.05\n", "key 'aog_brake_pct': 10.05 has more decimals than the firmware keeps");
    bad("[config]\naog_min_pwm = 256\n", "key 'aog_min_pwm': 256 out of the firmware's range 0..255");
}

/* The peers' settings in their users' units: PWM counts, gains a 50 ms loop, the four digits. */
static void test_scenario_peer_settings(void **state)
{
    (void)state;
    assert_int_equal(scenario_parse(&s, "[config]\ncontroller = aog\naog_kp = 125\naog_ki = 25\naog_brake_pct = 1.5\naog_slow_pct = 40\n"
                                    "aog_min_pwm = 70\naog_max_pwm = 200\nraven_valve_cal = 743\n[drive]\n0 5\n",
                                    "p.scn", err, sizeof err), 0);
    assert_int_equal(s.param[P_CONTROLLER], CTL_AOG);
    assert_int_equal(s.param[P_AOG_KP], 125);
    assert_int_equal(s.param[P_AOG_KI], 25);
    assert_int_equal(s.param[P_AOG_BRAKE], 15);
    assert_int_equal(s.param[P_AOG_SLOW], 40);
    assert_int_equal(s.param[P_AOG_MIN], 70);
    assert_int_equal(s.param[P_AOG_MAX], 200);
    assert_int_equal(s.param[P_RAVEN_CAL], 743);
}

/* A first-edition file (no motor, spacing or running-duty keys) still loads, the new keys at
 * their defaults: 0.12 running duty, 50 ms motor, 6 blades at 1.5 %, 2 % wheel spacing. */
static void test_scenario_first_edition_file_gets_the_new_defaults(void **state)
{
    (void)state;
    if (scenario_parse(&s, "[plant]\nvalve_stiction_duty = 0.3\n[drive]\n0 5\n", "old.scn", err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_true(s.plant.valve_running_duty == 0.12);
    assert_true(s.plant.valve_motor_tau_s == 0.05);
    assert_true(s.plant.meter_blades == 6 && s.plant.meter_blade_jitter_pct == 1.5);
    assert_true(s.plant.wheel_spacing_jitter_pct == 2);
}

static void test_scenario_drive_rows(void **state)
{
    (void)state;
    bad("[drive]\n0 0\n10 5\n9 6\n", "bad.scn:4: key 'drive': time goes backwards (9 after 10)");
    bad("[drive]\n0 0 1\n", "bad.scn:2: key 'drive': a row is 'time_s speed_kmh' (3 words here)");
    bad("[drive]\n0\n", "bad.scn:2: key 'drive': a row is 'time_s speed_kmh' (1 words here)");
    bad("[drive]\n0 fast\n", "bad.scn:2: key 'drive': speed 'fast' is not a number");
    bad("[drive]\n0 70\n", "bad.scn:2: key 'drive': speed 70 out of range 0..60 km/h");
    bad("[drive]\n-1 5\n", "bad.scn:2: key 'drive': time -1 is negative");
}

static void test_scenario_event_rows(void **state)
{
    (void)state;
    bad("[events]\n10 meter_explodes\n", "bad.scn:2: key 'meter_explodes': unknown event");
    bad("[events]\n10 meter_fail\n5 meter_restore\n", "bad.scn:3: key 'meter_restore': time goes backwards (5 after 10)");
    bad("[events]\n10 sections_open\n", "bad.scn:2: key 'sections_open': needs a value");
    bad("[events]\n10 meter_fail 3\n", "bad.scn:2: key 'meter_fail': takes no value ('3' given)");
    bad("[events]\n10 leak_lpm lots\n", "bad.scn:2: key 'leak_lpm': value 'lots' is not a number");
    bad("[events]\n10 sections_open 25\n",
        "bad.scn:2: key 'sections_open': 25 nozzles is not a whole number of sections (6 nozzles each)");
    bad("[events]\n10 sections_open 42\n", "bad.scn:2: key 'sections_open': 42 is not a number of nozzles 0..36");
    bad("[events]\n10 rate_l_ha 2000\n", "bad.scn:2: key 'rate_l_ha': 2000 out of the firmware's range 10..1000");
    bad("[events]\n10 given_speed_kmh 6.55\n", "bad.scn:2: key 'given_speed_kmh': 6.55 out of the firmware's range");
    bad("[events]\n10 tank_l 1200\n", "bad.scn:2: key 'tank_l': 1200 out of range 0..1000 L");
    bad("[events]\n10 clog_nozzles 1.5\n", "key 'clog_nozzles': 1.5 is not a number of nozzles");
    bad("[run]\nduration_s = 60\n[events]\n61 meter_fail\n",
        "bad.scn:4: key 'meter_fail': at 61 s, after the end of the run (duration_s 60)");
    /* checks that need the whole file see [config] written after [events] */
    bad("[events]\n10 sections_open 6\n[config]\nsections = 4\nnozzles = 36\n",
        "bad.scn:2: key 'sections_open': 6 nozzles is not a whole number of sections (9 nozzles each)");
    bad("[events]\n10 sections_open 6\n[config]\nsections = 5\n",
        "bad.scn:4: key 'sections': 36 nozzles do not split evenly over 5 sections");
}

/* The controller by any name ctl_name() gives, or an old name of the alias table; the override
 * of the program. */
static void test_scenario_controller_names(void **state)
{
    int id, alias_id;
    size_t a;
    const char *alias;
    char text[128];
    (void)state;
    for (id = 0; id < CTL_COUNT; id++) {
        snprintf(text, sizeof text, "[config]\ncontroller = %s\n[drive]\n0 5\n", ctl_name((uint8_t)id));
        assert_int_equal(scenario_parse(&s, text, "c.scn", err, sizeof err), 0);
        assert_int_equal(s.param[P_CONTROLLER], id);
    }
    assert_string_equal(ctl_name(CTL_FFMAP), "ffmap");
    assert_non_null(scenario_controller_alias(0, &alias_id));
    for (a = 0; (alias = scenario_controller_alias(a, &alias_id)) != NULL; a++) {
        snprintf(text, sizeof text, "[config]\ncontroller = %s\n[drive]\n0 5\n", alias);
        assert_int_equal(scenario_parse(&s, text, "c.scn", err, sizeof err), 0);
        assert_int_equal(s.param[P_CONTROLLER], alias_id);
        assert_int_equal(alias_id, CTL_FFMAP);
    }
    assert_int_equal(scenario_set_controller(&s, "bp_pid", err, sizeof err), 0);
    assert_int_equal(s.param[P_CONTROLLER], CTL_BP_PID);
    assert_int_equal(scenario_set_controller(&s, "nope", err, sizeof err), -1);
    assert_non_null(strstr(err, "unknown controller 'nope'"));
    assert_int_equal(s.param[P_CONTROLLER], CTL_BP_PID);
}

/* Files: a missing one is named; the example of docs/SCENARIOS.md, copied verbatim, loads as written. */
static void test_scenario_files(void **state)
{
    (void)state;
    assert_int_equal(scenario_load(&s, "scenarios/no_such_file.scn", err, sizeof err), -1);
    assert_non_null(strstr(err, "scenarios/no_such_file.scn: cannot open"));
    assert_int_equal(scenario_load(&s, "scenarios/plant_md_example.scn", err, sizeof err), 0);
    assert_true(s.duration_s == 300 && s.seed == 7);
    assert_int_equal(s.param[P_CONTROLLER], CTL_BP_PID);
    assert_int_equal(s.param[P_METER_K], 3800);
    assert_int_equal(s.param[P_WHEEL], 3927);
    assert_int_equal(s.param[P_MINF_SPEED], 40);
    assert_int_equal(s.n_drive, 3);
    assert_true(scenario_drive_kmh(&s, 32.5) == 7.5);  /* 4 + (11 - 4) * 27.5/55 */
    assert_int_equal(s.n_events, 2);
    assert_int_equal(s.events[0].kind, EV_SECTIONS_OPEN);
    assert_int_equal(s.events[1].kind, EV_METER_FAIL);
    assert_int_equal(s.events[1].line, 21);
}

/* A file as the programs read it: empty (0 bytes) or binary without NUL bytes, refused with a
 * message that prints. */
static void test_scenario_load_refuses_empty_and_binary_files(void **state)
{
    char path[] = "/tmp/test_scenario_XXXXXX";
    static const unsigned char elf[] = {0x7F, 'E', 'L', 'F', 2, 1, 1, 3, 0xEF, 0xFF, '\n', 0x1B, '[', '2', 'J'};
    int fd = mkstemp(path);
    FILE *f;
    (void)state;
    assert_true(fd >= 0);
    close(fd);
    assert_int_equal(scenario_load(&s, path, err, sizeof err), -1);
    assert_non_null(strstr(err, ": key '[drive]': missing"));
    f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(elf, 1, sizeof elf, f), sizeof elf);
    fclose(f);
    assert_int_equal(scenario_load(&s, path, err, sizeof err), -1);
    assert_non_null(strstr(err, ":1: key '\\x7FELF\\x02\\x01\\x01\\x03\\xEF\\xFF': comes before any [section]"));
    unlink(path);
}

/* Every [plant] key docs/SCENARIOS.md lists, at the default it states, and every event it lists. */
static void test_scenario_every_key_and_event_of_plant_md(void **state)
{
    static const char text[] =
        "[plant]\n"
        "pump_lpm_at_540 = 120\npump_slip_per_bar = 0.01\npump_pulsation_pct = 4\npto_coupled = 1\n"
        "pto_rpm = 540\nv_rated_kmh = 11\nrelief_bar = 5.0\nrelief_lpm_per_bar = 200\nvalve_cv_open = 120\n"
        "valve_rangeability = 30\nvalve_travel_s = 4\nvalve_stiction_duty = 0.2\nvalve_backlash = 0.02\n"
        "valve_start_pos = 0\nline_compliance_l_per_bar = 0.03\nnozzle_lpm_at_3bar = 1.18\n"
        "check_valve_bar = 0.3\nnozzle_wear_pct = 0\ntank_l = 1000\ntank_height_m = 1.2\n"
        "tank_start_l = 1000\nmeter_k_ppl = 380\nmeter_lag_s = 0.03\nwheel_elements = 12\n"
        "wheel_radius_m = 0.75\nwheel_slip_pct = 0\nspeed_bounce_pct = 0\npressure_noise_lsb = 1\n"
        "tractor_lag_s = 1\ntractor_accel_max = 0.5\n"
        "valve_running_duty = 0.12\nvalve_motor_tau_s = 0.05\nmeter_blades = 6\nmeter_blade_jitter_pct = 1.5\n"
        "wheel_spacing_jitter_pct = 2\n"
        "[config]\ngiven_speed_kmh = 0\n"
        "[events]\n"
        "1 sections_open 24\n2 rate_l_ha 125\n3 pto_rpm 450\n4 meter_fail\n5 meter_restore\n"
        "6 speed_sensor_fail\n7 speed_sensor_restore\n8 pressure_sensor_open\n9 pressure_sensor_restore\n"
        "10 valve_stuck\n11 valve_free\n12 speed_bounce_pct 5\n13 leak_lpm 2\n14 clog_nozzles 3\n"
        "15 tank_l 500\n16 given_speed_kmh 7\n"
        "[drive]\n0 5\n";
    plant_params_t def;
    (void)state;
    if (scenario_parse(&s, text, "all.scn", err, sizeof err) != 0)
        fail_msg("%s", err);
    plant_params_default(&def);
    /* the values docs/SCENARIOS.md states are the model's defaults, key by key */
#define SAME(key, d, lo, hi, isint) if (s.plant.key != def.key) fail_msg("%s: %g, default %g", #key, s.plant.key, def.key);
    PLANT_KEYS(SAME)
#undef SAME
    assert_int_equal(s.n_events, 16);
    assert_int_equal(s.events[15].kind, EV_GIVEN_SPEED);
}

/* A run cut short (the programs' --duration): the events after the cut dropped, the ones at it
 * kept; a cut past the end changes nothing; a cut that is no duration is refused. */
static void test_scenario_cut(void **state)
{
    (void)state;
    assert_int_equal(scenario_parse(&s, good, "good.scn", err, sizeof err), 0);
    assert_int_equal(scenario_cut(&s, 500, err, sizeof err), 0);
    assert_true(s.duration_s == 120);
    assert_int_equal(s.n_events, 4);
    assert_int_equal(scenario_cut(&s, 50, err, sizeof err), 0);
    assert_true(s.duration_s == 50);
    assert_int_equal(s.n_events, 3);                /* 30, 40 and 50 s; not 60 */
    assert_true(s.events[2].t_s == 50);
    assert_int_equal(scenario_cut(&s, 0, err, sizeof err), -1);
    assert_non_null(strstr(err, "0 is not a duration"));
    assert_int_equal(scenario_cut(&s, 2e6, err, sizeof err), -1);
    assert_true(s.duration_s == 50);
}

/* Every scenario the project ships loads. */
static void test_scenario_project_files_load(void **state)
{
    static const char *const files[] = {
        "scenarios/paper_dynamic_100.scn", "scenarios/paper_dynamic_125.scn", "scenarios/paper_dynamic_150.scn",
        "scenarios/paper_dynamic_100_fixed_pto.scn", "scenarios/paper_dynamic_125_fixed_pto.scn",
        "scenarios/paper_dynamic_150_fixed_pto.scn", "scenarios/target_step_100.scn",
        "scenarios/target_step_125.scn", "scenarios/target_step_150.scn", "scenarios/field_3220m_100.scn",
        "scenarios/field_3220m_125.scn", "scenarios/field_3220m_150.scn", "scenarios/faults_150.scn",
    };
    size_t i;
    (void)state;
    for (i = 0; i < sizeof files / sizeof files[0]; i++)
        if (scenario_load(&s, files[i], err, sizeof err) != 0)
            fail_msg("%s", err);
}

/* Key and serial rows: the text runs to the row's end, '#' included (the key, a checksum's
 * neighbour); a '#' row is still a comment; the new fault events take their values in range. */
static void test_scenario_key_serial_and_fault_events(void **state)
{
    static const char text[] =
        "[run]\nduration_s = 100\n[drive]\n0 8\n[events]\n"
        "# 5 key 1   (a comment, not a key)\n"
        "5 key #\n"
        "6   serial   SET 0 100*EA   \n"
        "7 meter_k_ppl 456 # the comment of a valued row\n"
        "8 pressure_offset_bar -1.5\n"
        "9 pressure_drift_bar_per_min 0.05\n"
        "10 level_offset_l 100\n"
        "11 wheel_pulse_mult 0.5\n"
        "12 power_cut 3\n";
    (void)state;
    assert_int_equal(scenario_parse(&s, text, "t.scn", err, sizeof err), 0);
    assert_int_equal(s.n_events, 8);
    assert_int_equal(s.events[0].kind, EV_KEY);
    assert_string_equal(s.events[0].text, "#");
    assert_int_equal(s.events[0].line, 7);
    assert_int_equal(s.events[1].kind, EV_SERIAL);
    assert_string_equal(s.events[1].text, "SET 0 100*EA");
    assert_int_equal(s.events[2].kind, EV_METER_K);
    assert_true(s.events[2].value == 456);
    assert_string_equal(s.events[2].text, "");
    assert_true(s.events[3].value == -1.5);
    assert_int_equal(s.events[6].kind, EV_WHEEL_MULT);
    assert_int_equal(s.events[7].kind, EV_POWER_CUT);
    assert_true(s.events[7].value == 3);
    bad("[events]\n5 key E\n", "bad.scn:2: key 'key': 'E' is not a key");
    bad("[events]\n5 key\n", "bad.scn:2: key 'key': '' is not a key");
    bad("[events]\n5 key 12\n", "bad.scn:2: key 'key': '12' is not a key");
    bad("[events]\n5 serial\n", "bad.scn:2: key 'serial': a serial line is 1-71 characters");
    bad("[events]\n5 serial 0123456789012345678901234567890123456789012345678901234567890123456789012\n",
        "bad.scn:2: key 'serial': a serial line is 1-71 characters (73 here)");
    bad("[events]\n5 serial GET 0\n4 key 1\n", "bad.scn:3: key 'key': time goes backwards");
    bad("[events]\nx key 1\n", "bad.scn:2: key 'events': time 'x' is not a number");
    bad("[run]\nduration_s = 10\n[events]\n11 key 1\n", "bad.scn:4: key 'key': at 11 s, after the end");
    bad("[events]\n5 wheel_pulse_mult 0\n", "bad.scn:2: key 'wheel_pulse_mult': 0 out of range 0.1..16");
    bad("[events]\n5 power_cut 0\n", "bad.scn:2: key 'power_cut': 0 out of range 0.01..86400 s");
    bad("[events]\n5 power_cut\n", "bad.scn:2: key 'power_cut': needs a value");
    bad("[events]\n5 meter_k_ppl 0.5\n", "bad.scn:2: key 'meter_k_ppl': 0.5 out of range 1..10000");
    bad("[events]\n5 pressure_offset_bar 17\n", "bad.scn:2: key 'pressure_offset_bar': 17 out of range -16..16");
    bad("[events]\n5 level_offset_l 1001\n", "bad.scn:2: key 'level_offset_l': 1001 out of range -1000..1000");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_scenario_good_file),
        cmocka_unit_test(test_scenario_drive_alone_is_the_defaults),
        cmocka_unit_test(test_scenario_refuses_a_file_without_drive_rows),
        cmocka_unit_test(test_scenario_messages_escape_what_does_not_print),
        cmocka_unit_test(test_scenario_cross_checks_name_their_line),
        cmocka_unit_test(test_scenario_crlf_and_bom),
        cmocka_unit_test(test_scenario_unknown_keys_and_sections),
        cmocka_unit_test(test_scenario_missing_and_bad_numbers),
        cmocka_unit_test(test_scenario_values_out_of_range),
        cmocka_unit_test(test_scenario_first_edition_file_gets_the_new_defaults),
        cmocka_unit_test(test_scenario_drive_rows),
        cmocka_unit_test(test_scenario_event_rows),
        cmocka_unit_test(test_scenario_controller_names),
        cmocka_unit_test(test_scenario_peer_settings),
        cmocka_unit_test(test_scenario_files),
        cmocka_unit_test(test_scenario_key_serial_and_fault_events),
        cmocka_unit_test(test_scenario_load_refuses_empty_and_binary_files),
        cmocka_unit_test(test_scenario_every_key_and_event_of_plant_md),
        cmocka_unit_test(test_scenario_project_files_load),
        cmocka_unit_test(test_scenario_cut),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

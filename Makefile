# Makefile: every entry point of the sprayer controller. `make help` lists them; README.md explains.
.DEFAULT_GOAL := firmware
SHELL := /bin/bash

# ==== configuration ================================================================================
V ?= 0
ifeq ($(V),1)
Q :=
else
Q := @
endif
msg = $(if $(Q),@printf '  %-6s %s\n' "$(1)" "$(2)",@true)

BUILD ?= build
# one Python for every script: the project's .venv. Every rule that runs $(PYTHON) depends on
# $(VENV), whose rule (tools/deps.sh) installs the toolchain and makes the .venv first, so that a
# fresh clone's first `make <anything>` works (the choice is not made when make starts). A PYTHON
# in the environment does not replace it (its packages may be missing); `make PYTHON=..` does.
VENV := .venv/.requirements
PYTHON := .venv/bin/python
CC ?= cc

# the chip: SDCC 4.2 for the STC12C5A60S2 (sizes in bytes)
SDCC ?= sdcc
SDAR ?= sdar
CODE_SIZE ?= 61440
IRAM_SIZE ?= 256
XRAM_SIZE ?= 1024
# headroom floors: `make firmware` fails below them (room for the next fix; docs/MEMORY.md): 10 %
# of the code free, 128 B of XRAM and a 40 B stack margin at the static worst case. The field
# image carries ffmap and the AgOpenGPS and RateControl frames; the research image (FW_PEERS=1:
# all six controllers, the paper's bp_pid among them) and the bench image (HIL=1: hardware in
# the loop, the I/O test) are held to the chip's size for their code (and HIL's XRAM) and to
# the stack margin.
CODE_FREE_PCT ?= $(if $(filter 1,$(FW_PEERS) $(HIL)),0,10)
XRAM_FREE_MIN ?= $(if $(filter 1,$(FW_PEERS) $(HIL)),0,128)
STACK_MARGIN_MIN ?= 40

# ==== sources: firmware/ in layers, bottom to top ====================================================
# math -> store -> measure -> control -> ops -> console, link -> app (tools/incgraph.py checks it)
FW_DIRS := math store measure control ops console link app
FW_INC := $(addprefix -Ifirmware/,$(FW_DIRS))
FW_SRC := $(wildcard $(addsuffix /*.c,$(addprefix firmware/,$(FW_DIRS))))
FW_LIB_SRC := $(filter-out firmware/app/main.c,$(FW_SRC))
# the 8051 port: the assembly routines (multiply, divide, saturation) of the SDCC builds; the host
# builds compile the C references in firmware/math instead
PORT_SRC := $(wildcard hal/mcs51/*.c)
SIM_MAIN := $(wildcard sim/*_main.c)
SIM_LIB_SRC := $(filter-out $(SIM_MAIN),$(wildcard sim/*.c))
UNIT_TEST_SRC := $(wildcard tests/*/test_*.c)
TEST_HELPER_SRC := $(wildcard tests/*/helper_*.c)
FUZZ_TARGETS := $(patsubst tests/fuzz/fuzz_%.c,%,$(wildcard tests/fuzz/fuzz_*.c))
TT_PROGS := $(filter-out tests/target/tt_common.c tests/target/tt_host.c,$(wildcard tests/target/tt_[a-z]*.c))

# ==== compiler flags =================================================================================
# Memory model: large. The application keeps about 0.5-0.8 KB of state; the 128 bytes of
# directly addressed RAM cannot hold it, the 1 KB of on-chip XRAM can. Large puts every variable
# there by default (movx, slower) and the few hot ones are placed in __data by hand.
# -MMD: each object's header dependencies in a .d beside it (included at the end).
SDCC_MODEL := --model-large
# HIL=1: hardware in the loop built into the chip's image (docs/HIL.md): held to the chip's size and
# the stack margin floor, not to the code and XRAM headroom floors (a bench image, not the field's)
HIL ?= 0
SDCC_CFLAGS := -mmcs51 $(SDCC_MODEL) -Ihal $(FW_INC) -DFW_HIL=$(HIL) $(SDCC_EXTRA)
SDCC_LDFLAGS := --code-size $(CODE_SIZE) --iram-size $(IRAM_SIZE) --xram-size $(XRAM_SIZE) --xram-loc 0x0000
# Shared sequences (docs/MEMORY.md): SDCC writes a firmware module's assembly, tools/share_moves.py
# replaces the sequences of its table by calls of the routines it generates from the same table
# (one module each in DIR/moves/, the archive links those called), sdas assembles it; from its
# listing, the long jumps the sharing brought within reach are made short (--relax), and sdas
# assembles it again. The 8051
# port's own assembly (hal/mcs51/) is left as written. SHARE_HOT_<file>: the functions whose
# cycles count (`*` the whole file): only the table's hot routines there. bp_pid's step takes
# 84 % of the step budget (make bench); the other controllers' steps under 21 % share all.
SDAS ?= sdas8051
SHARE_HOT_firmware/control/bp.c := bp_step
SHARE_HOT_firmware/control/ctl.c := ctl_step ctl_applied
# $(call sdcc_rel,FLAGS): $< compiled to $@ (and its .d), through share_moves.py where it applies
sdcc_rel = $(if $(filter firmware/%,$<),\
    $(SDCC) $(1) -MMD -S $< -o $(@:.rel=.asm) && sed -i '1s|\.asm:|.rel:|' $(@:.rel=.d) \
    && $(PYTHON) tools/share_moves.py $(foreach f,$(SHARE_HOT_$<),'--hot=$(f)') $(@:.rel=.asm) \
    && $(SDAS) -plosgffw $@ $(@:.rel=.asm) \
    && n=$$($(PYTHON) tools/share_moves.py --relax $(@:.rel=.asm)) && { [ "$$n" = 0 ] || $(SDAS) -plosgffw $@ $(@:.rel=.asm); },\
    $(SDCC) $(1) -MMD -c $< -o $@)
# $(1)/moves/: the shared routines, generated from the table and assembled, one module each
define moves_rule
$(1)/moves/.stamp: tools/share_moves.py | $(VENV)
	@mkdir -p $(1)/moves
	$$(call msg,GEN,$(1)/moves)
	$(Q)rm -f $(1)/moves/*.asm $(1)/moves/*.rel && $$(PYTHON) tools/share_moves.py --gen $(1)/moves \
	    && for f in $(1)/moves/*.asm; do $$(SDAS) -plosgffw $$$${f%.asm}.rel $$$$f || exit 1; done && touch $$@
endef
HOST_WARN := -std=c99 -Wall -Wextra -Werror -D_DEFAULT_SOURCE
HOST_INC := -Ihal -Ihal/host -Ihal/pil $(FW_INC) -Isim -Itests/target
TEST_CFLAGS := $(HOST_WARN) $(HOST_INC) -DHAL_HOST -g -O1 -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined
TEST_LDFLAGS := -fsanitize=address,undefined
# the simulator's build: -O3 without the straight-line (SLP) vectoriser, which packs the plant's
# scalar arithmetic into pairs it then unpacks (more instructions, not fewer); the physics stays
# IEEE (no -ffast-math: every result is rounded as the source says)
OPT_CFLAGS := $(HOST_WARN) $(HOST_INC) -DHAL_HOST -O3 -fno-tree-slp-vectorize -fno-math-errno -flto=auto -g

# ==== build folders and products =====================================================================
# each image its own folder: the objects of one are compiled with other flags than another's
STC_DIR := $(BUILD)/stc12$(if $(filter 1,$(FW_PEERS)),-peers)$(if $(filter 1,$(HIL)),-hil)
# the image links main and the chip's HAL (the interrupt handlers) by name and pulls from the
# firmware's archive only the modules something calls
STC_MAIN_REL := $(STC_DIR)/firmware/app/main.rel $(patsubst %.c,$(STC_DIR)/%.rel,$(wildcard hal/stc12/*.c))
# the controllers only the research image carries (FW_PEERS): not compiled into the field set,
# whose controllers' state union then holds ffmap's alone (ctl_int.h)
FW_PEER_SRC := $(addprefix firmware/control/,pid.c bp.c aog.c raven.c ctl_peer.c)
STC_LIB_REL := $(patsubst %.c,$(STC_DIR)/%.rel,$(if $(filter 1,$(FW_PEERS)),$(FW_LIB_SRC),$(filter-out $(FW_PEER_SRC),$(FW_LIB_SRC))) $(PORT_SRC))
STC_LIB := $(STC_DIR)/fw.lib
FW_IHX := $(STC_DIR)/sprayer.ihx
FW_HEX := $(STC_DIR)/sprayer.hex

TEST_DIR := $(BUILD)/host-test
OPT_DIR := $(BUILD)/host
HOST_LIB_SRC := $(FW_LIB_SRC) $(wildcard hal/host/*.c) $(SIM_LIB_SRC)
TEST_LIB := $(TEST_DIR)/libsprayer.a
OPT_LIB := $(OPT_DIR)/libsprayer.a
UNIT_TESTS := $(addprefix $(TEST_DIR)/,$(basename $(notdir $(UNIT_TEST_SRC))))
TEST_HELPERS := $(patsubst %.c,$(TEST_DIR)/%.o,$(TEST_HELPER_SRC))

# fuzzing: libFuzzer harnesses built by clang (make fuzz), and the same harnesses built by gcc
# with a replay main that runs the corpus kept in tests/fuzz/corpus/ (make test)
FUZZ_DIR := $(BUILD)/fuzz
FUZZ_CC ?= clang
FUZZ_CFLAGS := $(HOST_WARN) $(HOST_INC) -DHAL_HOST -g -O1 -fno-omit-frame-pointer -fsanitize=address,undefined -fno-sanitize-recover=undefined
FUZZ_LIB_OBJ := $(patsubst %.c,$(FUZZ_DIR)/%.o,$(HOST_LIB_SRC))
FUZZ_BINS := $(addprefix $(FUZZ_DIR)/bin/fuzz_,$(FUZZ_TARGETS))
FUZZ_REPLAY := $(addprefix $(TEST_DIR)/fuzz/replay_,$(FUZZ_TARGETS))
FUZZ_S ?= 60

UC_DIR := $(BUILD)/ucsim$(if $(SDCC_EXTRA),-variant)
UC_CFLAGS := $(SDCC_CFLAGS) -DHAL_UCSIM -Itests/target
UC_LIB_REL := $(patsubst %.c,$(UC_DIR)/%.rel,$(FW_LIB_SRC) $(PORT_SRC))
UC_TT_REL := $(UC_DIR)/tests/target/tt_common.rel $(UC_DIR)/hal/ucsim/tt_ucsim.rel
TT_IHX := $(patsubst tests/target/%.c,$(UC_DIR)/%.ihx,$(TT_PROGS))
TT_HOST := $(patsubst tests/target/%.c,$(TEST_DIR)/target/%,$(TT_PROGS))

# processor in the loop: the firmware as for the chip, hal/pil instead of hal/stc12, main in hal/pil
PIL_DIR := $(BUILD)/pil
PIL_SRC := $(filter-out $(FW_PEER_SRC),$(FW_LIB_SRC)) $(PORT_SRC) $(wildcard hal/pil/*.c)
PIL_REL := $(patsubst %.c,$(PIL_DIR)/%.rel,$(PIL_SRC))
PIL_IHX := $(PIL_DIR)/sprayer_pil.ihx
# s51 has 64 KB of XRAM: the PIL image may use more than the chip's 1 KB, so that it still runs
# while a change is over the chip's budget (make firmware is what checks the chip's fit)
PIL_XRAM_SIZE ?= 2048

SIM_PROGS := $(patsubst sim/%_main.c,$(OPT_DIR)/bin/%,$(SIM_MAIN))
SIM_BIN := $(OPT_DIR)/bin/sim
PANEL_BIN := $(OPT_DIR)/bin/panel
DEMO_DIR := $(BUILD)/demo

.SECONDARY:
.DELETE_ON_ERROR:
.PHONY: chip ucsim hil hil-host fuzz fuzz-merge firmware memory flash deps test host-tests target-tests mutate sabotage bench sim pil pil-image \
        sim-progs demo compare family faults report \
        bench-sim panel screenshots clean help FORCE

help:
	@echo "make demo      the main job: firmware image + the paper's run in the simulator, its figures beside the paper's, plots"
	@echo "make test      every test (host unit tests, s51 target tests, firmware build, fuzz corpus, scripts): \"N passed, N failed\" last"
	@echo "make firmware  (default) the STC12C5A60S2 image in $(STC_DIR), with its memory use and headroom floors;"
	@echo "               FW_PEERS=1 the research image with the peers, HIL=1 the bench image with hardware in the loop"
	@echo "make memory    the 20 largest users of each memory region of the image, the deepest call chain"
	@echo "make deps      install what the build needs (apt: sdcc sdcc-ucsim libcmocka-dev tmux, clang for fuzz; the .venv)"
	@echo "make flash PORT=/dev/ttyUSB0   write the image with stcgal"
	@echo "make bench     machine cycles in s51: the building blocks, each controller's step (budget 30,000), the interrupt"
	@echo "               handlers, the whole firmware's passes over pil_bench"
	@echo "make sim SCENARIO=f [CONTROLLER=n] [CSV=out.csv]   one scenario in the simulator: a summary, the metrics JSON last"
	@echo "make pil SCENARIO=f [CONTROLLER=n] [CSV=out.csv]   the same, the whole firmware in s51 (processor in the loop) + pass timing"
	@echo "make chip SCENARIO=f [CONTROLLER=n] [CSV=out.csv]  the field image in the STC12C5A60S2 model (build/ucsim/s51) + 1T timing"
	@echo "make ucsim     that model: Debian's uCsim source + sim/ucsim/stc12.patch, built into build/ucsim/s51"
	@echo "make compare   the six controllers on the same plant and seeds, beside the paper; ffmap against bp_pid, aog and raven over seeds 1-16"
	@echo "make family [N=200] [CONTROLLERS=..] [SEED=s] [TOLD=both|drawn] [KIND=both|dynamic|field] [EVENTS=1] [CORNERS=1]"
	@echo "               the controllers over N sprayers of the plant family: median and 95th percentile"
	@echo "make faults [FAULTS_CONTROLLER=ffmap] [ONLY=leak_growing,..]   every fault of issue 51 at two sizes: told or not (build/faults/table.md)"
	@echo "make help-research  the research harnesses' targets (tools/research/research.mk)"
	@echo "make report    docs/RESULTS.md and its plots, the README's headline: the paper's experiments reproduced, the family, the cost (minutes)"
	@echo "make bench-sim simulated seconds per second (wall, CPU time) of the paper's run, with the machine it ran on"
	@echo "make panel     the LCD and keypad in the terminal against the simulated sprayer"
	@echo "make screenshots  the run screen, a menu, a refused entry and the I/O test as PNG in docs/"
	@echo "make hil PORT=/dev/ttyUSB0 SCENARIO=f   the scenario's plant against a flashed board over RS232 (metrics JSON)"
	@echo "make hil-host SCENARIO=f   the same with the host build standing in for the board (a pseudo-terminal)"
	@echo "make fuzz [FUZZ_S=60]  libFuzzer (ASan+UBSan) on every parser, FUZZ_S seconds each; fuzz-merge keeps new coverage"
	@echo "make mutate    the safety rules' mutants against the host tests that cover them; survivors reported (docs/TESTING.md)"
	@echo "make sabotage SAB=n  tt_ops for s51 with routine n of mul.h's FX_SABOTAGE list wrong (make test shows each caught)"
	@echo "make clean     remove build/"
	@echo "parts: host-tests, target-tests, sim-progs (build/host/bin/*), pil-image; V=1 shows full commands"

# ==== the firmware image ==============================================================================
$(VENV): tools/requirements.txt tools/deps.sh
	$(Q)tools/deps.sh --quiet && touch $@

firmware: $(FW_HEX) $(VENV)
	$(Q)$(PYTHON) tools/memuse.py $(STC_DIR)/sprayer --code $(CODE_SIZE) --iram $(IRAM_SIZE) --xram $(XRAM_SIZE) \
	    --code-free $(CODE_FREE_PCT) --xram-free $(XRAM_FREE_MIN) --stack-margin $(STACK_MARGIN_MIN)
	$(Q)$(PYTHON) tools/callcheck.py --tree $(STC_DIR)

memory: $(FW_HEX) $(VENV)
	$(Q)$(PYTHON) tools/memmap.py $(STC_DIR) 20
	$(Q)$(PYTHON) tools/stackdepth.py $(STC_DIR) --path

$(STC_DIR)/%.rel: %.c tools/share_moves.py | $(VENV)
	@mkdir -p $(dir $@)
	$(call msg,SDCC,$<)
	$(Q)$(call sdcc_rel,$(SDCC_CFLAGS) -DHAL_STC12 $(if $(filter 1,$(FW_PEERS)),-DFW_PEERS=1))

$(eval $(call moves_rule,$(STC_DIR)))
$(STC_LIB): $(STC_LIB_REL) $(STC_DIR)/moves/.stamp
	$(call msg,AR,$@)
	$(Q)rm -f $@ && $(SDAR) -rcs $@ $(STC_LIB_REL) $(STC_DIR)/moves/*.rel

$(FW_IHX): $(STC_MAIN_REL) $(STC_LIB)
	$(call msg,LINK,$@)
	$(Q)$(SDCC) $(SDCC_CFLAGS) $(SDCC_LDFLAGS) $(STC_MAIN_REL) -L $(STC_DIR) -l fw.lib -o $@ > $(STC_DIR)/link.log 2>&1 || { cat $(STC_DIR)/link.log; rm -f $@; exit 1; }
	$(Q)if grep -qi "error\|insufficient\|overlap\|exceed" $(STC_DIR)/link.log; then cat $(STC_DIR)/link.log; rm -f $@; exit 1; fi

$(FW_HEX): $(FW_IHX)
	$(call msg,HEX,$@)
	$(Q)packihx $< > $@ 2>/dev/null

STCGAL ?= .venv/bin/stcgal
PORT ?= /dev/ttyUSB0
STCGAL_OPTS ?= -P stc12 -b 38400
flash: $(FW_HEX)
	$(Q)test -x $(STCGAL) || tools/deps.sh
	$(STCGAL) $(STCGAL_OPTS) -p $(PORT) $(FW_HEX)

# ==== host builds: the firmware and the plant model with gcc ===========================================
$(TEST_DIR)/%.o: %.c
	@mkdir -p $(dir $@)
	$(call msg,CC,$<)
	$(Q)$(CC) $(TEST_CFLAGS) -MMD -MP -c $< -o $@

$(OPT_DIR)/%.o: %.c
	@mkdir -p $(dir $@)
	$(call msg,CC,$<)
	$(Q)$(CC) $(OPT_CFLAGS) -MMD -MP -c $< -o $@

$(TEST_LIB): $(patsubst %.c,$(TEST_DIR)/%.o,$(HOST_LIB_SRC))
	$(Q)rm -f $@ && ar rcs $@ $^

$(OPT_LIB): $(patsubst %.c,$(OPT_DIR)/%.o,$(HOST_LIB_SRC))
	$(Q)rm -f $@ && gcc-ar rcs $@ $^

# tests/<layer>/test_<module>.c -> build/host-test/test_<module>
define unit_test_rule
$(TEST_DIR)/$(basename $(notdir $(1))): $(TEST_DIR)/$(1:.c=.o) $(TEST_HELPERS) $(TEST_LIB)
	$$(call msg,LD,$$@)
	$$(Q)$$(CC) $$(TEST_LDFLAGS) $$< $$(TEST_HELPERS) $$(TEST_LIB) -lcmocka -lm -o $$@
endef
$(foreach t,$(UNIT_TEST_SRC),$(eval $(call unit_test_rule,$(t))))

# tests/store/field_store.c: the store of an image without the frames (FW_PGN 0: params.c and
# store.c built so, ahead of the library's) on the records of one with them
FIELD_STORE_OBJ := $(patsubst %.c,$(TEST_DIR)/field/%.o,tests/store/field_store.c firmware/store/params.c firmware/store/store.c)
$(TEST_DIR)/field/%.o: %.c
	@mkdir -p $(dir $@)
	$(call msg,CC,$< [FW_PGN=0])
	$(Q)$(CC) $(TEST_CFLAGS) -DFW_PGN=0 -MMD -MP -c $< -o $@
$(TEST_DIR)/test_store_field: $(FIELD_STORE_OBJ) $(TEST_LIB)
	$(call msg,LD,$@)
	$(Q)$(CC) $(TEST_LDFLAGS) $(FIELD_STORE_OBJ) $(TEST_LIB) -lcmocka -lm -o $@

host-tests: $(UNIT_TESTS) $(TEST_DIR)/test_store_field $(FUZZ_REPLAY)

# tests/fuzz/fuzz_<t>.c + the replay main -> build/host-test/fuzz/replay_<t> (gcc, ASan, UBSan)
$(TEST_DIR)/fuzz/replay_%: $(TEST_DIR)/tests/fuzz/fuzz_%.o $(TEST_DIR)/tests/fuzz/replay_main.o $(TEST_LIB)
	@mkdir -p $(dir $@)
	$(call msg,LD,$@)
	$(Q)$(CC) $(TEST_LDFLAGS) $^ -lm -o $@

# make mutate [MUTATE_ARGS="--only firmware/ops/diag.c:rule" | "--sample 5 --seed N" | "--list"]: the
# safety rules' mutants (tools/mutate.py: comparisons flipped, constants off by one, conditions
# dropped), each built with the host test flags and run against the host tests that cover its file;
# the survivors reported (docs/TESTING.md)
MUTATE_ARGS ?=
mutate: $(UNIT_TESTS) $(TEST_HELPERS) $(TEST_LIB) $(VENV)
	$(Q)$(PYTHON) tools/mutate.py --cc="$(CC)" --cflags="$(TEST_CFLAGS)" --ldflags="$(TEST_LDFLAGS)" --build $(BUILD) $(MUTATE_ARGS)

# ==== target tests: the SDCC build run in s51 against the same program built for the host ================
$(UC_DIR)/%.rel: %.c tools/share_moves.py | $(VENV)
	@mkdir -p $(dir $@)
	$(call msg,SDCC,$< [s51])
	$(Q)$(call sdcc_rel,$(UC_CFLAGS))

$(eval $(call moves_rule,$(UC_DIR)))
$(UC_DIR)/fw.lib: $(UC_LIB_REL) $(UC_DIR)/moves/.stamp
	$(Q)rm -f $@ && $(SDAR) -rcs $@ $(UC_LIB_REL) $(UC_DIR)/moves/*.rel

$(UC_DIR)/tt_%.ihx: $(UC_DIR)/tests/target/tt_%.rel $(UC_DIR)/fw.lib $(UC_TT_REL)
	$(call msg,LINK,$@ [s51 program])
	$(Q)$(SDCC) $(UC_CFLAGS) $(SDCC_LDFLAGS) $< $(UC_TT_REL) -L $(UC_DIR) -l fw.lib -o $@ > $(UC_DIR)/tt_$*.log 2>&1 || { cat $(UC_DIR)/tt_$*.log; exit 1; }

$(TEST_DIR)/target/tt_%: $(TEST_DIR)/tests/target/tt_%.o $(TEST_DIR)/tests/target/tt_common.o $(TEST_DIR)/tests/target/tt_host.o $(TEST_LIB)
	@mkdir -p $(dir $@)
	$(call msg,LD,$@ [host twin])
	$(Q)$(CC) $^ $(TEST_LDFLAGS) -lm -o $@

target-tests: $(TT_IHX) $(TT_HOST)

# make sabotage SAB=n: tt_ops for s51 with routine n of mul.h's FX_SABOTAGE list built wrong (its
# file alone compiled with the switch, linked ahead of the s51 library) in $(UC_DIR)/sabotage-n/;
# tools/run_tests.sh shows the s51 comparison catching each of them
SAB_FILES := $(addprefix hal/mcs51/,mul acc acc upd mul_round mul_round acc acc acc sat16) firmware/math/fixed \
             $(addprefix firmware/math/,umath umath umath)
SAB ?= 1
sabotage: $(UC_DIR)/fw.lib $(UC_TT_REL) $(UC_DIR)/tests/target/tt_ops.rel
	@mkdir -p $(UC_DIR)/sabotage-$(SAB)
	$(Q)$(SDCC) $(UC_CFLAGS) -DFX_SABOTAGE=$(SAB) -c $(word $(SAB),$(SAB_FILES)).c -o $(UC_DIR)/sabotage-$(SAB)/sab.rel
	$(Q)$(SDCC) $(UC_CFLAGS) $(SDCC_LDFLAGS) $(UC_DIR)/tests/target/tt_ops.rel $(UC_DIR)/sabotage-$(SAB)/sab.rel $(UC_TT_REL) -L $(UC_DIR) -l fw.lib -o $(UC_DIR)/sabotage-$(SAB)/tt_ops.ihx > $(UC_DIR)/sabotage-$(SAB)/link.log 2>&1 || { cat $(UC_DIR)/sabotage-$(SAB)/link.log; exit 1; }

# ==== processor in the loop: the whole firmware in s51, the plant on the host (hal/pil, sim/pil_host.c) ====
$(PIL_DIR)/%.rel: %.c tools/share_moves.py | $(VENV)
	@mkdir -p $(dir $@)
	$(call msg,SDCC,$< [pil])
	$(Q)$(call sdcc_rel,$(SDCC_CFLAGS) -DHAL_PIL -Ihal/pil)

# the PIL image carries hal/pil's frames and pass stopwatch, larger than the chip's HAL: s51 gives
# it the 8051's whole 64 KB code space (the chip's image is checked by make firmware)
PIL_CODE_SIZE ?= 65536
$(eval $(call moves_rule,$(PIL_DIR)))
$(PIL_DIR)/moves.lib: $(PIL_DIR)/moves/.stamp
	$(Q)rm -f $@ && $(SDAR) -rcs $@ $(PIL_DIR)/moves/*.rel
$(PIL_IHX): $(PIL_REL) $(PIL_DIR)/moves.lib
	$(call msg,LINK,$@ [pil])
	$(Q)$(SDCC) $(SDCC_CFLAGS) $(SDCC_LDFLAGS) --code-size $(PIL_CODE_SIZE) --xram-size $(PIL_XRAM_SIZE) $(PIL_REL) -L $(PIL_DIR) -l moves.lib -o $@ > $(PIL_DIR)/link.log 2>&1 || { cat $(PIL_DIR)/link.log; rm -f $@; exit 1; }
	$(Q)if grep -qi "error\|insufficient\|overlap\|exceed" $(PIL_DIR)/link.log; then cat $(PIL_DIR)/link.log; rm -f $@; exit 1; fi

pil-image: $(PIL_IHX)

# make pil SCENARIO=file [CONTROLLER=name] [CSV=out.csv]: as make sim, the firmware running in s51
pil: $(SIM_BIN) $(PIL_IHX)
	$(Q)$(SIM_BIN) --pil $(PIL_IHX) --scenario $(SCENARIO) $(if $(CONTROLLER),--controller $(CONTROLLER)) $(if $(CSV),--csv $(CSV))

# ==== chip in the loop: the field image in the STC12C5A60S2 model (sim/ucsim/, sim/chip_host.c) =====
# the model: Debian's uCsim source with sim/ucsim/stc12.patch, built into build/ucsim/ (not /usr/bin)
UCSIM_STC12 := $(BUILD)/ucsim/s51
$(UCSIM_STC12): sim/ucsim/stc12.patch sim/ucsim/stc12.cc sim/ucsim/stc12_hw.cc sim/ucsim/stc12_link.cc \
		sim/ucsim/stc12cl.h sim/ucsim/stc12_link.h sim/ucsim/sources.list.in tools/ucsim_stc12.sh
	$(Q)tools/ucsim_stc12.sh

ucsim: $(UCSIM_STC12)

# make chip SCENARIO=file [CONTROLLER=name] [CSV=out.csv]: as make sim, the field image in the model
# (the simulator, the image and the model built side by side: from a fresh clone the model's
# build is as long as the other two together)
chip:
	$(Q)$(MAKE) --no-print-directory -j2 $(SIM_BIN) $(FW_IHX) $(UCSIM_STC12)
	$(Q)$(SIM_BIN) --chip $(FW_IHX) --s51 $(UCSIM_STC12) --scenario $(SCENARIO) $(if $(CONTROLLER),--controller $(CONTROLLER)) $(if $(CSV),--csv $(CSV))

# ==== tests and measurements ==========================================================================
test:
	$(Q)tools/deps.sh --quiet
	$(Q)tools/run_tests.sh

# the chip's interrupt handlers (hal/stc12) timed in s51: built as for the chip, called by a driver
ISR_IHX := $(UC_DIR)/isr_cycles.ihx
$(UC_DIR)/tests/bench/isr_cycles.rel: tests/bench/isr_cycles.c
	@mkdir -p $(dir $@)
	$(call msg,SDCC,$< [s51])
	$(Q)$(SDCC) $(SDCC_CFLAGS) -DHAL_STC12 $(if $(filter 1,$(FW_PEERS)),-DFW_PEERS=1) -Ihal/stc12 -MMD -c $< -o $@

$(ISR_IHX): $(UC_DIR)/tests/bench/isr_cycles.rel $(patsubst %.c,$(STC_DIR)/%.rel,$(wildcard hal/stc12/*.c))
	$(call msg,LINK,$@ [s51 program])
	$(Q)$(SDCC) $(SDCC_CFLAGS) $(SDCC_LDFLAGS) $^ -o $@ > $(UC_DIR)/isr_cycles.log 2>&1 || { cat $(UC_DIR)/isr_cycles.log; exit 1; }

# machine cycles in s51: the fixed-point blocks and one step of each controller, each step against
# the budget (ctl.h CTL_STEP_BUDGET_CYCLES: 30,000 classic cycles, under 4 ms on the chip); the
# interrupt handlers; the whole firmware's passes and stack over pil_bench's scripted 60 s
bench: $(TT_IHX) $(TT_HOST) $(ISR_IHX) $(SIM_BIN) $(PIL_IHX) $(FW_IHX) $(UCSIM_STC12)
	$(Q)tools/bench.sh $(UC_DIR)
	$(Q)tools/bench_pil.sh $(ISR_IHX) $(SIM_BIN) $(PIL_IHX)
	$(Q)tools/bench_chip.sh $(SIM_BIN) $(FW_IHX) $(UCSIM_STC12)

# simulated seconds per wall second for the paper's run (one process, one core; the fastest of 9)
bench-sim: $(SIM_BIN)
	$(Q)tools/bench_sim.sh $(SIM_BIN) scenarios/paper_dynamic_150.scn

# the six controllers (the paper's pid, fuzzy_pid, bp_pid, the project's ffmap, the peers aog and
# raven) on the same plant and seed (target steps, the paper's dynamic run coupled and with a fixed
# PTO, the field run), beside the paper's Table 2 and section 5.1; then ffmap against bp_pid, aog
# and raven figure by figure, means over seeds 1-16 of every scenario family
compare: $(SIM_BIN) $(VENV)
	$(Q)$(PYTHON) tools/compare.py $(SIM_BIN)
	$(Q)echo
	$(Q)$(PYTHON) tools/seeds.py $(SIM_BIN)
	$(Q)echo
	$(Q)$(PYTHON) tools/seeds.py $(SIM_BIN) --against aog
	$(Q)echo
	$(Q)$(PYTHON) tools/seeds.py $(SIM_BIN) --against raven

# the controllers over N sprayers drawn from the plant family (docs/SCENARIOS.md): median and 95th
# percentile per controller; every run in build/family/runs.csv, the table in summary.json
N ?= 200
CONTROLLERS ?= ffmap,bp_pid,fuzzy_pid,pid,aog,raven
SEED ?= 1
TOLD ?= both
# KIND=dynamic|field|both: the family's drives; EVENTS=1: an operator's events on every run;
# CORNERS=1: the family's corners (the valve's ends, every noise at its top; N=64 covers them)
KIND ?= both
EVENTS ?=
CORNERS ?=
family: $(SIM_BIN) $(VENV)
	$(Q)$(PYTHON) tools/family.py $(SIM_BIN) --n $(N) --controllers $(CONTROLLERS) --seed $(SEED) --told $(TOLD) --kind $(KIND) $(if $(EVENTS),--events) $(if $(CORNERS),--corners) --out $(BUILD)/family

# every fault of issue 51's first table at two sizes: the alarm or warning, its delay, the dose
# while untold and silent_wrong_s (tools/faults.py); the table in build/faults/table.md
FAULTS_CONTROLLER ?= ffmap
faults: $(SIM_BIN) $(VENV)
	$(Q)$(PYTHON) tools/faults.py $(SIM_BIN) --controller $(FAULTS_CONTROLLER) $(if $(ONLY),--only $(ONLY)) --out $(BUILD)/faults

# ==== the simulator, the demo and the virtual panel ========================================================
# Programs from sim/*_main.c, linked with the -O2 library: build/host/bin/<name> (build/host/sim/
# is the folder of the library's objects, so the programs live in bin/).
SCENARIO ?= scenarios/paper_dynamic_150.scn
CONTROLLER ?=
CSV ?=

$(SIM_PROGS): $(OPT_DIR)/bin/%: $(OPT_DIR)/sim/%_main.o $(OPT_LIB)
	@mkdir -p $(dir $@)
	$(call msg,LD,$@)
	$(Q)$(CC) -O2 -flto=auto $< $(OPT_LIB) -lm -o $@

sim-progs: $(SIM_PROGS)

# make sim SCENARIO=file [CONTROLLER=name] [CSV=out.csv]: a summary of the run's figures, then the
# metrics as JSON on the last line
sim: $(SIM_BIN)
	$(Q)$(SIM_BIN) --scenario $(SCENARIO) $(if $(CONTROLLER),--controller $(CONTROLLER)) $(if $(CSV),--csv $(CSV))

# the paper's run with the default controller: the simulator's summary beside the paper's figures,
# trace and plots (the simulator's whole output in build/demo/sim.out)
demo:
	$(Q)tools/deps.sh --quiet
	$(Q)$(MAKE) --no-print-directory firmware
	$(Q)$(MAKE) --no-print-directory $(SIM_BIN)
	@mkdir -p $(DEMO_DIR)
	$(Q)$(SIM_BIN) --scenario scenarios/paper_dynamic_150.scn --csv $(DEMO_DIR)/trace.csv --zones $(DEMO_DIR)/zones.csv > $(DEMO_DIR)/sim.out
	$(Q)tail -n 1 $(DEMO_DIR)/sim.out > $(DEMO_DIR)/metrics.json
	$(Q)$(PYTHON) tools/demo_report.py $(DEMO_DIR)/sim.out
	$(Q)$(PYTHON) tools/plot.py flow $(DEMO_DIR)/trace.csv $(DEMO_DIR)/flow.png --title "paper_dynamic_150: flow following (cf. paper Fig. 9)"
	$(Q)$(PYTHON) tools/plot.py zones $(DEMO_DIR)/zones.csv $(DEMO_DIR)/zones.png --rate 150 --title "paper_dynamic_150: volume per 5 m zone (cf. paper Table 4)"
	@echo "demo: wrote $(DEMO_DIR)/trace.csv $(DEMO_DIR)/zones.csv $(DEMO_DIR)/metrics.json $(DEMO_DIR)/flow.png $(DEMO_DIR)/zones.png"

# make panel [PANEL_SCENARIO=file] [PANEL_ARGS="--speed 2 ..."]: the LCD12864 and the keypad in the
# terminal, the firmware against the simulated sprayer in real time (sim/panel_main.c; q quits).
# make screenshots: the run screen, a menu, a refused entry and the I/O test as PNG in docs/ (the README shows
# them; the panel writes uncompressed PNG, Pillow recompresses).
PANEL_SCENARIO ?=
PANEL_ARGS ?=

panel: $(PANEL_BIN)
	$(Q)$(PANEL_BIN) $(if $(PANEL_SCENARIO),--scenario $(PANEL_SCENARIO)) $(PANEL_ARGS)

screenshots: $(PANEL_BIN) $(VENV)
	@mkdir -p docs
	$(Q)$(PANEL_BIN) --time 40 --keys "*......" --screenshot docs/panel_run.png
	$(Q)$(PANEL_BIN) --time 40 --keys "*......ABBBB" --screenshot docs/panel_menu.png
	$(Q)$(PANEL_BIN) --time 40 --keys "*......AD1500D" --screenshot docs/panel_refused.png
	$(Q)$(PANEL_BIN) --time 40 --keys "*......AAAD1......" --screenshot docs/panel_iotest.png
	$(Q)$(PYTHON) -c "import sys; from PIL import Image; [Image.open(f).save(f, optimize=True) for f in sys.argv[1:]]" docs/panel_run.png docs/panel_menu.png docs/panel_refused.png docs/panel_iotest.png

# ==== hardware in the loop (docs/HIL.md): the plant on the PC, the controller on the serial link ===========
# make hil PORT=/dev/ttyUSB0 SCENARIO=f [CONTROLLER=n]: against a flashed board, in real time (reset
# it first: the run sets it up with the scenario's settings, then HIL ON). make hil-host SCENARIO=f:
# the host build stands in for the board on a pseudo-terminal, as fast as it answers. Both print
# the metrics JSON of `make sim` last (with hil_frames, hil_lost), exit 3 when frames were lost.
HIL_BIN := $(OPT_DIR)/bin/hil
HILBOARD_BIN := $(OPT_DIR)/bin/hilboard
HIL_ARGS ?=

hil: $(HIL_BIN)
	$(Q)$(HIL_BIN) --scenario $(SCENARIO) --port $(PORT) $(if $(CONTROLLER),--controller $(CONTROLLER)) $(HIL_ARGS)

hil-host: $(HIL_BIN) $(HILBOARD_BIN)
	$(Q)tools/hil_host.sh $(OPT_DIR)/bin $(SCENARIO) $(if $(CONTROLLER),--controller $(CONTROLLER)) $(HIL_ARGS)

# ==== fuzzing: libFuzzer with ASan and UBSan (clang, installed by tools/deps.sh) =====================
# make fuzz [FUZZ_S=60] [FUZZ_TARGETS="serial hil"]: each target FUZZ_S seconds from the corpus in
# tests/fuzz/corpus/<t>/ (read only); new inputs in build/fuzz/<t>/corpus, findings (crash-*,
# with the input) in build/fuzz/<t>/; the summary per target in build/fuzz/summary.txt.
# make fuzz-merge: add what build/fuzz/<t>/corpus covers beyond the kept corpus to tests/fuzz/corpus/<t>/.
$(FUZZ_DIR)/%.o: %.c
	@mkdir -p $(dir $@)
	$(call msg,CLANG,$<)
	$(Q)$(FUZZ_CC) $(FUZZ_CFLAGS) -fsanitize=fuzzer-no-link -MMD -MP -c $< -o $@

$(FUZZ_DIR)/bin/fuzz_%: $(FUZZ_DIR)/tests/fuzz/fuzz_%.o $(FUZZ_LIB_OBJ)
	@mkdir -p $(dir $@)
	$(call msg,LD,$@ [libFuzzer])
	$(Q)$(FUZZ_CC) -fsanitize=fuzzer,address,undefined $^ -lm -o $@

fuzz:
	$(Q)tools/deps.sh --quiet --fuzz
	$(Q)$(MAKE) --no-print-directory -j2 $(addprefix $(FUZZ_DIR)/bin/fuzz_,$(FUZZ_TARGETS))
	$(Q)tools/fuzz.sh $(FUZZ_DIR) $(FUZZ_S) $(FUZZ_TARGETS)

fuzz-merge:
	$(Q)for t in $(FUZZ_TARGETS); do mkdir -p tests/fuzz/corpus/$$t; \
	    $(FUZZ_DIR)/bin/fuzz_$$t -merge=1 tests/fuzz/corpus/$$t $(FUZZ_DIR)/$$t/corpus 2>&1 | grep -E 'MERGE-OUTER: [0-9]+ new files' | sed "s/^/$$t: /"; done

# ==== set-up and cleaning ====================================================================================
deps:
	$(Q)tools/deps.sh
	$(Q)tools/ucsim_stc12.sh

clean:
	rm -rf $(BUILD)

# ==== research harnesses: their targets apart from the product's ==================================
include tools/research/research.mk

# ==== header dependencies (written by -MMD) ====================================================================
# SDCC has no -MP: a header that is gone is no reason to stop, the object is rebuilt
%.h: ;
-include $(shell find $(BUILD) -name '*.d' 2>/dev/null)

# ==== the results report ==================================================================================
# make report: docs/RESULTS.md and its plots from a clean build (tools/results.py): the paper's
# Tables 2-4 and section 5.1 beside this project's figures, ISO 5682-3 style changes, the plant family,
# single-factor sweeps, and the cost on the chip; also the README's headline table. Last, the
# simulator's speed with the machine it ran on: a measurement of that machine, not a result.
REPORT_DIR := $(BUILD)/report
report: $(VENV) firmware $(SIM_PROGS) $(TT_IHX) $(TT_HOST)
	@mkdir -p $(REPORT_DIR)
	$(Q)$(MAKE) --no-print-directory firmware > $(REPORT_DIR)/memory.txt 2>&1 || true
	$(Q)tools/bench.sh $(UC_DIR) > $(REPORT_DIR)/bench.txt 2>&1 || true
	$(Q)tools/bench_sim.sh $(SIM_BIN) scenarios/paper_dynamic_150.scn > $(REPORT_DIR)/bench_sim.txt 2>&1 || true
	$(Q)$(PYTHON) tools/results.py --sim $(SIM_BIN) --bench $(REPORT_DIR)/bench.txt \
	    --memory $(REPORT_DIR)/memory.txt --bench-sim $(REPORT_DIR)/bench_sim.txt
	$(Q)tail -n 1 $(REPORT_DIR)/bench_sim.txt

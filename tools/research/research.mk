# research.mk: the research harnesses' targets (tools/research/, docs/TARGETS.md), included by the
# Makefile: questions asked of the design, not part of building, testing or measuring the product.
.PHONY: help-research redraw robust bound crc8-choice

help-research:
	@echo "make redraw [PLANTS=\"28/35/untold ..\"] [SELECT=fast-high|fast-stiff] [SEEDS=1-140] [DRAWS=12]   family plants with more noise draws: runs with an alarm"
	@echo "make robust [ROBUST_ARGS=\"--seeds 1-8 --only ..\"]   ffmap and bp_pid on valves other than the default, told or not"
	@echo "make bound [SCENARIO=f] [CONTROLLER=n]   what an ideal controller could reach on the run"
	@echo "make crc8-choice   why the serial link's check is the CRC-8 with polynomial 0x65"
	@echo "by hand: tools/research/overshoot_split.py SIM, tools/research/ctl_tail.py DIR.. (docs/TARGETS.md)"

# family plants again with more noise draws (the plant's own seed, then --seed 1..DRAWS-1): the
# runs with an alarm per plant; PLANTS as SEED/NUMBER/told|untold, or SELECT a class of SEEDS'
# plants (tools/research/redraw.py); neither: the plants its --help names
PLANTS ?=
SELECT ?=
SEEDS ?= 1-140
DRAWS ?= 12
redraw: $(SIM_BIN) $(VENV)
	$(Q)$(PYTHON) tools/research/redraw.py $(SIM_BIN) $(PLANTS) $(if $(SELECT),--select $(SELECT) --seeds $(SEEDS)) --draws $(DRAWS) --out $(BUILD)/redraw

ROBUST_ARGS ?=
robust: $(SIM_BIN) $(VENV)
	$(Q)$(PYTHON) tools/research/robust.py $(SIM_BIN) $(ROBUST_ARGS)

bound: $(SIM_BIN) $(VENV)
	$(Q)$(PYTHON) tools/research/bound.py --run $(SIM_BIN) $(SCENARIO) $(CONTROLLER)

crc8-choice: $(VENV)
	$(Q)$(PYTHON) tools/research/crc8_choice.py

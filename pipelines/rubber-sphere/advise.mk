# `shapepress advise` on the rubber sphere (issue 21, points 2 and 3):
#   make -C pipelines/rubber-sphere advise stability-map SHAPEPRESS=... OUT=...
# advise: the BMS ladder of the plate study (ADVISE_COUNTS, ADVISE_FILLS fills per rung, the
#   shipped config) and the cheapest N within ADVISE_TOLERANCE RMS of the finest, to hold beside
#   the study's own table (docs/models.md: N = 545 is 3.5 % from N = 1322 with 32 fills);
# stability-map: rigid clumps (cheap, deterministic) of MAP_COUNTS sub-spheres at every
#   time-step fraction of MAP_FRACTIONS, each point within the tolerance, off, diverged (exit 1
#   with its named cause) or refused by the step checks; $(OUT)/stability-map/stability_map.svg.
# Both resume: a rung already run in the folder is reused (advise --resume), so an interrupted
# target continues and an extended ladder runs only its new rungs. Included by the Makefile.
ADVISE_COUNTS ?= 100,250,545,819,1322
ADVISE_FILLS ?= 8
ADVISE_TOLERANCE ?= 0.05
MAP_COUNTS ?= 20,50,100,300
MAP_FRACTIONS ?= 0.05,0.1,0.2,0.35,0.5,0.75,1

$(OUT)/advise/run.json: $(CONFIG)
	$(SP) advise --config $< --particle bms --counts $(ADVISE_COUNTS) --fills $(ADVISE_FILLS) \
	  --tolerance $(ADVISE_TOLERANCE) --resume --out $(OUT)/advise
$(OUT)/stability-map/run.json: $(CONFIG)
	$(SP) advise --config $< --particle cms --counts $(MAP_COUNTS) --fractions $(MAP_FRACTIONS) \
	  --tolerance $(ADVISE_TOLERANCE) --resume --out $(OUT)/stability-map

.PHONY: advise stability-map
advise: $(OUT)/advise/run.json
stability-map: $(OUT)/stability-map/run.json

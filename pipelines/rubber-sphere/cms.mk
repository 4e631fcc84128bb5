# The CMS half of the rubber-sphere study (Giannis et al. 2023, §3.3 and Fig. 3; issue 6): the
# same rubber sphere as one RIGID clump of N overlapping spheres (the CMS filler's cover of the
# sphere, `shapepress fill --kind cms`), each N pressed to 40 % like the BMS runs, and the
# convergence question: does the force settle as N grows, for CMS and for BMS?
#   make -C pipelines/rubber-sphere cms SHAPEPRESS=/abs/path/shapepress OUT=/abs/path/out
# Included by the Makefile (it uses its SP, OUT, CONFIG, COUNTS and BMS rules). Products in
# $(OUT)/cms-report/:
#   cms_force.*           force–deformation of every CMS N with the finest BMS run, Hertz, Tatara;
#   cms_contacts.*        sub-sphere–plate contacts against deformation (the dropouts);
#   convergence_change.*  change of the force at 20/30/40 % from the next coarser N, against N,
#                         CMS and BMS;
#   convergence_spread.*  spread (max − min)/mean of the force at 20/30/40 % across
#                         N = CMS_SPREAD_FROM…, beside the BMS spread across N = BMS_SPREAD_FROM…;
#   convergence_runs.csv, convergence_spread.csv  the numbers (force at 20/30/40 %, dropouts, CPU s).
CMS_COUNTS ?= 50 89 150 750 1500 3000
CMS_SPREAD_FROM ?= 150
BMS_SPREAD_FROM ?= 819
CMS_CONFIG ?= $(CONFIG)

$(OUT)/cms-%/force.csv: $(CMS_CONFIG)
	$(call on_cluster,$(THREADS)) $(SP) plate --config $< --particle cms --spheres $* --out $(OUT)/cms-$*
CMS_RUNS := $(foreach n,$(CMS_COUNTS),$(OUT)/cms-$(n)/force.csv)
# Every BMS run of the ladder (for the change against N) and the Hertz sphere.
CMS_REPORT_INPUTS := $(CMS_RUNS) $(foreach n,$(COUNTS),$(OUT)/bms-$(n)/force.csv) \
                     $(OUT)/hertz/force.csv

$(OUT)/cms-report/report.html: $(CMS_REPORT_INPUTS)
	$(SP) report $(dir $(CMS_REPORT_INPUTS)) --poisson-ratio 0.46 \
	  --spread-from cms=$(CMS_SPREAD_FROM) --spread-from bms=$(BMS_SPREAD_FROM) \
	  --out $(OUT)/cms-report

.PHONY: cms cms-runs
cms-runs: $(CMS_RUNS)
cms: $(OUT)/cms-report/report.html
all: cms

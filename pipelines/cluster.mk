# The study Makefiles' one switch for a cluster (issue 25), included by each of them:
#   make -C pipelines/<study> CLUSTER=slurm -j 50 OUT=/shared/path/out [SRUN_FLAGS='--time=4:00:00']
# turns every simulation rule (calibrate, plate, compact, fill, generate) into one Slurm job,
# `srun` with the rule's thread count as --cpus-per-task, so make keeps up to 50 jobs in the
# queue and gathers their files as on one machine. Cheap rules (configs, sums, report, plots)
# stay on the machine running make. Without CLUSTER every command is byte for byte what it was.
# srun rather than `sbatch --wait`: the job's stdout and stderr come back to make, so a rule's
# `> summary.txt` and its error messages work unchanged, and srun's exit code is the run's.
# OUT and the binary must be on a filesystem the compute nodes share; run make on a login node,
# not inside an allocation (there srun would make job steps of that allocation instead).
#   CLUSTER       empty (run here) or slurm
#   SRUN_FLAGS    more srun options for every job: --partition, --account, --time, --mem, ...
#                 (srun also reads SLURM_PARTITION, SLURM_ACCOUNT, SLURM_TIMELIMIT from the
#                 environment)
CLUSTER ?=
SRUN_FLAGS ?=

# $(call on_cluster,THREADS): the prefix that runs a recipe's command as one job of THREADS CPUs;
# empty without the switch (make strips the blank it leaves before the command).
# OMP_NUM_THREADS: a stage run without --threads uses its allocation, not every core of the node
# (an explicit --threads wins over it). --quit-on-interrupt: make's Ctrl-C cancels the job.
# --input=none: with make -j, no job reads the terminal.
ifeq ($(CLUSTER),slurm)
on_cluster = $(strip srun --job-name=$(notdir $(@D))/$(@F) --ntasks=1 \
  --cpus-per-task=$(1) --export=ALL,OMP_NUM_THREADS=$(1) --input=none --quit-on-interrupt \
  $(SRUN_FLAGS))
else ifneq ($(CLUSTER),)
$(error CLUSTER=$(CLUSTER): the cluster known is slurm (CLUSTER=slurm), or none (CLUSTER empty))
endif

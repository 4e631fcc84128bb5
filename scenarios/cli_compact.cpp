#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "common/atomic_file.hpp"
#include "common/command_options.hpp"
#include "common/config.hpp"
#include "common/csv.hpp"
#include "common/progress.hpp"
#include "common/provenance.hpp"
#include "common/resume.hpp"
#include "scenarios/cli.hpp"
#include "scenarios/compact_checkpoint.hpp"
#include "scenarios/compact_setup.hpp"
#include "scenarios/run_facts.hpp"
#include "simulate/checkpoint.hpp"

namespace shapepress::scenarios {
namespace {

struct CompactCli {
  std::string config;
  std::string packing;
  std::string restart;
  std::string out;
  std::string resume;
  std::optional<std::int64_t> steps;
};

// compact's options, bound once: parsed, recorded for --resume, written into run.json and
// documented (docs/stages.md).
CommandOptions compact_command(CompactCli& cli) {
  CommandOptions options("compact");
  options.text("--config", &cli.config, "compact config TOML (materials, box, punch, run)")
      .config()
      .text("--packing", &cli.packing,
            "the bed: pack's packed.h5 (spheres, BMS or CMS bodies), or spheres as 'x y z r' "
            "text (m) or HDF5 /particles/{position,radius} (a compact snapshot of plain "
            "spheres); without it the config's [generate] and [clumps] pour one")
      .text("--restart", &cli.restart, "continue from a snapshot written by compact")
      .excludes("--packing")
      .whole("--steps", &cli.steps, "stop at this total step count (overrides run.steps)")
      .range(Range::non_negative())
      .text("--out", &cli.out,
            "output folder (punch.csv, snapshots/, snapshots.xdmf, effective.toml)")
      .output();
  return options;
}

namespace fs = std::filesystem;

// The run's arguments and command line: as given, or as the killed run was started (--resume).
struct CompactInvocation {
  CompactCli cli;
  std::string command_line;
};

CompactInvocation resolve_invocation(const CompactCli& given, const RunContext& context) {
  CompactInvocation invocation{given, context.command_line};
  if (!given.resume.empty())
    invocation.command_line =
        compact_command(invocation.cli)
            .resume(fs::absolute(given.resume) / std::string(checkpoint_folder) / "resume.json",
                    given.resume);
  if (invocation.cli.config.empty())
    throw InputError("compact: give --config FILE (or --resume OUT)");
  if (invocation.cli.out.empty()) throw InputError("compact: give --out FOLDER (or --resume OUT)");
  return invocation;
}

// Where a resumed run continues: a checkpoint of the compaction, else one of the settle of a
// generated bed before it (neither: from the start).
struct ResumePoint {
  std::optional<CheckpointFiles> compaction, settle;
};

ResumePoint find_resume_point(const fs::path& out, const fs::path& checkpoints) {
  ResumePoint point;
  point.compaction = latest_checkpoint(checkpoints);
  if (!point.compaction) point.settle = latest_checkpoint(checkpoints, settle_checkpoint_prefix);
  if (point.compaction)
    spdlog::info("compact: resuming {} from the checkpoint at step {}", out.string(),
                 point.compaction->step);
  else if (point.settle)
    spdlog::info("compact: resuming {} from the settle's checkpoint at step {}", out.string(),
                 point.settle->step);
  else
    spdlog::info("compact: {} has no checkpoint yet: starting the run again", out.string());
  for (const auto* sub : {"", "snapshots"})
    remove_stale_temporaries(out / sub);
  return point;
}

// The settle's checkpoints (of a generated bed), from `resume` when there is one; the settle's
// step is kept in `settle_steps` for the record of a stopped run.
SettleCheckpoints settle_checkpoints(const std::optional<CheckpointFiles>& resume,
                                     ResumableRun& resumable, const fs::path& out,
                                     const Provenance& provenance, std::int64_t& settle_steps) {
  SettleCheckpoints checkpoints;
  if (resume) checkpoints.resume = read_snapshot(resume->snapshot);
  checkpoints.after_step = [&](const Engine& e) {
    settle_steps = e.step_index();
    return resumable.after_step(e.step_index(),
                                [&] { write_settle_checkpoint(out, e, provenance); });
  };
  return checkpoints;
}

// The bed the compaction starts (or continues) from, with the records and snapshot index it had
// written before its checkpoint.
struct StartedBed {
  PreparedCompaction prepared;  // no engine: the settle was stopped
  CheckpointHistory history;
};

// The compaction's checkpoint, its records' fractions by shape volume filled in from their gaps.
StartedBed continue_from_checkpoint(const CompactConfig& config,
                                    const CheckpointFiles& checkpoint) {
  StartedBed bed;
  bed.history = read_checkpoint_history(checkpoint.record);
  bed.prepared = resume_compaction(config, read_snapshot(checkpoint.snapshot));
  if (bed.history.compaction.records.empty() && bed.prepared.punch.phase != PunchPhase::relax)
    throw InputError(
        fmt::format("{}: no records, and the snapshot's punch is past its "
                    "relaxation (a damaged checkpoint)",
                    checkpoint.record.string()));
  // The checkpoint keeps each record's gap; its fraction by shape volume follows from it.
  const CompactionSetup& setup = bed.prepared.setup;
  for (PunchRecord& r : bed.history.compaction.records)
    r.solid_fraction_shape = setup.shape_volume / (setup.die_area * r.gap);
  return bed;
}

// The bed from the compaction's checkpoint, a --restart snapshot, a --packing or the config's
// [generate] (settled), each input named in `meta`.
StartedBed start_bed(const CompactCli& cli, const CompactConfig& config,
                     const std::optional<CheckpointFiles>& checkpoint,
                     SettleCheckpoints settle_checkpoints, RunMetadata& meta) {
  StartedBed bed;
  if (checkpoint) {
    bed = continue_from_checkpoint(config, *checkpoint);
    // The inputs the run started from, so run.json is the uninterrupted run's.
    if (!cli.restart.empty()) meta.input("restart", cli.restart);
    if (!cli.packing.empty()) meta.input("packing", cli.packing);
    if (cli.restart.empty() && config.clumps && !config.clumps->templates.empty())
      meta.input("templates", config.clumps->templates);
  } else if (!cli.restart.empty()) {
    bed.prepared = resume_compaction(config, read_snapshot(cli.restart));
    meta.input("restart", cli.restart);
  } else {
    if (!cli.packing.empty() && is_body_packing(cli.packing)) {
      bed.prepared = prepare_compaction(config, read_packing(cli.packing));
    } else {
      std::optional<SphereList> spheres;
      if (!cli.packing.empty()) spheres = read_spheres(cli.packing);
      bed.prepared = prepare_compaction(config, spheres, std::move(settle_checkpoints));
      if (!bed.prepared.engine) return bed;
    }
    if (!cli.packing.empty()) meta.input("packing", cli.packing);
    if (config.clumps && !config.clumps->templates.empty())
      meta.input("templates", config.clumps->templates);
  }
  return bed;
}

void log_time_step(const Engine& engine, const CompactionSetup& setup) {
  spdlog::info(
      "compact: {} spheres ({} rigid clumps), time step {:.3g} s ({:.3g} of the Rayleigh time, "
      "{:.0f} steps per Hertz collision)",
      engine.state().size(), engine.clumps().size(), setup.time_step.time_step,
      setup.time_step.time_step / setup.time_step.rayleigh_time,
      setup.time_step.collision_time / setup.time_step.time_step);
}

// What the run used, every key with its value (defaults and --steps included).
void write_effective_config(const fs::path& out, const std::string& command_line,
                            const CompactConfig& config) {
  write_file_atomically(
      out / "effective.toml",
      fmt::format("# {}\n# the effective config of this compact run\n", command_line) +
          compact_config_toml(config));
}

// What punch.csv's three solid fractions of a bed of bodies are by.
std::string solid_volumes_comment(const CompactionSetup& setup) {
  if (setup.solid_fraction_volume == packing::SolidVolume::shape)
    return fmt::format(
        "solid_fraction is by the bodies' shapes' (meshes') volume {:.10g} m^3 "
        "(punch.solid_fraction_volume = \"shape\"), as solid_fraction_shape; their volume in the "
        "bed (their sub-spheres' union closed by a ball of their radius) is {:.10g} m^3; "
        "solid_fraction_spheres by their sub-spheres' {:.10g} m^3",
        setup.shape_volume, setup.body_volume, setup.sphere_volume);
  return fmt::format(
      "solid_fraction is by the bodies' volume in the bed {:.10g} m^3 (their sub-spheres' union "
      "closed by a ball of their radius); solid_fraction_shape by their shapes' (meshes') "
      "{:.10g} m^3; solid_fraction_spheres by their sub-spheres' {:.10g} m^3",
      setup.body_volume, setup.shape_volume, setup.sphere_volume);
}

// punch.csv's comments: the strain's reference, the volumes its solid fractions divide by, the
// mass scaling and where loading stops.
void write_punch_csv_comments(CsvWriter& csv, const PreparedCompaction& prepared,
                              const CompactConfig& config) {
  const CompactionSetup& setup = prepared.setup;
  csv.comment(fmt::format("shapepress compact; strain from H0 = {:.10g} m; die area {:.10g} m^2",
                          prepared.punch.reference_gap, setup.die_area));
  csv.comment(strain_reference_comment(setup));
  csv.comment(fmt::format("solid volume {:.10g} m^3; solid fraction ceiling {} at gap {:.10g} m",
                          setup.solid_volume, setup.max_solid_fraction, *setup.program.min_gap));
  if (setup.sphere_volume != setup.body_volume) csv.comment(solid_volumes_comment(setup));
  if (config.density_scale != 1.0)
    csv.comment(fmt::format("mass scaling: particle density x {} (run.density_scale)",
                            config.density_scale));
  if (setup.ceiling_limits_load)
    csv.comment(fmt::format(
        "loading stops at the solid fraction ceiling {} (gap {:.10g} m, strain {:.6g}) before "
        "the target gap {:.10g} m",
        setup.max_solid_fraction, *setup.program.min_gap,
        1.0 - *setup.program.min_gap / prepared.punch.reference_gap, *setup.program.target_gap));
  csv.comment("phase: 0 load, 1 hold, 2 unload, 4 release, 3 done");
}

// What the compaction writes as it runs: punch.csv's rows, the snapshots and their index, and
// the checkpoints.
CompactionHooks output_hooks(CsvWriter& csv, std::vector<SnapshotIndexEntry>& index,
                             const fs::path& out, const CompactionSetup& setup,
                             const Provenance& provenance, ResumableRun& resumable) {
  CompactionHooks hooks;
  hooks.record = [&](const PunchRecord& r) { csv.row(punch_csv_row(r)); };
  hooks.snapshot = [&](const Engine& e, const PunchState& punch) {
    const std::string name = fmt::format("step_{:010d}.h5", e.step_index());
    write_snapshot(out / "snapshots" / name, e, compaction_scenario_state(punch, setup),
                   provenance);
    index.push_back({fs::path("snapshots") / name, e.time(), e.state().size(), e.walls().size(),
                     e.computes_particle_stress(), e.bonds().size(), e.clumps().size()});
    write_xdmf(out / "snapshots.xdmf", index);
  };
  hooks.after_step = [&](const Engine& e, const PunchState& punch, const CompactionHistory& h) {
    return resumable.after_step(e.step_index(), [&] {
      write_compact_checkpoint(out, e, compaction_scenario_state(punch, setup), provenance,
                               {h, index});
    });
  };
  return hooks;
}

// Steps to the run's limit, or the punch program's estimate (a displacement run), from here:
// a resumed run's rate and ETA are this process's.
double steps_to_go(const Engine& engine, const PreparedCompaction& prepared,
                   const CompactConfig& config) {
  const CompactionSetup& setup = prepared.setup;
  const double gap =
      engine.walls()[setup.punch_wall].position - engine.walls()[setup.bottom_wall].position;
  const double stress = engine.wall_load(setup.punch_wall) / setup.die_area;
  return config.setup.max_steps > 0
             ? static_cast<double>(config.setup.max_steps - engine.step_index())
             : remaining_steps_estimate(setup.program, prepared.punch, engine.time(), gap, stress,
                                        engine.settings().time_step);
}

void warn_unless_quasi_static(const char* phase, const PhaseQuasiStatic& p) {
  if (p.records == 0 || p.quasi_static()) return;
  spdlog::warn(
      "compact: the {} was not quasi-static: kinetic energy up to {:.3g} of the punch's work "
      "(limit {}), top and bottom forces {:.3g} apart on average (limit {}), inertial number "
      "up to {:.3g} (limit {}); slow the punch, or lower run.density_scale",
      phase, p.max_kinetic_to_work, PhaseQuasiStatic::max_kinetic_energy_ratio,
      p.mean_force_imbalance, PhaseQuasiStatic::max_mean_force_imbalance, p.max_inertial_number,
      PhaseQuasiStatic::max_inertial_number_limit);
}

// One machine-readable line for scripts (tests/bench/hertz-compaction/run.sh).
void print_summary_line(const CompactionSummary& summary, const Engine& engine, double h0) {
  const PunchRecord& last = summary.last;
  std::printf(
      "SUMMARY steps=%lld loop_s=%.6g particle_steps_per_s=%.6g punch_force_N=%.6g "
      "bottom_force_N=%.6g max_stress_Pa=%.6g contacts_per_particle=%.6g kinetic_energy_J=%.6g "
      "list_builds=%lld h0_m=%.10g\n",
      static_cast<long long>(summary.steps), summary.loop_seconds,
      summary.loop_seconds > 0 ? static_cast<double>(engine.state().size()) *
                                     static_cast<double>(summary.loop_steps) / summary.loop_seconds
                               : 0.0,
      last.top_force, last.bottom_force, summary.max_stress, last.contacts_per_particle,
      last.kinetic_energy, static_cast<long long>(engine.list_builds()), h0);
}

int run(const CompactCli& given, const RunContext& context) {
  const fs::path resumed(given.resume);
  if (finished_before_resume("compact", given.resume, resumed / std::string(checkpoint_folder),
                             resumed / std::string(run_metadata_name)))
    return 0;
  auto [cli, command_line] = resolve_invocation(given, context);
  const fs::path out(cli.out);
  const fs::path checkpoints = out / std::string(checkpoint_folder);
  const ResumePoint resume =
      given.resume.empty() ? ResumePoint{} : find_resume_point(out, checkpoints);
  RunMetadata meta("compact", command_line);
  const ConfigTable root = ConfigTable::load_file(cli.config);
  // Hashed once each reader has accepted the file, so a missing file keeps the reader's message.
  meta.input("config", cli.config);
  CompactConfig config = read_compact_config(root);
  root.check_unknown_keys();
  if (cli.steps) config.setup.max_steps = *cli.steps;
  ensure_output_folder(out / "snapshots");
  // Before the settle, so --resume can start a run killed before its first checkpoint again.
  ResumableRun resumable("compact", out, checkpoints,
                         {config.checkpoint_every, config.checkpoint_minutes});
  resumable.start(!given.resume.empty(), compact_command(cli).invocation(command_line));
  const Provenance provenance{
      command_line, root.text(),
      config.generate ? std::optional(config.generate->seed) : std::nullopt};
  std::int64_t settle_steps = 0;
  StartedBed bed =
      start_bed(cli, config, resume.compaction,
                settle_checkpoints(resume.settle, resumable, out, provenance, settle_steps), meta);
  PreparedCompaction& prepared = bed.prepared;
  if (!prepared.engine) return resumable.stopped(settle_steps);
  Engine& engine = *prepared.engine;
  const CompactionSetup& setup = prepared.setup;
  // Where the punch starts when [box] leaves it to the packing: the effective config states it.
  if (std::isnan(config.punch)) config.punch = engine.walls()[setup.punch_wall].position;
  log_time_step(engine, setup);
  // A resumed run has its effective config from its start (where the punch started is no longer
  // in the engine); again after a settle checkpoint: the same text.
  if (!resume.compaction) write_effective_config(out, command_line, config);

  CsvWriter csv(out / "punch.csv", punch_csv_columns());
  write_punch_csv_comments(csv, prepared, config);
  std::vector<SnapshotIndexEntry>& index = bed.history.snapshots;
  CompactionHooks hooks = output_hooks(csv, index, out, setup, provenance, resumable);
  // The rows before the checkpoint, as the run wrote them (the same numbers, the same text).
  for (const PunchRecord& r : bed.history.compaction.records)
    hooks.record(r);
  const std::int64_t first_step = engine.step_index();
  const double total = steps_to_go(engine, prepared, config);
  ProgressReporter progress("compact", total, {.quiet = context.quiet});
  // The estimate is renewed as the run goes: the spring-back is known only while it happens.
  if (total > 0)
    hooks.progress = [&](std::int64_t step) {
      const double done = static_cast<double>(step - first_step);
      progress.update(done, phase_name(prepared.punch.phase),
                      [&] { return done + steps_to_go(engine, prepared, config); });
    };
  const double h0 = prepared.punch.reference_gap;
  const CompactionSummary summary =
      run_compaction(engine, setup, prepared.punch, hooks, std::move(bed.history.compaction));
  if (summary.interrupted) return resumable.stopped(engine.step_index());  // not "100 % done"
  progress.finish();
  warn_unless_quasi_static("loading", summary.quasi_static);
  warn_unless_quasi_static("unloading", summary.quasi_static.unload);

  csv.commit();
  meta.output("punch.csv");
  if (!index.empty()) meta.output("snapshots.xdmf");
  meta.options(compact_command(cli).json());
  add_compaction_facts(meta, config, setup, prepared.punch.reference_gap, engine, summary);
  meta.write(out / run_metadata_name);
  resumable.finish();
  print_summary_line(summary, engine, h0);
  return 0;
}

}  // namespace

StageOptions compact_options() {
  return compact_config_options();
}

CommandOptions compact_command_options() {
  static CompactCli defaults;
  return compact_command(defaults);
}

StageRunner setup_compact_cli(CLI::App& app) {
  auto cli = std::make_shared<CompactCli>();
  compact_command(*cli).add_to(app, &cli->resume,
                               "continue the killed run in this output folder from its last "
                               "checkpoint, with the arguments it was started with");
  return [cli](const RunContext& context) { return run(*cli, context); };
}

}  // namespace shapepress::scenarios

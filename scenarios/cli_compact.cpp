#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "common/atomic_file.hpp"
#include "common/config.hpp"
#include "common/csv.hpp"
#include "common/progress.hpp"
#include "common/provenance.hpp"
#include "scenarios/cli.hpp"
#include "scenarios/compact_setup.hpp"
#include "scenarios/run_facts.hpp"

namespace shapepress::scenarios {
namespace {

struct CompactCli {
  std::string config;
  std::string packing;
  std::string restart;
  std::string out;
  std::int64_t steps = -1;
};

int run(const CompactCli& cli, const RunContext& context) {
  RunMetadata meta("compact", context.command_line);
  const ConfigTable root = ConfigTable::load_file(cli.config);
  // Hashed once each reader has accepted the file, so a missing file keeps the reader's message.
  meta.input("config", cli.config);
  CompactConfig config = read_compact_config(root);
  root.check_unknown_keys();
  if (cli.steps >= 0) config.setup.max_steps = cli.steps;
  PreparedCompaction prepared;
  if (!cli.restart.empty()) {
    prepared = resume_compaction(config, read_snapshot(cli.restart));
    meta.input("restart", cli.restart);
  } else {
    if (!cli.packing.empty() && is_body_packing(cli.packing)) {
      prepared = prepare_compaction(config, read_packing(cli.packing));
    } else {
      std::optional<SphereList> spheres;
      if (!cli.packing.empty()) spheres = read_spheres(cli.packing);
      prepared = prepare_compaction(config, spheres);
    }
    if (!cli.packing.empty()) meta.input("packing", cli.packing);
    if (config.clumps && !config.clumps->templates.empty())
      meta.input("templates", config.clumps->templates);
  }
  Engine& engine = *prepared.engine;
  // Where the punch starts when [box] leaves it to the packing: the effective config states it.
  if (std::isnan(config.punch)) config.punch = engine.walls()[prepared.setup.punch_wall].position;
  spdlog::info(
      "compact: {} spheres ({} rigid clumps), time step {:.3g} s ({:.3g} of the Rayleigh time, "
      "{:.0f} steps per Hertz collision)",
      engine.state().size(), engine.clumps().size(), prepared.time_step.time_step,
      prepared.time_step.time_step / prepared.time_step.rayleigh_time,
      prepared.time_step.collision_time / prepared.time_step.time_step);

  const std::filesystem::path out(cli.out);
  std::filesystem::create_directories(out / "snapshots");
  // What the run used, every key with its value (defaults and --steps included).
  write_file_atomically(
      out / "effective.toml",
      fmt::format("# {}\n# the effective config of this compact run\n", context.command_line) +
          compact_config_toml(config));
  const Provenance provenance{
      context.command_line, root.text(),
      config.generate ? std::optional(config.generate->seed) : std::nullopt};
  CsvWriter csv(out / "punch.csv",
                {"time_s", "step", "gap_m", "strain", "top_force_N", "bottom_force_N", "stress_Pa",
                 "solid_fraction", "phase", "kinetic_energy_J", "contacts", "wall_contacts",
                 "contacts_per_particle", "intact_bonds", "solid_fraction_spheres",
                 "punch_work_J"});
  const CompactionSetup& setup = prepared.setup;
  csv.comment(fmt::format("shapepress compact; strain from H0 = {:.10g} m; die area {:.10g} m^2",
                          prepared.punch.reference_gap, setup.die_area));
  csv.comment(setup.strain_from_fill
                  ? "H0 is the loose fill height (generate.height, punch.strain_reference = fill)"
                  : "H0 is the gap when loading starts (punch.strain_reference = start)");
  csv.comment(fmt::format("solid volume {:.10g} m^3; solid fraction ceiling {} at gap {:.10g} m",
                          setup.solid_volume, setup.max_solid_fraction, *setup.program.min_gap));
  if (setup.sphere_volume != setup.solid_volume)
    csv.comment(fmt::format(
        "solid_fraction is by the bodies' shape volume {:.10g} m^3; solid_fraction_spheres by "
        "their sub-spheres' {:.10g} m^3 ({:.4g} of it)",
        setup.solid_volume, setup.sphere_volume, setup.sphere_volume / setup.solid_volume));
  if (config.density_scale != 1.0)
    csv.comment(fmt::format("mass scaling: particle density x {} (run.density_scale)",
                            config.density_scale));
  if (setup.ceiling_limits_load)
    csv.comment(fmt::format(
        "loading stops at the solid fraction ceiling {} (gap {:.10g} m, strain {:.6g}) before "
        "the target gap {:.10g} m",
        setup.max_solid_fraction, *setup.program.min_gap,
        1.0 - *setup.program.min_gap / prepared.punch.reference_gap, *setup.program.target_gap));
  csv.comment("phase: 0 load, 1 hold, 2 unload, 3 done");
  std::vector<SnapshotIndexEntry> index;
  CompactionHooks hooks;
  hooks.record = [&](const PunchRecord& r) {
    csv.row({r.time, static_cast<double>(r.step), r.gap, r.strain, r.top_force, r.bottom_force,
             r.stress, r.solid_fraction, static_cast<double>(r.phase), r.kinetic_energy,
             static_cast<double>(r.sphere_contacts), static_cast<double>(r.wall_contacts),
             r.contacts_per_particle, static_cast<double>(r.intact_bonds),
             r.solid_fraction_spheres, r.punch_work});
  };
  hooks.snapshot = [&](const Engine& e, const PunchState& punch) {
    const std::string name = fmt::format("step_{:010d}.h5", e.step_index());
    write_snapshot(out / "snapshots" / name, e, compaction_scenario_state(punch, setup),
                   provenance);
    index.push_back({std::filesystem::path("snapshots") / name, e.time(), e.state().size(),
                     e.walls().size(), e.computes_particle_stress(), e.bonds().size(),
                     e.clumps().size()});
    write_xdmf(out / "snapshots.xdmf", index);
  };
  const double total =
      config.setup.max_steps > 0 ? static_cast<double>(config.setup.max_steps) : 0.0;
  ProgressReporter progress("compact", total, {.quiet = context.quiet});
  if (total > 0)
    hooks.progress = [&](std::int64_t step) { progress.update(static_cast<double>(step)); };
  const double h0 = prepared.punch.reference_gap;
  const CompactionSummary summary = run_compaction(engine, prepared.setup, prepared.punch, hooks);
  progress.finish();
  const QuasiStaticCheck& qs = summary.quasi_static;
  if (qs.records > 0 && !qs.quasi_static())
    spdlog::warn(
        "compact: the run was not quasi-static: kinetic energy up to {:.3g} of the punch's work "
        "(limit {}), top and bottom forces {:.3g} apart on average (limit {}); slow the punch, "
        "or lower run.density_scale",
        qs.max_kinetic_to_work, QuasiStaticCheck::max_kinetic_energy_ratio,
        qs.mean_force_imbalance, QuasiStaticCheck::max_mean_force_imbalance);
  csv.commit();
  meta.output("punch.csv");
  if (!index.empty()) meta.output("snapshots.xdmf");
  add_compaction_facts(meta, config, setup, prepared.punch.reference_gap, prepared.time_step,
                       engine, summary);
  meta.write(out / run_metadata_name);
  const PunchRecord& last = summary.last;
  // One machine-readable line for scripts (tests/bench/hertz-compaction/run.sh).
  std::printf(
      "SUMMARY steps=%lld loop_s=%.6g particle_steps_per_s=%.6g punch_force_N=%.6g "
      "bottom_force_N=%.6g max_stress_Pa=%.6g contacts_per_particle=%.6g kinetic_energy_J=%.6g "
      "list_builds=%lld h0_m=%.10g\n",
      static_cast<long long>(summary.steps), summary.loop_seconds,
      summary.loop_seconds > 0 ? static_cast<double>(engine.state().size()) *
                                     static_cast<double>(summary.steps) / summary.loop_seconds
                               : 0.0,
      last.top_force, last.bottom_force, summary.max_stress, last.contacts_per_particle,
      last.kinetic_energy, static_cast<long long>(engine.list_builds()), h0);
  return 0;
}

}  // namespace

StageOptions compact_options() {
  return compact_config_options();
}

StageRunner setup_compact_cli(CLI::App& app) {
  auto cli = std::make_shared<CompactCli>();
  app.add_option("--config", cli->config, "compact config TOML (materials, box, punch, run)")
      ->required();
  auto* packing =
      app.add_option("--packing", cli->packing,
                     "spheres: 'x y z r' text (m) or HDF5 /particles/{position,radius}; "
                     "without it the config's [generate] makes a bed");
  app.add_option("--restart", cli->restart, "continue from a snapshot written by compact")
      ->excludes(packing);
  app.add_option("--steps", cli->steps, "stop at this total step count (overrides run.steps)");
  app.add_option("--out", cli->out,
                 "output folder (punch.csv, snapshots/, snapshots.xdmf, effective.toml)")
      ->required();
  return [cli](const RunContext& context) { return run(*cli, context); };
}

}  // namespace shapepress::scenarios

#include "scenarios/advise_bed_size.hpp"

#include <cmath>
#include <filesystem>
#include <set>
#include <tuple>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "analysis/bed_size.hpp"
#include "analysis/compaction.hpp"
#include "analysis/runs.hpp"
#include "common/atomic_file.hpp"
#include "common/error.hpp"
#include "common/run_metadata.hpp"
#include "scenarios/advise_runs.hpp"

namespace shapepress::scenarios {
namespace {

namespace fs = std::filesystem;

analysis::BedRun read_bed_run(const fs::path& folder) {
  const RunRecord run = RunRecord::read(folder / run_metadata_name, "compact");
  const fs::path packing = run.input_file("packing");
  const RunRecord pack = RunRecord::read(run_metadata_beside(packing), "pack");
  analysis::BedRun bed;
  bed.label = folder.string();
  bed.bodies = static_cast<int>(pack.integer("bodies"));
  const std::int64_t sub_spheres = pack.integer("sub_spheres");
  if (bed.bodies < 1 || sub_spheres % bed.bodies != 0)
    throw InputError(fmt::format("{}: {} sub-spheres in {} bodies: not one count per body",
                                 pack.path().string(), sub_spheres, bed.bodies));
  bed.sub_spheres = static_cast<int>(sub_spheres / bed.bodies);
  bed.seed = static_cast<std::uint64_t>(pack.integer("seed"));
  if (pack.has("bed_height_m") && pack.has("x50_m"))
    bed.bed_height_diameters = pack.number("bed_height_m") / pack.number("x50_m");
  bed.counted_cost = counted_cost(folder, "compact");
  const analysis::CompactionMetrics m =
      analysis::analyse_compaction(analysis::read_punch_curve(folder / "punch.csv"));
  bed.peak_stress = m.peak_stress;
  bed.elastic_recovery = m.elastic_recovery;
  bed.yield_pressure = m.heckel.yield_pressure;
  return bed;
}

void draw(const analysis::Chart& chart, const fs::path& stem, RunMetadata& meta) {
  if (analysis::find_gnuplot().empty()) return;
  analysis::plot_chart(chart, stem);
  meta.output(stem.filename().string() + ".svg");
}

}  // namespace

int run_bed_size_advise(const BedSizeAdviseRequest& request, const RunContext& context) {
  RunMetadata meta("advise", context.command_line);
  std::vector<analysis::BedRun> ladder;
  std::set<std::tuple<int, int, std::uint64_t>> packings;
  for (const std::string& folder : request.runs) {
    ladder.push_back(read_bed_run(folder));
    const analysis::BedRun& run = ladder.back();
    // Two compactions of one (bodies, N, seed) are one packing counted twice: its scatter would
    // be too small and its weight too large.
    if (!packings.insert({run.bodies, run.sub_spheres, run.seed}).second)
      throw InputError(fmt::format(
          "{}: a second run of {} bodies of {} sub-spheres with seed {}: one run per packing",
          folder, run.bodies, run.sub_spheres, run.seed));
    meta.input("run", (fs::path(folder) / "punch.csv").string());
  }
  const analysis::BedSizeAdvice advice = analysis::advise_bed_size(ladder, request.tolerance);
  const fs::path out(request.out);
  ensure_output_folder(out);
  analysis::write_bed_size_csv(out / "bed_size.csv", advice);
  meta.output("bed_size.csv");
  for (analysis::BedFigure f : analysis::bed_figures)
    draw(analysis::bed_size_chart(advice, f), out / fmt::format("bed_size_{}", figure_name(f)),
         meta);
  draw(analysis::bed_speed_accuracy_chart(advice), out / "bed_speed_accuracy", meta);
  const analysis::BedSetting& reference = advice.settings[advice.reference];
  meta.fact("tolerance", request.tolerance)
      .fact("runs", static_cast<int>(ladder.size()))
      .fact("reference_bodies", reference.bodies)
      .fact("reference_sub_spheres", reference.sub_spheres)
      .fact("reference_seeds", static_cast<int>(reference.runs.size()));
  if (!advice.pick) {
    meta.write(out / run_metadata_name);
    throw ComputationError(fmt::format(
        "advise: no bed size within {:.3g} of the reference ({} bodies of {} sub-spheres): "
        "bed_size.csv has each setting's bias",
        request.tolerance, reference.bodies, reference.sub_spheres));
  }
  const analysis::BedSetting& pick = advice.settings[*advice.pick];
  meta.fact("pick_bodies", pick.bodies)
      .fact("pick_sub_spheres", pick.sub_spheres)
      .fact("pick_seeds_needed", pick.seeds_needed)
      .fact("pick_bias", pick.bias)
      .fact("pick_bias_standard_error", pick.bias_standard_error)
      .fact("pick_resolved", pick.resolved)
      .fact("pick_scatter", pick.scatter);
  if (pick.predicted_cost >= 0.0)
    meta.fact("pick_counted_cost_per_run", pick.cost_per_run)
        .fact("predicted_counted_cost", pick.predicted_cost);
  meta.write(out / run_metadata_name);
  spdlog::info(
      "advise: {} bodies of {} sub-spheres with {} seeds, {:.2g} % from the reference ({} "
      "bodies of {}) ± {:.2g} %{}, scatter {:.2g} % per packing; predicted counted cost {:.3g}",
      pick.bodies, pick.sub_spheres, pick.seeds_needed, 100.0 * pick.bias, reference.bodies,
      reference.sub_spheres, 100.0 * pick.bias_standard_error,
      pick.resolved ? "" : " (not resolved by the seeds run: run more to tell)",
      100.0 * pick.scatter, pick.predicted_cost);
  return 0;
}

}  // namespace shapepress::scenarios

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <filesystem>
#include <memory>

#include "common/csv.hpp"
#include "common/run_metadata.hpp"
#include "geometry/cli.hpp"
#include "geometry/cli_mesh_input.hpp"
#include "geometry/descriptors.hpp"

namespace shapepress::geometry {
namespace {

struct DescribeCli {
  std::vector<std::string> meshes;
  std::string mesh_unit = "1 m";
  int directions = 64;
  std::uint64_t seed = 1;
  std::string out;
};

int run(const DescribeCli& cli, const RunContext& context) {
  // With --out, a run.json beside the CSV (describe --out is a file, not a folder).
  RunMetadata meta("describe", context.command_line);
  std::unique_ptr<CsvWriter> csv;
  if (!cli.out.empty()) {
    std::vector<std::string> header = {"mesh"};
    header.insert(header.end(), descriptor_scalar_names.begin(), descriptor_scalar_names.end());
    csv = std::make_unique<CsvWriter>(cli.out, header);
    csv->comment(
        "shapepress describe: L >= I >= S from the minimum oriented bounding box; "
        "asr = S/L, elongation = I/L, flatness = S/I (Giannis et al. 2023 Eqs. 8-9)");
    csv->comment(
        fmt::format("projected_asr: Feret min / Feret max of silhouettes in {} random "
                    "directions (seed {}); convexity = V / V(convex hull)",
                    cli.directions, cli.seed));
  }
  fmt::print("{:<32} {:>10} {:>10} {:>10} {:>6} {:>6} {:>6} {:>6} {:>6} {:>8}\n", "mesh", "L_m",
             "I_m", "S_m", "ASR", "I/L", "S/I", "psi", "conv", "projASR");
  for (const std::string& path : cli.meshes) {
    const ShapeDescriptors d =
        describe(load_checked_mesh(path, cli.mesh_unit), {cli.directions, cli.seed});
    if (csv) meta.input("mesh", path);
    fmt::print(
        "{:<32} {:>10.4g} {:>10.4g} {:>10.4g} {:>6.3f} {:>6.3f} {:>6.3f} {:>6.3f} {:>6.3f} "
        "{:>8.3f}\n",
        path, d.L_m, d.I_m, d.S_m, d.asr, d.elongation, d.flatness, d.sphericity, d.convexity,
        d.projected_asr_mean);
    if (csv) {
      ShapeDescriptors scalars = d;
      std::vector<std::string> cells = {path};
      for (const double* value : descriptor_scalars(scalars))
        cells.push_back(format_number(*value));
      csv->row_text(cells);
    }
  }
  if (csv) {
    csv->commit();
    meta.output(std::filesystem::path(cli.out).filename())
        .fact("meshes", cli.meshes.size())
        .fact("mesh_unit", cli.mesh_unit)
        .fact("directions", cli.directions)
        .fact("seed", cli.seed)
        .write(run_metadata_beside(cli.out));
  }
  return 0;
}

}  // namespace

StageRunner setup_describe_cli(CLI::App& app) {
  auto cli = std::make_shared<DescribeCli>();
  app.add_option("meshes", cli->meshes, "closed meshes (.stl binary/ASCII, .off, .ply)")
      ->required();
  app.add_option("--mesh-unit", cli->mesh_unit, "length of one mesh coordinate unit (1mm, 1um)")
      ->capture_default_str();
  app.add_option("--directions", cli->directions, "random views for the projected ASR")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  app.add_option("--seed", cli->seed, "seed of the views and of the bounding-box search")
      ->capture_default_str();
  app.add_option("--out", cli->out, "also write the descriptors to this CSV");
  return [cli](const RunContext& context) { return run(*cli, context); };
}

}  // namespace shapepress::geometry

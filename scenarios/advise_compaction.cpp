// shapepress advise on a compaction config. A rung is a sub-sphere count N, a time-step fraction
// and a mass scaling; its bed is bed-<N>/: the templates re-filled at N by `fill` with the
// options the given templates were made with (their run.json), packed by `pack` with the pack
// config, the reduced body count and one seed, so every N presses the same bodies. Beds and
// rungs are shapepress processes of their own (advise_runs.hpp), each on one thread, side by side.
#include "scenarios/advise_compaction.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <optional>

#include <omp.h>

#include "analysis/advise.hpp"
#include "analysis/compaction.hpp"
#include "analysis/runs.hpp"
#include "common/atomic_file.hpp"
#include "common/config.hpp"
#include "common/error.hpp"
#include "common/job_pool.hpp"
#include "common/run_metadata.hpp"
#include "common/sha256.hpp"
#include "scenarios/advise_runs.hpp"
#include "scenarios/config_io.hpp"

namespace shapepress::scenarios {
namespace {

namespace fs = std::filesystem;

// How the given templates were filled: their meshes and fill's options, from their run.json.
struct FillRecipe {
  std::string kind;                  // bms or cms
  std::vector<std::string> meshes;   // and --sphere R, --ellipsoid a,b,c as fill was given them
  std::vector<std::string> options;  // fill's options besides the meshes, --count and --out
  // The shapes themselves: each mesh's SHA-256 when filled, and the analytic shapes' sizes.
  std::vector<std::string> shapes;
  int count = 0;  // the sub-spheres these templates were filled with (0: not stated)
};

// A recorded mesh path as given to fill: relative to where fill ran (unknown), so it is taken
// as it is when it exists, else relative to the templates' folder.
std::string locate_mesh(const std::string& recorded, const fs::path& templates) {
  if (fs::exists(recorded)) return fs::absolute(recorded).string();
  const fs::path beside = templates.parent_path() / fs::path(recorded).filename();
  if (fs::exists(beside)) return fs::absolute(beside).string();
  throw InputError(
      fmt::format("{}: its mesh {} is neither there nor beside it: advise re-fills "
                  "the meshes",
                  templates.string(), recorded));
}

FillRecipe fill_recipe(const fs::path& templates) {
  const RunRecord record = RunRecord::read(run_metadata_beside(templates), "fill");
  FillRecipe recipe;
  recipe.kind = record.text("particle_kind");
  if (record.has("requested_count"))
    recipe.count = static_cast<int>(record.integer("requested_count"));
  for (const auto& input : record.json().at("inputs"))
    if (input.value("role", "") == "mesh") {
      recipe.meshes.push_back(locate_mesh(input.at("path").get<std::string>(), templates));
      recipe.shapes.push_back(input.value("sha256", ""));
    }
  for (const char* shape : {"sphere", "ellipsoid"})
    if (record.has(shape)) {
      recipe.meshes.insert(recipe.meshes.end(), {std::string("--") + shape, record.text(shape)});
      recipe.shapes.push_back(fmt::format("{} {}", shape, record.text(shape)));
    }
  if (recipe.meshes.empty())
    throw InputError(
        fmt::format("{}: its run.json names no mesh or analytic shape to re-fill "
                    "(a fill from before advise could re-fill analytic shapes: "
                    "fill them again)",
                    record.path().string()));
  recipe.options = {"--kind",       recipe.kind,
                    "--resolution", std::to_string(record.integer("resolution")),
                    "--mesh-unit",  record.text("mesh_unit"),
                    "--seed",       std::to_string(record.integer("seed"))};
  if (record.has("sub_sphere_radius_m"))
    throw InputError(
        fmt::format("{}: filled at a fixed sub-sphere radius (--radius), not a count: "
                    "advise varies the count",
                    record.path().string()));
  if (recipe.kind == "bms")
    recipe.options.insert(
        recipe.options.end(),
        {"--lattice", record.text("lattice"), "--placement", record.text("placement"),
         "--bond-multiplier", fmt::format("{:.17g}", record.number("bond_multiplier"))});
  return recipe;
}

struct BedJob {
  int count = 0;  // 1: plain spheres of the same sizes, packed without templates
  std::optional<std::uint64_t> seed;  // empty: the pack config's
  fs::path folder;
  nlohmann::json key;
};

struct RungJob {
  std::string label;
  std::size_t bed = 0;  // index into the beds
  double fraction = 0.0, density_scale = 1.0;
  fs::path folder;
  nlohmann::json key;
};

std::string number_text(double f) {
  return fmt::format("{:.4g}", f);
}

// Fills and packs one bed; its record says how that ended (a bed that failed fails its rungs).
nlohmann::json make_bed(const BedJob& bed, const FillRecipe& recipe,
                        const CompactionAdviseRequest& request, int bodies) {
  ensure_output_folder(bed.folder);
  const std::string binary = this_binary();
  nlohmann::json record = {{"key", bed.key}};
  ChildEnd end;
  if (bed.count > 1) {
    std::vector<std::string> fill = {binary, "--quiet", "fill"};
    fill.insert(fill.end(), recipe.meshes.begin(), recipe.meshes.end());
    fill.insert(fill.end(), recipe.options.begin(), recipe.options.end());
    fill.insert(fill.end(), {"--count", std::to_string(bed.count), "--out",
                             (bed.folder / "templates.h5").string()});
    end = run_process(fill, bed.folder / "fill.log");
    record["fill_cpu_s"] = end.cpu_seconds;
    if (end.exit_code != 0)
      record["message"] = "fill: " + error_line(bed.folder / "fill.log", "fill");
  }
  if (end.exit_code == 0) {
    std::vector<std::string> pack = {binary, "--quiet", "--threads", "1", "pack"};
    // One sub-sphere: plain spheres of the same draw of sizes (the cheapest point of a ladder).
    if (bed.count > 1)
      pack.push_back((bed.folder / "templates.h5").string());
    else
      pack.insert(pack.end(), {"--template", "sphere"});
    pack.insert(pack.end(), {"--config", fs::absolute(request.pack_config).string(), "--count",
                             std::to_string(bodies), "--out", (bed.folder / "packed.h5").string()});
    if (bed.seed) pack.insert(pack.end(), {"--seed", std::to_string(*bed.seed)});
    end = run_process(pack, bed.folder / "pack.log");
    record["pack_cpu_s"] = end.cpu_seconds;
    if (end.exit_code != 0)
      record["message"] = "pack: " + error_line(bed.folder / "pack.log", "pack");
  }
  record["exit_code"] = end.exit_code;
  write_file_atomically(bed.folder / "bed.json", record.dump(1) + "\n");
  return record;
}

// The rung's compact config: the given one at the rung's step and mass scaling, without
// snapshots (a rung is judged on punch.csv).
void write_rung_config(const RungJob& job, CompactConfig config) {
  config.run.time_step_fraction = job.fraction;
  config.density_scale = job.density_scale;
  config.setup.snapshot_every = 0;
  write_file_atomically(job.folder / "compact.toml", compact_config_toml(config));
}

nlohmann::json press(const RungJob& job, const BedJob& bed, const CompactConfig& config) {
  ensure_output_folder(job.folder);
  write_rung_config(job, config);
  const ChildEnd end =
      run_process({this_binary(), "--quiet", "--threads", "1", "compact", "--config",
                   (job.folder / "compact.toml").string(), "--packing",
                   (bed.folder / "packed.h5").string(), "--out", job.folder.string()},
                  job.folder / "log.txt");
  nlohmann::json record = {
      {"key", job.key}, {"exit_code", end.exit_code}, {"cpu_s", end.cpu_seconds}};
  if (end.exit_code != 0) record["message"] = error_line(job.folder / "log.txt", "compact");
  if (end.exit_code != 0 && end.exit_code != 1 && end.exit_code != 2)
    throw ComputationError(fmt::format("advise: rung {} ended with {} (log: {})", job.label,
                                       end.how(), (job.folder / "log.txt").string()));
  write_file_atomically(job.folder / "rung.json", record.dump(1) + "\n");
  return record;
}

void read_pressed_curve(analysis::Rung& rung, const fs::path& punch_csv, bool solid_fraction_axis);

// The rung as it ended: its loading stress against strain (or the solid fraction by shape
// volume: beds that settled to different densities compared where they are equally dense), its
// peak, recovery and Py, or the
// named cause of its end (its bed's, when the bed could not be made).
analysis::Rung load_rung(const RungJob& job, const BedJob& bed, const nlohmann::json& bed_record,
                         const std::optional<nlohmann::json>& record, bool solid_fraction_axis) {
  analysis::Rung rung;
  rung.label = job.label;
  rung.sub_spheres = bed.count;
  rung.time_step_fraction = job.fraction;
  rung.density_scale = job.density_scale;
  rung.seed = bed.seed ? static_cast<int>(*bed.seed) : 0;
  if (bed_record.at("exit_code").get<int>() != 0) {
    rung.end = analysis::RunEnd::refused;
    rung.cause = "bed";
    rung.message = bed_record.value("message", "");
    return rung;
  }
  const int code = record->at("exit_code").get<int>();
  rung.cpu_seconds = record->at("cpu_s").get<double>();
  if (code != 0) {
    rung.end = code == 1 ? analysis::RunEnd::diverged : analysis::RunEnd::refused;
    rung.message = record->value("message", "");
    rung.cause = code == 1 ? divergence_cause(rung.message) : "refused";
    return rung;
  }
  read_pressed_curve(rung, job.folder / "punch.csv", solid_fraction_axis);
  rung.counted_cost = counted_cost(job.folder, "compact");
  return rung;
}

// A finished compaction's punch.csv as a rung: its loading curve and figures (a non-finite
// stress makes it diverged).
void read_pressed_curve(analysis::Rung& rung, const fs::path& punch_csv, bool solid_fraction_axis) {
  const analysis::PunchCurve punch = analysis::read_punch_curve(punch_csv);
  // compact checks for divergence every run.check_every steps; a short run can end between
  // two checks, and a curve with a non-finite stress is a diverged run, never one to compare.
  if (!std::all_of(punch.stress.begin(), punch.stress.end(),
                   [](double s) { return std::isfinite(s); })) {
    rung.end = analysis::RunEnd::diverged;
    rung.cause = "non-finite";
    rung.message = punch_csv.string() + " holds a non-finite stress";
    return;
  }
  rung.curve.label = rung.label;
  for (std::size_t i : analysis::loading_rows(punch)) {
    const double x = solid_fraction_axis
                         ? punch.solid_fraction[i]
                         : (punch.reference_gap - punch.gap[i]) / punch.reference_gap;
    if (rung.curve.x.empty() || x > rung.curve.x.back()) {
      rung.curve.x.push_back(x);
      rung.curve.y.push_back(punch.stress[i]);
    }
  }
  analysis::CompactionMetrics m;
  try {
    m = analysis::analyse_compaction(punch);
  } catch (const ComputationError& e) {
    throw ComputationError(fmt::format("advise: rung {}: {} (record more often: run.record_every)",
                                       rung.label, e.what()));
  }
  rung.compaction =
      analysis::CompactionFigures{m.peak_stress, m.elastic_recovery, m.heckel.yield_pressure};
}

int pack_count(const fs::path& pack_config) {
  const ConfigTable root = ConfigTable::load_file(pack_config);
  const std::int64_t count = root.has("pack") ? root.table("pack").integer("count", 0) : 0;
  if (count <= 0)
    throw InputError(
        fmt::format("{}: no pack.count (a target_mass bed): give --bodies and "
                    "--full-bodies",
                    pack_config.string()));
  return static_cast<int>(count);
}

// A compaction made outside the ladder (--reference-run), such as the full study's at a count
// the ladder cannot afford, taken as a rung of it. It must press one of the ladder's beds at
// another count: templates filled from the same shapes with the same options, packed by the same
// pack config into as many bodies with a seed of the ladder (the pack's effective config equals
// that of a ladder's bed), and pressed by the same compact config but for the step, the mass
// scaling, the snapshots and checkpoints.
struct GivenRun {
  fs::path folder;
  int count = 0;            // the sub-spheres asked of its fill
  std::string pack_config;  // its pack's effective config
  double fraction = 0.0, density_scale = 1.0;
  std::optional<double> loop_seconds;  // its loop's wall seconds, when compact stated them
};

GivenRun read_given_run(const fs::path& folder, const FillRecipe& recipe, int bodies) {
  const RunRecord run = RunRecord::read(folder / run_metadata_name, "compact");
  GivenRun given;
  given.folder = folder;
  const fs::path packing = run.input_file("packing");
  const RunRecord pack = RunRecord::read(run_metadata_beside(packing), "pack");
  if (pack.integer("bodies") != bodies)
    throw InputError(fmt::format("{}: {} bodies, against the ladder's {} (--bodies)",
                                 pack.path().string(), pack.integer("bodies"), bodies));
  given.pack_config = pack.text("effective_config");
  const fs::path templates = pack.input_file("templates");
  const FillRecipe filled = fill_recipe(templates);
  if (filled.kind != recipe.kind || filled.options != recipe.options ||
      filled.shapes != recipe.shapes)
    throw InputError(fmt::format(
        "{}: filled from other shapes or with other options than the ladder's templates "
        "(fill {} against {})",
        templates.string(), fmt::join(filled.options, " "), fmt::join(recipe.options, " ")));
  given.count = filled.count;
  if (given.count == 0)
    throw InputError(
        fmt::format("{}: no requested_count (a fill from before fill stated it: fill again)",
                    run_metadata_beside(templates).string()));
  const ConfigTable effective = ConfigTable::load_file(folder / "effective.toml");
  given.fraction = effective.table("run").number("time_step_fraction");
  given.density_scale = effective.table("run").number("density_scale", 1.0);
  if (run.has("loop_s")) given.loop_seconds = run.number("loop_s");
  if (!fs::exists(folder / "punch.csv"))
    throw InputError(
        fmt::format("{}: no punch.csv (an unfinished run: resume it first)", folder.string()));
  return given;
}

// A compact run's effective config without its comments and what a ladder varies: the step, the
// mass scaling, snapshots and checkpoints, and the punch's start (its bed's height).
std::vector<std::string> pressing_lines(const fs::path& effective) {
  std::ifstream in(effective);
  if (!in) throw InputError(effective.string() + ": missing (not a compact run's folder)");
  std::vector<std::string> lines;
  std::string table;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    if (line[0] == '[') table = line;
    const std::string key = line.substr(0, line.find(" ="));
    const bool varied =
        (table == "[run]" &&
         (key == "time_step_fraction" || key == "density_scale" || key == "snapshot_every" ||
          key == "checkpoint_every" || key == "checkpoint_minutes")) ||
        (table == "[box]" && key == "punch");
    if (!varied) lines.push_back(line);
  }
  return lines;
}

// The compact config a ladder varies: the given one, checked to be a compaction of a packed bed
// at a step fraction (each rung sets its own).
CompactConfig read_ladder_config(const CompactionAdviseRequest& request, RunMetadata& meta) {
  if (request.pack_config.empty())
    throw InputError("advise --templates needs --pack-config (the bed's pack config)");
  const ConfigTable root = ConfigTable::load_file(request.config);
  meta.input("config", request.config)
      .input("templates", request.templates)
      .input("pack_config", request.pack_config);
  if (!root.has("punch"))
    throw InputError(request.config + ": advise --templates needs a compaction config ([punch])");
  const CompactConfig config = read_compact_config(root);
  root.check_unknown_keys();
  if (config.run.time_step)
    throw InputError(request.config +
                     ": advise varies run.time_step_fraction, but the config fixes run.time_step");
  if (config.generate || config.clumps)
    throw InputError(request.config +
                     ": advise presses the packed bed; [generate] and [clumps] pour another");
  return config;
}

// The settings every bed is pressed at: the step fractions and mass scalings (the config's when
// none are given).
struct PressSettings {
  std::vector<double> fractions, scales;
};

PressSettings press_settings(const CompactionAdviseRequest& request, const CompactConfig& config) {
  return {
      request.fractions.empty() ? std::vector{config.run.time_step_fraction} : request.fractions,
      request.density_scales.empty() ? std::vector{config.density_scale} : request.density_scales};
}

// The --reference-run folders, each refused when the ladder runs its setting itself.
std::vector<GivenRun> read_given_runs(const CompactionAdviseRequest& request,
                                      const FillRecipe& recipe, int bodies,
                                      const PressSettings& settings, RunMetadata& meta) {
  const auto in_ladder = [](const auto& values, auto value) {
    return std::find(values.begin(), values.end(), value) != values.end();
  };
  std::vector<GivenRun> given_runs;
  for (const std::string& folder : request.reference_runs) {
    given_runs.push_back(read_given_run(folder, recipe, bodies));
    const GivenRun& given = given_runs.back();
    // Refused before the ladder runs: its own rung of that setting would be the same run.
    if (in_ladder(request.counts, given.count) && in_ladder(settings.fractions, given.fraction) &&
        in_ladder(settings.scales, given.density_scale))
      throw InputError(fmt::format(
          "{}: the ladder runs its setting itself (N = {}, step {} of critical, density scale {})",
          folder, given.count, number_text(given.fraction), number_text(given.density_scale)));
    meta.input("reference_run", fs::path(folder) / "punch.csv");
  }
  return given_runs;
}

// The beds (one per count and seed) and the rungs pressed on them (one per step fraction and mass
// scaling), each with its folder in `out` and the key its record must hold to be reused.
struct LadderPlan {
  std::vector<std::optional<std::uint64_t>> seeds;  // one empty: the pack config's
  std::vector<BedJob> beds;
  std::vector<RungJob> rungs;
};

// A label's seed suffix: only when the ladder packs more than one seed.
std::string seed_text(const std::optional<std::uint64_t>& seed, std::size_t seeds) {
  return seeds > 1 ? fmt::format("-seed{}", *seed) : std::string();
}

LadderPlan plan_ladder(const CompactionAdviseRequest& request, const FillRecipe& recipe, int bodies,
                       const PressSettings& settings, const fs::path& out) {
  const nlohmann::json bed_key = {{"templates_sha256", sha256_file(request.templates)},
                                  {"pack_config_sha256", sha256_file(request.pack_config)},
                                  {"bodies", bodies}};
  LadderPlan plan;
  plan.seeds.assign(request.seeds.begin(), request.seeds.end());
  if (plan.seeds.empty()) plan.seeds.push_back(std::nullopt);  // the pack config's
  const std::size_t seeds = plan.seeds.size();
  for (const auto& seed : plan.seeds)
    for (int count : request.counts) {
      const std::string kind = count > 1 ? recipe.kind : "sphere";
      BedJob bed{count, seed, out / fmt::format("bed-{}{}", count, seed_text(seed, seeds)),
                 bed_key};
      bed.key["count"] = count;
      bed.key["seed"] = seed ? nlohmann::json(*seed) : nlohmann::json("pack config's");
      for (double fraction : settings.fractions)
        for (double scale : settings.scales) {
          RungJob job;
          job.label = fmt::format("{}-{}-f{}-s{}{}", kind, count, number_text(fraction),
                                  number_text(scale), seed_text(seed, seeds));
          job.bed = plan.beds.size();
          job.fraction = fraction;
          job.density_scale = scale;
          job.folder = out / job.label;
          job.key = bed.key;
          job.key["config_sha256"] = sha256_file(request.config);
          job.key["time_step_fraction"] = fraction;
          job.key["density_scale"] = scale;
          plan.rungs.push_back(std::move(job));
        }
      plan.beds.push_back(std::move(bed));
    }
  return plan;
}

// Every bed's record: reused when finished, else filled and packed now (one fill and one pack
// per count and seed, side by side).
struct BedRecords {
  std::vector<std::optional<nlohmann::json>> records;  // all set once made
  int made = 0;
};

bool bed_made(const nlohmann::json& bed_record) {
  return bed_record.at("exit_code").get<int>() == 0;
}

BedRecords make_beds(const LadderPlan& plan, const FillRecipe& recipe,
                     const CompactionAdviseRequest& request, int bodies, int threads) {
  const std::vector<BedJob>& beds = plan.beds;
  BedRecords made{std::vector<std::optional<nlohmann::json>>(beds.size()), 0};
  std::vector<std::size_t> beds_to_make;
  for (std::size_t k = 0; k < beds.size(); ++k) {
    made.records[k] = finished_record(beds[k].folder / "bed.json", beds[k].key, request.resume);
    if (!made.records[k]) beds_to_make.push_back(k);
  }
  std::mutex lock;
  run_jobs(beds_to_make.size(), threads, [&](std::size_t i) {
    const BedJob& bed = beds[beds_to_make[i]];
    nlohmann::json record = make_bed(bed, recipe, request, bodies);
    spdlog::info("advise: bed of {} sub-spheres per body {}", bed.count,
                 bed_made(record) ? "packed" : "failed: " + record.value("message", ""));
    const std::lock_guard guard(lock);
    made.records[beds_to_make[i]] = std::move(record);
  });
  made.made = static_cast<int>(beds_to_make.size());
  return made;
}

// Every rung's record: reused when finished, else pressed now on its bed (none on a bed that
// could not be made).
struct RungRecords {
  std::vector<std::optional<nlohmann::json>> records;
  int run_now = 0;
};

RungRecords press_rungs(const LadderPlan& plan, const BedRecords& beds, const CompactConfig& config,
                        const CompactionAdviseRequest& request, int bodies, int threads) {
  const std::vector<RungJob>& rungs = plan.rungs;
  RungRecords pressed{std::vector<std::optional<nlohmann::json>>(rungs.size()), 0};
  std::vector<std::size_t> pending;
  for (std::size_t k = 0; k < rungs.size(); ++k) {
    pressed.records[k] =
        finished_record(rungs[k].folder / "rung.json", rungs[k].key, request.resume);
    if (!pressed.records[k] && bed_made(*beds.records[rungs[k].bed])) pending.push_back(k);
  }
  spdlog::info("advise: {} rungs on {} beds of {} bodies, {} to run", rungs.size(),
               plan.beds.size(), bodies, pending.size());
  std::mutex lock;
  run_jobs(pending.size(), threads, [&](std::size_t i) {
    const RungJob& job = rungs[pending[i]];
    nlohmann::json record = press(job, plan.beds[job.bed], config);
    const int code = record.at("exit_code").get<int>();
    spdlog::info("advise: {} {}", job.label,
                 code == 0
                     ? "done"
                     : (code == 1 ? "diverged: " : "refused: ") + record.value("message", ""));
    const std::lock_guard guard(lock);
    pressed.records[pending[i]] = std::move(record);
  });
  pressed.run_now = static_cast<int>(pending.size());
  return pressed;
}

// A given run's bed among the ladder's: the one packed by the same effective pack config.
std::size_t bed_of_given(const GivenRun& given, const LadderPlan& plan, const BedRecords& beds,
                         const fs::path& out) {
  for (std::size_t k = 0; k < plan.beds.size(); ++k)
    if (plan.beds[k].count > 1 && bed_made(*beds.records[k]) &&
        RunRecord::read(run_metadata_beside(plan.beds[k].folder / "packed.h5"))
                .text("effective_config") == given.pack_config)
      return k;
  throw InputError(fmt::format(
      "{}: its bed was packed by another pack config or seed than every bed of the ladder "
      "({}/bed-*/packed.h5.run.json)",
      given.folder.string(), out.string()));
}

// InputError unless the given run was pressed by the config of a rung of its bed that ran, but
// for what a ladder varies.
void check_pressed_alike(const GivenRun& given, const LadderPlan& plan,
                         const std::optional<std::uint64_t>& seed) {
  std::optional<fs::path> pressed;  // a rung of that bed that ran, to compare configs with
  for (const RungJob& job : plan.rungs)
    if (!pressed && plan.beds[job.bed].seed == seed && fs::exists(job.folder / "effective.toml"))
      pressed = job.folder;
  if (!pressed)
    throw InputError(fmt::format("{}: no rung of its bed ran to compare its config with",
                                 given.folder.string()));
  const auto ours = pressing_lines(*pressed / "effective.toml");
  const auto theirs = pressing_lines(given.folder / "effective.toml");
  if (ours != theirs) {
    const auto [a, b] = std::mismatch(ours.begin(), ours.end(), theirs.begin(), theirs.end());
    throw InputError(fmt::format(
        "{}: pressed by another config than the ladder's ({}: \"{}\" against \"{}\")",
        (given.folder / "effective.toml").string(), (*pressed / "effective.toml").string(),
        b == theirs.end() ? "(end)" : *b, a == ours.end() ? "(end)" : *a));
  }
}

// A given run as a rung of the ladder, at its bed's seed.
analysis::Rung given_rung(const GivenRun& given, const LadderPlan& plan, const BedRecords& beds,
                          const FillRecipe& recipe, const CompactionAdviseRequest& request,
                          const fs::path& out) {
  const auto& seed = plan.beds[bed_of_given(given, plan, beds, out)].seed;
  check_pressed_alike(given, plan, seed);
  analysis::Rung rung;
  rung.label =
      fmt::format("given-{}-{}-f{}-s{}{}", recipe.kind, given.count, number_text(given.fraction),
                  number_text(given.density_scale), seed_text(seed, plan.seeds.size()));
  rung.sub_spheres = given.count;
  rung.time_step_fraction = given.fraction;
  rung.density_scale = given.density_scale;
  rung.seed = seed ? static_cast<int>(*seed) : 0;
  // Its counted cost is its run.json's, as a rung's; its CPU seconds are not advise's to know.
  rung.cpu_seconds = -1.0;
  rung.counted_cost = counted_cost(given.folder, "compact");
  read_pressed_curve(rung, given.folder / "punch.csv", request.curve_axis == "solid_fraction");
  return rung;
}

// The ladder as it ended: its rungs, then the given runs.
std::vector<analysis::Rung> load_ladder(const LadderPlan& plan, const BedRecords& beds,
                                        const RungRecords& pressed,
                                        const std::vector<GivenRun>& given_runs,
                                        const FillRecipe& recipe,
                                        const CompactionAdviseRequest& request, const fs::path& out,
                                        RunMetadata& meta) {
  std::vector<analysis::Rung> ladder;
  for (std::size_t k = 0; k < plan.rungs.size(); ++k) {
    const RungJob& job = plan.rungs[k];
    ladder.push_back(load_rung(job, plan.beds[job.bed], *beds.records[job.bed], pressed.records[k],
                               request.curve_axis == "solid_fraction"));
  }
  for (const GivenRun& given : given_runs) {
    analysis::Rung rung = given_rung(given, plan, beds, recipe, request, out);
    if (given.loop_seconds) meta.fact("reference_run_loop_s", *given.loop_seconds);
    ladder.push_back(std::move(rung));
  }
  return ladder;
}

// The sizes of the ladder: its reduced bed and the full one whose cost is predicted.
struct BedSizes {
  int bodies = 0, full_bodies = 0;
};

// The pick's facts in run.json (written here) and its line in the log: the full run at the pick's
// setting costs more as the bodies grow, and in the same die the bed's height, the punch's travel
// to the same strain and so the steps do too. The counted cost is scaled, and the CPU seconds
// measured beside it.
void report_pick(const analysis::Advice& advice, const std::vector<analysis::Rung>& ladder,
                 const CompactionAdviseRequest& request, BedSizes sizes, const fs::path& out,
                 RunMetadata& meta) {
  if (advice.seed_scatter) meta.fact("seed_scatter", *advice.seed_scatter);
  const analysis::Rung& pick = ladder[*advice.pick];
  const analysis::Rung& reference = ladder[*advice.reference];
  const double body_factor = static_cast<double>(sizes.full_bodies) / sizes.bodies;
  const double scale = body_factor * body_factor;
  meta.fact("reference", reference.label)
      .fact("pick", pick.label)
      .fact("pick_sub_spheres", pick.sub_spheres)
      .fact("pick_time_step_fraction", pick.time_step_fraction)
      .fact("pick_density_scale", pick.density_scale)
      .fact("pick_error_vs_reference", advice.rows[*advice.pick].error)
      .fact("cost_scaling", "counted_cost (and cpu_s) x (full_bodies / bodies)^2");
  const auto costs = [&](const analysis::Rung& rung, const char* name, const char* predicted) {
    if (rung.counted_cost >= 0)
      meta.fact(fmt::format("{}_counted_cost", name), rung.counted_cost)
          .fact(fmt::format("{}_counted_cost", predicted),
                static_cast<double>(rung.counted_cost) * scale);
    // A given run's CPU seconds are not advise's to know (its loop's wall seconds are stated
    // when compact stated them).
    if (rung.cpu_seconds >= 0.0)
      meta.fact(fmt::format("{}_cpu_s", name), rung.cpu_seconds)
          .fact(fmt::format("{}_cpu_s", predicted), rung.cpu_seconds * scale);
  };
  costs(reference, "reference", "predicted_full_reference");
  costs(pick, "pick", "predicted_full_run");
  if (reference.counted_cost >= 0 && pick.counted_cost > 0)
    meta.fact("cost_saved_factor",
              static_cast<double>(reference.counted_cost) / static_cast<double>(pick.counted_cost));
  if (reference.cpu_seconds >= 0.0 && pick.cpu_seconds > 0.0)
    meta.fact("cpu_saved_factor", reference.cpu_seconds / pick.cpu_seconds);
  meta.write(out / run_metadata_name);
  if (pick.cpu_seconds < 0.0) {
    spdlog::info("advise: no rung of the ladder within {:.2g} % of the given run {}: its setting",
                 100.0 * request.tolerance, reference.label);
    return;
  }
  spdlog::info(
      "advise: pick {} ({} sub-spheres per body, step {} of critical, density scale {}): {:.2g} % "
      "from {} (largest of curve RMS, peak, recovery, Py), counted cost {} ({:.3g} s CPU){} on {} "
      "bodies; {} bodies predicted at {:.3g} ({:.3g} s CPU)",
      pick.label, pick.sub_spheres, number_text(pick.time_step_fraction),
      number_text(pick.density_scale), 100.0 * advice.rows[*advice.pick].error, reference.label,
      pick.counted_cost, pick.cpu_seconds,
      reference.counted_cost >= 0 && pick.counted_cost > 0
          ? fmt::format(" against {} ({:.3g}x less)", reference.counted_cost,
                        static_cast<double>(reference.counted_cost) /
                            static_cast<double>(pick.counted_cost))
          : std::string(),
      sizes.bodies, sizes.full_bodies, static_cast<double>(pick.counted_cost) * scale,
      pick.cpu_seconds * scale);
}

}  // namespace

int run_compaction_advise(const CompactionAdviseRequest& request, const RunContext& context) {
  RunMetadata meta("advise", context.command_line);
  const CompactConfig config = read_ladder_config(request, meta);
  const FillRecipe recipe = fill_recipe(request.templates);
  const int bodies = request.bodies > 0 ? request.bodies : pack_count(request.pack_config);
  const int full_bodies =
      request.full_bodies > 0 ? request.full_bodies : pack_count(request.pack_config);
  const PressSettings settings = press_settings(request, config);
  const std::vector<GivenRun> given_runs = read_given_runs(request, recipe, bodies, settings, meta);
  // Absolute, so that every rung's run.json names its packing wherever it is read from (the
  // report follows a compaction to its bed).
  const fs::path out = fs::absolute(request.out);
  ensure_output_folder(out);

  const LadderPlan plan = plan_ladder(request, recipe, bodies, settings, out);
  const int threads = context.threads > 0 ? context.threads : omp_get_max_threads();
  // First the beds (one fill and one pack per count), then every rung on its bed.
  const BedRecords beds = make_beds(plan, recipe, request, bodies, threads);
  const RungRecords pressed = press_rungs(plan, beds, config, request, bodies, threads);
  const std::vector<analysis::Rung> ladder =
      load_ladder(plan, beds, pressed, given_runs, recipe, request, out, meta);

  const analysis::Advice advice = analysis::advise(ladder, request.tolerance, 0.0, 1.0);
  write_advice(advice, out, meta);
  const int rungs = static_cast<int>(plan.rungs.size());
  meta.fact("particle_kind", recipe.kind)
      .fact("tolerance", request.tolerance)
      .fact("bodies", bodies)
      .fact("full_bodies", full_bodies)
      .fact("rungs", rungs)
      .fact("rungs_run", pressed.run_now)
      .fact("rungs_reused", rungs - pressed.run_now)
      .fact("beds_made", beds.made)
      .fact("seeds", static_cast<int>(plan.seeds.size()))
      .fact("curve_axis", request.curve_axis)
      .fact("curve_from", advice.from)
      .fact("curve_to", advice.to);
  if (!advice.pick) {
    meta.write(out / run_metadata_name);
    throw ComputationError("advise: no rung finished, so none can be recommended (advice.csv)");
  }
  report_pick(advice, ladder, request, {bodies, full_bodies}, out, meta);
  return 0;
}

}  // namespace shapepress::scenarios

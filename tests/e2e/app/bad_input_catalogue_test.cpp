// The bad-input catalogue (issue 23): one table of what a user can get wrong, over every stage
// and every format a stage reads. Each row runs the binary as a user would and holds it to
// docs/architecture.md, "Exit codes and errors": the exit code (2 bad input or usage, 1 a failed
// computation), a message naming the file, key or value, and no file left under a final name
// (every output is atomic). The valid inputs the rows spoil are made once, by the stages.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/hdf5_file.hpp"
#include "common/run_lock.hpp"
#include "common/sha256.hpp"
#include "tests/support/command.hpp"
#include "tests/support/files.hpp"

namespace shapepress {
namespace {

using shapepress::testing::files_under;
using shapepress::testing::fresh_directory;
using shapepress::testing::read_text;
using shapepress::testing::run_command;
using shapepress::testing::run_shapepress;
using shapepress::testing::shell_quoted;
using shapepress::testing::test_data_text;
using shapepress::testing::write_text;
namespace fs = std::filesystem;

// The first `bytes` bytes of a file (negative: all but the last -bytes).
std::string head_of(const fs::path& file, long bytes) {
  const std::string text = read_text(file);
  const auto n =
      bytes >= 0 ? static_cast<std::size_t>(bytes) : text.size() - static_cast<std::size_t>(-bytes);
  return text.substr(0, std::min(n, text.size()));
}

// A copy of `file` with `count` bytes from `at` overwritten: a damaged file whose size is whole.
std::string scrambled(const fs::path& file, std::size_t at, std::size_t count) {
  std::string text = read_text(file);
  for (std::size_t k = at; k < std::min(at + count, text.size()); ++k)
    text[k] = static_cast<char>(text[k] ^ 0x5a);
  return text;
}

// A copy of the HDF5 file `file` with one bit flipped in the stored values of its dataset
// `dataset` (found by their bytes): a number off in its last digit, which only the dataset's
// checksum can tell from a true one.
std::string values_damaged(const fs::path& file, const std::string& dataset) {
  const std::vector<double> values = H5Reader(file).doubles(dataset);
  const std::string bytes(reinterpret_cast<const char*>(values.data()),
                          sizeof(double) * std::min<std::size_t>(values.size(), 4));
  std::string text = read_text(file);
  const auto at = text.find(bytes);
  if (at == std::string::npos)
    ADD_FAILURE() << dataset << "'s values are not stored as they are in " << file;
  else
    text[at] = static_cast<char>(text[at] ^ 0x01);
  return text;
}

// --- the valid inputs -------------------------------------------------------------------------

const std::string compact_base =
    test_data_text("scenarios/powder.toml") + test_data_text("scenarios/powder-die.toml") + R"(
[box]
x = "4 mm"
y = "4 mm"
punch = "12 mm"

[generate]
count = 30
diameter_min = "0.8 mm"
diameter_max = "1.2 mm"
seed = 3
settle_time = "2 ms"

[punch]
speed = "0.5 m/s"
target_strain = 0.05

[run]
steps = 400
snapshot_every = 200
)";

const std::string plate_base = test_data_text("scenarios/rubber.toml") + R"(
[sphere]
radius = "1 mm"
material = "rubber"

[plate]
material = "rubber"
speed = "5 mm/s"
max_deformation = 0.01
records = 10
)";

const std::string pack_base =
    "[pack]\ncount = 6\nseed = 3\nbox_x = 1.0e-3\nbox_y = 1.0e-3\n"
    "[[template]]\nname = \"cms/ellipsoid\"\n"
    "[sizes]\nsize_quantiles = [200e-6, 250e-6, 300e-6]\nsize_quantile_levels = [0.1, 0.5, 0.9]\n"
    "diameter_min = 200e-6\ndiameter_max = 300e-6\n[settle]\nkinetic_energy_ratio = 1e-3\n";

// A unit tetrahedron in each mesh format the stages read.
const std::string tetra_off =
    "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n"
    "3 1 2 3\n";
const std::string tetra_ply =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
    "property float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
const std::string tetra_stl =
    "solid t\nfacet normal 0 0 -1\nouter loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 1 0 0\nendloop\n"
    "endfacet\nfacet normal 0 -1 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 0 1\nendloop\n"
    "endfacet\nfacet normal -1 0 0\nouter loop\nvertex 0 0 0\nvertex 0 0 1\nvertex 0 1 0\nendloop\n"
    "endfacet\nfacet normal 1 1 1\nouter loop\nvertex 1 0 0\nvertex 0 1 0\nvertex 0 0 1\nendloop\n"
    "endfacet\nendsolid t\n";

// Made once for the whole table: a templates file, a packing, a snapshot, a compaction run.
class BadInputCatalogue : public ::testing::Test {
 protected:
  static fs::path valid() { return valid_; }

  static void SetUpTestSuite() {
    valid_ = fresh_directory("catalogue_valid");
    const fs::path v = valid();
    write_text(v / "compact.toml", compact_base);
    write_text(v / "plate.toml", plate_base);
    write_text(v / "pack.toml", pack_base);
    write_text(v / "tetra.off", tetra_off);
    for (const char* image : {"coins.png", "blobs.gif", "blobs16.tif"})
      fs::copy_file(fs::path(SHAPEPRESS_TEST_DATA) / "imaging" / image, v / image);
    fs::copy(fs::path(SHAPEPRESS_TEST_DATA) / "analysis" / "compaction_run", v / "compaction_run");
    const auto quiet = [](const std::string& arguments) {
      const auto r = run_shapepress("--quiet " + arguments);
      ASSERT_EQ(r.exit_code, 0) << arguments << "\n" << r.output;
    };
    quiet("fill --ellipsoid 150um,100um,80um --kind cms --count 10 --out " +
          shell_quoted(v / "t.h5"));
    quiet("pack " + shell_quoted(v / "t.h5") + " --config " + shell_quoted(v / "pack.toml") +
          " --out " + shell_quoted(v / "packed.h5"));
    quiet("compact --config " + shell_quoted(v / "compact.toml") + " --out " +
          shell_quoted(v / "run"));
    fs::copy_file(v / "run" / "snapshots" / "step_0000000200.h5", v / "snapshot.h5");
  }

 private:
  inline static fs::path valid_;
};

// One row of the catalogue.
struct Row {
  std::string name;  // what is wrong
  // Writes the row's bad input into its folder (nothing: the command alone is wrong).
  std::function<void(const fs::path& dir)> make;
  // The shapepress arguments; {d} is the row's folder, {v} the valid inputs' folder, {r} the
  // repository's root.
  std::string command;
  int exit_code = 2;
  std::vector<std::string> named;  // the message names these ({d}, {v} replaced)
  // File size limit in KiB (a full disk: the write fails with EFBIG, SIGXFSZ ignored).
  std::optional<int> file_size_limit;
  // Files a failing run may leave, because it writes them as it goes (a diverged run's
  // snapshots) and they are whole; any other new file is a failure.
  std::vector<std::string> may_leave;
  // An output ({d} replaced) another run holds while the command runs (common/run_lock.hpp).
  std::optional<std::pair<std::string, RunOutput>> held;
};

std::string substituted(std::string text, const fs::path& dir, const fs::path& valid) {
  for (const auto& [key, path] : {std::pair{"{d}", dir}, std::pair{"{v}", valid},
                                  std::pair{"{r}", shapepress::testing::repository_root()}})
    for (std::size_t at; (at = text.find(key)) != std::string::npos;)
      text.replace(at, 3, path.string());
  return text;
}

std::function<void(const fs::path&)> file(std::string name, std::string text) {
  return [name, text](const fs::path& dir) { write_text(dir / name, text); };
}

std::function<void(const fs::path&)> compact_config(const std::string& extra) {
  return file("c.toml", compact_base + extra);
}

// A compact config whose `key = value` line (under its section) is replaced.
std::function<void(const fs::path&)> compact_with(const std::string& line,
                                                  const std::string& replacement) {
  std::string text = compact_base;
  const auto at = text.find(line);
  if (at != std::string::npos) text.replace(at, line.size(), replacement);
  return file("c.toml", text);
}

std::function<void(const fs::path&)> plate_with(const std::string& line,
                                                const std::string& replacement) {
  std::string text = plate_base;
  const auto at = text.find(line);
  if (at != std::string::npos) text.replace(at, line.size(), replacement);
  return file("p.toml", text);
}

// A killed generate's folder {d}/shapes: its targets t.toml, resume.json (with the targets'
// SHA-256 `sha256`, "" for the true one, and its `count`) and, when given, one checkpoint file.
std::function<void(const fs::path&)> generate_killed(std::string sha256,
                                                     std::string checkpoint = {},
                                                     std::string count = "4") {
  return [sha256, checkpoint, count](const fs::path& d) {
    write_text(d / "t.toml", test_data_text("geometry/paper_box_targets.toml"));
    const nlohmann::json record{
        {"command", "shapepress generate --targets t.toml --count 4 --out shapes"},
        {"working_directory", d.string()},
        {"config", "t.toml"},
        {"config_sha256", sha256.empty() ? sha256_file(d / "t.toml") : sha256},
        {"arguments",
         {{"count", {count}},
          {"seed", {"1"}},
          {"subdivisions", {"2"}},
          {"max-degree", {"15"}},
          {"format", {"stl"}},
          {"directions", {"8"}},
          {"ks-tolerance", {"0.1"}},
          {"checkpoint-every", {"2"}},
          {"checkpoint-minutes", {"10"}}}}};
    fs::create_directories(d / "shapes" / "checkpoints");
    write_text(d / "shapes" / "checkpoints" / "resume.json", record.dump(2));
    if (!checkpoint.empty())
      write_text(d / "shapes" / "checkpoints" / "particles_0000000002.json", checkpoint);
  };
}

// A killed run's start record `record` ({d} replaced by the row's folder) for its config
// `config` (written with the text `text`, its SHA-256 the record's) and the stage's `arguments`.
std::function<void(const fs::path&)> killed_run(std::string record, std::string config,
                                                std::string text, std::string command,
                                                nlohmann::json arguments) {
  return [=](const fs::path& d) {
    const fs::path path = substituted(record, d, {});
    fs::create_directories(path.parent_path());
    write_text(d / config, text);
    const nlohmann::json json{{"command", command},
                              {"working_directory", d.string()},
                              {"config", config},
                              {"config_sha256", sha256_file(d / config)},
                              {"arguments", arguments}};
    write_text(path, json.dump(2));
  };
}

const std::string compact_c = "--quiet compact --config {d}/c.toml --out {d}/out";
const std::string compact_v = "--quiet compact --config {v}/compact.toml --out {d}/out";
const std::string plate_p = "--quiet plate --config {d}/p.toml --out {d}/out";

std::vector<Row> catalogue(const fs::path& v) {
  std::vector<Row> rows;
  const auto add = [&](std::string name, std::function<void(const fs::path&)> make,
                       std::string command, int exit_code, std::vector<std::string> named,
                       std::optional<int> file_size_limit = std::nullopt,
                       std::vector<std::string> may_leave = {}) {
    rows.push_back({std::move(name), std::move(make), std::move(command), exit_code,
                    std::move(named), file_size_limit, std::move(may_leave), std::nullopt});
  };
  // TOML configs: syntax, keys, units, values.
  add("compact: malformed TOML", compact_config("\n[run\nsteps = 3\n"), compact_c, 2,
      {"c.toml:41"});
  add("compact: an empty config", file("c.toml", ""), compact_c, 2, {"c.toml"});
  add("compact: unknown key", compact_config("[walls2]\nmaterial = \"powder\"\n"), compact_c, 2,
      {"walls2"});
  add("compact: misspelt key", compact_with("snapshot_every = 200", "snapshot_evry = 200"),
      compact_c, 2, {"snapshot_evry", "snapshot_every"});
  add("compact: wrong unit", compact_with("speed = \"0.5 m/s\"", "speed = \"0.5 MPa\""), compact_c,
      2, {"punch.speed", "MPa"});
  add("compact: unknown unit", compact_with("x = \"4 mm\"", "x = \"4 furlong\""), compact_c, 2,
      {"box.x", "furlong"});
  add("compact: NaN", compact_with("target_strain = 0.05", "target_strain = nan"), compact_c, 2,
      {"punch.target_strain", "NaN"});
  add("compact: infinite", compact_with("target_strain = 0.05", "target_strain = inf"), compact_c,
      2, {"punch.target_strain", "inf"});
  add("compact: negative", compact_with("count = 30", "count = -30"), compact_c, 2,
      {"generate.count", "-30"});
  add("compact: a string for a number", compact_with("steps = 400", "steps = \"many\""), compact_c,
      2, {"run.steps", "many"});
  add("compact: missing config", nullptr, compact_c, 2, {"{d}/c.toml"});
  // Packings and snapshots.
  add("compact: empty packing", file("p.xyz", ""), compact_v + " --packing {d}/p.xyz", 2,
      {"{d}/p.xyz"});
  add("compact: packing with a word for a number", file("p.xyz", "0 0 1e-3 5e-4\n0 x 2e-3 5e-4\n"),
      compact_v + " --packing {d}/p.xyz", 2, {"{d}/p.xyz"});
  add("compact: packing with NaN", file("p.xyz", "0 0 1e-3 5e-4\n0 nan 2e-3 5e-4\n"),
      compact_v + " --packing {d}/p.xyz", 2, {"{d}/p.xyz"});
  add("compact: packing with a negative radius", file("p.xyz", "0 0 1e-3 -5e-4\n"),
      compact_v + " --packing {d}/p.xyz", 2, {"{d}/p.xyz"});
  add("compact: truncated packing (HDF5)",
      [v](const fs::path& d) { write_text(d / "p.h5", head_of(v / "packed.h5", 3000)); },
      compact_v + " --packing {d}/p.h5", 2, {"{d}/p.h5"});
  add("compact: corrupt packing (HDF5)",
      [v](const fs::path& d) { write_text(d / "p.h5", scrambled(v / "packed.h5", 0, 600)); },
      compact_v + " --packing {d}/p.h5", 2, {"{d}/p.h5"});
  add("compact: a templates file as the packing (no /particles)", nullptr,
      compact_v + " --packing {v}/t.h5", 2, {"{v}/t.h5"});
  add("compact: truncated snapshot",
      [v](const fs::path& d) { write_text(d / "s.h5", head_of(v / "snapshot.h5", -2000)); },
      compact_v + " --restart {d}/s.h5", 2, {"{d}/s.h5"});
  // Damage only a checksum sees (HDF5's Fletcher-32 on every dataset of ours).
  add("compact: a packed.h5 with a damaged value",
      [v](const fs::path& d) {
        write_text(d / "p.h5", values_damaged(v / "packed.h5", "/bodies/scale"));
      },
      compact_v + " --packing {d}/p.h5", 2, {"{d}/p.h5", "/bodies/scale"});
  add("compact: a snapshot with a damaged value",
      [v](const fs::path& d) {
        write_text(d / "s.h5", values_damaged(v / "snapshot.h5", "/particles/radius"));
      },
      compact_v + " --restart {d}/s.h5", 2, {"{d}/s.h5", "/particles/radius"});
  add("pack: a templates file with a damaged value",
      [v](const fs::path& d) {
        write_text(d / "t.h5", values_damaged(v / "t.h5", "/cms/ellipsoid/radii"));
      },
      "--quiet pack {d}/t.h5 --config {v}/pack.toml --out {d}/packed.h5", 2,
      {"{d}/t.h5", "/cms/ellipsoid/radii"});
  add("compact: a packing as the restart (no engine state)", nullptr,
      compact_v + " --restart {v}/packed.h5", 2, {"{v}/packed.h5"});
  // Outputs.
  add("compact: --out under a file", file("f", "a file"),
      "--quiet compact --config {v}/compact.toml --out {d}/f/out", 2, {"{d}/f"});
  add("compact: a full disk", nullptr, "--quiet compact --config {v}/compact.toml --out {d}/out", 1,
      {"{d}/out"}, 8, {"out/checkpoints/resume.json", "out/effective.toml"});
  // A time step too large for the collisions the run can foresee is refused before it runs
  // (a divergence, were one to come, is exit 1 naming the step size: simulate/diagnostics.cpp).
  add("compact: a time step too large for the collisions",
      compact_config("time_step = \"20 us\"\n"), compact_c, 2, {"time step 2e-05 s", "time_step"});
  // One that passes those checks and diverges all the same: a rigid clump of 50 sub-spheres at
  // half the critical step (docs/measurements.md, the stability map: every N <= 100 blows up
  // from 0.5). Exit 1 naming the cause, the step reached and the step size; no force.csv.
  add("plate: a time step past the checks that diverges (a clump at 0.5 of the critical step)",
      nullptr,
      "--quiet plate --config {r}/pipelines/configs/rubber-sphere.toml --particle cms --spheres 50 "
      "--time-step-fraction 0.5 --out {d}/out",
      1, {"diverged at step", "energy", "grew beyond", "time step", "time_step_fraction"});

  // pack: its config, templates files.
  add("pack: misspelt key", file("k.toml", pack_base + "[press]\nsolid_fracton = 0.5\n"),
      "--quiet pack {v}/t.h5 --config {d}/k.toml --out {d}/packed.h5", 2, {"solid_fracton"});
  add("pack: a table twice", file("k.toml", pack_base + "[pack]\n"),
      "--quiet pack {v}/t.h5 --config {d}/k.toml --out {d}/packed.h5", 2, {"k.toml"});
  add("pack: negative diameter",
      [](const fs::path& d) {
        std::string text = pack_base;
        text.replace(text.find("diameter_min = 200e-6"), 21, "diameter_min = -200e-6");
        write_text(d / "k.toml", text);
      },
      "--quiet pack {v}/t.h5 --config {d}/k.toml --out {d}/packed.h5", 2,
      {"sizes.diameter_min", "-0.0002"});
  add("pack: empty templates file", file("t.h5", ""),
      "--quiet pack {d}/t.h5 --config {v}/pack.toml --out {d}/packed.h5", 2, {"{d}/t.h5"});
  add("pack: truncated templates file",
      [v](const fs::path& d) { write_text(d / "t.h5", head_of(v / "t.h5", 4000)); },
      "--quiet pack {d}/t.h5 --config {v}/pack.toml --out {d}/packed.h5", 2, {"{d}/t.h5"});
  add("pack: a packing as the templates file (no /cms)", nullptr,
      "--quiet pack {v}/packed.h5 --config {v}/pack.toml --out {d}/packed.h5", 2,
      {"{v}/packed.h5", "cms/ellipsoid"});
  add("pack: corrupt sizes.summary",
      [](const fs::path& d) {
        std::string text = pack_base;
        text.replace(text.find("size_quantiles"),
                     text.find("diameter_min") - text.find("size_quantiles"),
                     "summary = \"s.json\"\n");
        write_text(d / "k.toml", text);
        write_text(d / "s.json", "{\"size\": {\"x10_m\": ");
      },
      "--quiet pack {v}/t.h5 --config {d}/k.toml --out {d}/packed.h5", 2, {"s.json"});
  add("pack: a full disk", nullptr,
      "--quiet pack {v}/t.h5 --config {v}/pack.toml --out {d}/packed.h5", 1, {"packed"}, 8,
      {"packed.h5.checkpoints/resume.json"});

  // plate.
  add("plate: wrong unit", plate_with("speed = \"5 mm/s\"", "speed = \"5 mm\""), plate_p, 2,
      {"plate.speed"});
  add("plate: negative radius", plate_with("radius = \"1 mm\"", "radius = \"-1 mm\""), plate_p, 2,
      {"sphere.radius"});
  add("plate: unknown material",
      plate_with("material = \"rubber\"\n\n[plate]", "material = \"rubbr\"\n\n[plate]"), plate_p, 2,
      {"rubbr"});

  // Meshes: fill and describe.
  for (const char* ext : {"stl", "off", "ply"}) {
    const std::string mesh = std::string("m.") + ext;
    add(std::string("describe: empty .") + ext, file(mesh, ""), "--quiet describe {d}/" + mesh, 2,
        {"{d}/" + mesh});
  }
  add("describe: truncated OFF", file("m.off", tetra_off.substr(0, 40)),
      "--quiet describe {d}/m.off", 2, {"{d}/m.off"});
  add("describe: OFF face out of range",
      file("m.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 9\n"),
      "--quiet describe {d}/m.off", 2, {"{d}/m.off"});
  add("describe: NaN vertex",
      file("m.off",
           "OFF\n4 4 0\nnan 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"),
      "--quiet describe {d}/m.off", 2, {"{d}/m.off"});
  add("describe: truncated PLY", file("m.ply", tetra_ply.substr(0, tetra_ply.size() - 30)),
      "--quiet describe {d}/m.ply", 2, {"{d}/m.ply"});
  add("describe: corrupt ASCII STL",
      file("m.stl", "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0\n"),
      "--quiet describe {d}/m.stl", 2, {"{d}/m.stl"});
  add("describe: truncated binary STL",
      file("m.stl",
           std::string(80, ' ') + std::string("\x05\x00\x00\x00", 4) + std::string(60, '\0')),
      "--quiet describe {d}/m.stl", 2, {"{d}/m.stl"});
  add("fill: corrupt mesh", file("m.ply", "ply\nformat binary_little_endian 1.0\nend_header\n"),
      "--quiet fill {d}/m.ply --out {d}/t.h5", 2, {"{d}/m.ply"});
  add("fill: --out under a file", file("f", "a file"),
      "--quiet fill {v}/tetra.off --mesh-unit 1mm --out {d}/f/t.h5", 2, {"{d}/f"});
  add("fill: a full disk", nullptr,
      "--quiet fill --ellipsoid 150um,100um,80um --kind cms --count 10 --out {d}/t.h5", 1, {"t.h5"},
      4);

  // generate: its targets.
  add("generate: empty targets", file("s.json", ""),
      "--quiet generate --targets {d}/s.json --out {d}/out", 2, {"{d}/s.json"});
  add("generate: truncated targets", file("s.toml", "[aspect_ratio]\nmean = "),
      "--quiet generate --targets {d}/s.toml --out {d}/out", 2, {"{d}/s.toml"});

  // generate --resume: nothing to resume, targets changed since the start, a damaged checkpoint.
  add("generate: --resume of a folder with nothing to resume", nullptr,
      "--quiet generate --resume {d}/shapes", 2, {"{d}/shapes", "no run to resume"});
  add("generate: --resume after its targets changed", generate_killed(std::string(64, '0')),
      "--quiet generate --resume {d}/shapes", 2, {"{d}/shapes", "t.toml", "changed"});
  // A checkpoint record (common/checkpoint.hpp) of stage `stage`, version `version`, holding the
  // draws `draws`.
  const auto generate_record = [](std::string stage, int version, std::string draws) {
    return R"({"format":"shapepress checkpoint","version":)" + std::to_string(version) +
           R"(,"stage":")" + stage + R"(","step":2,"state":{"draws":[)" + draws +
           R"(],"views":[],"boxes":[],"descriptors":[]}})";
  };
  const std::string two_draws =
      R"({"particle":0,"seed":17,"redraws":0},{"particle":1,"seed":18,"redraws":0})";
  add("generate: --resume from a checkpoint without a key",
      generate_killed("", generate_record("generate", 1, R"({"particle":0,"redraws":0})")),
      "--quiet generate --resume {d}/shapes", 2,
      {"{d}/shapes/checkpoints/particles_0000000002.json", "key 'state.draws[0].seed' is missing",
       "damaged"});
  add("generate: --resume from a cut-short checkpoint",
      generate_killed("", generate_record("generate", 1, two_draws).substr(0, 90)),
      "--quiet generate --resume {d}/shapes", 2,
      {"{d}/shapes/checkpoints/particles_0000000002.json", "cut short"});
  add("generate: --resume from another stage's checkpoint",
      generate_killed("", generate_record("compact", 1, two_draws)),
      "--quiet generate --resume {d}/shapes", 2,
      {"{d}/shapes/checkpoints/particles_0000000002.json", "key 'stage' is 'compact'"});
  add("generate: --resume from a checkpoint of another version",
      generate_killed("", generate_record("generate", 2, two_draws)),
      "--quiet generate --resume {d}/shapes", 2,
      {"{d}/shapes/checkpoints/particles_0000000002.json", "key 'version' is 2"});
  add("generate: --resume with a damaged resume record", generate_killed("", "", "-4"),
      "--quiet generate --resume {d}/shapes", 2,
      {"{d}/shapes/checkpoints/resume.json", "count", "-4"});

  // resume.json damaged, and runs into an output another run holds: exit 2 naming the file, or
  // the holder, before anything in the folder is touched.
  add("compact: --resume with a truncated resume.json",
      [](const fs::path& d) {
        fs::create_directories(d / "out" / "checkpoints");
        write_text(d / "out" / "checkpoints" / "resume.json", "{\"command\": \"shapepress co");
      },
      "--quiet compact --resume {d}/out", 2, {"{d}/out/checkpoints/resume.json"});
  add("compact: --resume with a word for the steps in resume.json",
      killed_run("{d}/out/checkpoints/resume.json", "c.toml", compact_base,
                 "shapepress compact --config c.toml --steps 40 --out out", {{"steps", {"forty"}}}),
      "--quiet compact --resume {d}/out", 2, {"{d}/out/checkpoints/resume.json", "steps", "forty"});
  add("plate: --resume with a word for the count in resume.json",
      killed_run("{d}/out/checkpoints/resume.json", "p.toml", plate_base,
                 "shapepress plate --config p.toml --out out",
                 {{"particle", {"sphere"}},
                  {"count", {"x"}},
                  {"spheres", {"0"}},
                  {"fills", {"0"}},
                  {"seed", {"-1"}},
                  {"time_step_fraction", {"0x0p+0"}},
                  {"snapshot", {"0"}}}),
      "--quiet plate --resume {d}/out", 2, {"{d}/out/checkpoints/resume.json", "count", "'x'"});
  add("plate: --resume with a resume.json without its arguments",
      killed_run("{d}/out/checkpoints/resume.json", "p.toml", plate_base,
                 "shapepress plate --config p.toml --out out", nlohmann::json::object()),
      "--quiet plate --resume {d}/out", 2, {"{d}/out/checkpoints/resume.json", "particle"});
  add("pack: --resume with a negative seed in resume.json",
      killed_run("{d}/packed.h5.checkpoints/resume.json", "k.toml", pack_base,
                 "shapepress pack t.h5 --config k.toml --seed 5 --out packed.h5",
                 {{"templates", {(v / "t.h5").string()}}, {"seed", {"-5"}}}),
      "--quiet pack --resume {d}/packed.h5", 2,
      {"{d}/packed.h5.checkpoints/resume.json", "seed", "-5"});
  add("compact: --out of a run still running", nullptr, compact_v, 2,
      {"{d}/out: in use by another run", "the catalogue's first run"});
  rows.back().held = {"{d}/out", RunOutput::folder};
  add("compact: --resume of a run still running",
      killed_run("{d}/out/checkpoints/resume.json", "c.toml", compact_base,
                 "shapepress compact --config c.toml --out out", nlohmann::json::object()),
      "--quiet compact --resume {d}/out", 2,
      {"{d}/out: in use by another run", "the catalogue's first run"});
  rows.back().held = {"{d}/out", RunOutput::folder};
  add("pack: --out of a pack still running", nullptr,
      "--quiet pack {v}/t.h5 --config {v}/pack.toml --out {d}/packed.h5", 2,
      {"{d}/packed.h5: in use by another run", "the catalogue's first run"});
  rows.back().held = {"{d}/packed.h5", RunOutput::file};

  // Images.
  add("shape-stats: empty PNG", file("i.png", ""), "--quiet shape-stats {d}/i.png --out {d}/out", 2,
      {"{d}/i.png"});
  add("shape-stats: truncated PNG",
      [v](const fs::path& d) { write_text(d / "i.png", head_of(v / "coins.png", 2000)); },
      "--quiet shape-stats {d}/i.png --out {d}/out", 2, {"{d}/i.png"});
  add("shape-stats: truncated TIFF",
      [v](const fs::path& d) { write_text(d / "i.tif", head_of(v / "blobs16.tif", 1000)); },
      "--quiet shape-stats {d}/i.tif --out {d}/out", 2, {"{d}/i.tif"});
  add("shape-stats: corrupt GIF",
      [v](const fs::path& d) { write_text(d / "i.gif", scrambled(v / "blobs.gif", 0, 16)); },
      "--quiet shape-stats {d}/i.gif --out {d}/out", 2, {"{d}/i.gif"});
  add("shape-stats: wrong unit of --pixel-size", nullptr,
      "--quiet shape-stats {v}/coins.png --pixel-size \"2 kg\" --out {d}/out", 2, {"kg"});

  // calibrate's reference CSV.
  const std::string calibrate =
      "--quiet calibrate --config {r}/pipelines/configs/rubber-sphere.toml --reference {d}/r.csv "
      "--count 20 --out {d}/out";
  add("calibrate: empty reference", file("r.csv", ""), calibrate, 2, {"{d}/r.csv"});
  add("calibrate: reference without the columns", file("r.csv", "a,b\n1,2\n"), calibrate, 2,
      {"{d}/r.csv"});
  add("calibrate: reference with a word for a number",
      file("r.csv", "deformation,F_tatara_N\n0.01,x\n"), calibrate, 2, {"{d}/r.csv"});
  add("calibrate: reference with NaN", file("r.csv", "deformation,F_tatara_N\n0.01,1\n0.02,nan\n"),
      calibrate, 2, {"{d}/r.csv", "nan"});
  add("calibrate: truncated reference row", file("r.csv", "deformation,F_tatara_N\n0.01,1\n0.02\n"),
      calibrate, 2, {"{d}/r.csv"});

  // report: run folders.
  const auto run_copy = [v](const std::string& name, std::function<void(const fs::path&)> spoil) {
    return [v, name, spoil](const fs::path& d) {
      fs::copy(v / "compaction_run", d / name);
      spoil(d / name);
    };
  };
  add("report: truncated punch.csv",
      run_copy(
          "r",
          [](const fs::path& r) { write_text(r / "punch.csv", head_of(r / "punch.csv", -7)); }),
      "--quiet report {d}/r --out {d}/out", 2, {"punch.csv"});
  add("report: corrupt run.json",
      run_copy("r",
               [](const fs::path& r) { write_text(r / "run.json", "{\"stage\": \"compact\", "); }),
      "--quiet report {d}/r --out {d}/out", 2, {"run.json"});
  add("report: NaN stress",
      run_copy("r",
               [](const fs::path& r) {
                 std::string text = read_text(r / "punch.csv");
                 const auto last = text.rfind('\n', text.size() - 2);
                 text = text.substr(0, last + 1) + "nan" + text.substr(text.find(',', last + 1));
                 write_text(r / "punch.csv", text);
               }),
      "--quiet report {d}/r --out {d}/out", 2, {"punch.csv"});
  return rows;
}

TEST_F(BadInputCatalogue, EveryRowIsRefusedNamingItsCauseAndLeavesNoFile) {
  const fs::path v = valid();
  const std::vector<Row> rows = catalogue(v);
  int index = 0;
  for (const Row& row : rows) {
    SCOPED_TRACE(row.name);
    const fs::path dir = fresh_directory("catalogue_" + std::to_string(index++));
    if (row.make) row.make(dir);
    const std::vector<fs::path> before = files_under(dir);
    std::string command = std::string(SHAPEPRESS_BINARY) + " " + substituted(row.command, dir, v);
    if (row.file_size_limit)  // ignored, SIGXFSZ is inherited: the write fails with EFBIG
      command =
          "ulimit -f " + std::to_string(2 * *row.file_size_limit) + "; trap '' XFSZ; " + command;
    std::optional<RunFolderLock> holder;
    if (row.held)
      holder.emplace(substituted(row.held->first, dir, v), row.held->second,
                     "shapepress (the catalogue's first run)");
    const auto result = run_command(command);
    holder.reset();
    EXPECT_EQ(result.exit_code, row.exit_code) << result.output;
    for (const std::string& name : row.named)
      EXPECT_THAT(result.output, ::testing::HasSubstr(substituted(name, dir, v)));
    std::set<fs::path> left;
    for (const fs::path& f : files_under(dir))
      left.insert(f);
    for (const fs::path& f : before)
      left.erase(f);
    for (const std::string& f : row.may_leave)
      left.erase(f);
    for (const fs::path& f : left)
      ADD_FAILURE() << "left behind: " << f;
  }
  std::printf("%zu rows\n", rows.size());
}

}  // namespace
}  // namespace shapepress

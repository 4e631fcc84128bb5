// `pack --resume`: a pack (settle, press, relax) killed with SIGKILL at three chosen checkpoints
// and resumed each time ends with the uninterrupted run's packed.h5 (every dataset, bit for bit),
// packed.xmf, and run.json (its wall times aside); SIGTERM writes a checkpoint and exits 143.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "packing/body_packing.hpp"
#include "tests/support/command.hpp"
#include "tests/support/files.hpp"
#include "tests/support/kill_resume.hpp"

namespace shapepress::packing {
namespace {

using shapepress::testing::CommandResult;
using shapepress::testing::files_under;
using shapepress::testing::fresh_directory;
using shapepress::testing::kill_at_checkpoints;
using shapepress::testing::KilledRuns;
using shapepress::testing::read_text;
using shapepress::testing::run_shapepress;
using shapepress::testing::shell_quoted;
using shapepress::testing::spread_steps;
using shapepress::testing::terminate_when;
using shapepress::testing::write_text;
using ::testing::HasSubstr;
namespace fs = std::filesystem;

// Spheres and rigid (CMS) ellipsoids settled, pressed to 0.5 and relaxed at 4 × density, then
// released at the true density, checkpointing every 400 steps.
std::string resumable_config() {
  return "[pack]\ncount = 12\nseed = 5\nbox_x = 3.0e-3\nbox_y = 3.0e-3\n"
         "[[template]]\nname = \"cms/ellipsoid\"\nweight = 1\n"
         "[[template]]\nname = \"sphere\"\nweight = 1\n"
         "[sizes]\nsize_quantiles = [0.8e-3, 1.0e-3, 1.2e-3]\n"
         "size_quantile_levels = [0.1, 0.5, 0.9]\n"
         "diameter_min = 0.8e-3\ndiameter_max = 1.2e-3\n"
         "[settle]\nkinetic_energy_ratio = 1e-3\ndensity_scale = 4\n"
         "[press]\nsolid_fraction = 0.5\nspeed = 0.2\n"
         "[run]\ncheckpoint_every = 400\n";
}

fs::path rigid_templates(const fs::path& dir) {
  const fs::path t = dir / "t.h5";
  const auto r = run_shapepress(
      "--quiet fill --ellipsoid 150um,100um,80um --kind cms --count 20 --out " + shell_quoted(t));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return t;
}

// The two packings hold the same bodies, sub-spheres, bonds and measures, bit for bit.
void expect_same_packing(const fs::path& a, const fs::path& b) {
  const BodyPacking x = read_packing(a), y = read_packing(b);
  ASSERT_EQ(x.size(), y.size());
  for (std::size_t k = 0; k < x.size(); ++k) {
    EXPECT_EQ(x.bodies[k].template_index, y.bodies[k].template_index) << k;
    EXPECT_EQ(x.bodies[k].scale, y.bodies[k].scale) << k;
    EXPECT_EQ(x.bodies[k].centre, y.bodies[k].centre) << k;
    EXPECT_EQ(x.bodies[k].orientation.w, y.bodies[k].orientation.w) << k;
    EXPECT_EQ(x.bodies[k].orientation.x, y.bodies[k].orientation.x) << k;
  }
  EXPECT_EQ(x.particles.x, y.particles.x);
  EXPECT_EQ(x.particles.y, y.particles.y);
  EXPECT_EQ(x.particles.z, y.particles.z);
  EXPECT_EQ(x.particles.radius, y.particles.radius);
  EXPECT_EQ(x.bonds, y.bonds);
  EXPECT_EQ(x.top, y.top);
  EXPECT_EQ(x.measures.solid_fraction_shape, y.measures.solid_fraction_shape);
  EXPECT_EQ(x.measures.coordination, y.measures.coordination);
}

// run.json without what depends on the machine's speed.
nlohmann::json timeless(const fs::path& run_json) {
  nlohmann::json j = nlohmann::json::parse(read_text(run_json));
  j["facts"].erase("loop_s");
  return j;
}

TEST(PackResume, KilledThreeTimesEndsAsTheUninterruptedRun) {
  const fs::path dir = fresh_directory("pack_resume");
  const fs::path templates = rigid_templates(dir);
  write_text(dir / "pack.toml", resumable_config());
  fs::create_directories(dir / "run");
  const std::string start = "pack " + shell_quoted(templates) + " --config " +
                            shell_quoted(dir / "pack.toml") + " --out " +
                            shell_quoted(dir / "run" / "packed.h5");
  const CommandResult whole = run_shapepress(start);
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  const auto steps =
      nlohmann::json::parse(read_text(dir / "run" / "packed.h5.run.json"))["facts"]["steps"]
          .get<std::int64_t>();
  EXPECT_THAT(whole.output, HasSubstr("settled at solid fraction"));
  EXPECT_FALSE(fs::exists(dir / "run" / "packed.h5.checkpoints"));  // gone once whole
  fs::rename(dir / "run", dir / "uninterrupted");
  fs::create_directories(dir / "run");

  // Killed at a quarter, half and three quarters of its steps (the settle, press and relax
  // share one step count), each at a checkpoint past the one its attempt resumed from.
  const KilledRuns runs = kill_at_checkpoints(
      start, "pack --resume " + shell_quoted(dir / "run" / "packed.h5"),
      {dir / "run" / "packed.h5.checkpoints", "step_", spread_steps(steps, 400, 3)});
  // At least one attempt resumed from a checkpoint (a later one may find the run finished).
  EXPECT_NE(std::count(runs.resumed_from.begin(), runs.resumed_from.end(), "start"),
            static_cast<std::ptrdiff_t>(runs.resumed_from.size()));
  ASSERT_TRUE(runs.finished) << runs.output;

  const fs::path ref = dir / "uninterrupted", run = dir / "run";
  EXPECT_EQ(files_under(run), files_under(ref));  // no checkpoint, no hidden temporary left
  expect_same_packing(ref / "packed.h5", run / "packed.h5");
  EXPECT_EQ(read_text(run / "packed.xmf"), read_text(ref / "packed.xmf"));
  EXPECT_EQ(timeless(run / "packed.h5.run.json"), timeless(ref / "packed.h5.run.json"));
}

TEST(PackResume, SigtermWritesACheckpointAndExitsWithItsCode) {
  const fs::path dir = fresh_directory("pack_sigterm");
  const fs::path templates = rigid_templates(dir);
  write_text(dir / "pack.toml", resumable_config());
  // SIGTERM once the first checkpoint is out.
  // Any checkpoint: the newest two are kept, so the first may be gone when the loop looks.
  const auto stopped = terminate_when(
      "pack " + shell_quoted(templates) + " --config " + shell_quoted(dir / "pack.toml") +
          " --out " + shell_quoted(dir / "packed.h5"),
      shell_quoted(dir / "packed.h5.checkpoints") + "/*_*.json", "0.02");
  EXPECT_EQ(stopped.exit_code, 128 + 15) << stopped.output;
  EXPECT_THAT(stopped.output, HasSubstr("--resume"));
  EXPECT_FALSE(fs::exists(dir / "packed.h5"));
  const auto resumed = run_shapepress("pack --resume " + shell_quoted(dir / "packed.h5"));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_THAT(resumed.output, HasSubstr("checkpoint at step"));
  EXPECT_TRUE(fs::exists(dir / "packed.h5"));
}

TEST(PackResume, NothingToResumeIsExitTwoNamingTheFile) {
  const fs::path dir = fresh_directory("pack_resume_nothing");
  const auto result = run_shapepress("pack --resume " + shell_quoted(dir / "nowhere.h5"));
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_THAT(result.output, HasSubstr("nowhere.h5"));
}

}  // namespace
}  // namespace shapepress::packing

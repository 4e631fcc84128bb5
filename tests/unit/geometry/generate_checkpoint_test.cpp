// generate's checkpoints (geometry/generate_checkpoint.hpp): a population stopped in each phase,
// written out, read back and continued, on one thread and then two, is the uninterrupted one bit
// for bit; a damaged checkpoint is an InputError naming its file and its key.
#include "geometry/generate_checkpoint.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <omp.h>

#include <filesystem>
#include <optional>
#include <string>

#include "common/error.hpp"
#include "geometry/generate.hpp"
#include "tests/support/files.hpp"

namespace shapepress::geometry {
namespace {

namespace fs = std::filesystem;
const fs::path data = fs::path(SHAPEPRESS_TEST_DATA) / "geometry";

struct Population {
  std::vector<GeneratedParticle> particles;
  std::vector<ShapeDescriptors> descriptors;
};

GenerateOptions small_options() {
  GenerateOptions options;
  options.count = 5;
  options.subdivisions = 2;  // 162 vertices: milliseconds a particle
  options.seed = 9;
  return options;
}

// Generates and describes from the checkpoints in `folder`, writing one after every block of two
// steps, and stops once `stop_at` steps are done (never: -1). Nothing when stopped.
std::optional<Population> run_until(const ShapeTargets& targets, const fs::path& folder,
                                    std::int64_t stop_at) {
  const GenerateOptions options = small_options();
  std::int64_t step = 0;
  GenerateWork work = read_generate_checkpoints(folder, 5, step);
  GenerateCheckpoints writer(folder, work);
  GenerateHooks hooks;
  hooks.block_steps = 2;
  hooks.after_block = [&](const GenerateWork& w) {
    writer.write(w);
    return stop_at < 0 || w.steps() < stop_at;
  };
  auto particles = generate_population(targets, options, work, hooks);
  if (!particles) return std::nullopt;
  auto descriptors = describe_population(*particles, 16, options.seed, work, hooks);
  if (!descriptors) return std::nullopt;
  return Population{std::move(*particles), std::move(*descriptors)};
}

void expect_same(const Population& a, const Population& b) {
  ASSERT_EQ(a.particles.size(), b.particles.size());
  for (std::size_t i = 0; i < a.particles.size(); ++i) {
    EXPECT_EQ(a.particles[i].mesh.vertices, b.particles[i].mesh.vertices) << i;
    EXPECT_EQ(a.particles[i].seed, b.particles[i].seed) << i;
    EXPECT_EQ(a.particles[i].roughness, b.particles[i].roughness) << i;
    EXPECT_EQ(a.particles[i].elongation_target, b.particles[i].elongation_target) << i;
    const ShapeDescriptors &x = a.descriptors[i], &y = b.descriptors[i];
    EXPECT_EQ(x.L_m, y.L_m) << i;
    EXPECT_EQ(x.convexity, y.convexity) << i;
    EXPECT_EQ(x.projected_asr, y.projected_asr) << i;
    EXPECT_EQ(x.projected_asr_std, y.projected_asr_std) << i;
  }
}

class GenerateCheckpoint : public ::testing::TestWithParam<const char*> {};

TEST_P(GenerateCheckpoint, StoppedInEveryPhaseAndResumedFromTheFilesIsTheWholeRun) {
  const ShapeTargets targets = read_shape_targets(data / GetParam());
  const fs::path folder = testing::fresh_directory("generate_checkpoint");
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  GenerateWork none;
  const std::vector<GeneratedParticle> particles = generate_population(targets, small_options());
  const Population whole{particles, *describe_population(particles, 16, 9, none, {})};
  // Stopped among the draws (5), in the shape phase (5 or 10), among the descriptors, resumed on
  // two threads at last.
  for (const std::int64_t stop : {3, 7, 13})
    EXPECT_FALSE(run_until(targets, folder, stop)) << stop;
  omp_set_num_threads(2);
  const std::optional<Population> resumed = run_until(targets, folder, -1);
  omp_set_num_threads(threads);
  ASSERT_TRUE(resumed);
  expect_same(whole, *resumed);
}

INSTANTIATE_TEST_SUITE_P(Targets, GenerateCheckpoint,
                         ::testing::Values("avicel_ph200_projected.toml",
                                           "paper_box_targets.toml"));

TEST(GenerateCheckpointFiles, ADamagedOneIsAnInputErrorNamingIt) {
  const ShapeTargets targets = read_shape_targets(data / "paper_box_targets.toml");
  const fs::path folder = testing::fresh_directory("generate_checkpoint_damaged");
  EXPECT_FALSE(run_until(targets, folder, 4));
  const fs::path file = folder / "particles_0000000004.json";
  ASSERT_TRUE(fs::exists(file));
  std::int64_t step = 0;
  EXPECT_EQ(read_generate_checkpoints(folder, 5, step).draws.size(), 4u);
  EXPECT_EQ(step, 4);
  const auto expect_refused = [&](const std::string& state, const std::string& why,
                                  std::int64_t record_step = 4) {
    testing::write_text(file,
                        "{\"format\":\"shapepress checkpoint\",\"version\":1,"
                        "\"stage\":\"generate\",\"step\":" +
                            std::to_string(record_step) + ",\"state\":" + state + "}");
    try {
      read_generate_checkpoints(folder, 5, step);
      ADD_FAILURE() << "accepted: " << state;
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), ::testing::HasSubstr(file.string()));
      EXPECT_THAT(e.what(), ::testing::HasSubstr(why));
    }
  };
  const auto draws = [](const std::string& items, const std::string& boxes = "[]") {
    return "{\"draws\":[" + items + "],\"views\":[],\"boxes\":" + boxes + ",\"descriptors\":[]}";
  };
  const std::string two = R"({"particle":2,"seed":17,"redraws":0})";
  const std::string three = R"({"particle":3,"seed":18,"redraws":0})";
  expect_refused(draws(two + "," + three).substr(0, 30), "not JSON or cut short");
  expect_refused(draws(three + "," + two), "particle 3");
  expect_refused(draws(two + R"(,{"particle":3,"seed":18,"redraws":"x"})"),
                 "key 'state.draws[1].redraws' is \"x\"");
  expect_refused(draws(two + R"(,{"particle":3,"redraws":0})"),
                 "key 'state.draws[1].seed' is missing");
  expect_refused(draws(two), "step 3");
  expect_refused(draws(two + "," + three), "its name says 4", 5);
  expect_refused(draws(two, R"([{"particle":0,"applied":true}])"), "drawn");
  expect_refused(R"({"draws":[]})", "key 'state.views' is missing");
  testing::write_text(file, "a particle mesh\n");
  try {
    read_generate_checkpoints(folder, 5, step);
    ADD_FAILURE() << "accepted a mesh";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr(file.string()));
  }
  testing::write_text(file, R"({"format":"shapepress checkpoint","version":1,"stage":"compact",)"
                            R"("step":4,"state":{}})");
  EXPECT_THROW(read_generate_checkpoints(folder, 5, step), InputError);
}

}  // namespace
}  // namespace shapepress::geometry

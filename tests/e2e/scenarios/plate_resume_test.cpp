// `plate --resume` of an ensemble of fills: killed with SIGKILL at three chosen checkpoints and
// resumed each time (finished fills reused, the unfinished ones continued from their
// checkpoints), it ends with the uninterrupted run's force.csv (its CPU and wall seconds aside),
// run.json, effective.toml and final snapshot; SIGTERM writes a checkpoint and exits 128 + 15.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/csv.hpp"
#include "simulate/snapshot.hpp"
#include "tests/support/command.hpp"
#include "tests/support/files.hpp"
#include "tests/support/kill_resume.hpp"

namespace shapepress {
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

// The rubber sphere of the paper as three BMS fills of 100 sub-spheres, each checkpointing every
// 1000 steps, so kills land between checkpoints of the running fills and after some fills ended.
// Random fills (not the shipped carved ones, which take most of such a small run to make), so
// that most of the run is pressing.
fs::path resumable_config(const fs::path& dir) {
  std::string text =
      read_text(shapepress::testing::repository_root() / "pipelines/configs/rubber-sphere.toml");
  for (const auto& [line, replacement] :
       {std::pair<std::string, std::string>{"[run]\n", "[run]\ncheckpoint_every = 1000\n"},
        {"lattice = \"carved\"", "lattice = \"random\""}}) {
    const auto at = text.find(line);
    EXPECT_NE(at, std::string::npos) << line;
    if (at != std::string::npos) text.replace(at, line.size(), replacement);
  }
  write_text(dir / "plate.toml", text);
  return dir / "plate.toml";
}

std::string start_command(const fs::path& dir) {
  return "--threads 2 plate --config " + shell_quoted(resumable_config(dir)) +
         " --particle bms --count 100 --fills 3 --snapshot --out " + shell_quoted(dir / "run");
}

// force.csv without its cpu_s and wall_s columns (the machine's time, different in any two
// runs); every other cell as written.
std::string timeless_force_csv(const fs::path& path) {
  std::istringstream in(read_text(path));
  std::string line, out;
  std::size_t cpu = 0;
  while (std::getline(in, line)) {
    if (line.starts_with("#")) {
      out += line + "\n";
      continue;
    }
    std::vector<std::string> cells;
    std::istringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');)
      cells.push_back(cell);
    if (cpu == 0) {
      cpu =
          static_cast<std::size_t>(std::find(cells.begin(), cells.end(), "cpu_s") - cells.begin());
      EXPECT_LT(cpu + 1, cells.size()) << "force.csv has no cpu_s, wall_s columns";
    }
    if (cpu + 1 < cells.size()) cells.erase(cells.begin() + cpu, cells.begin() + cpu + 2);
    for (const std::string& cell : cells)
      out += cell + ",";
    out += "\n";
  }
  return out;
}

void expect_same_snapshot(const fs::path& a, const fs::path& b) {
  const simulate::LoadedSnapshot x = simulate::read_snapshot(a), y = simulate::read_snapshot(b);
  EXPECT_EQ(x.checkpoint.step, y.checkpoint.step);
  EXPECT_EQ(x.checkpoint.time, y.checkpoint.time);
  for (const auto& [p, q] :
       {std::pair(&x.state.position, &y.state.position),
        std::pair(&x.state.velocity, &y.state.velocity), std::pair(&x.state.force, &y.state.force)})
    EXPECT_TRUE(p->x == q->x && p->y == q->y && p->z == q->z);
  EXPECT_EQ(x.checkpoint.first, y.checkpoint.first);
  EXPECT_EQ(x.checkpoint.wall_force, y.checkpoint.wall_force);
  EXPECT_EQ(x.checkpoint.bonds.size(), y.checkpoint.bonds.size());
}

TEST(PlateResume, EnsembleKilledThreeTimesEndsAsTheUninterruptedRun) {
  const fs::path dir = fresh_directory("plate_resume");
  const std::string start = start_command(dir);
  const CommandResult whole = run_shapepress(start);
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  // A fill's steps: its last record's time over the time step.
  const double dt =
      nlohmann::json::parse(read_text(dir / "run" / "run.json"))["facts"]["time_step_s"]
          .get<double>();
  const std::vector<double> times = read_csv(dir / "run" / "force.csv").column("time_s");
  ASSERT_FALSE(times.empty());
  const auto steps = static_cast<std::int64_t>(times.back() / dt);
  EXPECT_FALSE(fs::exists(dir / "run" / "checkpoints"));  // gone once whole
  // The same --out, so run.json's command and effective.toml's header are the same too.
  fs::rename(dir / "run", dir / "uninterrupted");

  // Killed once a fill's checkpoint reaches a quarter, half and three quarters of a fill's
  // steps (the fills run side by side: the others are then near there too).
  const KilledRuns runs = kill_at_checkpoints(
      start, "plate --resume " + shell_quoted(dir / "run"),
      {dir / "run" / "checkpoints", "fill[0-9]+_", spread_steps(steps, 1000, 3)});
  // At least one attempt resumed from a checkpoint (a later one may find the run finished).
  EXPECT_NE(std::count(runs.resumed_from.begin(), runs.resumed_from.end(), "start"),
            static_cast<std::ptrdiff_t>(runs.resumed_from.size()));
  ASSERT_TRUE(runs.finished) << runs.output;

  const fs::path ref = dir / "uninterrupted", run = dir / "run";
  EXPECT_EQ(files_under(run), files_under(ref));  // no checkpoint, no hidden temporary left
  EXPECT_EQ(timeless_force_csv(run / "force.csv"), timeless_force_csv(ref / "force.csv"));
  for (const auto* name : {"run.json", "effective.toml", "final.xdmf"})
    EXPECT_EQ(read_text(run / name), read_text(ref / name)) << name;
  expect_same_snapshot(ref / "final.h5", run / "final.h5");
  // run.json's counted work (advise's cost), the same as the uninterrupted run's above: the
  // three fills' sub-sphere-, contact- and bond-steps summed, kept across the kills.
  const auto facts = nlohmann::json::parse(read_text(run / "run.json"))["facts"];
  const auto count = [&](const char* key) { return facts.at(key).get<std::int64_t>(); };
  EXPECT_GT(count("sphere_steps"), 3 * steps * 50);  // ~100 sub-spheres per fill
  EXPECT_GT(count("contact_steps"), 0);
  EXPECT_GT(count("bond_steps"), count("sphere_steps"));  // bonded: several bonds per sub-sphere
  EXPECT_EQ(count("counted_cost"),
            count("sphere_steps") + count("contact_steps") + count("bond_steps"));
}

TEST(PlateResume, SigtermWritesACheckpointAndExitsWithItsCode) {
  const fs::path dir = fresh_directory("plate_sigterm");
  // SIGTERM once a fill has written a checkpoint (any: the newest two are kept).
  const auto stopped = terminate_when(
      start_command(dir), shell_quoted(dir / "run" / "checkpoints") + "/*_*.json", "0.02");
  EXPECT_EQ(stopped.exit_code, 128 + 15) << stopped.output;
  EXPECT_THAT(stopped.output, HasSubstr("--resume"));
  EXPECT_FALSE(fs::exists(dir / "run" / "force.csv"));
  const auto resumed = run_shapepress("plate --resume " + shell_quoted(dir / "run"));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_THAT(resumed.output, HasSubstr("checkpoint at step"));
  EXPECT_TRUE(fs::exists(dir / "run" / "force.csv"));
  EXPECT_FALSE(fs::exists(dir / "run" / "checkpoints"));
}

TEST(PlateResume, NothingToResumeIsExitTwoNamingTheFolder) {
  const fs::path dir = fresh_directory("plate_resume_nothing");
  const auto result = run_shapepress("plate --resume " + shell_quoted(dir / "nowhere"));
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_THAT(result.output, HasSubstr("nowhere"));
}

}  // namespace
}  // namespace shapepress

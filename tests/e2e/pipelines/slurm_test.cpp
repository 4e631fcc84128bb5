// The study Makefiles' cluster switch (pipelines/cluster.mk) on a real Slurm: a one-node cluster
// on this machine (scripts/local-slurm.sh) runs a reduced rubber-sphere study end to end (the
// calibration, one BMS count, the Hertz and multi-contact spheres, the report), each simulation
// one job of its thread count, and every file it writes is the local run's, byte for byte, once
// the run clocks are left out.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/command.hpp"
#include "tests/support/files.hpp"

namespace shapepress {
namespace {

namespace fs = std::filesystem;
using shapepress::testing::CommandResult;
using shapepress::testing::read_text;
using shapepress::testing::repository_root;
using shapepress::testing::run_command;
using shapepress::testing::shell_quoted;

// The cluster of scripts/local-slurm.sh in `folder`, stopped when the test ends however it ends
// (and, through --owner, by the script itself should this process die first).
class LocalSlurm {
 public:
  explicit LocalSlurm(fs::path folder) : folder_(std::move(folder)) {
    start_ = run_command(script() + " start " + shell_quoted(folder_) + " --owner " +
                         std::to_string(::getpid()));
  }
  ~LocalSlurm() { run_command(script() + " stop " + shell_quoted(folder_)); }
  LocalSlurm(const LocalSlurm&) = delete;
  LocalSlurm& operator=(const LocalSlurm&) = delete;

  const CommandResult& start() const { return start_; }
  // 77: Slurm cannot be had on this machine (not root, or the packages not installable).
  bool unavailable() const { return start_.exit_code == 77; }
  // A command line with this cluster's configuration in its environment.
  std::string with_cluster(const std::string& command) const {
    return "SLURM_CONF=" + shell_quoted(folder_ / "slurm.conf") + " " + command;
  }

 private:
  static std::string script() {
    return shell_quoted(repository_root() / "scripts" / "local-slurm.sh");
  }
  fs::path folder_;
  CommandResult start_;
};

std::vector<std::string> split(const std::string& line, char separator) {
  std::vector<std::string> fields;
  std::stringstream in(line);
  for (std::string field; std::getline(in, field, separator);)
    fields.push_back(field);
  return fields;
}

// A CSV without its clock columns (cpu_s, wall_s: the runs' CPU and wall seconds), found by name
// in the header, the first line that is not a # comment.
std::string without_clock_columns(const std::string& csv) {
  std::stringstream in(csv);
  std::string out;
  std::vector<bool> keep;
  for (std::string line; std::getline(in, line);) {
    if (line.starts_with('#')) {
      out += line + '\n';
      continue;
    }
    const std::vector<std::string> fields = split(line, ',');
    if (keep.empty())
      for (const std::string& name : fields)
        keep.push_back(name != "cpu_s" && name != "wall_s");
    std::string kept;
    for (std::size_t i = 0; i < fields.size(); ++i)
      if (i >= keep.size() || keep[i]) kept += (kept.empty() ? "" : ",") + fields[i];
    out += kept + '\n';
  }
  return out;
}

// What must be equal in a study's file: its bytes, with the run's own output folder named alike,
// the clock columns of CSVs left out, and in run.json (provenance) the inputs' hashes left out
// (they hash CSVs with clocks).
std::string comparable(const fs::path& file, const fs::path& out, const fs::path& reference_out) {
  std::string text = read_text(file);
  for (std::size_t at = text.find(out.string()); at != std::string::npos;
       at = text.find(out.string(), at + reference_out.string().size()))
    text.replace(at, out.string().size(), reference_out.string());
  if (file.extension() == ".csv") return without_clock_columns(text);
  if (file.filename() == "run.json") {
    std::stringstream in(text);
    std::string kept;
    for (std::string line; std::getline(in, line);)
      if (line.find("\"sha256\"") == std::string::npos) kept += line + '\n';
    return kept;
  }
  return text;
}

std::set<fs::path> files_under(const fs::path& root) {
  std::set<fs::path> files;
  for (const auto& entry : fs::recursive_directory_iterator(root))
    if (entry.is_regular_file()) files.insert(fs::relative(entry.path(), root));
  return files;
}

TEST(Slurm, ReducedRubberSphereStudyMatchesTheLocalRun) {
  const fs::path work = shapepress::testing::fresh_directory("pipelines_slurm");
  LocalSlurm cluster(work / "cluster");
  if (cluster.unavailable()) GTEST_SKIP() << "no local Slurm: " << cluster.start().output;
  ASSERT_EQ(cluster.start().exit_code, 0) << cluster.start().output;

  // The study's rules at their smallest: a two-evaluation calibration of one parameter at
  // N = 100, that N as the whole ladder, one fill; two threads, so each job asks for two CPUs.
  // FEM= leaves out the CalculiX run (its logs carry timings, and it is not the DEM rules'
  // concern here).
  const std::string study =
      "make -s -C " + shell_quoted(repository_root() / "pipelines" / "rubber-sphere") +
      " SHAPEPRESS=" + shell_quoted(SHAPEPRESS_BINARY) +
      " COUNTS=100 CALIBRATION_COUNT=100 FILLS=1 FIT=modulus MAX_EVALUATIONS=2 THREADS=2 FEM=";
  const fs::path local = work / "local";
  const fs::path on_slurm = work / "slurm";
  const CommandResult here = run_command(study + " OUT=" + shell_quoted(local) + " report");
  ASSERT_EQ(here.exit_code, 0) << here.output;
  const CommandResult there = run_command(
      cluster.with_cluster(study + " -j2 CLUSTER=slurm OUT=" + shell_quoted(on_slurm) + " report"));
  ASSERT_EQ(there.exit_code, 0) << there.output;

  // Every simulation rule was one job of THREADS CPUs, and nothing else (the report ran here).
  const CommandResult jobs = run_command(cluster.with_cluster("scontrol -o show jobs"));
  ASSERT_EQ(jobs.exit_code, 0) << jobs.output;
  std::set<std::string> names;
  for (const std::string& job : split(jobs.output, '\n')) {
    for (const std::string& field : split(job, ' '))
      if (field.starts_with("JobName=")) names.insert(field.substr(8));
    EXPECT_THAT(job, ::testing::HasSubstr("JobState=COMPLETED"));
    EXPECT_THAT(job, ::testing::HasSubstr("NumCPUs=2"));
  }
  EXPECT_EQ(names, (std::set<std::string>{"calibration/calibrated.toml", "bms-100/force.csv",
                                          "hertz/force.csv", "multicontact/force.csv"}))
      << jobs.output;

  const std::set<fs::path> files = files_under(local);
  ASSERT_EQ(files_under(on_slurm), files);
  EXPECT_TRUE(files.contains("report/report.html"));
  for (const fs::path& file : files)
    EXPECT_EQ(comparable(on_slurm / file, on_slurm, local), comparable(local / file, local, local))
        << file;
}

}  // namespace
}  // namespace shapepress

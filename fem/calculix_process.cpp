#include "fem/calculix_process.hpp"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "common/child_process.hpp"
#include "common/error.hpp"

namespace shapepress::fem {
namespace {

// User + system CPU seconds of a running process and its threads (/proc/PID/stat fields 14, 15).
double process_cpu_seconds(int pid) {
  std::ifstream in(fmt::format("/proc/{}/stat", pid));
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t close = text.rfind(')');  // the command name may hold spaces
  if (close == std::string::npos) return 0.0;
  std::istringstream fields(text.substr(close + 2));
  std::string field;
  unsigned long long user = 0, system = 0;
  for (int i = 3; i <= 15 && fields >> field; ++i) {
    if (i == 14) user = std::stoull(field);
    if (i == 15) system = std::stoull(field);
  }
  return static_cast<double>(user + system) / static_cast<double>(sysconf(_SC_CLK_TCK));
}

// Follows CalculiX's increment messages: "actual step time=…" opens an attempt (its "actual
// total time=…" follows), a line starting with "convergence" closes it as converged.
class IncrementTracker {
 public:
  explicit IncrementTracker(std::function<void(const ConvergedIncrement&)> on_increment)
      : on_increment_(std::move(on_increment)) {}
  void line(const std::string& text, int pid, double wall_seconds, CcxOutcome& outcome) {
    const std::size_t start = text.find_first_not_of(' ');
    if (start == std::string::npos) return;
    const std::string_view view = std::string_view(text).substr(start);
    if (view.starts_with("actual step time=")) {
      attempt_time_ = std::strtod(text.c_str() + start + 17, nullptr);
      attempt_total_ = attempt_time_;  // one step: the same
    } else if (view.starts_with("actual total time=")) {
      attempt_total_ = std::strtod(text.c_str() + start + 18, nullptr);
    } else if (view.starts_with("convergence")) {
      ConvergedIncrement done{static_cast<int>(outcome.increments.size()) + 1, attempt_time_,
                              attempt_total_, process_cpu_seconds(pid), wall_seconds};
      outcome.increments.push_back(done);
      if (on_increment_) on_increment_(done);
    } else if (view.starts_with("*ERROR") && outcome.error.empty()) {
      outcome.error = std::string(view);
    }
  }

 private:
  std::function<void(const ConvergedIncrement&)> on_increment_;
  double attempt_time_ = 0.0;
  double attempt_total_ = 0.0;
};

}  // namespace

bool CcxOutcome::completed(int steps) const {
  return exit_status == 0 && error.empty() && !increments.empty() &&
         increments.back().step_time > 1.0 - 1e-9 &&
         increments.back().total_time > steps - 1e-9 * steps;
}

CcxOutcome run_ccx(const std::string& program, const std::filesystem::path& folder,
                   const std::string& job, int threads,
                   const std::function<void(const ConvergedIncrement&)>& on_increment) {
  const std::string count = std::to_string(std::max(1, threads));
  ChildCommand command{{program, "-i", job},
                       "the finite element solver",
                       "install Debian's calculix-ccx: scripts/install-deps.sh, or name the "
                       "program with --ccx",
                       folder,
                       {},
                       folder / (job + ".log")};
  for (const char* name :
       {"OMP_NUM_THREADS", "CCX_NPROC_STIFFNESS", "CCX_NPROC_EQUATION_SOLVER", "CCX_NPROC_RESULTS"})
    command.environment.push_back(std::string(name) + "=" + count);
  CcxOutcome outcome;
  IncrementTracker tracker(on_increment);
  const ChildEnd end = run_child(command, [&](const std::string& line, int pid, double wall) {
    tracker.line(line, pid, wall, outcome);
  });
  outcome.exit_status = end.exit_code;
  outcome.cpu_seconds = end.cpu_seconds;
  outcome.wall_seconds = end.wall_seconds;
  return outcome;
}

std::vector<NodeSetTotal> read_total_forces(const std::filesystem::path& dat,
                                            const std::string& set) {
  std::ifstream in(dat);
  if (!in) throw InputError(fmt::format("{}: cannot open CalculiX's results", dat.string()));
  std::string upper_set = set;
  std::transform(upper_set.begin(), upper_set.end(), upper_set.begin(),
                 [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
  const std::string header = "total force (fx,fy,fz) for set " + upper_set + " and time";
  std::vector<NodeSetTotal> totals;
  std::string line;
  while (std::getline(in, line)) {
    const std::size_t at = line.find(header);
    if (at == std::string::npos) continue;
    NodeSetTotal total;
    total.step_time = std::strtod(line.c_str() + at + header.size(), nullptr);
    std::string values;
    while (std::getline(in, values) && values.find_first_not_of(" \t\r") == std::string::npos) {
    }
    std::istringstream fields(values);
    if (!(fields >> total.fx >> total.fy >> total.fz))
      throw InputError(fmt::format("{}: no three force values after '{}'", dat.string(), line));
    totals.push_back(total);
  }
  return totals;
}

}  // namespace shapepress::fem

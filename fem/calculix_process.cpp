#include "fem/calculix_process.hpp"

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "common/error.hpp"

namespace shapepress::fem {
namespace {

// User + system CPU seconds of a running process and its threads (/proc/PID/stat fields 14, 15).
double process_cpu_seconds(pid_t pid) {
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

// Follows CalculiX's increment messages: "actual step time=…" opens an attempt, a line
// starting with "convergence" closes it as converged.
class IncrementTracker {
 public:
  explicit IncrementTracker(std::function<void(const ConvergedIncrement&)> on_increment)
      : on_increment_(std::move(on_increment)) {}
  void line(const std::string& text, pid_t pid, double wall_seconds, CcxOutcome& outcome) {
    const std::size_t start = text.find_first_not_of(' ');
    if (start == std::string::npos) return;
    const std::string_view view = std::string_view(text).substr(start);
    if (view.starts_with("actual step time=")) {
      attempt_time_ = std::strtod(text.c_str() + start + 17, nullptr);
    } else if (view.starts_with("convergence")) {
      ConvergedIncrement done{static_cast<int>(outcome.increments.size()) + 1, attempt_time_,
                              process_cpu_seconds(pid), wall_seconds};
      outcome.increments.push_back(done);
      if (on_increment_) on_increment_(done);
    } else if (view.starts_with("*ERROR") && outcome.error.empty()) {
      outcome.error = std::string(view);
    }
  }

 private:
  std::function<void(const ConvergedIncrement&)> on_increment_;
  double attempt_time_ = 0.0;
};

// What the child is given, built before fork(): between fork() and exec() a child of a
// multi-threaded parent may only call async-signal-safe functions (no setenv, no allocation).
struct ChildCommand {
  std::vector<std::string> argument_text, environment_text;
  std::vector<char*> arguments, environment;
};

ChildCommand child_command(const std::string& program, const std::string& job, int threads) {
  ChildCommand c;
  c.argument_text = {program, "-i", job};
  const std::string count = std::to_string(std::max(1, threads));
  const std::vector<std::string> limits = {"OMP_NUM_THREADS", "CCX_NPROC_STIFFNESS",
                                           "CCX_NPROC_EQUATION_SOLVER", "CCX_NPROC_RESULTS"};
  for (char** entry = environ; *entry != nullptr; ++entry) {
    const std::string_view text(*entry);
    const bool replaced = std::any_of(limits.begin(), limits.end(), [&](const std::string& name) {
      return text.starts_with(name + "=");
    });
    if (!replaced) c.environment_text.emplace_back(text);
  }
  for (const std::string& name : limits)
    c.environment_text.push_back(name + "=" + count);
  for (std::string& a : c.argument_text)
    c.arguments.push_back(a.data());
  for (std::string& e : c.environment_text)
    c.environment.push_back(e.data());
  c.arguments.push_back(nullptr);
  c.environment.push_back(nullptr);
  return c;
}

[[noreturn]] void exec_child(ChildCommand& command, const std::filesystem::path& folder, int output,
                             int report) {
  if (chdir(folder.c_str()) == 0 && dup2(output, STDOUT_FILENO) >= 0 &&
      dup2(output, STDERR_FILENO) >= 0)
    execvpe(command.arguments[0], command.arguments.data(), command.environment.data());
  const int error = errno;  // tell the parent why through the close-on-exec pipe
  (void)!write(report, &error, sizeof error);
  _exit(127);
}

}  // namespace

bool CcxOutcome::completed() const {
  return exit_status == 0 && error.empty() && !increments.empty() &&
         increments.back().step_time > 1.0 - 1e-9;
}

CcxOutcome run_ccx(const std::string& program, const std::filesystem::path& folder,
                   const std::string& job, int threads,
                   const std::function<void(const ConvergedIncrement&)>& on_increment) {
  int output[2], report[2];
  if (pipe(output) != 0 || pipe2(report, O_CLOEXEC) != 0)
    throw ComputationError(
        fmt::format("cannot create a pipe for {}: {}", program, std::strerror(errno)));
  ChildCommand command = child_command(program, job, threads);
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid < 0)
    throw ComputationError(fmt::format("cannot start {}: {}", program, std::strerror(errno)));
  if (pid == 0) {
    close(output[0]);
    close(report[0]);
    exec_child(command, folder, output[1], report[1]);
  }
  close(output[1]);
  close(report[1]);
  // A signal (SIGINT noted for a checkpoint, say) may interrupt any wait on the child: each is
  // retried, or the child's output would be lost and the child left a zombie.
  int exec_error = 0;
  ssize_t got;
  while ((got = read(report[0], &exec_error, sizeof exec_error)) < 0 && errno == EINTR) {
  }
  const bool exec_failed = got == sizeof exec_error;
  close(report[0]);
  if (exec_failed) {
    close(output[0]);
    while (waitpid(pid, nullptr, 0) < 0 && errno == EINTR) {
    }
    throw InputError(fmt::format(
        "cannot run the finite element solver '{}': {}{}", program, std::strerror(exec_error),
        exec_error == ENOENT ? " (install Debian's calculix-ccx: scripts/install-deps.sh, or "
                               "name the program with --ccx)"
                             : ""));
  }

  CcxOutcome outcome;
  IncrementTracker tracker(on_increment);
  std::ofstream log(folder / (job + ".log"));
  FILE* stream = fdopen(output[0], "r");
  std::string line;
  for (int c = std::fgetc(stream);; c = std::fgetc(stream)) {
    if (c == EOF) {
      if (!std::ferror(stream) || errno != EINTR) break;
      std::clearerr(stream);
      continue;
    }
    if (c != '\n') {
      line.push_back(static_cast<char>(c));
      continue;
    }
    log << line << '\n';
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    tracker.line(line, pid, wall, outcome);
    line.clear();
  }
  std::fclose(stream);
  int status = 0;
  rusage usage{};
  while (wait4(pid, &status, 0, &usage) < 0)
    if (errno != EINTR)
      throw ComputationError(fmt::format("lost the run of {}: {}", program, std::strerror(errno)));
  outcome.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  outcome.cpu_seconds = static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
                        1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
  outcome.exit_status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
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

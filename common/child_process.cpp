#include "common/child_process.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>
#include <string_view>

#include <fmt/format.h>

#include "common/error.hpp"

extern char** environ;

namespace shapepress {
namespace {

// Our environment with the command's variables set over it.
std::vector<std::string> child_environment(const std::vector<std::string>& overrides) {
  std::vector<std::string> out;
  for (char** entry = environ; *entry != nullptr; ++entry) {
    const std::string_view text(*entry);
    const bool replaced =
        std::any_of(overrides.begin(), overrides.end(), [&](const std::string& o) {
          return text.starts_with(std::string_view(o).substr(0, o.find('=') + 1));
        });
    if (!replaced) out.emplace_back(text);
  }
  out.insert(out.end(), overrides.begin(), overrides.end());
  return out;
}

std::vector<char*> pointers(std::vector<std::string>& texts) {
  std::vector<char*> out;
  for (std::string& t : texts)
    out.push_back(t.data());
  out.push_back(nullptr);
  return out;
}

// The file actions of a spawn, released however the spawn ends.
class SpawnActions {
 public:
  SpawnActions() { posix_spawn_file_actions_init(&actions_); }
  SpawnActions(const SpawnActions&) = delete;
  SpawnActions& operator=(const SpawnActions&) = delete;
  ~SpawnActions() { posix_spawn_file_actions_destroy(&actions_); }
  posix_spawn_file_actions_t* get() { return &actions_; }

 private:
  posix_spawn_file_actions_t actions_;
};

// Reads the child's output from `fd` to its end, line by line into `log` and `on_line`.
void follow_output(int fd, int pid, const std::filesystem::path& log, const ChildLine& on_line,
                   std::chrono::steady_clock::time_point start) {
  std::ofstream out(log);
  std::string pending;
  const auto deliver = [&](const std::string& line) {
    out << line << '\n';
    on_line(line, pid,
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  };
  char buffer[4096];
  for (;;) {
    const ssize_t got = read(fd, buffer, sizeof buffer);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) break;
    pending.append(buffer, static_cast<std::size_t>(got));
    std::size_t begin = 0;
    for (std::size_t end; (end = pending.find('\n', begin)) != std::string::npos; begin = end + 1)
      deliver(pending.substr(begin, end - begin));
    pending.erase(0, begin);
  }
  if (!pending.empty()) deliver(pending);
  close(fd);
}

}  // namespace

std::string ChildEnd::how() const {
  if (signal != 0) return fmt::format("signal {} ({})", signal, strsignal(signal));
  return fmt::format("exit status {}", exit_code);
}

ChildEnd run_child(const ChildCommand& command, const ChildLine& on_line) {
  const std::string& program = command.arguments.at(0);
  std::vector<std::string> argument_text = command.arguments;
  std::vector<std::string> environment_text = child_environment(command.environment);
  const std::vector<char*> arguments = pointers(argument_text);
  const std::vector<char*> environment = pointers(environment_text);

  // Close-on-exec, so that children started at the same time on other threads do not hold the
  // pipe open; dup2 into the child's stdout clears the flag there.
  int output[2] = {-1, -1};
  if (on_line && pipe2(output, O_CLOEXEC) != 0)
    throw ComputationError(
        fmt::format("cannot create a pipe for {}: {}", program, std::strerror(errno)));
  SpawnActions actions;
  if (on_line)
    posix_spawn_file_actions_adddup2(actions.get(), output[1], STDOUT_FILENO);
  else  // opened before the chdir below: a relative log is ours
    posix_spawn_file_actions_addopen(actions.get(), STDOUT_FILENO, command.log.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(actions.get(), STDOUT_FILENO, STDERR_FILENO);
  if (!command.folder.empty())
    posix_spawn_file_actions_addchdir_np(actions.get(), command.folder.c_str());

  const auto start = std::chrono::steady_clock::now();
  pid_t pid = 0;
  const int error = posix_spawnp(&pid, program.c_str(), actions.get(), nullptr, arguments.data(),
                                 environment.data());
  if (on_line) close(output[1]);
  if (error != 0) {
    if (on_line) close(output[0]);
    throw InputError(fmt::format(
        "cannot run {} '{}': {}{}", command.role, program, std::strerror(error),
        error == ENOENT && !command.install_hint.empty() ? " (" + command.install_hint + ")"
                                                         : std::string()));
  }
  if (on_line) follow_output(output[0], pid, command.log, on_line, start);

  int status = 0;
  rusage usage{};
  while (wait4(pid, &status, 0, &usage) < 0)
    if (errno != EINTR)
      throw ComputationError(
          fmt::format("lost the run of {} '{}': {}", command.role, program, std::strerror(errno)));
  const auto seconds = [](const timeval& t) {
    return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
  };
  ChildEnd end;
  end.signal = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
  end.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + end.signal;
  end.cpu_seconds = seconds(usage.ru_utime) + seconds(usage.ru_stime);
  end.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return end;
}

}  // namespace shapepress

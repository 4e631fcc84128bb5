#include "common/resume.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <charconv>
#include <csignal>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <regex>

#include <nlohmann/json.hpp>

#include "common/atomic_file.hpp"
#include "common/checkpoint.hpp"
#include "common/error.hpp"
#include "common/sha256.hpp"

namespace shapepress {
namespace {

// The signal SIGINT or SIGTERM delivered, 0 before one is. The program's one global: a signal
// handler can reach nothing else safely (C++ [support.signal]: a lock-free volatile
// sig_atomic_t of static storage), and the stepping loops poll it through CheckpointClock.
volatile std::sig_atomic_t received_signal = 0;

extern "C" void note_signal(int signal) {
  received_signal = signal;
  std::signal(signal, SIG_DFL);  // a second one stops the run at once
}

}  // namespace

SignalCheckpoints::SignalCheckpoints()
    : interrupt_(std::signal(SIGINT, note_signal)), terminate_(std::signal(SIGTERM, note_signal)) {}

SignalCheckpoints::~SignalCheckpoints() {
  std::signal(SIGINT, interrupt_);
  std::signal(SIGTERM, terminate_);
}

int SignalCheckpoints::received() {
  return received_signal;
}

CheckpointClock::CheckpointClock(CheckpointPolicy policy)
    : policy_(policy), last_(std::chrono::steady_clock::now()) {}

bool CheckpointClock::due(std::int64_t step) const {
  const std::chrono::duration<double> interval(60.0 * policy_.minutes);
  return SignalCheckpoints::received() != 0 ||
         (policy_.every_steps > 0 && step % policy_.every_steps == 0) ||
         (policy_.minutes > 0.0 && std::chrono::steady_clock::now() - last_ >= interval);
}

void CheckpointClock::taken() {
  last_ = std::chrono::steady_clock::now();
}

void write_invocation(const std::filesystem::path& path, const RunInvocation& i) {
  nlohmann::ordered_json json{{"command", i.command_line},
                              {"working_directory", i.working_directory.string()},
                              {"config", i.config},
                              {"config_sha256", i.config_sha256},
                              {"arguments", i.arguments}};
  for (const RecordedInput& input : i.inputs)
    json["inputs"].push_back(
        {{"role", input.role}, {"file", input.file}, {"sha256", input.sha256}});
  write_file_atomically(path, json.dump(2) + "\n");
}

RunInvocation resume_invocation(const std::filesystem::path& path, const std::string& run) {
  std::ifstream in(path);
  if (!in)
    throw InputError(
        fmt::format("{}: no run to resume here ({} is missing: not the output of a resumable run, "
                    "or the run finished)",
                    run, path.string()));
  RunInvocation i;
  try {
    const nlohmann::json j = nlohmann::json::parse(in);
    i.command_line = j.at("command").get<std::string>();
    i.working_directory = j.at("working_directory").get<std::string>();
    i.config = j.at("config").get<std::string>();
    i.config_sha256 = j.at("config_sha256").get<std::string>();
    i.arguments = j.at("arguments").get<std::map<std::string, std::vector<std::string>>>();
    for (const nlohmann::json& input : j.value("inputs", nlohmann::json::array()))
      i.inputs.push_back({input.at("role").get<std::string>(), input.at("file").get<std::string>(),
                          input.at("sha256").get<std::string>()});
  } catch (const nlohmann::json::exception& e) {
    throw InputError(fmt::format("{}: not a resume record ({})", path.string(), e.what()));
  }
  std::error_code ec;
  std::filesystem::current_path(i.working_directory, ec);
  if (ec)
    throw InputError(fmt::format("{}: the run was started in {}, which is gone ({})", run,
                                 i.working_directory.string(), ec.message()));
  std::vector<RecordedInput> files = {{"config", i.config, i.config_sha256}};
  files.insert(files.end(), i.inputs.begin(), i.inputs.end());
  for (const RecordedInput& file : files)
    if (!std::filesystem::is_regular_file(file.file) || sha256_file(file.file) != file.sha256)
      throw InputError(fmt::format(
          "{}: the {} {} is missing or changed since the run started; a resumed run needs the "
          "same one",
          run, file.role, file.file));
  return i;
}

CheckpointFolderGuard::CheckpointFolderGuard(std::filesystem::path folder)
    : folder_(std::move(folder)), exceptions_(std::uncaught_exceptions()) {}

CheckpointFolderGuard::~CheckpointFolderGuard() {
  if (std::uncaught_exceptions() <= exceptions_ || holds_checkpoints(folder_)) return;
  std::error_code ec;
  std::filesystem::remove_all(folder_, ec);
}

std::string exact_text(double value) {
  return fmt::format("{:a}", value);
}

namespace {

template <typename Whole>
Whole parse_whole_number(const std::string& token, std::string_view name,
                         const std::filesystem::path& record, Whole least, Whole most) {
  Whole value{};
  const char* end = token.data() + token.size();
  const auto [stop, error] = std::from_chars(token.data(), end, value);
  if (token.empty() || error != std::errc() || stop != end || value < least || value > most)
    throw InputError(fmt::format("{}: argument '{}' is '{}' (a damaged resume record)",
                                 record.string(), name, token));
  return value;
}

}  // namespace

std::int64_t parse_whole(const std::string& token, std::string_view name,
                         const std::filesystem::path& record, std::int64_t least,
                         std::int64_t most) {
  return parse_whole_number(token, name, record, least, most);
}

std::uint64_t parse_unsigned(const std::string& token, std::string_view name,
                             const std::filesystem::path& record) {
  return parse_whole_number(token, name, record, std::uint64_t{0},
                            std::numeric_limits<std::uint64_t>::max());
}

void remove_stale_temporaries(const std::filesystem::path& folder, const std::string& prefix) {
  static const std::regex temporary(R"(\..+\.tmp\.\d+)");
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
    const std::string name = entry.path().filename().string();
    if (std::regex_match(name, temporary) && name.substr(1).starts_with(prefix))
      std::filesystem::remove(entry.path(), ec);
  }
}

bool finished_before_resume(std::string_view stage, const std::string& run,
                            const std::filesystem::path& checkpoints,
                            const std::filesystem::path& run_metadata) {
  if (run.empty() || std::filesystem::exists(checkpoints / "resume.json") ||
      !std::filesystem::exists(run_metadata))
    return false;
  spdlog::info("{}: {} is finished (its run.json is written): nothing to resume", stage, run);
  std::error_code ignored;
  std::filesystem::remove_all(checkpoints, ignored);
  return true;
}

namespace {

// The per-stage text checkpoints (step_N.history, particles_N.history) before the one format.
bool holds_text_checkpoints(const std::filesystem::path& folder) {
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(folder, ec))
    if (entry.path().extension() == ".history") return true;
  return false;
}

}  // namespace

ResumableRun::ResumableRun(std::string stage, std::filesystem::path output,
                           std::filesystem::path folder, CheckpointPolicy policy)
    : stage_(std::move(stage)),
      output_(std::move(output)),
      folder_(std::move(folder)),
      policy_(policy),
      clock_(policy) {}

bool ResumableRun::start(bool resumed, const RunInvocation& invocation) {
  if (resumed) remove_stale_temporaries(folder_);
  const bool continues = resumed && holds_checkpoints(folder_);
  if (resumed && !continues && holds_text_checkpoints(folder_))
    spdlog::warn(
        "{}: {} holds checkpoints of the text format of builds before the one format "
        "(*.history), which this build does not read: the run starts again",
        stage_, folder_.string());
  if (!continues) {
    std::filesystem::remove_all(folder_);
    ensure_output_folder(folder_);
    write_invocation(folder_ / "resume.json", invocation);
  }
  guard_.emplace(folder_);
  signals_.emplace();
  clock_.taken();  // the wall-time interval counts from here
  return continues;
}

bool ResumableRun::after_step(std::int64_t step, const std::function<void()>& write) {
  if (clock_.due(step)) {
    write();
    clock_.taken();
  }
  return SignalCheckpoints::received() == 0;
}

int ResumableRun::stopped(std::optional<std::int64_t> step) const {
  spdlog::warn(
      "{}: stopped by signal {}{}; checkpoint written: continue with `shapepress {} --resume {}`",
      stage_, SignalCheckpoints::received(), step ? fmt::format(" at step {}", *step) : "", stage_,
      output_.string());
  return 128 + SignalCheckpoints::received();
}

void ResumableRun::finish() const {
  std::error_code ignored;
  std::filesystem::remove_all(folder_, ignored);
}

}  // namespace shapepress

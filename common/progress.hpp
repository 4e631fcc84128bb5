#pragma once
// Progress of a long run on stderr: on a terminal one self-overwriting line with percent, rate
// and ETA; otherwise (a log file, CI) one plain line every `interval` seconds; nothing when
// quiet. update() is cheap enough to call every step: it only reads the clock every 64 calls.
#include <chrono>
#include <cstdint>
#include <functional>
#include <string>

namespace shapepress {

struct ProgressOptions {
  bool quiet = false;
  double interval_seconds = 10.0;  // between plain lines when stderr is not a terminal
  std::string unit = "steps";
};

class ProgressReporter {
 public:
  ProgressReporter(std::string label, double total, ProgressOptions options = {});
  ~ProgressReporter();
  ProgressReporter(const ProgressReporter&) = delete;
  ProgressReporter& operator=(const ProgressReporter&) = delete;

  void update(double done, std::string_view detail = {});
  // As update(), with the total renewed by `total()` when a line is printed (a run whose length
  // is known better as it goes); the call is made only then, so it may cost more than a step.
  void update(double done, std::string_view detail, const std::function<double()>& total);
  void finish();
  // The line it would print, for tests: "compact  42.0 %  1.2e+04 steps/s  ETA 0:01:13".
  std::string format_line(double done, double elapsed_seconds, std::string_view detail) const;

 private:
  using Clock = std::chrono::steady_clock;
  std::string label_;
  double total_;
  ProgressOptions options_;
  bool terminal_;
  Clock::time_point start_;
  Clock::time_point last_print_;
  std::uint64_t calls_ = 0;
  bool finished_ = false;
  bool printed_on_terminal_ = false;
};

// "1:02:03" or "2:03".
std::string format_duration(double seconds);

}  // namespace shapepress

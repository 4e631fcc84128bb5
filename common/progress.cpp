#include "common/progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <fmt/format.h>

namespace shapepress {

std::string format_duration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "?";
  auto s = static_cast<long long>(std::llround(seconds));
  if (s >= 3600) return fmt::format("{}:{:02}:{:02}", s / 3600, (s / 60) % 60, s % 60);
  return fmt::format("{}:{:02}", s / 60, s % 60);
}

ProgressReporter::ProgressReporter(std::string label, double total, ProgressOptions options)
    : label_(std::move(label)),
      total_(total),
      options_(std::move(options)),
      terminal_(::isatty(STDERR_FILENO) != 0),
      start_(Clock::now()),
      last_print_(start_) {}

ProgressReporter::~ProgressReporter() {
  if (printed_on_terminal_ && !finished_) std::fputc('\n', stderr);
}

std::string ProgressReporter::format_line(double done, double elapsed,
                                          std::string_view detail) const {
  double fraction = total_ > 0 ? std::clamp(done / total_, 0.0, 1.0) : 0.0;
  double rate = elapsed > 0 ? done / elapsed : 0.0;
  double eta = rate > 0 ? (total_ - done) / rate : NAN;
  std::string line =
      fmt::format("{} {:5.1f} %  {:.3g} {}/s  elapsed {}  ETA {}", label_, 100.0 * fraction, rate,
                  options_.unit, format_duration(elapsed), format_duration(eta));
  if (!detail.empty()) line += fmt::format("  {}", detail);
  return line;
}

void ProgressReporter::update(double done, std::string_view detail) {
  update(done, detail, {});
}

void ProgressReporter::update(double done, std::string_view detail,
                              const std::function<double()>& total) {
  if (options_.quiet || (calls_++ % 64) != 0) return;
  Clock::time_point now = Clock::now();
  double since_print = std::chrono::duration<double>(now - last_print_).count();
  double interval = terminal_ ? 0.2 : options_.interval_seconds;
  if (since_print < interval) return;
  last_print_ = now;
  if (total) total_ = total();
  std::string line = format_line(done, std::chrono::duration<double>(now - start_).count(), detail);
  if (terminal_) {
    std::fprintf(stderr, "\r\033[K%s", line.c_str());
    printed_on_terminal_ = true;
  } else {
    std::fprintf(stderr, "%s\n", line.c_str());
  }
  std::fflush(stderr);
}

void ProgressReporter::finish() {
  if (finished_) return;
  finished_ = true;
  if (options_.quiet) return;
  double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
  std::string line = format_line(total_, elapsed, "done");
  if (terminal_)
    std::fprintf(stderr, "\r\033[K%s\n", line.c_str());
  else
    std::fprintf(stderr, "%s\n", line.c_str());
}

}  // namespace shapepress

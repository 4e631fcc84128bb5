#include "common/run_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <ctime>
#include <string>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "common/atomic_file.hpp"
#include "common/error.hpp"

namespace shapepress {
namespace {

namespace fs = std::filesystem;

std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  std::tm t{};
  gmtime_r(&now, &t);
  std::array<char, 32> text{};
  std::strftime(text.data(), text.size(), "%Y-%m-%dT%H:%M:%SZ", &t);
  return text.data();
}

std::string host_name() {
  std::array<char, 256> name{};
  if (::gethostname(name.data(), name.size() - 1) != 0) return "an unknown host";
  return name.data();
}

// The holder's own words (pid, host, start, command), as it wrote them; a few lines at most.
std::string holder_of(int descriptor) {
  std::string text;
  std::array<char, 4096> buffer{};
  for (;;) {
    const ssize_t n =
        ::pread(descriptor, buffer.data(), buffer.size(), static_cast<off_t>(text.size()));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    text.append(buffer.data(), static_cast<std::size_t>(n));
    if (text.size() >= 16384) break;
  }
  while (!text.empty() && (text.back() == '\n' || text.back() == ' '))
    text.pop_back();
  std::replace(text.begin(), text.end(), '\n', ';');
  return text.empty() ? std::string("a run that has not yet written its name") : text;
}

// The outermost missing folder on the way to `folder` (empty when it exists): what a lock that
// creates `folder` must remove again if the run leaves it empty.
fs::path outermost_missing(const fs::path& folder) {
  fs::path missing;
  std::error_code ec;
  for (fs::path p = folder; !p.empty() && !fs::exists(p, ec); p = p.parent_path()) {
    missing = p;
    if (p == p.parent_path()) break;
  }
  return missing;
}

bool same_file(int descriptor, const fs::path& path) {
  struct stat held {};
  struct stat named {};
  return ::fstat(descriptor, &held) == 0 && ::stat(path.c_str(), &named) == 0 &&
         held.st_dev == named.st_dev && held.st_ino == named.st_ino;
}

}  // namespace

fs::path run_lock_path(const fs::path& output, RunOutput kind) {
  if (kind == RunOutput::folder) return output / ".shapepress.lock";
  // Appended piece by piece: GCC 12 at -O3 warns falsely (-Wrestrict) on "." + name + ".lock".
  std::string name = ".";
  name += output.filename().string();
  name += ".lock";
  return output.parent_path() / name;
}

RunFolderLock::RunFolderLock(const fs::path& output, RunOutput kind, std::string_view command_line)
    // Absolute: a resumed run changes to the folder it was started in.
    : lock_(fs::absolute(run_lock_path(output, kind))), folder_(lock_.parent_path()) {
  created_ = outermost_missing(folder_);
  ensure_output_folder(folder_);
  // The holder unlinks the file as it lets go; a file opened just before that is no longer the
  // one under the name, so the lock is taken again on the file the name now holds.
  for (;;) {
    descriptor_ = ::open(lock_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (descriptor_ < 0)
      throw InputError(fmt::format("{}: cannot create the lock file {} ({})", output.string(),
                                   lock_.string(), std::strerror(errno)));
    int locked;
    while ((locked = ::flock(descriptor_, LOCK_EX | LOCK_NB)) != 0 && errno == EINTR) {
    }
    if (locked != 0) {
      const int error = errno;
      if (error == EWOULDBLOCK) {
        const std::string holder = holder_of(descriptor_);
        ::close(descriptor_);
        descriptor_ = -1;
        throw InputError(
            fmt::format("{}: in use by another run ({}); wait for it to end, or give another --out "
                        "(the lock is {})",
                        output.string(), holder, lock_.string()));
      }
      // A file system without flock (some network mounts): the run goes on unguarded.
      spdlog::warn("{}: cannot lock {} ({}): a second run into it would not be refused",
                   output.string(), lock_.string(), std::strerror(error));
      break;
    }
    if (same_file(descriptor_, lock_)) break;
    ::close(descriptor_);
  }
  const std::string holder = fmt::format("pid {} on {}, started {}: {}\n", ::getpid(), host_name(),
                                         utc_now(), command_line);
  if (::ftruncate(descriptor_, 0) == 0) {
    // Only the next run's message depends on it: a short write is not worth failing this one.
    (void)!::pwrite(descriptor_, holder.data(), holder.size(), 0);
  }
}

RunFolderLock::~RunFolderLock() {
  if (descriptor_ < 0) return;
  std::error_code ignored;
  fs::remove(lock_, ignored);  // while still held, so no one locks the file being removed
  ::close(descriptor_);
  if (created_.empty()) return;
  // Up from the run's folder to the outermost one this lock made, each removed when empty.
  for (fs::path p = folder_;; p = p.parent_path()) {
    if (!fs::remove(p, ignored)) break;  // not empty (or gone): what is above stays too
    if (p == created_ || p == p.parent_path()) break;
  }
}

}  // namespace shapepress

#include "common/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>

#include <fmt/format.h>

#include "common/error.hpp"

namespace shapepress {

std::filesystem::path temporary_path_for(const std::filesystem::path& final_path) {
  std::filesystem::path name = final_path.filename();
  return final_path.parent_path() / fmt::format(".{}.tmp.{}", name.string(), ::getpid());
}

void ensure_parent_directory(const std::filesystem::path& path) {
  std::filesystem::path parent = path.parent_path();
  if (parent.empty()) return;
  std::error_code ec;
  std::filesystem::create_directories(parent, ec);
  if (ec)
    throw InputError(
        fmt::format("{}: cannot create the output folder: {}", parent.string(), ec.message()));
}

void ensure_output_folder(const std::filesystem::path& folder) {
  std::error_code ec;
  std::filesystem::create_directories(folder, ec);
  if (ec)
    throw InputError(
        fmt::format("{}: cannot create the output folder: {}", folder.string(), ec.message()));
  if (::access(folder.c_str(), W_OK | X_OK) != 0)
    throw InputError(fmt::format("{}: the output folder is not writable ({})", folder.string(),
                                 std::strerror(errno)));
}

AtomicOutputFile::AtomicOutputFile(std::filesystem::path final_path)
    : final_path_(std::move(final_path)), temporary_path_(temporary_path_for(final_path_)) {
  ensure_parent_directory(final_path_);
  out_.open(temporary_path_, std::ios::binary | std::ios::trunc);
  if (!out_)
    throw InputError(
        fmt::format("{}: cannot write here ({})", final_path_.string(), std::strerror(errno)));
}

AtomicOutputFile::~AtomicOutputFile() {
  if (committed_) return;
  out_.close();
  std::error_code ignored;
  std::filesystem::remove(temporary_path_, ignored);
}

void AtomicOutputFile::commit() {
  out_.flush();
  bool ok = static_cast<bool>(out_);
  out_.close();
  if (!ok || out_.fail())
    throw ComputationError(fmt::format(
        "{}: writing failed (the disk full, or over a file size limit?)", final_path_.string()));
  commit_temporary_file(temporary_path_, final_path_);
  committed_ = true;
}

void write_file_atomically(const std::filesystem::path& path, std::string_view content) {
  AtomicOutputFile file(path);
  file.stream().write(content.data(), static_cast<std::streamsize>(content.size()));
  file.commit();
}

void commit_temporary_file(const std::filesystem::path& temporary,
                           const std::filesystem::path& final_path) {
  int fd = ::open(temporary.c_str(), O_RDONLY);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
  std::error_code ec;
  std::filesystem::rename(temporary, final_path, ec);
  if (ec) {
    std::filesystem::remove(temporary, ec);
    throw ComputationError(fmt::format("{}: cannot move the finished file into place: {}",
                                       final_path.string(), ec.message()));
  }
}

}  // namespace shapepress

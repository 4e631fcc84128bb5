#pragma once
// Outputs are written to a temporary name in the same folder and renamed when complete, so a
// killed run never leaves a half-written file under the final name (docs/architecture.md, "Files").
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

namespace shapepress {

// The temporary name used while `final_path` is being written: ".name.tmp.<pid>" beside it.
std::filesystem::path temporary_path_for(const std::filesystem::path& final_path);

// Creates the parent folders of `path`; InputError naming the folder if that is not possible.
void ensure_parent_directory(const std::filesystem::path& path);

// Creates an output folder (--out) and checks it can be written to; InputError naming the folder
// if not (a usage error, exit 2, not a raw filesystem message).
void ensure_output_folder(const std::filesystem::path& folder);

class AtomicOutputFile {
 public:
  // Opens the temporary file; InputError naming the path if the folder is not writable.
  explicit AtomicOutputFile(std::filesystem::path final_path);
  AtomicOutputFile(const AtomicOutputFile&) = delete;
  AtomicOutputFile& operator=(const AtomicOutputFile&) = delete;
  ~AtomicOutputFile();  // removes the temporary file unless commit() succeeded

  std::ostream& stream() { return out_; }
  // Flushes, syncs and renames onto the final name; ComputationError if any write failed.
  void commit();
  const std::filesystem::path& path() const { return final_path_; }

 private:
  std::filesystem::path final_path_;
  std::filesystem::path temporary_path_;
  std::ofstream out_;
  bool committed_ = false;
};

void write_file_atomically(const std::filesystem::path& path, std::string_view content);

// Moves a finished temporary file onto its final name (fsync first, so a crash after the rename
// cannot leave an empty file). Used by every writer, the HDF5 one included.
void commit_temporary_file(const std::filesystem::path& temporary,
                           const std::filesystem::path& final_path);

}  // namespace shapepress

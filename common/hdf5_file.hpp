#pragma once
// HDF5 helpers: datasets of numbers and strings, attributes, groups created on demand.
// H5Writer writes to a temporary name and renames on commit(), adding the provenance root
// attributes every shapepress file carries. Its files cannot crash their reader: strings are
// fixed-length (HDF5 1.10.8 crashes on damaged variable-length ones), every dataset carries a
// Fletcher-32 checksum and the metadata HDF5 1.8's checksums, so damage is an InputError naming
// the file (docs/architecture.md, "Files"). hdf5.h stays in the .cpp.
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "common/atomic_file.hpp"
#include "common/provenance.hpp"

namespace shapepress {

class H5Writer {
 public:
  H5Writer(std::filesystem::path final_path, Provenance provenance);
  H5Writer(const H5Writer&) = delete;
  H5Writer& operator=(const H5Writer&) = delete;
  ~H5Writer();  // an uncommitted file is not written

  // `shape` empty means one dimension of values.size(). Intermediate groups are created.
  void write(std::string_view dataset, std::span<const double> values,
             std::vector<std::size_t> shape = {});
  void write(std::string_view dataset, std::span<const std::int64_t> values,
             std::vector<std::size_t> shape = {});
  void write(std::string_view dataset, std::span<const std::int32_t> values,
             std::vector<std::size_t> shape = {});
  void write(std::string_view dataset, std::span<const std::uint8_t> values,
             std::vector<std::size_t> shape = {});
  void write_strings(std::string_view dataset, const std::vector<std::string>& values);

  void attribute(std::string_view object, std::string_view name, double value);
  void attribute(std::string_view object, std::string_view name, std::int64_t value);
  void attribute(std::string_view object, std::string_view name, std::string_view value);
  // The SI unit of a dataset, as the attribute "unit" (docs/architecture.md, "Files").
  void unit(std::string_view dataset, std::string_view si_unit) {
    attribute(dataset, "unit", si_unit);
  }
  void group(std::string_view path);

  void commit();
  const std::filesystem::path& path() const { return final_path_; }

 private:
  void write_raw(std::string_view dataset, const void* data, std::int64_t type,
                 std::span<const std::size_t> shape);
  std::filesystem::path final_path_;
  // The file is made in memory and written out whole by commit() through an atomic, checked
  // write: a full disk is then an error of ours, where inside HDF5's close it cannot be
  // recovered from (a failed H5Fclose leaves a file HDF5 crashes on at exit).
  AtomicOutputFile output_;
  Provenance provenance_;
  std::int64_t file_ = -1;  // hid_t
};

class H5Reader {
 public:
  explicit H5Reader(std::filesystem::path path);  // InputError naming the file
  H5Reader(const H5Reader&) = delete;
  H5Reader& operator=(const H5Reader&) = delete;
  ~H5Reader();

  bool has(std::string_view object) const;
  // InputError naming the file and the dataset when it is missing or of another rank.
  std::vector<double> doubles(std::string_view dataset,
                              std::vector<std::size_t>* shape = nullptr) const;
  std::vector<std::int64_t> int64s(std::string_view dataset,
                                   std::vector<std::size_t>* shape = nullptr) const;
  std::vector<std::int32_t> int32s(std::string_view dataset,
                                   std::vector<std::size_t>* shape = nullptr) const;
  std::vector<std::uint8_t> uint8s(std::string_view dataset,
                                   std::vector<std::size_t>* shape = nullptr) const;
  std::vector<std::string> strings(std::string_view dataset) const;
  std::vector<std::string> members(std::string_view group) const;

  double attribute_double(std::string_view object, std::string_view name) const;
  std::int64_t attribute_int64(std::string_view object, std::string_view name) const;
  std::string attribute_string(std::string_view object, std::string_view name) const;
  bool has_attribute(std::string_view object, std::string_view name) const;

  const std::filesystem::path& path() const { return path_; }

 private:
  void read_raw(std::string_view dataset, void* out, std::int64_t type) const;
  void check_chunks(std::int64_t dataset_id, std::string_view dataset) const;
  // InputError when `count` values of `size` bytes cannot come from a file this size.
  void check_count(std::string_view dataset, std::size_t count, std::size_t size) const;
  template <typename T>
  std::vector<T> read_numbers(std::string_view dataset, std::int64_t type,
                              std::vector<std::size_t>* shape) const;
  std::vector<std::size_t> shape_of(std::string_view dataset) const;
  std::size_t string_width(std::int64_t type, std::string_view object, std::string_view name) const;
  std::filesystem::path path_;
  std::int64_t file_ = -1;
  // Written with fixed-length strings only (layout 2): a variable-length one is damage.
  bool fixed_strings_only_ = false;
};

}  // namespace shapepress

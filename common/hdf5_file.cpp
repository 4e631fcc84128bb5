#include "common/hdf5_file.hpp"

#include <hdf5.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <numeric>

#include <fmt/format.h>

#include "common/atomic_file.hpp"
#include "common/error.hpp"

namespace shapepress {
namespace {

// HDF5 prints its own error stack to stderr by default; ours name the file instead.
void silence_hdf5_errors() {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

std::string z(std::string_view s) {
  return std::string(s);
}

// Closes an HDF5 handle at scope exit.
struct Handle {
  hid_t id;
  herr_t (*close)(hid_t);
  ~Handle() {
    if (id >= 0) close(id);
  }
};

std::string iso_time_now() {
  std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buffer[32];
  std::strftime(buffer, sizeof buffer, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buffer;
}

hid_t string_type() {
  hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, H5T_VARIABLE);
  H5Tset_cset(type, H5T_CSET_UTF8);
  return type;
}

}  // namespace

H5Writer::H5Writer(std::filesystem::path final_path, Provenance provenance)
    : final_path_(std::move(final_path)), output_(final_path_), provenance_(std::move(provenance)) {
  silence_hdf5_errors();
  Handle access{H5Pcreate(H5P_FILE_ACCESS), H5Pclose};
  // The core driver without a backing store: the file lives in memory until commit().
  H5Pset_fapl_core(access.id, 1 << 20, 0);
  file_ = H5Fcreate(final_path_.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access.id);
  if (file_ < 0)
    throw ComputationError(
        fmt::format("{}: cannot create the HDF5 file in memory", final_path_.string()));
}

H5Writer::~H5Writer() {
  if (file_ >= 0) H5Fclose(static_cast<hid_t>(file_));
}

void H5Writer::group(std::string_view path) {
  if (H5Lexists(file_, z(path).c_str(), H5P_DEFAULT) > 0) return;
  Handle lcpl{H5Pcreate(H5P_LINK_CREATE), H5Pclose};
  H5Pset_create_intermediate_group(lcpl.id, 1);
  Handle g{H5Gcreate2(file_, z(path).c_str(), lcpl.id, H5P_DEFAULT, H5P_DEFAULT), H5Gclose};
  if (g.id < 0)
    throw ComputationError(fmt::format("{}: cannot create group {}", final_path_.string(), path));
}

void H5Writer::write_raw(std::string_view dataset, const void* data, std::int64_t type,
                         std::span<const std::size_t> shape) {
  std::vector<hsize_t> dims(shape.begin(), shape.end());
  Handle space{H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose};
  Handle lcpl{H5Pcreate(H5P_LINK_CREATE), H5Pclose};
  H5Pset_create_intermediate_group(lcpl.id, 1);
  Handle set{
      H5Dcreate2(file_, z(dataset).c_str(), type, space.id, lcpl.id, H5P_DEFAULT, H5P_DEFAULT),
      H5Dclose};
  std::size_t count =
      std::accumulate(shape.begin(), shape.end(), std::size_t{1}, std::multiplies<>());
  if (set.id < 0 || (count > 0 && H5Dwrite(set.id, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0))
    throw ComputationError(
        fmt::format("{}: cannot write dataset {}", final_path_.string(), dataset));
}

namespace {
std::vector<std::size_t> shape_or_flat(std::vector<std::size_t> shape, std::size_t size,
                                       std::string_view dataset) {
  if (shape.empty()) return {size};
  std::size_t count =
      std::accumulate(shape.begin(), shape.end(), std::size_t{1}, std::multiplies<>());
  if (count != size)
    throw std::logic_error(
        fmt::format("dataset {}: shape does not match {} values", dataset, size));
  return shape;
}
}  // namespace

void H5Writer::write(std::string_view dataset, std::span<const double> values,
                     std::vector<std::size_t> shape) {
  auto s = shape_or_flat(std::move(shape), values.size(), dataset);
  write_raw(dataset, values.data(), H5T_NATIVE_DOUBLE, s);
}
void H5Writer::write(std::string_view dataset, std::span<const std::int64_t> values,
                     std::vector<std::size_t> shape) {
  auto s = shape_or_flat(std::move(shape), values.size(), dataset);
  write_raw(dataset, values.data(), H5T_NATIVE_INT64, s);
}
void H5Writer::write(std::string_view dataset, std::span<const std::int32_t> values,
                     std::vector<std::size_t> shape) {
  auto s = shape_or_flat(std::move(shape), values.size(), dataset);
  write_raw(dataset, values.data(), H5T_NATIVE_INT32, s);
}
void H5Writer::write(std::string_view dataset, std::span<const std::uint8_t> values,
                     std::vector<std::size_t> shape) {
  auto s = shape_or_flat(std::move(shape), values.size(), dataset);
  write_raw(dataset, values.data(), H5T_NATIVE_UINT8, s);
}

void H5Writer::write_strings(std::string_view dataset, const std::vector<std::string>& values) {
  std::vector<const char*> pointers;
  pointers.reserve(values.size());
  for (const std::string& v : values)
    pointers.push_back(v.c_str());
  Handle type{string_type(), H5Tclose};
  std::size_t n = values.size();
  write_raw(dataset, pointers.data(), type.id, std::span<const std::size_t>(&n, 1));
}

namespace {
void write_attribute(hid_t file, std::string_view object, std::string_view name, hid_t type,
                     const void* data, const std::filesystem::path& path) {
  std::string target = object.empty() ? "/" : z(object);
  Handle space{H5Screate(H5S_SCALAR), H5Sclose};
  if (H5Aexists_by_name(file, target.c_str(), z(name).c_str(), H5P_DEFAULT) > 0)
    H5Adelete_by_name(file, target.c_str(), z(name).c_str(), H5P_DEFAULT);
  Handle attr{H5Acreate_by_name(file, target.c_str(), z(name).c_str(), type, space.id, H5P_DEFAULT,
                                H5P_DEFAULT, H5P_DEFAULT),
              H5Aclose};
  if (attr.id < 0 || H5Awrite(attr.id, type, data) < 0)
    throw ComputationError(
        fmt::format("{}: cannot write attribute {} on {}", path.string(), name, target));
}
}  // namespace

void H5Writer::attribute(std::string_view object, std::string_view name, double value) {
  write_attribute(file_, object, name, H5T_NATIVE_DOUBLE, &value, final_path_);
}
void H5Writer::attribute(std::string_view object, std::string_view name, std::int64_t value) {
  write_attribute(file_, object, name, H5T_NATIVE_INT64, &value, final_path_);
}
void H5Writer::attribute(std::string_view object, std::string_view name, std::string_view value) {
  Handle type{string_type(), H5Tclose};
  std::string text(value);
  const char* pointer = text.c_str();
  write_attribute(file_, object, name, type.id, &pointer, final_path_);
}

void H5Writer::commit() {
  attribute("/", "shapepress_version", shapepress_version());
  attribute("/", "git_revision", shapepress_git_revision());
  attribute("/", "command_line", provenance_.command_line);
  attribute("/", "config_text", provenance_.config_text);
  attribute("/", "created_utc", iso_time_now());
  if (provenance_.seed) attribute("/", "seed", static_cast<std::int64_t>(*provenance_.seed));
  if (H5Fflush(file_, H5F_SCOPE_GLOBAL) < 0)
    throw ComputationError(fmt::format("{}: flushing the HDF5 file failed", final_path_.string()));
  const ssize_t size = H5Fget_file_image(file_, nullptr, 0);
  std::string image(static_cast<std::size_t>(std::max<ssize_t>(size, 0)), '\0');
  if (size <= 0 || H5Fget_file_image(file_, image.data(), image.size()) != size)
    throw ComputationError(fmt::format("{}: no image of the HDF5 file", final_path_.string()));
  H5Fclose(file_);
  file_ = -1;
  output_.stream().write(image.data(), static_cast<std::streamsize>(image.size()));
  output_.commit();  // ComputationError naming the file when the disk is full
}

H5Reader::H5Reader(std::filesystem::path path) : path_(std::move(path)) {
  silence_hdf5_errors();
  if (!std::filesystem::exists(path_))
    throw InputError(fmt::format("{}: no such file", path_.string()));
  if (H5Fis_hdf5(path_.c_str()) <= 0)
    throw InputError(fmt::format("{}: not an HDF5 file", path_.string()));
  file_ = H5Fopen(path_.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file_ < 0) throw InputError(fmt::format("{}: cannot open the HDF5 file", path_.string()));
}

H5Reader::~H5Reader() {
  if (file_ >= 0) H5Fclose(file_);
}

bool H5Reader::has(std::string_view object) const {
  // Check each level, since H5Lexists fails on a path whose parent is missing.
  std::string path;
  std::string_view rest = object;
  while (!rest.empty()) {
    std::size_t slash = rest.find('/', 1);
    path += rest.substr(0, slash);
    if (path != "/" && H5Lexists(file_, path.c_str(), H5P_DEFAULT) <= 0) return false;
    if (slash == std::string_view::npos) break;
    rest.remove_prefix(slash);
  }
  return true;
}

std::vector<std::size_t> H5Reader::shape_of(std::string_view dataset) const {
  if (!has(dataset))
    throw InputError(fmt::format("{}: dataset {} is missing", path_.string(), dataset));
  Handle set{H5Dopen2(file_, z(dataset).c_str(), H5P_DEFAULT), H5Dclose};
  if (set.id < 0) throw InputError(fmt::format("{}: {} is not a dataset", path_.string(), dataset));
  Handle space{H5Dget_space(set.id), H5Sclose};
  int rank = H5Sget_simple_extent_ndims(space.id);
  std::vector<hsize_t> dims(static_cast<std::size_t>(std::max(rank, 0)));
  H5Sget_simple_extent_dims(space.id, dims.data(), nullptr);
  return {dims.begin(), dims.end()};
}

void H5Reader::check_count(std::string_view dataset, std::size_t count, std::size_t size) const {
  // A damaged header may announce any extent: no dataset of ours compresses a thousandfold, so
  // more values than that is a damaged file, not an allocation to try (found by tests/fuzz).
  std::error_code ec;
  const std::uintmax_t bytes = std::filesystem::file_size(path_, ec);
  if (!ec && count > 0 && count / 1000 > (bytes + (1u << 20)) / size)
    throw InputError(fmt::format("{}: dataset {} announces {} values, more than the file holds",
                                 path_.string(), dataset, count));
}

void H5Reader::read_raw(std::string_view dataset, void* out, std::int64_t type) const {
  Handle set{H5Dopen2(file_, z(dataset).c_str(), H5P_DEFAULT), H5Dclose};
  if (set.id < 0 || H5Dread(set.id, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out) < 0)
    throw InputError(fmt::format("{}: cannot read dataset {}", path_.string(), dataset));
}

template <typename T>
std::vector<T> H5Reader::read_numbers(std::string_view dataset, std::int64_t type,
                                      std::vector<std::size_t>* shape) const {
  std::vector<std::size_t> dims = shape_of(dataset);
  std::size_t count =
      std::accumulate(dims.begin(), dims.end(), std::size_t{1}, std::multiplies<>());
  check_count(dataset, count, sizeof(T));
  std::vector<T> values(count);
  if (count > 0) read_raw(dataset, values.data(), type);
  if (shape != nullptr) *shape = std::move(dims);
  return values;
}

std::vector<double> H5Reader::doubles(std::string_view dataset,
                                      std::vector<std::size_t>* shape) const {
  return read_numbers<double>(dataset, H5T_NATIVE_DOUBLE, shape);
}
std::vector<std::int64_t> H5Reader::int64s(std::string_view dataset,
                                           std::vector<std::size_t>* shape) const {
  return read_numbers<std::int64_t>(dataset, H5T_NATIVE_INT64, shape);
}
std::vector<std::int32_t> H5Reader::int32s(std::string_view dataset,
                                           std::vector<std::size_t>* shape) const {
  return read_numbers<std::int32_t>(dataset, H5T_NATIVE_INT32, shape);
}
std::vector<std::uint8_t> H5Reader::uint8s(std::string_view dataset,
                                           std::vector<std::size_t>* shape) const {
  return read_numbers<std::uint8_t>(dataset, H5T_NATIVE_UINT8, shape);
}

std::vector<std::string> H5Reader::strings(std::string_view dataset) const {
  std::vector<std::size_t> dims = shape_of(dataset);
  std::size_t count = dims.empty() ? 1 : dims[0];
  check_count(dataset, count, sizeof(char*));
  std::vector<char*> pointers(count, nullptr);
  Handle type{string_type(), H5Tclose};
  if (count > 0) read_raw(dataset, pointers.data(), type.id);
  std::vector<std::string> out;
  for (char* p : pointers) {
    out.emplace_back(p != nullptr ? p : "");
    H5free_memory(p);
  }
  return out;
}

std::vector<std::string> H5Reader::members(std::string_view group) const {
  std::vector<std::string> names;
  if (!has(group)) return names;
  Handle g{H5Gopen2(file_, z(group).c_str(), H5P_DEFAULT), H5Gclose};
  H5G_info_t info{};
  if (g.id < 0 || H5Gget_info(g.id, &info) < 0) return names;
  for (hsize_t i = 0; i < info.nlinks; ++i) {
    ssize_t size =
        H5Lget_name_by_idx(g.id, ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0, H5P_DEFAULT);
    if (size < 0)  // a damaged link table (found by tests/fuzz)
      throw InputError(
          fmt::format("{}: cannot read the name of member {} of {}", path_.string(), i, group));
    std::string name(static_cast<std::size_t>(size), '\0');
    H5Lget_name_by_idx(g.id, ".", H5_INDEX_NAME, H5_ITER_INC, i, name.data(),
                       static_cast<std::size_t>(size) + 1, H5P_DEFAULT);
    names.push_back(name);
  }
  return names;
}

bool H5Reader::has_attribute(std::string_view object, std::string_view name) const {
  std::string target = object.empty() ? "/" : z(object);
  if (target != "/" && !has(target)) return false;
  return H5Aexists_by_name(file_, target.c_str(), z(name).c_str(), H5P_DEFAULT) > 0;
}

namespace {
void read_attribute(hid_t file, std::string_view object, std::string_view name, hid_t type,
                    void* out, const std::filesystem::path& path) {
  std::string target = object.empty() ? "/" : z(object);
  Handle attr{H5Aopen_by_name(file, target.c_str(), z(name).c_str(), H5P_DEFAULT, H5P_DEFAULT),
              H5Aclose};
  if (attr.id < 0 || H5Aread(attr.id, type, out) < 0)
    throw InputError(
        fmt::format("{}: attribute '{}' of {} is missing", path.string(), name, target));
}
}  // namespace

double H5Reader::attribute_double(std::string_view object, std::string_view name) const {
  double value = 0.0;
  read_attribute(file_, object, name, H5T_NATIVE_DOUBLE, &value, path_);
  return value;
}
std::int64_t H5Reader::attribute_int64(std::string_view object, std::string_view name) const {
  std::int64_t value = 0;
  read_attribute(file_, object, name, H5T_NATIVE_INT64, &value, path_);
  return value;
}
std::string H5Reader::attribute_string(std::string_view object, std::string_view name) const {
  char* pointer = nullptr;
  Handle type{string_type(), H5Tclose};
  read_attribute(file_, object, name, type.id, &pointer, path_);
  std::string value = pointer != nullptr ? pointer : "";
  H5free_memory(pointer);
  return value;
}

}  // namespace shapepress

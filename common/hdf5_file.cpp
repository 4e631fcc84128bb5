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

// The variable-length string type files before layout 2 hold (read only: HDF5 1.10.8 crashes,
// hangs or allocates gigabytes on a damaged one, tests/fuzz/library-crashes).
hid_t variable_string_type() {
  hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, H5T_VARIABLE);
  H5Tset_cset(type, H5T_CSET_UTF8);
  return type;
}

// A fixed-length string of `size` bytes (at least 1: HDF5 has no empty fixed string), padded
// with NULs: what every string this writer stores is. Read in the file's character set
// (`cset`): HDF5 converts no fixed-length string from one set to another, and another
// program's file may hold ASCII ones.
hid_t fixed_string_type(std::size_t size, H5T_cset_t cset = H5T_CSET_UTF8) {
  hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, std::max<std::size_t>(size, 1));
  H5Tset_strpad(type, H5T_STR_NULLPAD);
  H5Tset_cset(type, cset == H5T_CSET_ASCII ? H5T_CSET_ASCII : H5T_CSET_UTF8);
  return type;
}

// The root attribute that says a file holds no variable-length string and checksums its data
// (fixed-length strings, Fletcher-32 on every dataset, checksummed metadata); its reader then
// refuses a variable-length string as damage instead of handing it to HDF5.
constexpr const char* layout_attribute = "shapepress_hdf5_layout";
constexpr std::int64_t checked_layout = 2;

// Objects tracking their attributes' creation order have HDF5 1.8's object headers, which carry
// a checksum: damage to an attribute is then an error too. (Not by H5Pset_libver_bounds: its
// superblock has a checksum that the image commit() takes before closing leaves stale, and
// H5Fopen refuses the file.) Readable by HDF5 1.8 and later (h5py, ParaView).
struct PropertyList {
  hid_t id;
  ~PropertyList() { H5Pclose(id); }
};
PropertyList object_creation(hid_t kind) {
  PropertyList list{H5Pcreate(kind)};
  H5Pset_attr_creation_order(list.id, H5P_CRT_ORDER_TRACKED);
  return list;
}

// Each dataset chunked (at most about 1 MiB a chunk, along its first dimension) with HDF5's
// Fletcher-32 filter, which needs chunks: a damaged byte of data is then a read error naming the
// file, not a wrong number in a bed. An empty dataset stays contiguous (no data to damage; HDF5
// refuses chunks of extent 0).
hid_t dataset_creation(std::span<const hsize_t> dims, std::size_t element_size) {
  hid_t plist = H5Pcreate(H5P_DATASET_CREATE);
  H5Pset_attr_creation_order(plist, H5P_CRT_ORDER_TRACKED);
  if (dims.empty() || std::find(dims.begin(), dims.end(), hsize_t{0}) != dims.end()) return plist;
  constexpr std::size_t chunk_bytes = 1 << 20;
  std::vector<hsize_t> chunk(dims.begin(), dims.end());
  const std::size_t row_bytes = std::accumulate(dims.begin() + 1, dims.end(), element_size,
                                                [](std::size_t a, hsize_t b) { return a * b; });
  chunk[0] = std::clamp<hsize_t>(chunk_bytes / std::max<std::size_t>(row_bytes, 1), 1, dims[0]);
  H5Pset_chunk(plist, static_cast<int>(chunk.size()), chunk.data());
  H5Pset_fletcher32(plist);
  return plist;
}

}  // namespace

H5Writer::H5Writer(std::filesystem::path final_path, Provenance provenance)
    : final_path_(std::move(final_path)), output_(final_path_), provenance_(std::move(provenance)) {
  silence_hdf5_errors();
  Handle access{H5Pcreate(H5P_FILE_ACCESS), H5Pclose};
  // The core driver without a backing store: the file lives in memory until commit().
  H5Pset_fapl_core(access.id, 1 << 20, 0);
  const PropertyList creation = object_creation(H5P_FILE_CREATE);
  // Most datasets are one chunk: an index node of 8 chunks, not HDF5's 64 (2.5 KB each, which
  // made small files four times their size).
  H5Pset_istore_k(creation.id, 4);
  file_ = H5Fcreate(final_path_.c_str(), H5F_ACC_TRUNC, creation.id, access.id);
  if (file_ < 0)
    throw ComputationError(
        fmt::format("{}: cannot create the HDF5 file in memory", final_path_.string()));
}

H5Writer::~H5Writer() {
  if (file_ >= 0) H5Fclose(static_cast<hid_t>(file_));
}

void H5Writer::group(std::string_view path) {
  // Level by level, so that every group has the checksummed header (object_creation).
  const PropertyList creation = object_creation(H5P_GROUP_CREATE);
  for (std::size_t end = path.find('/', 1);; end = path.find('/', end + 1)) {
    const std::string level = z(path.substr(0, end));
    if (!level.empty() && level != "/" && H5Lexists(file_, level.c_str(), H5P_DEFAULT) <= 0) {
      Handle g{H5Gcreate2(file_, level.c_str(), H5P_DEFAULT, creation.id, H5P_DEFAULT), H5Gclose};
      if (g.id < 0)
        throw ComputationError(
            fmt::format("{}: cannot create group {}", final_path_.string(), level));
    }
    if (end == std::string_view::npos) return;
  }
}

void H5Writer::write_raw(std::string_view dataset, const void* data, std::int64_t type,
                         std::span<const std::size_t> shape) {
  std::vector<hsize_t> dims(shape.begin(), shape.end());
  Handle space{H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose};
  if (const std::size_t slash = dataset.rfind('/'); slash != 0 && slash != dataset.npos)
    group(dataset.substr(0, slash));
  Handle dcpl{dataset_creation(dims, H5Tget_size(static_cast<hid_t>(type))), H5Pclose};
  Handle set{
      H5Dcreate2(file_, z(dataset).c_str(), type, space.id, H5P_DEFAULT, dcpl.id, H5P_DEFAULT),
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
  std::size_t width = 1;
  for (const std::string& v : values)
    width = std::max(width, v.size());
  std::string packed(values.size() * width, '\0');
  for (std::size_t k = 0; k < values.size(); ++k)
    std::copy(values[k].begin(), values[k].end(), packed.begin() + k * width);
  Handle type{fixed_string_type(width), H5Tclose};
  std::size_t n = values.size();
  write_raw(dataset, packed.data(), type.id, std::span<const std::size_t>(&n, 1));
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
  Handle type{fixed_string_type(value.size()), H5Tclose};
  std::string text(value);
  text.resize(std::max<std::size_t>(text.size(), 1), '\0');
  write_attribute(file_, object, name, type.id, text.data(), final_path_);
}

void H5Writer::commit() {
  attribute("/", "shapepress_version", shapepress_version());
  attribute("/", "git_revision", shapepress_git_revision());
  attribute("/", "command_line", provenance_.command_line);
  attribute("/", "config_text", provenance_.config_text);
  attribute("/", "created_utc", iso_time_now());
  if (provenance_.seed) attribute("/", "seed", static_cast<std::int64_t>(*provenance_.seed));
  attribute("/", layout_attribute, checked_layout);
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
  // A file without the attribute was written before layout 2 (or by another program): its
  // variable-length strings are read as before.
  try {
    if (H5Aexists_by_name(file_, "/", layout_attribute, H5P_DEFAULT) > 0)
      fixed_strings_only_ = attribute_int64("/", layout_attribute) >= checked_layout;
  } catch (const InputError&) {
    H5Fclose(file_);  // no destructor runs for a constructor that throws
    throw;
  }
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

// HDF5 1.10.8 runs a chunk through its filters at the size the chunk index states: a damaged
// size under Fletcher-32's 4 bytes makes it checksum some 2^64 bytes (a crash found by
// tests/fuzz), and the index's B-tree has no checksum of its own. So every stored chunk's size
// and place are checked against the file before a read; a chunk of this writer (Fletcher-32
// alone) is exactly its values and the checksum.
void H5Reader::check_chunks(std::int64_t dataset_id, std::string_view dataset) const {
  const auto set = static_cast<hid_t>(dataset_id);
  const auto damaged = [&](std::string_view what) {
    return InputError(
        fmt::format("{}: dataset {}: {} (a damaged file)", path_.string(), dataset, what));
  };
  Handle plist{H5Dget_create_plist(set), H5Pclose};
  if (plist.id < 0) throw damaged("its creation properties cannot be read");
  if (H5Pget_layout(plist.id) != H5D_CHUNKED) return;
  Handle space{H5Dget_space(set), H5Sclose};
  Handle type{H5Dget_type(set), H5Tclose};
  const int rank = H5Pget_chunk(plist.id, 0, nullptr);
  if (space.id < 0 || type.id < 0 || rank <= 0 || rank != H5Sget_simple_extent_ndims(space.id))
    throw damaged("its chunks do not match its shape");
  std::vector<hsize_t> chunk(static_cast<std::size_t>(rank)), dims(chunk.size());
  H5Pget_chunk(plist.id, rank, chunk.data());
  H5Sget_simple_extent_dims(space.id, dims.data(), nullptr);
  std::error_code ec;
  const std::uintmax_t bytes = std::filesystem::file_size(path_, ec);
  if (ec) throw InputError(fmt::format("{}: cannot read its size", path_.string()));
  // The chunks' grid: more chunks than the file has bytes is a damaged extent or chunk shape.
  std::uintmax_t chunks = 1, chunk_bytes = H5Tget_size(type.id);
  for (std::size_t k = 0; k < chunk.size(); ++k) {
    if (chunk[k] == 0) throw damaged("a chunk of extent 0");
    if (dims[k] == 0) return;  // no values, no chunk
    chunks *= (dims[k] + chunk[k] - 1) / chunk[k];
    chunk_bytes *= chunk[k];
    if (chunks > bytes || chunk_bytes > 1000 * (bytes + (1u << 20)))
      throw damaged("more chunks, or larger ones, than the file holds");
  }
  const int filters = H5Pget_nfilters(plist.id);
  unsigned flags = 0;
  std::size_t values = 0;
  const bool fletcher32 = H5Pget_filter_by_id2(plist.id, H5Z_FILTER_FLETCHER32, &flags, &values,
                                               nullptr, 0, nullptr, nullptr) >= 0;
  const bool ours = fixed_strings_only_ && fletcher32 && filters == 1;
  std::vector<hsize_t> at(chunk.size(), 0);
  for (;;) {
    unsigned mask = 0;
    haddr_t address = HADDR_UNDEF;
    hsize_t size = 0;
    if (H5Dget_chunk_info_by_coord(set, at.data(), &mask, &address, &size) < 0)
      throw damaged("its chunk index cannot be read");
    if (address != HADDR_UNDEF && (size > bytes || address > bytes - size ||
                                   (fletcher32 && size < 4) || (ours && size != chunk_bytes + 4)))
      throw damaged(fmt::format("a chunk of {} bytes at {}", size, address));
    std::size_t k = at.size();
    while (k > 0) {  // the next chunk, the last dimension fastest
      --k;
      at[k] += chunk[k];
      if (at[k] < dims[k]) break;
      at[k] = 0;
      if (k == 0) return;
    }
  }
}

void H5Reader::read_raw(std::string_view dataset, void* out, std::int64_t type) const {
  Handle set{H5Dopen2(file_, z(dataset).c_str(), H5P_DEFAULT), H5Dclose};
  if (set.id < 0)
    throw InputError(fmt::format("{}: cannot read dataset {}", path_.string(), dataset));
  check_chunks(set.id, dataset);
  if (H5Dread(set.id, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out) < 0)
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

namespace {

// The text of a fixed-length string of `width` bytes: up to its first NUL (NULTERM and NULLPAD
// alike), spaces kept (SPACEPAD is not ours).
std::string fixed_string_text(const char* bytes, std::size_t width) {
  return std::string(bytes, std::find(bytes, bytes + width, '\0'));
}

}  // namespace

// The string type of a dataset or attribute (`type`, its file type) as this reader takes it:
// fixed-length (its width returned), or variable-length (0 returned) only in a file written
// before layout 2; InputError otherwise (not a string, or a damaged file).
std::size_t H5Reader::string_width(std::int64_t type, std::string_view object,
                                   std::string_view name) const {
  const auto id = static_cast<hid_t>(type);
  if (type < 0 || H5Tget_class(id) != H5T_STRING)
    throw InputError(fmt::format("{}: {}{} is not text", path_.string(), object, name));
  const htri_t variable = H5Tis_variable_str(id);
  if (variable < 0)
    throw InputError(fmt::format("{}: the type of {}{} is damaged", path_.string(), object, name));
  if (variable > 0) {
    if (fixed_strings_only_)
      throw InputError(
          fmt::format("{}: {}{} is a variable-length string, which this file's writer never "
                      "stores (a damaged file)",
                      path_.string(), object, name));
    return 0;
  }
  return H5Tget_size(id);
}

std::vector<std::string> H5Reader::strings(std::string_view dataset) const {
  std::vector<std::size_t> dims = shape_of(dataset);
  std::size_t count = dims.empty() ? 1 : dims[0];
  Handle set{H5Dopen2(file_, z(dataset).c_str(), H5P_DEFAULT), H5Dclose};
  Handle file_type{set.id >= 0 ? H5Dget_type(set.id) : -1, H5Tclose};
  const std::size_t width = string_width(file_type.id, dataset, "");
  std::vector<std::string> out;
  if (width > 0) {
    check_count(dataset, count, width);
    std::string bytes(count * width, '\0');
    Handle type{fixed_string_type(width, H5Tget_cset(file_type.id)), H5Tclose};
    if (count > 0) read_raw(dataset, bytes.data(), type.id);
    for (std::size_t k = 0; k < count; ++k)
      out.push_back(fixed_string_text(bytes.data() + k * width, width));
    return out;
  }
  check_count(dataset, count, sizeof(char*));
  std::vector<char*> pointers(count, nullptr);
  Handle type{variable_string_type(), H5Tclose};
  if (count > 0) read_raw(dataset, pointers.data(), type.id);
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
  const std::string target = object.empty() ? "/" : z(object);
  Handle attr{H5Aopen_by_name(file_, target.c_str(), z(name).c_str(), H5P_DEFAULT, H5P_DEFAULT),
              H5Aclose};
  if (attr.id < 0)
    throw InputError(
        fmt::format("{}: attribute '{}' of {} is missing", path_.string(), name, target));
  Handle file_type{H5Aget_type(attr.id), H5Tclose};
  Handle space{H5Aget_space(attr.id), H5Sclose};
  if (space.id < 0 || H5Sget_simple_extent_npoints(space.id) != 1)
    throw InputError(
        fmt::format("{}: attribute '{}' of {} is not one string", path_.string(), name, target));
  const std::size_t width = string_width(file_type.id, target, "'s attribute " + z(name));
  if (width > 0) {
    check_count(name, 1, width);
    std::string bytes(width, '\0');
    Handle type{fixed_string_type(width, H5Tget_cset(file_type.id)), H5Tclose};
    if (H5Aread(attr.id, type.id, bytes.data()) < 0)
      throw InputError(
          fmt::format("{}: cannot read attribute '{}' of {}", path_.string(), name, target));
    return fixed_string_text(bytes.data(), width);
  }
  char* pointer = nullptr;
  Handle type{variable_string_type(), H5Tclose};
  if (H5Aread(attr.id, type.id, &pointer) < 0)
    throw InputError(
        fmt::format("{}: cannot read attribute '{}' of {}", path_.string(), name, target));
  std::string value = pointer != nullptr ? pointer : "";
  H5free_memory(pointer);
  return value;
}

}  // namespace shapepress

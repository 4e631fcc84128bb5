#include "imaging/sem_tiff.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>
#include <vector>

#include "common/atomic_file.hpp"
#include "common/error.hpp"

namespace shapepress::imaging {
namespace {

constexpr std::uint16_t tiff_type_ascii = 2;
constexpr std::uint16_t tiff_type_short = 3;
constexpr std::uint16_t tiff_type_long = 4;

// Reads integers in the byte order the TIFF header declared.
class TiffBytes {
 public:
  TiffBytes(std::vector<char> bytes, bool little_endian)
      : bytes_(std::move(bytes)), little_endian_(little_endian) {}
  bool has(std::uint64_t offset, std::uint64_t size) const {
    return offset <= bytes_.size() && size <= bytes_.size() - offset;
  }
  std::uint32_t read(std::uint64_t offset, int size) const {
    std::uint32_t value = 0;
    for (int i = 0; i < size; ++i) {
      auto byte = static_cast<std::uint8_t>(bytes_[offset + (little_endian_ ? size - 1 - i : i)]);
      value = (value << 8) | byte;
    }
    return value;
  }
  std::string text(std::uint64_t offset, std::uint64_t size) const {
    std::string s(bytes_.data() + offset, bytes_.data() + offset + size);
    return s.substr(0, s.find('\0'));
  }

 private:
  std::vector<char> bytes_;
  bool little_endian_;
};

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t'))
    s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

std::optional<double> to_double(std::string_view text) {
  double value = 0.0;
  auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || !std::isfinite(value))
    return std::nullopt;
  return value;
}

void put(std::string& out, std::uint32_t value, int size) {
  for (int i = 0; i < size; ++i)
    out.push_back(static_cast<char>((value >> (8 * i)) & 0xff));
}

}  // namespace

std::optional<std::string> read_tiff_ascii_tag(const std::filesystem::path& path,
                                               std::uint16_t tag) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.size() < 8) return std::nullopt;
  bool little = bytes[0] == 'I' && bytes[1] == 'I';
  bool big = bytes[0] == 'M' && bytes[1] == 'M';
  if (!little && !big) return std::nullopt;
  TiffBytes tiff(std::move(bytes), little);
  if (tiff.read(2, 2) != 42) return std::nullopt;  // not classic TIFF (BigTIFF has 43)
  auto malformed = [&](std::string_view what) {
    return InputError(fmt::format("{}: malformed TIFF ({})", path.string(), what));
  };
  std::uint64_t ifd = tiff.read(4, 4);
  if (!tiff.has(ifd, 2)) throw malformed("first IFD offset beyond the end of the file");
  std::uint32_t entries = tiff.read(ifd, 2);
  if (!tiff.has(ifd + 2, 12ull * entries)) throw malformed("IFD entries truncated");
  for (std::uint32_t i = 0; i < entries; ++i) {
    std::uint64_t entry = ifd + 2 + 12ull * i;
    if (tiff.read(entry, 2) != tag) continue;
    std::uint32_t type = tiff.read(entry + 2, 2);
    std::uint64_t count = tiff.read(entry + 4, 4);
    if (type != tiff_type_ascii && type != 1 && type != 7)  // ASCII, BYTE or UNDEFINED text
      throw malformed(fmt::format("tag {} has type {}, expected text", tag, type));
    std::uint64_t offset = count <= 4 ? entry + 8 : tiff.read(entry + 8, 4);
    if (!tiff.has(offset, count)) throw malformed(fmt::format("tag {} data truncated", tag));
    return tiff.text(offset, count);
  }
  return std::nullopt;
}

SemMetadata parse_fei_metadata(std::string_view ini_text) {
  SemMetadata metadata;
  std::string_view section;
  std::optional<int> scan_rows;
  while (!ini_text.empty()) {
    auto end = ini_text.find('\n');
    std::string_view line = trim(ini_text.substr(0, end));
    ini_text.remove_prefix(end == std::string_view::npos ? ini_text.size() : end + 1);
    if (line.size() >= 2 && line.front() == '[' && line.back() == ']') {
      section = line.substr(1, line.size() - 2);
      continue;
    }
    auto equals = line.find('=');
    if (equals == std::string_view::npos) continue;
    std::string_view key = trim(line.substr(0, equals));
    std::optional<double> value = to_double(trim(line.substr(equals + 1)));
    if (!value) continue;
    if (section == "Scan" && key == "PixelWidth" && *value > 0) metadata.pixel_width_m = *value;
    if (key == "ResolutionY" && *value >= 1) {
      if (section == "Image") metadata.data_rows = static_cast<int>(*value);
      if (section == "Scan") scan_rows = static_cast<int>(*value);
    }
  }
  if (!metadata.data_rows) metadata.data_rows = scan_rows;
  return metadata;
}

SemMetadata read_sem_metadata(const std::filesystem::path& path) {
  for (std::uint16_t tag : {fei_metadata_tag, fei_sfeg_tag}) {
    if (auto text = read_tiff_ascii_tag(path, tag)) return parse_fei_metadata(*text);
  }
  return {};
}

void write_sem_tiff(const std::filesystem::path& path, const GrayImage& image,
                    std::string_view metadata_text) {
  const std::uint32_t width = static_cast<std::uint32_t>(image.width);
  const std::uint32_t height = static_cast<std::uint32_t>(image.height);
  constexpr std::uint32_t entry_count = 9;
  const std::uint32_t ifd_offset = 8;
  const std::uint32_t text_offset = ifd_offset + 2 + 12 * entry_count + 4;
  const std::uint32_t text_size = static_cast<std::uint32_t>(metadata_text.size()) + 1;
  const std::uint32_t pixel_offset = text_offset + text_size + (text_size % 2);  // word aligned

  std::string out = "II";
  put(out, 42, 2);
  put(out, ifd_offset, 4);
  put(out, entry_count, 2);
  auto entry = [&](std::uint16_t tag, std::uint16_t type, std::uint32_t count,
                   std::uint32_t value) {
    put(out, tag, 2);
    put(out, type, 2);
    put(out, count, 4);
    put(out, value, 4);  // SHORT values sit in the low bytes (little-endian)
  };
  // Entries sorted by tag, as TIFF 6.0 requires.
  entry(256, tiff_type_long, 1, width);
  entry(257, tiff_type_long, 1, height);
  entry(258, tiff_type_short, 1, 8);  // BitsPerSample
  entry(259, tiff_type_short, 1, 1);  // no compression
  entry(262, tiff_type_short, 1, 1);  // BlackIsZero
  entry(273, tiff_type_long, 1, pixel_offset);
  entry(278, tiff_type_long, 1, height);  // RowsPerStrip: one strip
  entry(279, tiff_type_long, 1, width * height);
  entry(fei_metadata_tag, tiff_type_ascii, text_size, text_offset);
  put(out, 0, 4);  // no next IFD
  out.append(metadata_text);
  out.push_back('\0');
  if (text_size % 2) out.push_back('\0');
  out.reserve(out.size() + image.pixels.size());
  for (float v : image.pixels)
    out.push_back(static_cast<char>(
        static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f))));
  write_file_atomically(path, out);
}

}  // namespace shapepress::imaging

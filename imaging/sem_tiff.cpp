#include "imaging/sem_tiff.hpp"

#include <fmt/format.h>
#include <tiffio.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <fstream>
#include <memory>
#include <vector>

#include "common/atomic_file.hpp"
#include "common/error.hpp"

namespace shapepress::imaging {
namespace {

constexpr std::uint16_t tiff_type_ascii = 2;
constexpr std::uint16_t tiff_type_short = 3;
constexpr std::uint16_t tiff_type_long = 4;

// "II*\0" or "MM\0*": a classic TIFF. Anything else (a PNG, a BigTIFF, an unreadable file) has no
// FEI tag, and is not handed to libtiff, whose failure to open it would read as a damaged TIFF.
bool is_classic_tiff(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::array<char, 4> magic{};
  if (!in.read(magic.data(), magic.size())) return false;
  return std::string_view(magic.data(), 4) == std::string_view("II*\0", 4) ||
         std::string_view(magic.data(), 4) == std::string_view("MM\0*", 4);
}

// libtiff's messages about one file, kept for the InputError instead of printed on stderr.
struct TiffMessages {
  std::string error;  // the first
  std::vector<std::string> warnings;
};

std::string formatted(const char* module, const char* format, va_list args) {
  std::array<char, 512> text{};
  std::vsnprintf(text.data(), text.size(), format, args);
  return fmt::format("{}: {}", module ? module : "libtiff", text.data());
}

int keep_error(TIFF*, void* user_data, const char* module, const char* format, va_list args) {
  auto& messages = *static_cast<TiffMessages*>(user_data);
  if (messages.error.empty()) messages.error = formatted(module, format, args);
  return 1;  // handled: libtiff's global handler stays silent
}

int keep_warning(TIFF*, void* user_data, const char* module, const char* format, va_list args) {
  static_cast<TiffMessages*>(user_data)->warnings.push_back(formatted(module, format, args));
  return 1;
}

struct TiffCloser {
  void operator()(TIFF* tiff) const noexcept { TIFFClose(tiff); }
};

// The first IFD of a classic TIFF, opened by libtiff with its messages collected.
std::unique_ptr<TIFF, TiffCloser> open_tiff(const std::filesystem::path& path,
                                            TiffMessages& messages) {
  std::unique_ptr<TIFFOpenOptions, decltype(&TIFFOpenOptionsFree)> options(TIFFOpenOptionsAlloc(),
                                                                           &TIFFOpenOptionsFree);
  TIFFOpenOptionsSetErrorHandlerExtR(options.get(), keep_error, &messages);
  TIFFOpenOptionsSetWarningHandlerExtR(options.get(), keep_warning, &messages);
  return std::unique_ptr<TIFF, TiffCloser>(TIFFOpenExt(path.c_str(), "r", options.get()));
}

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
  if (!is_classic_tiff(path)) return std::nullopt;
  auto malformed = [&](std::string_view what) {
    return InputError(fmt::format("{}: malformed TIFF ({})", path.string(), what));
  };
  TiffMessages messages;
  const auto tiff = open_tiff(path, messages);
  if (!tiff || !messages.error.empty())
    throw malformed(messages.error.empty() ? "libtiff cannot read its first directory"
                                           : messages.error);
  // A private tag libtiff does not know becomes an anonymous field of the file's own type when
  // the directory has it.
  const TIFFField* field = TIFFFindField(tiff.get(), tag, TIFF_ANY);
  if (!field) return std::nullopt;
  const TIFFDataType type = TIFFFieldDataType(field);
  if (type != TIFF_ASCII && type != TIFF_BYTE && type != TIFF_UNDEFINED)
    throw malformed(fmt::format("tag {} has type {}, expected text", tag, static_cast<int>(type)));
  const char* data = nullptr;
  std::uint32_t size = 0;
  bool read = false;
  if (TIFFFieldPassCount(field) && TIFFFieldReadCount(field) == TIFF_VARIABLE2) {
    read = TIFFGetField(tiff.get(), tag, &size, &data) == 1;
  } else if (TIFFFieldPassCount(field)) {
    std::uint16_t count = 0;
    read = TIFFGetField(tiff.get(), tag, &count, &data) == 1;
    size = count;
  } else {
    read = TIFFGetField(tiff.get(), tag, &data) == 1;
    size = data ? static_cast<std::uint32_t>(std::char_traits<char>::length(data)) : 0;
  }
  if (!read) {
    // In the directory but not read: libtiff ignored it with a warning (its data lies beyond
    // the end of the file).
    if (!TIFFFieldIsAnonymous(field)) return std::nullopt;
    const std::string named = fmt::format("\"Tag {}\"", tag);
    const auto said = std::find_if(messages.warnings.begin(), messages.warnings.end(),
                                   [&](const std::string& w) { return w.find(named) != w.npos; });
    throw malformed(said != messages.warnings.end() ? *said
                                                    : fmt::format("tag {} data unreadable", tag));
  }
  const std::string text(data, size);
  return text.substr(0, text.find('\0'));
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

#pragma once
// Thermo Fisher / FEI SEM TIFF metadata. The instrument stores an INI-like text block
// ("[Scan]\nPixelWidth=2.5e-08\n...") in a private TIFF tag; libtiff reads it, and the
// synthetic SEM images are written in the same layout.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "imaging/image.hpp"

namespace shapepress::imaging {

inline constexpr std::uint16_t fei_metadata_tag = 34682;  // FEI_HELIOS, INI text
inline constexpr std::uint16_t fei_sfeg_tag = 34680;      // FEI_SFEG, older instruments

struct SemMetadata {
  std::optional<double> pixel_width_m;  // [Scan] PixelWidth, metres
  std::optional<int> data_rows;         // [Image] ResolutionY: rows above the information bar
};

// The ASCII text of a TIFF tag in the first IFD, if the file is a TIFF and has it.
// Throws InputError when the file claims to be a TIFF but its IFD is truncated or malformed.
std::optional<std::string> read_tiff_ascii_tag(const std::filesystem::path& path,
                                               std::uint16_t tag);

// Parses the INI text: PixelWidth from the [Scan] section, ResolutionY from [Image] (or [Scan]).
SemMetadata parse_fei_metadata(std::string_view ini_text);

// Metadata of an image file: empty when the file is not a TIFF or has no FEI tag.
SemMetadata read_sem_metadata(const std::filesystem::path& path);

// Writes an 8-bit grayscale, uncompressed, little-endian TIFF with `metadata_text` in tag
// 34682, as an FEI instrument does (the synthetic SEM images carry their pixel size this way).
void write_sem_tiff(const std::filesystem::path& path, const GrayImage& image,
                    std::string_view metadata_text);

}  // namespace shapepress::imaging

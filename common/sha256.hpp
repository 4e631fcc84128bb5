#pragma once
// SHA-256 (FIPS 180-4) of a byte string or a file, as 64 lowercase hex digits: the content hash
// of every input a run.json lists. Implemented here because none of the linked Debian libraries
// (OpenCV, Boost.Iostreams, HDF5, ...) exposes one, and a hash is too small to add a package for.
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace shapepress {

class Sha256 {
 public:
  Sha256();
  void update(std::string_view bytes);
  std::string hex_digest();  // finishes the hash; call once

 private:
  void compress(const unsigned char* block);
  std::uint32_t state_[8];
  unsigned char buffer_[64];
  std::size_t buffered_ = 0;
  std::uint64_t length_ = 0;  // bytes hashed so far
};

std::string sha256_hex(std::string_view bytes);
// Streams the file (images and snapshots can be large); InputError naming it if unreadable.
std::string sha256_file(const std::filesystem::path& path);

}  // namespace shapepress

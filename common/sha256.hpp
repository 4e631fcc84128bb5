#pragma once
// SHA-256 (FIPS 180-4) of a byte string or a file, as 64 lowercase hex digits: the content hash
// of every input a run.json lists. The digest is OpenSSL's (libcrypto's EVP interface), whose
// implementation is maintained, tested against the NIST vectors and vectorised.
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>

struct evp_md_ctx_st;  // OpenSSL's EVP_MD_CTX; its header stays in the .cpp

namespace shapepress {

class Sha256 {
 public:
  Sha256();
  void update(std::string_view bytes);
  std::string hex_digest();  // finishes the hash; call once

 private:
  struct ContextDeleter {
    void operator()(evp_md_ctx_st* context) const noexcept;
  };
  std::unique_ptr<evp_md_ctx_st, ContextDeleter> context_;
};

std::string sha256_hex(std::string_view bytes);
// Streams the file (images and snapshots can be large); InputError naming it if unreadable.
std::string sha256_file(const std::filesystem::path& path);

}  // namespace shapepress

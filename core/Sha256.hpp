// SHA-256 (FIPS 180-4) of bytes and of files: the fingerprint of a loaded plug-in library and the
// checksum that guards a checkpoint's content.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>

namespace bc::core {

class Sha256 {
 public:
  Sha256();
  Sha256& update(const void* data, std::size_t size);
  Sha256& update(const std::string& text) { return update(text.data(), text.size()); }
  // The digest as 64 lower-case hexadecimal digits (the object is spent afterwards).
  std::string hex();

 private:
  void block(const unsigned char* p);
  std::uint32_t h_[8];
  unsigned char buffer_[64];
  std::size_t used_ = 0;
  std::uint64_t bytes_ = 0;
};

std::string sha256Hex(const std::string& text);
// The digest of a file's bytes; throws std::runtime_error naming the file when it cannot be read.
std::string sha256File(const std::filesystem::path& path);

}  // namespace bc::core

#pragma once
// Content hashes that identify imported files, array definitions and
// processing configs in the catalogue (idempotent import, stale results).
// SHA-256 (FIPS 180-4) as lowercase hex.
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>

namespace napkin::formats {

// Incremental SHA-256.
class Sha256 {
 public:
  Sha256();
  void Update(std::span<const std::uint8_t> bytes);
  void Update(std::string_view text);
  // The digest as 64 lowercase hex characters; the object is spent afterwards.
  std::string HexDigest();

 private:
  void Block(const std::uint8_t* block);
  std::uint32_t state_[8];
  std::uint8_t buffer_[64];
  std::size_t buffered_ = 0;
  std::uint64_t total_bytes_ = 0;
};

std::string Sha256Hex(std::string_view bytes);
// Hash of a file's bytes, or of a folder's files (relative path and bytes, in
// sorted path order). Throws InputError naming the path when unreadable.
std::string HashPath(const std::filesystem::path& path);

}  // namespace napkin::formats

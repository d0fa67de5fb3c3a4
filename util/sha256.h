#pragma once
// SHA-256 (FIPS 180-4) as lowercase hex: the content hashes that identify
// imported files, array definitions and processing configs in the catalogue
// (idempotent import, stale results).
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace napkin::util {

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
}  // namespace napkin::util

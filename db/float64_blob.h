#pragma once
// Signal BLOBs: IEEE-754 float64 values, little-endian, 8 bytes each, or
// (derived channels stored as "float32", docs/formats.md "Derived-channel
// storage") IEEE-754 float32 values, little-endian, 4 bytes each, whatever
// the host's byte order (the catalogue file is portable).
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace napkin::db {

// Reverses the byte order of a 32-bit word.
constexpr std::uint32_t ByteSwap32(std::uint32_t word) {
  std::uint32_t swapped = 0;
  for (int byte = 0; byte < 4; ++byte) {
    swapped = (swapped << 8) | (word & 0xffu);
    word >>= 8;
  }
  return swapped;
}

// Reverses the byte order of a 64-bit word.
constexpr std::uint64_t ByteSwap64(std::uint64_t word) {
  std::uint64_t swapped = 0;
  for (int byte = 0; byte < 8; ++byte) {
    swapped = (swapped << 8) | (word & 0xffu);
    word >>= 8;
  }
  return swapped;
}

// The little-endian bytes of `values`. On a little-endian host this is a view
// of the values themselves (no copy) and `scratch` is untouched; otherwise
// the swapped bytes are written to `scratch` and viewed there.
std::span<const std::byte> Float64LittleEndianBytes(std::span<const double> values,
                                                    std::vector<std::byte>& scratch);

// A copy of `values` as little-endian bytes.
std::vector<std::byte> EncodeFloat64LittleEndian(std::span<const double> values);

// Decodes little-endian float64 `bytes` into `values`, bit for bit.
// Throws std::invalid_argument when bytes.size() != 8 * values.size().
void DecodeFloat64LittleEndian(std::span<const std::byte> bytes, std::span<double> values);

// The little-endian float32 bytes of `values`, each rounded to the nearest
// float (static_cast<float>), written to `scratch` and viewed there.
std::span<const std::byte> Float32LittleEndianBytes(std::span<const double> values,
                                                    std::vector<std::byte>& scratch);

// A copy of `values` as little-endian float32 bytes (rounded to nearest).
std::vector<std::byte> EncodeFloat32LittleEndian(std::span<const double> values);

// Decodes little-endian float32 `bytes` into `values` (each float widened to
// double exactly). Throws std::invalid_argument when
// bytes.size() != 4 * values.size().
void DecodeFloat32LittleEndian(std::span<const std::byte> bytes, std::span<double> values);

}  // namespace napkin::db

#include "db/float64_blob.h"

#include <bit>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

namespace napkin::db {

namespace {
constexpr bool kHostIsLittleEndian = std::endian::native == std::endian::little;
static_assert(sizeof(double) == 8 && std::numeric_limits<double>::is_iec559,
              "signal BLOBs assume IEEE-754 binary64 doubles");
static_assert(sizeof(float) == 4 && std::numeric_limits<float>::is_iec559,
              "float32 BLOBs assume IEEE-754 binary32 floats");
}  // namespace

std::span<const std::byte> Float64LittleEndianBytes(std::span<const double> values,
                                                    std::vector<std::byte>& scratch) {
  if constexpr (kHostIsLittleEndian) {
    return std::as_bytes(values);
  } else {
    scratch.resize(values.size() * 8);
    for (std::size_t i = 0; i < values.size(); ++i) {
      const std::uint64_t swapped = ByteSwap64(std::bit_cast<std::uint64_t>(values[i]));
      std::memcpy(scratch.data() + 8 * i, &swapped, 8);
    }
    return scratch;
  }
}

std::vector<std::byte> EncodeFloat64LittleEndian(std::span<const double> values) {
  std::vector<std::byte> scratch;
  const std::span<const std::byte> bytes = Float64LittleEndianBytes(values, scratch);
  if constexpr (kHostIsLittleEndian) scratch.assign(bytes.begin(), bytes.end());
  return scratch;
}

void DecodeFloat64LittleEndian(std::span<const std::byte> bytes, std::span<double> values) {
  if (bytes.size() != 8 * values.size())
    throw std::invalid_argument("float64 BLOB of " + std::to_string(bytes.size()) + " bytes cannot hold " +
                                std::to_string(values.size()) + " samples");
  if (bytes.empty()) return;
  if constexpr (kHostIsLittleEndian) {
    std::memcpy(values.data(), bytes.data(), bytes.size());
  } else {
    for (std::size_t i = 0; i < values.size(); ++i) {
      std::uint64_t word = 0;
      std::memcpy(&word, bytes.data() + 8 * i, 8);
      values[i] = std::bit_cast<double>(ByteSwap64(word));
    }
  }
}

std::span<const std::byte> Float32LittleEndianBytes(std::span<const double> values,
                                                    std::vector<std::byte>& scratch) {
  scratch.resize(values.size() * 4);
  for (std::size_t i = 0; i < values.size(); ++i) {
    std::uint32_t word = std::bit_cast<std::uint32_t>(static_cast<float>(values[i]));
    if constexpr (!kHostIsLittleEndian) word = ByteSwap32(word);
    std::memcpy(scratch.data() + 4 * i, &word, 4);
  }
  return scratch;
}

std::vector<std::byte> EncodeFloat32LittleEndian(std::span<const double> values) {
  std::vector<std::byte> scratch;
  Float32LittleEndianBytes(values, scratch);
  return scratch;
}

void DecodeFloat32LittleEndian(std::span<const std::byte> bytes, std::span<double> values) {
  if (bytes.size() != 4 * values.size())
    throw std::invalid_argument("float32 BLOB of " + std::to_string(bytes.size()) + " bytes cannot hold " +
                                std::to_string(values.size()) + " samples");
  for (std::size_t i = 0; i < values.size(); ++i) {
    std::uint32_t word = 0;
    std::memcpy(&word, bytes.data() + 4 * i, 4);
    if constexpr (!kHostIsLittleEndian) word = ByteSwap32(word);
    values[i] = static_cast<double>(std::bit_cast<float>(word));
  }
}

}  // namespace napkin::db

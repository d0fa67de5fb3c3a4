#pragma once
// Distance in units in the last place between two floats or two doubles, for
// tests that hold a result to a few ulps of a reference (0 for -0 and +0;
// NaN is at distance 0 from NaN only).
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace napkin::test_support {

template <typename Real, typename Bits>
std::uint64_t UlpDistanceOf(Real a, Real b) {
  if (std::isnan(a) || std::isnan(b))
    return std::isnan(a) && std::isnan(b) ? 0 : std::numeric_limits<std::uint64_t>::max();
  // Map the sign-magnitude bit patterns onto one ordered integer line.
  const auto ordered = [](Real x) -> std::int64_t {
    const auto bits = std::bit_cast<Bits>(x);
    return bits < 0 ? std::int64_t{std::numeric_limits<Bits>::min()} - bits : std::int64_t{bits};
  };
  const std::int64_t oa = ordered(a), ob = ordered(b);
  return oa > ob ? static_cast<std::uint64_t>(oa) - static_cast<std::uint64_t>(ob)
                 : static_cast<std::uint64_t>(ob) - static_cast<std::uint64_t>(oa);
}

inline std::uint64_t UlpDistance(float a, float b) { return UlpDistanceOf<float, std::int32_t>(a, b); }
inline std::uint64_t UlpDistance(double a, double b) { return UlpDistanceOf<double, std::int64_t>(a, b); }

}  // namespace napkin::test_support

#include "engine/finite_samples.h"

#include <cmath>
#include <cstdint>
#include <limits>

#include "engine/kinematics_completer.h"

namespace napkin::engine::internal {

// |x| <= the largest double is false exactly for an infinity and a NaN. The
// count of the others (no branch, no early exit) is a loop GCC vectorizes
// with AVX2 (SSE2 has no vector type for 64-bit counts of double
// comparisons), so it is compiled for both (NAPKIN_SAMPLE_LOOP_CLONES,
// engine/kinematics_completer.h); a count is the same in either.
NAPKIN_SAMPLE_LOOP_CLONES bool AllFinite(const double* samples, Eigen::Index count) {
  constexpr double kLargest = std::numeric_limits<double>::max();
  std::int64_t non_finite = 0;
  for (Eigen::Index k = 0; k < count; ++k) non_finite += !(std::abs(samples[k]) <= kLargest);
  return non_finite == 0;
}

}  // namespace napkin::engine::internal

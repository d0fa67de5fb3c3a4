#pragma once
// The input checks the injury criteria share (engine/hic.cpp, criteria.cpp,
// damage.cpp): one sentence naming the criterion, the sample and its time.
#include <Eigen/Core>
#include <cmath>
#include <sstream>

#include "common/error.h"
#include "engine/finite_samples.h"

namespace napkin::engine::internal {

inline void CheckInterval(double dt_s, const char* what) {
  if (!(std::isfinite(dt_s) && dt_s > 0.0)) {
    std::ostringstream message;
    message << what << ": the sampling interval " << dt_s << " s is not a finite positive number.";
    throw InputError(message.str());
  }
}

inline void CheckFiniteSamples(const Eigen::Ref<const Eigen::VectorXd>& values, double dt_s, double t0_s,
                               const char* what) {
  if (AllFinite(values.data(), values.size())) return;  // every solved test's: one vectorised pass
  for (Eigen::Index k = 0; k < values.size(); ++k) {
    if (!std::isfinite(values[k])) {
      std::ostringstream message;
      message << what << ": sample " << k << " (t = " << t0_s + static_cast<double>(k) * dt_s
              << " s) is not finite.";
      throw InputError(message.str());
    }
  }
}

}  // namespace napkin::engine::internal

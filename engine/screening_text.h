#pragma once
// What the two halves of screening (engine/channel_checks.cpp,
// engine/screening.cpp) say findings with: numbers in sentences, findings,
// RMS and median.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "engine/screening.h"
#include "engine/units.h"

namespace napkin::engine::internal {

inline double Median(std::vector<double> values) { return MedianInPlace(values); }

inline std::string Number(double value, int digits = 4) {
  std::ostringstream out;
  out << std::setprecision(digits) << value;
  return out.str();
}

inline Finding MakeFinding(Check check, const std::optional<std::string>& channel, Severity severity,
                           std::string detail) {
  Finding finding;
  finding.check = NameOf(check);
  finding.channel = channel;
  finding.severity = severity;
  finding.detail = std::move(detail);
  return finding;
}

// RMS of a residual series; +infinity when the solve diverged (non-finite).
inline double Rms(const Eigen::VectorXd& values) {
  if (values.size() == 0) return 0.0;
  const double rms = std::sqrt(values.squaredNorm() / static_cast<double>(values.size()));
  return std::isfinite(rms) ? rms : std::numeric_limits<double>::infinity();
}

// "from A g to B g", or "from a diverging solve to B g".
inline std::string FromTo(double from_mps2, double to_mps2) {
  const std::string from = std::isfinite(from_mps2) ? "from " + Number(from_mps2 / kStandardGravity) + " g"
                                                    : "from a diverging solve";
  return from + " to " + Number(to_mps2 / kStandardGravity, 3) + " g";
}

}  // namespace napkin::engine::internal

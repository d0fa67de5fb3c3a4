// a3ms, BrIC and the criteria of a result (engine/criteria.h); HIC is
// engine/hic.cpp, DAMAGE engine/damage.cpp.
#include "engine/criteria.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <sstream>
#include <vector>

#include "common/error.h"
#include "engine/cancellation.h"
#include "engine/criterion_checks.h"
#include "engine/finite_samples.h"
#include "engine/injury_risk.h"
#include "engine/summary_fields.h"
#include "engine/units.h"

namespace napkin::engine {

using internal::CheckFiniteSamples;
using internal::CheckInterval;

namespace {

// The number of samples that stand for `duration_s` (each stands for dt),
// after the checks both a3ms definitions share.
Eigen::Index A3msSamples(const Eigen::Ref<const Eigen::VectorXd>& acc_g, double dt_s, double duration_s) {
  CheckInterval(dt_s, "a3ms");
  if (!(std::isfinite(duration_s) && duration_s > 0.0)) {
    std::ostringstream message;
    message << "a3ms: the duration " << duration_s << " s is not positive.";
    throw InputError(message.str());
  }
  CheckFiniteSamples(acc_g, dt_s, 0.0, "a3ms");
  const double needed = std::ceil(duration_s / dt_s * (1.0 - 1e-9));
  if (needed > static_cast<double>(acc_g.size())) {
    std::ostringstream message;
    message << "a3ms: the record (" << acc_g.size() << " samples at " << dt_s << " s) is shorter than "
            << duration_s << " s.";
    throw InputError(message.str());
  }
  return static_cast<Eigen::Index>(needed);
}

}  // namespace

double A3msContinuous(const Eigen::Ref<const Eigen::VectorXd>& acc_g, double dt_s, double duration_s) {
  const Eigen::Index window = A3msSamples(acc_g, dt_s, duration_s);
  // Sliding-window minimum (a deque of indices of increasing values), O(n).
  std::vector<Eigen::Index> candidates(static_cast<std::size_t>(acc_g.size()));
  std::size_t head = 0, tail = 0;  // candidates[head, tail)
  double best = -std::numeric_limits<double>::infinity();
  for (Eigen::Index k = 0; k < acc_g.size(); ++k) {
    while (tail > head && acc_g[candidates[tail - 1]] >= acc_g[k]) --tail;
    candidates[tail++] = k;
    if (candidates[head] <= k - window) ++head;
    if (k + 1 >= window) best = std::max(best, acc_g[candidates[head]]);
  }
  return best;
}

namespace {

// A3ms, partially sorting a copy of acc_g in `values` (its capacity kept).
double A3msIn(const Eigen::Ref<const Eigen::VectorXd>& acc_g, double dt_s, double duration_s,
              std::vector<double>& values) {
  const auto rank =
      static_cast<std::ptrdiff_t>(A3msSamples(acc_g, dt_s, duration_s)) - 1;  // 0-based, descending
  values.assign(acc_g.data(), acc_g.data() + acc_g.size());
  std::nth_element(values.begin(), values.begin() + rank, values.end(), std::greater<>());
  return values[static_cast<std::size_t>(rank)];
}

}  // namespace

double A3ms(const Eigen::Ref<const Eigen::VectorXd>& acc_g, double dt_s, double duration_s) {
  std::vector<double> values;
  return A3msIn(acc_g, dt_s, duration_s, values);
}

double Bric(const Eigen::Ref<const Series3>& omega_body_radps, const Eigen::Vector3d& critical_radps) {
  for (int axis = 0; axis < 3; ++axis) {
    if (!(std::isfinite(critical_radps[axis]) && critical_radps[axis] > 0.0)) {
      std::ostringstream message;
      message << "BrIC: the critical angular velocity about axis "
              << "xyz"[axis] << " (" << critical_radps[axis] << " rad/s) is not positive.";
      throw InputError(message.str());
    }
  }
  if (omega_body_radps.rows() == 0) return 0.0;
  if (!internal::AllFinite(omega_body_radps))
    throw InputError("BrIC: the angular velocity has a non-finite sample.");
  const Eigen::Vector3d peak = omega_body_radps.cwiseAbs().colwise().maxCoeff().transpose();
  return peak.cwiseQuotient(critical_radps).norm();
}

void FillCriteria(const Kinematics& kinematics, const ProcessingConfig& config, TestSummary& summary,
                  const std::atomic<bool>* cancel, CriteriaWork* work) {
  CriteriaWork local;
  CriteriaWork& scratch = work != nullptr ? *work : local;
  const Eigen::Index n = kinematics.size();
  if (n < 2) throw InputError("injury criteria need at least 2 samples of kinematics.");
  // Windows are found on sample indices and their length is steps x dt, so
  // dt must not come from differences of absolute times: a record starting
  // at t0 ~ 2e5 s would lose digits (and a 15 ms window a step).
  const double t0 = kinematics.time_s[0];
  const double dt =
      kinematics.dt_s > 0.0 ? kinematics.dt_s : (kinematics.time_s[n - 1] - t0) / static_cast<double>(n - 1);
  CheckInterval(dt, "injury criteria");
  // An acceleration-only array's CG acceleration is known in body axes only
  // (docs/algorithms.md "Acceleration-only arrays"): its resultant is the same.
  const bool rotation = HasRotation(kinematics);
  Eigen::VectorXd& acc_g = scratch.resultant_g;
  if (rotation)
    acc_g = kinematics.acc_fixed.rowwise().norm() / kStandardGravity;
  else
    acc_g = kinematics.acc_body.rowwise().norm() / kStandardGravity;

  ThrowIfCancelled(cancel);
  const std::vector<HicWindow> hic =
      HicForWindows(acc_g, dt, t0, {kHic15Window, kHic36Window, kUnlimitedHicWindow},
                    config.hic.from_time_zero, cancel, scratch.hic);
  summary.hic15 = hic[0];
  summary.hic36 = hic[1];
  summary.hic_d = HicD(summary.hic36.value);
  summary.hic = hic[2];
  ThrowIfCancelled(cancel);
  summary.a3ms_g = config.a3ms.definition == A3msDefinition::kContinuous
                       ? A3msContinuous(acc_g, dt)
                       : A3msIn(acc_g, dt, kA3msDurationS, scratch.a3ms_values);
  constexpr double kUndetermined = std::numeric_limits<double>::quiet_NaN();
  ThrowIfCancelled(cancel);
  summary.bric = rotation ? Bric(kinematics.omega_body, config.bric.critical_radps) : kUndetermined;
  ThrowIfCancelled(cancel);
  summary.damage =
      rotation ? Damage(kinematics.alpha_body, dt, {}, cancel, scratch.damage_displacement) : kUndetermined;
  for (const SummaryField& field : SummaryFields())  // the criteria their rows compute
    if (field.compute != nullptr) {
      ThrowIfCancelled(cancel);
      field.Set(summary, field.compute(kinematics));
    }
  FillInjuryRisks(summary);
}

}  // namespace napkin::engine

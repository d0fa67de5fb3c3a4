#include "engine/summary.h"

#include <algorithm>
#include <limits>

#include "engine/integration.h"
#include "engine/rotation.h"
#include "engine/units.h"

namespace napkin::engine {

namespace {

// The largest AngleBetween(initial, q_k) over the samples. That angle is
// 2 atan2(|v|, |w|) of the relative quaternion r = initial^-1 q_k, which
// increases with sin^2(angle / 2) = |v|^2 / (|v|^2 + w^2); so the atan2 is
// evaluated only for the samples within 1e-9 (relative) of the largest
// sin^2, far wider than the few ulp by which the two roundings can differ.
// The result is the maximum of the same computed values, at one atan2 per
// candidate instead of one per sample.
double MaxRotationFromInitialRad(const Series4& quat_fixed_from_body) {
  const Eigen::Index n = quat_fixed_from_body.rows();
  const Eigen::Quaterniond initial = QuatAt(quat_fixed_from_body, 0);
  const Eigen::Quaterniond initial_inverse = initial.conjugate();
  Eigen::VectorXd sin_sq_half(n);
  double largest = 0.0;
  for (Eigen::Index k = 0; k < n; ++k) {
    const Eigen::Quaterniond relative = initial_inverse * QuatAt(quat_fixed_from_body, k);
    const double vec_sq = relative.vec().squaredNorm();
    const double norm_sq = vec_sq + relative.w() * relative.w();
    sin_sq_half[k] = norm_sq > 0.0 ? vec_sq / norm_sq : 0.0;
    largest = std::max(largest, sin_sq_half[k]);
  }
  const double cutoff = largest * (1.0 - 1e-9);
  double max_rotation_rad = 0.0;
  for (Eigen::Index k = 0; k < n; ++k)
    if (sin_sq_half[k] >= cutoff)
      max_rotation_rad = std::max(max_rotation_rad, AngleBetween(initial, QuatAt(quat_fixed_from_body, k)));
  return max_rotation_rad;
}

}  // namespace

void SummarizeKinematics(const Kinematics& kin, TestSummary& summary) {
  const Eigen::Index n = kin.size();
  if (n == 0) return;
  if (!HasRotation(kin)) {
    // Acceleration only (docs/algorithms.md "Acceleration-only arrays"): the
    // resultant CG acceleration, and NaN (null in the catalogue, the JSON and
    // `napkin query`) for every field that needs the rotation.
    constexpr double kUndetermined = std::numeric_limits<double>::quiet_NaN();
    summary.peak_omega_body_radps.setConstant(kUndetermined);
    summary.peak_omega_radps = summary.peak_alpha_radps2 = kUndetermined;
    summary.peak_acc_g = kin.acc_body.rowwise().norm().maxCoeff() / kStandardGravity;
    summary.final_quat_wxyz.setConstant(kUndetermined);
    summary.final_roll_pitch_yaw_deg.setConstant(kUndetermined);
    summary.final_pos_fixed_m.setConstant(kUndetermined);
    summary.max_rotation_deg = kUndetermined;
    summary.max_residual_mps2 = kUndetermined;
    return;
  }
  summary.peak_omega_body_radps = kin.omega_body.cwiseAbs().colwise().maxCoeff().transpose();
  summary.peak_omega_radps = kin.omega_body.rowwise().norm().maxCoeff();
  summary.peak_alpha_radps2 = kin.alpha_body.rowwise().norm().maxCoeff();
  summary.peak_acc_g = kin.acc_fixed.rowwise().norm().maxCoeff() / kStandardGravity;

  const Eigen::Quaterniond final_quat = QuatAt(kin.quat_fixed_from_body, n - 1);
  summary.final_quat_wxyz = kin.quat_fixed_from_body.row(n - 1).transpose();
  summary.final_roll_pitch_yaw_deg = RollPitchYaw(final_quat.toRotationMatrix()) * kDegPerRad;
  summary.final_pos_fixed_m = kin.pos_fixed.row(n - 1).transpose();
  summary.max_rotation_deg = MaxRotationFromInitialRad(kin.quat_fixed_from_body) * kDegPerRad;
  summary.max_residual_mps2 = kin.residual.size() > 0 ? kin.residual.maxCoeff() : 0.0;
}

}  // namespace napkin::engine

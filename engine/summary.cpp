#include "engine/summary.h"

#include <algorithm>
#include <limits>

#include "engine/integration.h"
#include "engine/rotation.h"
#include "engine/units.h"

namespace napkin::engine {

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

  const Eigen::Quaterniond initial = QuatAt(kin.quat_fixed_from_body, 0);
  const Eigen::Quaterniond final_quat = QuatAt(kin.quat_fixed_from_body, n - 1);
  summary.final_quat_wxyz = kin.quat_fixed_from_body.row(n - 1).transpose();
  summary.final_roll_pitch_yaw_deg = RollPitchYaw(final_quat.toRotationMatrix()) * kDegPerRad;
  summary.final_pos_fixed_m = kin.pos_fixed.row(n - 1).transpose();
  double max_rotation_rad = 0.0;
  for (Eigen::Index k = 0; k < n; ++k)
    max_rotation_rad = std::max(max_rotation_rad, AngleBetween(initial, QuatAt(kin.quat_fixed_from_body, k)));
  summary.max_rotation_deg = max_rotation_rad * kDegPerRad;
  summary.max_residual_mps2 = kin.residual.size() > 0 ? kin.residual.maxCoeff() : 0.0;
}

}  // namespace napkin::engine

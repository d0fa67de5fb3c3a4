#pragma once
// Rotations on SO(3). Convention (docs/formats.md): R = fixed_from_body, so a
// vector in body axes times R gives fixed axes; dR/dt = R [omega_body]x.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace napkin::engine {

Eigen::Matrix3d Rx(double angle_rad);
Eigen::Matrix3d Ry(double angle_rad);
Eigen::Matrix3d Rz(double angle_rad);

// Initial body-to-fixed rotation from the test's initial orientation,
// R0 = Rx(phi) Ry(theta) Rz(psi) (report eq. 2.1-14/15 and the LC_COMP
// listing's T initialisation).
Eigen::Matrix3d InitialFixedFromBody(const Eigen::Vector3d& phi_theta_psi_rad);

// Skew-symmetric cross-product matrix: Skew(a) * b = a x b.
Eigen::Matrix3d Skew(const Eigen::Vector3d& v);

// cos(theta/2) and sin(theta/2)/theta of QuaternionExp for t = theta^2 <=
// kQuaternionExpTaylorMaxSquaredAngle: their Taylor series in t through t^4,
// exact in double there (the first omitted terms are t^5 / 3.7e9 and
// t^5 / 8.2e10, below 3e-20).
inline constexpr double kQuaternionExpTaylorMaxSquaredAngle = 0.01;
inline void QuaternionExpTaylor(double t, double& w, double& k) {
  w = 1.0 + t * (-1.0 / 8.0 + t * (1.0 / 384.0 + t * (-1.0 / 46080.0 + t * (1.0 / 10321920.0))));
  k = 0.5 + t * (-1.0 / 48.0 + t * (1.0 / 3840.0 + t * (-1.0 / 645120.0 + t * (1.0 / 185794560.0))));
}

// Exponential map of a rotation vector (axis * angle) to a unit quaternion,
// with the small-angle Taylor branch (Sophus expAndTheta).
inline Eigen::Quaterniond QuaternionExp(const Eigen::Vector3d& rotation_vector) {
  // q = (cos(theta/2), sin(theta/2)/theta * v). For theta <= 0.1 (the
  // per-sample step of any recorded test: |omega| dt) by QuaternionExpTaylor.
  const double t = rotation_vector.squaredNorm();
  double w, k;
  if (t <= kQuaternionExpTaylorMaxSquaredAngle) {
    QuaternionExpTaylor(t, w, k);
  } else {
    const double theta = std::sqrt(t);
    w = std::cos(0.5 * theta);
    k = std::sin(0.5 * theta) / theta;
  }
  return Eigen::Quaterniond(w, k * rotation_vector.x(), k * rotation_vector.y(), k * rotation_vector.z());
}

// Rotation vector of a unit quaternion (angle in [0, pi]).
Eigen::Vector3d QuaternionLog(const Eigen::Quaterniond& q);

// Nearest rotation (polar decomposition) of an almost-orthonormal matrix,
// e.g. the Euler-integrated direction-cosine matrix of the seed solver.
Eigen::Matrix3d NearestRotation(const Eigen::Matrix3d& m);

// Roll, pitch, yaw (rad) with R = Rz(yaw) Ry(pitch) Rx(roll), full range
// via atan2 (pitch in [-pi/2, pi/2], roll and yaw in (-pi, pi]); at gimbal
// lock the roll is set to 0 and the yaw carries the rotation.
inline Eigen::Vector3d RollPitchYaw(const Eigen::Matrix3d& r) {
  // R = Rz(yaw) Ry(pitch) Rx(roll): R(2,0) = -sin(pitch),
  // R(2,1) = cos(pitch) sin(roll), R(2,2) = cos(pitch) cos(roll),
  // R(1,0) = cos(pitch) sin(yaw), R(0,0) = cos(pitch) cos(yaw).
  // The entries of a rotation matrix lie in [-1, 1], so sqrt(a^2 + b^2)
  // cannot overflow and is within an ulp of hypot(a, b), at a fraction of
  // its cost; the gimbal-lock test compares the square itself.
  const double pitch = std::atan2(-r(2, 0), std::sqrt(r(0, 0) * r(0, 0) + r(1, 0) * r(1, 0)));
  const double cos_pitch_sq = r(2, 1) * r(2, 1) + r(2, 2) * r(2, 2);
  if (cos_pitch_sq < 1e-24) {
    // Gimbal lock: only yaw -/+ roll is defined; put it all in yaw.
    const double yaw = std::atan2(-r(0, 1), r(1, 1));
    return {0.0, pitch, yaw};
  }
  const double roll = std::atan2(r(2, 1), r(2, 2));
  const double yaw = std::atan2(r(1, 0), r(0, 0));
  return {roll, pitch, yaw};
}

// Angles between body and fixed axes: acos of the diagonal of R (rad),
// the report's DCOS.011/.022/.033. Arguments are clamped to [-1, 1].
inline Eigen::Vector3d DirectionCosineAngles(const Eigen::Matrix3d& r) {
  Eigen::Vector3d angles;
  for (int i = 0; i < 3; ++i) angles[i] = std::acos(std::clamp(r(i, i), -1.0, 1.0));
  return angles;
}

// Angle (rad) between two orientations.
double AngleBetween(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b);

}  // namespace napkin::engine

#include "engine/rotation.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

namespace napkin::engine {

Eigen::Matrix3d Rx(double angle_rad) {
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  Eigen::Matrix3d r;
  r << 1, 0, 0, 0, c, -s, 0, s, c;
  return r;
}

Eigen::Matrix3d Ry(double angle_rad) {
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  Eigen::Matrix3d r;
  r << c, 0, s, 0, 1, 0, -s, 0, c;
  return r;
}

Eigen::Matrix3d Rz(double angle_rad) {
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  Eigen::Matrix3d r;
  r << c, -s, 0, s, c, 0, 0, 0, 1;
  return r;
}

Eigen::Matrix3d InitialFixedFromBody(const Eigen::Vector3d& phi_theta_psi_rad) {
  return Rx(phi_theta_psi_rad.x()) * Ry(phi_theta_psi_rad.y()) * Rz(phi_theta_psi_rad.z());
}

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d s;
  s << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return s;
}

Eigen::Quaterniond QuaternionExp(const Eigen::Vector3d& rotation_vector) {
  // q = (cos(theta/2), sin(theta/2)/theta * v). For theta <= 0.1 (the
  // per-sample step of any recorded test: |omega| dt) the Taylor series of
  // cos(x/2) and sin(x/2)/x in t = theta^2 through t^4 is exact in double:
  // the first omitted terms are t^5 / 3.7e9 and t^5 / 8.2e10, below 3e-20.
  const double t = rotation_vector.squaredNorm();
  double w, k;
  if (t <= 0.01) {
    w = 1.0 + t * (-1.0 / 8.0 + t * (1.0 / 384.0 + t * (-1.0 / 46080.0 + t * (1.0 / 10321920.0))));
    k = 0.5 + t * (-1.0 / 48.0 + t * (1.0 / 3840.0 + t * (-1.0 / 645120.0 + t * (1.0 / 185794560.0))));
  } else {
    const double theta = std::sqrt(t);
    w = std::cos(0.5 * theta);
    k = std::sin(0.5 * theta) / theta;
  }
  return Eigen::Quaterniond(w, k * rotation_vector.x(), k * rotation_vector.y(), k * rotation_vector.z());
}

Eigen::Vector3d QuaternionLog(const Eigen::Quaterniond& q_in) {
  // Choose the hemisphere with w >= 0 so the angle lies in [0, pi].
  const Eigen::Quaterniond q = q_in.w() < 0 ? Eigen::Quaterniond(-q_in.coeffs()) : q_in;
  const double sin_half = q.vec().norm();
  if (sin_half < 1e-8) return 2.0 * q.vec() / q.w();  // theta ~ 2 sin(theta/2)
  const double theta = 2.0 * std::atan2(sin_half, q.w());
  return q.vec() * (theta / sin_half);
}

Eigen::Matrix3d NearestRotation(const Eigen::Matrix3d& m) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d u = svd.matrixU();
  const Eigen::Matrix3d v = svd.matrixV();
  if ((u * v.transpose()).determinant() < 0) u.col(2) *= -1.0;
  return u * v.transpose();
}

Eigen::Vector3d RollPitchYaw(const Eigen::Matrix3d& r) {
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

Eigen::Vector3d DirectionCosineAngles(const Eigen::Matrix3d& r) {
  Eigen::Vector3d angles;
  for (int i = 0; i < 3; ++i) angles[i] = std::acos(std::clamp(r(i, i), -1.0, 1.0));
  return angles;
}

double AngleBetween(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return QuaternionLog(a.conjugate() * b).norm();
}

}  // namespace napkin::engine

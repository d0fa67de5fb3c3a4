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
  const Eigen::Matrix3d& v = svd.matrixV();
  if ((u * v.transpose()).determinant() < 0) u.col(2) *= -1.0;
  return u * v.transpose();
}

double AngleBetween(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return QuaternionLog(a.conjugate() * b).norm();
}

}  // namespace napkin::engine

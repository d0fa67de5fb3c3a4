#pragma once
// Rotations on SO(3). Convention (docs/formats.md): R = fixed_from_body, so a
// vector in body axes times R gives fixed axes; dR/dt = R [omega_body]x.
#include <Eigen/Core>
#include <Eigen/Geometry>

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

// Exponential map of a rotation vector (axis * angle) to a unit quaternion,
// with the small-angle Taylor branch (Sophus expAndTheta).
Eigen::Quaterniond QuaternionExp(const Eigen::Vector3d& rotation_vector);
// Rotation vector of a unit quaternion (angle in [0, pi]).
Eigen::Vector3d QuaternionLog(const Eigen::Quaterniond& q);

// Nearest rotation (polar decomposition) of an almost-orthonormal matrix,
// e.g. the Euler-integrated direction-cosine matrix of the seed solver.
Eigen::Matrix3d NearestRotation(const Eigen::Matrix3d& m);

// Roll, pitch, yaw (rad) with R = Rz(yaw) Ry(pitch) Rx(roll), full range
// via atan2 (pitch in [-pi/2, pi/2], roll and yaw in (-pi, pi]); at gimbal
// lock the roll is set to 0 and the yaw carries the rotation.
Eigen::Vector3d RollPitchYaw(const Eigen::Matrix3d& fixed_from_body);

// Angles between body and fixed axes: acos of the diagonal of R (rad),
// the report's DCOS.011/.022/.033. Arguments are clamped to [-1, 1].
Eigen::Vector3d DirectionCosineAngles(const Eigen::Matrix3d& fixed_from_body);

// Angle (rad) between two orientations.
double AngleBetween(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b);

}  // namespace napkin::engine

#pragma once
// Six-degree-of-freedom head kinematics, one row per sample. Column-major
// Eigen matrices: each component is a contiguous column (cheap to map, to
// filter and to write as a BLOB). All SI: rad/s, rad/s^2, m/s^2, m/s, m.
#include <Eigen/Core>

namespace napkin::engine {

using Series3 = Eigen::Matrix<double, Eigen::Dynamic, 3>;
using Series4 = Eigen::Matrix<double, Eigen::Dynamic, 4>;

struct Kinematics {
  Eigen::VectorXd time_s;
  // Sampling interval of time_s as given (the solvers copy the signals'
  // dt_s); 0 = unknown, derived from time_s. Differences of time_s lose
  // digits when the record starts far from t = 0.
  double dt_s = 0.0;
  Series3 omega_body;            // angular velocity, body axes
  Series3 alpha_body;            // angular acceleration, body axes
  Series3 omega_fixed;           // = R * omega_body
  Series3 alpha_fixed;           // = R * alpha_body
  Series3 acc_body;              // head CG acceleration, body axes (m/s^2)
  Series3 acc_fixed;             // = R * acc_body
  Series3 vel_fixed;             // CG velocity, starts at the initial velocity
  Series3 pos_fixed;             // CG displacement, starts at 0
  Series4 quat_fixed_from_body;  // (w, x, y, z), unit; v_fixed = q * v_body
  Series3 roll_pitch_yaw_rad;    // R = Rz(yaw) Ry(pitch) Rx(roll), full range
  Series3 dcos_rad;              // acos of the diagonal of R
  Eigen::VectorXd residual;      // per-sample least-squares residual norm (m/s^2), 0 if none

  Eigen::Index size() const { return time_s.size(); }
  // n rows in every series.
  void Resize(Eigen::Index n);
  // n rows in time_s and acc_body; every other series (they need the
  // rotation) and the residual empty: the shape of acceleration-only
  // kinematics (HasRotation).
  void ResizeWithoutRotation(Eigen::Index n);
  // n rows in every series but omega_fixed, alpha_fixed, roll_pitch_yaw_rad
  // and dcos_rad, which are empty: what the summary and the criteria read
  // (SolveOptions::summary_series_only).
  void ResizeForSummary(Eigen::Index n);
};

// Whether the kinematics hold a rotation. The kinematics of an
// acceleration-only array (engine/array_geometry.h DeterminesRotation; docs/
// algorithms.md "Acceleration-only arrays") have time_s and acc_body only:
// every series that needs the head's rotation (omega, alpha, acc_fixed,
// vel_fixed, pos_fixed, quaternion, angles) and the residual are empty (0
// rows; ResizeWithoutRotation), so a long recording holds, and the catalogue
// stores, 4 of the 36 series (docs/formats.md "Derived-channel storage").
// Kinematics whose quaternion is NaN (results stored before that change)
// count as acceleration-only too. Solved kinematics are otherwise finite
// throughout. Empty kinematics count as having one.
bool HasRotation(const Kinematics& kinematics);

}  // namespace napkin::engine

#include "engine/kinematics_completer.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "engine/cancellation.h"
#include "engine/rotation.h"
#include "engine/rotation_angles.h"

namespace napkin::engine::internal {
namespace {

using Eigen::Index;
using Eigen::Vector3d;

// Rows [begin, end) of the quaternion series normalized (the chain leaves
// them a few ulp off unit length) and the rotation
// R_k = RotationMatrixOfUnitQuaternion(q_k) applied: with kCompensateGravity, docs/algorithms.md "Gravity":
// zeroed accelerometers read a - (R^T - R0^T) g, so the term is added back to acc_body with the integrated
// orientation; then omega, alpha and the acceleration in fixed axes. Every sample on its own (a loop the
// compiler vectorizes over samples), each entry as RotationMatrixOfUnitQuaternion forms it. Without
// kFixedRates (SolveOptions::summary_series_only) omega and alpha stay in body axes only.
template <bool kCompensateGravity, bool kFixedRates>
NAPKIN_SAMPLE_LOOP_CLONES void RotateRows(Index begin, Index end, const Vector3d& g_fixed,
                                          const Vector3d& gravity_body_0, Kinematics& kin) {
  double* qw = kin.quat_fixed_from_body.col(0).data();
  double* qx = kin.quat_fixed_from_body.col(1).data();
  double* qy = kin.quat_fixed_from_body.col(2).data();
  double* qz = kin.quat_fixed_from_body.col(3).data();
  const SeriesColumns<const double> omega = ColumnsOf(std::as_const(kin.omega_body));
  const SeriesColumns<const double> alpha = ColumnsOf(std::as_const(kin.alpha_body));
  const SeriesColumns<double> acc = ColumnsOf(kin.acc_body);
  const SeriesColumns<double> omega_fixed =
      kFixedRates ? ColumnsOf(kin.omega_fixed) : SeriesColumns<double>{};
  const SeriesColumns<double> alpha_fixed =
      kFixedRates ? ColumnsOf(kin.alpha_fixed) : SeriesColumns<double>{};
  const SeriesColumns<double> acc_fixed = ColumnsOf(kin.acc_fixed);
  const double gx = g_fixed.x(), gy = g_fixed.y(), gz = g_fixed.z();
  const double gb0x = gravity_body_0.x(), gb0y = gravity_body_0.y(), gb0z = gravity_body_0.z();
  NAPKIN_INDEPENDENT_SAMPLES
  for (Index k = begin; k < end; ++k) {
    const double scale = 1.0 / std::sqrt(qw[k] * qw[k] + qx[k] * qx[k] + qy[k] * qy[k] + qz[k] * qz[k]);
    qw[k] *= scale;
    qx[k] *= scale;
    qy[k] *= scale;
    qz[k] *= scale;
    const double tx = 2.0 * qx[k], ty = 2.0 * qy[k], tz = 2.0 * qz[k];
    const double twx = tx * qw[k], twy = ty * qw[k], twz = tz * qw[k];
    const double txx = tx * qx[k], txy = ty * qx[k], txz = tz * qx[k];
    const double tyy = ty * qy[k], tyz = tz * qy[k], tzz = tz * qz[k];
    const double r00 = 1.0 - (tyy + tzz), r01 = txy - twz, r02 = txz + twy;
    const double r10 = txy + twz, r11 = 1.0 - (txx + tzz), r12 = tyz - twx;
    const double r20 = txz - twy, r21 = tyz + twx, r22 = 1.0 - (txx + tyy);
    if constexpr (kCompensateGravity) {
      acc.x[k] += r00 * gx + r10 * gy + r20 * gz - gb0x;
      acc.y[k] += r01 * gx + r11 * gy + r21 * gz - gb0y;
      acc.z[k] += r02 * gx + r12 * gy + r22 * gz - gb0z;
    }
    if constexpr (kFixedRates) {
      const double wx = omega.x[k], wy = omega.y[k], wz = omega.z[k];
      omega_fixed.x[k] = r00 * wx + r01 * wy + r02 * wz;
      omega_fixed.y[k] = r10 * wx + r11 * wy + r12 * wz;
      omega_fixed.z[k] = r20 * wx + r21 * wy + r22 * wz;
      const double ax = alpha.x[k], ay = alpha.y[k], az = alpha.z[k];
      alpha_fixed.x[k] = r00 * ax + r01 * ay + r02 * az;
      alpha_fixed.y[k] = r10 * ax + r11 * ay + r12 * az;
      alpha_fixed.z[k] = r20 * ax + r21 * ay + r22 * az;
    }
    const double bx = acc.x[k], by = acc.y[k], bz = acc.z[k];
    acc_fixed.x[k] = r00 * bx + r01 * by + r02 * bz;
    acc_fixed.y[k] = r10 * bx + r11 * by + r12 * bz;
    acc_fixed.z[k] = r20 * bx + r21 * by + r22 * bz;
  }
}

// The increments Exp(theta_k) of rows [first, end) into increment[.][k - begin]
// and |theta_k|^2 into angle_sq[k - begin] (KinematicsCompleter::CompleteRows).
NAPKIN_SAMPLE_LOOP_CLONES void OrientationIncrements(Index first, Index end, Index begin, double half_dt,
                                                     double dt2_12, const Kinematics& kin,
                                                     double (&increment)[4][kCompletionBlock],
                                                     double (&angle_sq_of)[kCompletionBlock]) {
  const SeriesColumns<const double> w = ColumnsOf(kin.omega_body);
  const SeriesColumns<const double> a = ColumnsOf(kin.alpha_body);
  double* increment_w = increment[0];
  double* increment_x = increment[1];
  double* increment_y = increment[2];
  double* increment_z = increment[3];
  double* angle_sq = angle_sq_of;
  // theta_k of sample k (Eigen's cross product, term for term).
  auto step_rotation = [&](Index k) {
    return Vector3d(half_dt * (w.x[k - 1] + w.x[k]) + dt2_12 * (a.x[k - 1] - a.x[k]) +
                        dt2_12 * (w.y[k - 1] * w.z[k] - w.z[k - 1] * w.y[k]),
                    half_dt * (w.y[k - 1] + w.y[k]) + dt2_12 * (a.y[k - 1] - a.y[k]) +
                        dt2_12 * (w.z[k - 1] * w.x[k] - w.x[k - 1] * w.z[k]),
                    half_dt * (w.z[k - 1] + w.z[k]) + dt2_12 * (a.z[k - 1] - a.z[k]) +
                        dt2_12 * (w.x[k - 1] * w.y[k] - w.y[k - 1] * w.x[k]));
  };
  NAPKIN_INDEPENDENT_SAMPLES
  for (Index k = first; k < end; ++k) {
    const Vector3d theta = step_rotation(k);
    const double sx = theta.x(), sy = theta.y(), sz = theta.z();
    const double t = sx * sx + sy * sy + sz * sz;
    angle_sq[k - begin] = t;
    double cos_half, sin_half_over;
    QuaternionExpTaylor(t, cos_half, sin_half_over);
    increment_w[k - begin] = cos_half;
    increment_x[k - begin] = sin_half_over * sx;
    increment_y[k - begin] = sin_half_over * sy;
    increment_z[k - begin] = sin_half_over * sz;
  }
  for (Index k = first; k < end; ++k) {
    if (angle_sq[k - begin] <= kQuaternionExpTaylorMaxSquaredAngle) continue;
    const Eigen::Quaterniond exp = QuaternionExp(step_rotation(k));
    increment_w[k - begin] = exp.w();
    increment_x[k - begin] = exp.x();
    increment_y[k - begin] = exp.y();
    increment_z[k - begin] = exp.z();
  }
}

// The Hermite increments of samples 2 .. n - 2 (KinematicsCompleter::Finish):
// dv[k] = dt/2 (a[k-1] + a[k]) + dt^2/12 (a'[k-1] - a'[k]) with central
// differences a'[k] = (a[k+1] - a[k-1]) / (2 dt), and dx[k] = dt^2/12 (a[k-1] - a[k]).
NAPKIN_SAMPLE_LOOP_CLONES void HermiteIncrements(const double* __restrict a, Index n, double half_dt,
                                                 double dt2_12, double inv_2dt, double* __restrict dv,
                                                 double* __restrict dx) {
  for (Index k = 2; k + 1 < n; ++k) {
    const double rate_prev = (a[k] - a[k - 2]) * inv_2dt, rate = (a[k + 1] - a[k - 1]) * inv_2dt;
    dv[k] = half_dt * (a[k - 1] + a[k]) + dt2_12 * (rate_prev - rate);
    dx[k] = dt2_12 * (a[k - 1] - a[k]);
  }
}

}  // namespace

KinematicsCompleter::KinematicsCompleter(const InitialState& initial, const GravityOptions& gravity,
                                         double dt_s, Kinematics& kin, const std::atomic<bool>* cancel,
                                         bool summary_series_only)
    : kin_(kin),
      cancel_(cancel),
      gravity_(gravity),
      initial_(initial),
      fixed_from_body_0_(InitialFixedFromBody(initial.orientation_rad)),
      gravity_body_0_(fixed_from_body_0_.transpose() * gravity.g_fixed_mps2),
      dt_(dt_s),
      half_dt_(0.5 * dt_s),
      dt2_12_(dt_s * dt_s / 12.0),
      summary_series_only_(summary_series_only) {}

void KinematicsCompleter::CompleteRows(Index begin, Index end) {
  // The increments Exp(theta_k) of IntegrateOrientation, q[k] = q[k-1] Exp(theta_k),
  // each sample on its own: the Hermite step rotation
  //   theta_k = dt/2 (w[k-1] + w[k]) + dt^2/12 (a[k-1] - a[k]) + dt^2/12 w[k-1] x w[k]
  // and QuaternionExp's Taylor branch, in a loop over samples the compiler
  // vectorizes; the rare step beyond that branch is redone by QuaternionExp.
  const Index first = std::max<Index>(begin, 1);
  OrientationIncrements(first, end, begin, half_dt_, dt2_12_, kin_, increment_, angle_sq_);
  const double* increment_w = increment_[0];
  const double* increment_x = increment_[1];
  const double* increment_y = increment_[2];
  const double* increment_z = increment_[3];
  // The chain: the product alone. Body-frame increments multiply on the
  // right (dR/dt = R [omega_body]x). Products of unit quaternions stay unit
  // to a few ulp per step, and a scalar factor does not change the rotation,
  // so the chain carries the products as they come and RotateRows
  // normalizes each one off the chain; each block starts from the last
  // normalized row, so the length never drifts.
  Series4& quat = kin_.quat_fixed_from_body;
  if (begin == 0) fixed_from_body_ = Eigen::Quaterniond(fixed_from_body_0_).normalized();
  double qw = fixed_from_body_.w(), qx = fixed_from_body_.x(), qy = fixed_from_body_.y(),
         qz = fixed_from_body_.z();
  if (begin == 0) {
    quat(0, 0) = qw;
    quat(0, 1) = qx;
    quat(0, 2) = qy;
    quat(0, 3) = qz;
  }
  for (Index k = first; k < end; ++k) {
    const double bw = increment_w[k - begin], bx = increment_x[k - begin], by = increment_y[k - begin],
                 bz = increment_z[k - begin];
    const double pw = (qw * bw - qx * bx) - (qy * by + qz * bz);
    const double px = (qw * bx + qx * bw) + (qy * bz - qz * by);
    const double py = (qw * by + qy * bw) + (qz * bx - qx * bz);
    const double pz = (qw * bz + qz * bw) + (qx * by - qy * bx);
    qw = pw;
    qx = px;
    qy = py;
    qz = pz;
    quat(k, 0) = qw;
    quat(k, 1) = qx;
    quat(k, 2) = qy;
    quat(k, 3) = qz;
  }
  if (gravity_.compensate && !summary_series_only_)
    RotateRows<true, true>(begin, end, gravity_.g_fixed_mps2, gravity_body_0_, kin_);
  else if (gravity_.compensate)
    RotateRows<true, false>(begin, end, gravity_.g_fixed_mps2, gravity_body_0_, kin_);
  else if (!summary_series_only_)
    RotateRows<false, true>(begin, end, gravity_.g_fixed_mps2, gravity_body_0_, kin_);
  else
    RotateRows<false, false>(begin, end, gravity_.g_fixed_mps2, gravity_body_0_, kin_);
  fixed_from_body_ =
      Eigen::Quaterniond(quat(end - 1, 0), quat(end - 1, 1), quat(end - 1, 2), quat(end - 1, 3));
}

void KinematicsCompleter::Finish() {
  ThrowIfCancelled(cancel_);
  if (!summary_series_only_)
    OrientationAngles(kin_.quat_fixed_from_body, kin_.roll_pitch_yaw_rad, kin_.dcos_rad,
                      BestAnglesImplementation(), cancel_);
  ThrowIfCancelled(cancel_);
  const Index n = kin_.size();
  if (n == 0) return;
  // Velocity (from the initial velocity) and position (from 0) by the
  // Hermite rule, with the slope of acc_fixed by second-order differences
  // (as DifferentiateSecondOrder takes them):
  //   v[k] = v[k-1] + dt/2 (a[k-1] + a[k]) + dt^2/12 (a'[k-1] - a'[k])
  //   x[k] = x[k-1] + dt/2 (v[k-1] + v[k]) + dt^2/12 (a[k-1] - a[k]).
  // The increments of every sample first (a loop over samples), then the sums.
  const Series3& acc = kin_.acc_fixed;
  const double inv_2dt = 0.5 / dt_;
  for (int c = 0; c < 3; ++c) {
    const double* a = acc.col(c).data();
    double* vel = kin_.vel_fixed.col(c).data();
    double* pos = kin_.pos_fixed.col(c).data();
    vel[0] = initial_.velocity_fixed_mps(c);
    pos[0] = 0.0;
    if (n == 1) continue;
    auto rate = [&](Index k) {
      if (n == 2) return (a[1] - a[0]) / dt_;
      if (k == 0) return (-3.0 * a[0] + 4.0 * a[1] - a[2]) * inv_2dt;
      if (k == n - 1) return (3.0 * a[n - 1] - 4.0 * a[n - 2] + a[n - 3]) * inv_2dt;
      return (a[k + 1] - a[k - 1]) * inv_2dt;
    };
    HermiteIncrements(a, n, half_dt_, dt2_12_, inv_2dt, vel, pos);  // samples 2 .. n - 2
    for (const Index k : {Index{1}, n - 1}) {
      vel[k] = half_dt_ * (a[k - 1] + a[k]) + dt2_12_ * (rate(k - 1) - rate(k));
      pos[k] = dt2_12_ * (a[k - 1] - a[k]);
    }
    double vel_prev = vel[0], pos_prev = pos[0];
    for (Index k = 1; k < n; ++k) {
      ThrowIfCancelled(cancel_, k);
      const double v = vel_prev + vel[k];
      const double x = pos_prev + half_dt_ * (vel_prev + v) + pos[k];
      vel[k] = vel_prev = v;
      pos[k] = pos_prev = x;
    }
  }
}

}  // namespace napkin::engine::internal

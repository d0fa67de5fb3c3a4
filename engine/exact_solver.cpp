#include "engine/exact_solver.h"

#include <Eigen/SVD>
#include <cmath>
#include <vector>

#include "common/error.h"
#include "engine/array_analysis.h"
#include "engine/cancellation.h"
#include "engine/integration.h"
#include "engine/rotation.h"
#include "engine/rotation_angles.h"

namespace napkin::engine {
namespace {

using Eigen::Index;
using Eigen::Matrix3Xd;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;
using Vector6d = Eigen::Matrix<double, 6, 1>;

// Arrays with up to this many linear sensors are solved with fixed-capacity
// (stack) storage; larger ones with heap storage allocated once per test.
constexpr int kMaxFixedSizeSensors = 16;

// How far ahead (samples) the exact solver prefetches the recorded channels.
constexpr Index kPrefetchSamples = 64;

// Per-sensor constants of the centripetal term of the linear sensors,
//   c_i(omega) = n_i . (omega x (omega x r_i)) = (n_i.omega)(r_i.omega) - (n_i.r_i)|omega|^2,
// and of its time derivative given alpha:
//   dc_i/dt = (n_i.alpha)(r_i.omega) + (n_i.omega)(r_i.alpha) - 2 (n_i.r_i)(omega.alpha).
struct LinearSensors {
  Matrix3Xd axis_body;         // n_i, one column per sensor
  Matrix3Xd position_body;     // r_i
  VectorXd axis_dot_position;  // n_i . r_i
  MatrixXd rows;               // [n_i^T, (r_i x n_i)^T], L x 6
  // Work buffers (allocated once, reused every sample).
  VectorXd n_omega, r_omega, n_alpha, r_alpha;

  LinearSensors(const ArrayGeometry& array, const std::vector<std::size_t>& indices) {
    const auto count = static_cast<Index>(indices.size());
    axis_body.resize(3, count);
    position_body.resize(3, count);
    axis_dot_position.resize(count);
    for (Index i = 0; i < count; ++i) {
      const Sensor& sensor = array.sensors[indices[static_cast<std::size_t>(i)]];
      axis_body.col(i) = sensor.axis_body;
      position_body.col(i) = sensor.position_body_m;
      axis_dot_position(i) = sensor.axis_body.dot(sensor.position_body_m);
    }
    rows = LinearRigidBodyRows(array, indices);
    n_omega.resize(count);
    r_omega.resize(count);
    n_alpha.resize(count);
    r_alpha.resize(count);
  }

  Index size() const { return axis_body.cols(); }

  // centripetal = c(omega); keeps n.omega and r.omega for CentripetalRate.
  void Centripetal(const Vector3d& omega, VectorXd& centripetal) {
    n_omega.noalias() = axis_body.transpose() * omega;
    r_omega.noalias() = position_body.transpose() * omega;
    centripetal = n_omega.cwiseProduct(r_omega) - omega.squaredNorm() * axis_dot_position;
  }

  // rate = dc/dt at (omega, alpha); call after Centripetal(omega).
  void CentripetalRate(const Vector3d& omega, const Vector3d& alpha, VectorXd& rate) {
    n_alpha.noalias() = axis_body.transpose() * alpha;
    r_alpha.noalias() = position_body.transpose() * alpha;
    rate = n_alpha.cwiseProduct(r_omega) + n_omega.cwiseProduct(r_alpha) -
           (2.0 * omega.dot(alpha)) * axis_dot_position;
  }
};

// Samples of the sensors `indices` in SI, one column per sample (so each
// sample is contiguous for the per-sample solves).
MatrixXd MeasurementsBySample(const ArrayGeometry& array, const std::vector<std::size_t>& indices,
                              const TestSignals& signals) {
  MatrixXd by_sample(static_cast<Index>(indices.size()), signals.size());
  for (std::size_t i = 0; i < indices.size(); ++i) {
    const Sensor& sensor = array.sensors[indices[i]];
    const int column = signals.FindSlot(sensor.slot);
    by_sample.row(static_cast<Index>(i)) = signals.samples.col(column).transpose() * sensor.si_per_unit;
  }
  return by_sample;
}

// CompleteKinematics one sample at a time, so that a solver can complete
// each sample while it is in cache: Step(k) once rows k of omega_body,
// alpha_body and acc_body are final (k = 0, 1, ... in order), then Finish().
// The arithmetic is IntegrateOrientation's, DifferentiateSecondOrder's and
// IntegrateHermite's (engine/integration.h), operation for operation.
class KinematicsCompleter {
 public:
  KinematicsCompleter(const InitialState& initial, const GravityOptions& gravity, double dt_s,
                      Kinematics& kin, const std::atomic<bool>* cancel)
      : kin_(kin),
        cancel_(cancel),
        gravity_(gravity),
        initial_(initial),
        fixed_from_body_0_(InitialFixedFromBody(initial.orientation_rad)),
        gravity_body_0_(fixed_from_body_0_.transpose() * gravity.g_fixed_mps2),
        dt_(dt_s),
        half_dt_(0.5 * dt_s),
        dt2_12_(dt_s * dt_s / 12.0) {}

  // Orientation (q[k] = q[k-1] Exp(theta_k), IntegrateOrientation), the
  // gravity term, and the fixed-frame series of sample k (the angles: Finish).
  void Step(Index k) {
    // Row k one coefficient at a time (the previous row is kept), so that no
    // packet load spans the solver's scalar stores of rows k - 1 and k.
    const Vector3d w1(kin_.omega_body(k, 0), kin_.omega_body(k, 1), kin_.omega_body(k, 2));
    const Vector3d a1(kin_.alpha_body(k, 0), kin_.alpha_body(k, 1), kin_.alpha_body(k, 2));
    if (k == 0) {
      fixed_from_body_ = Eigen::Quaterniond(fixed_from_body_0_).normalized();
    } else {
      const Vector3d& w0 = omega_body_prev_;
      const Vector3d& a0 = alpha_body_prev_;
      const Vector3d step_rotation = half_dt_ * (w0 + w1) + dt2_12_ * (a0 - a1) + dt2_12_ * w0.cross(w1);
      // Body-frame increment multiplies on the right: dR/dt = R [omega_body]x.
      fixed_from_body_ = NormalizedProduct(fixed_from_body_, QuaternionExp(step_rotation));
    }
    omega_body_prev_ = w1;
    alpha_body_prev_ = a1;
    const double qw = fixed_from_body_.w(), qx = fixed_from_body_.x(), qy = fixed_from_body_.y(),
                 qz = fixed_from_body_.z();
    kin_.quat_fixed_from_body(k, 0) = qw;
    kin_.quat_fixed_from_body(k, 1) = qx;
    kin_.quat_fixed_from_body(k, 2) = qy;
    kin_.quat_fixed_from_body(k, 3) = qz;
    const Eigen::Matrix3d r = RotationMatrixOfUnitQuaternion(qw, qx, qy, qz);
    const double r00 = r(0, 0), r01 = r(0, 1), r02 = r(0, 2);
    const double r10 = r(1, 0), r11 = r(1, 1), r12 = r(1, 2);
    const double r20 = r(2, 0), r21 = r(2, 1), r22 = r(2, 2);
    // docs/algorithms.md "Gravity": zeroed accelerometers read a - (R^T - R0^T) g;
    // add the term back with the integrated orientation.
    if (gravity_.compensate) {
      const double gx = gravity_.g_fixed_mps2.x(), gy = gravity_.g_fixed_mps2.y(),
                   gz = gravity_.g_fixed_mps2.z();
      kin_.acc_body(k, 0) += r00 * gx + r10 * gy + r20 * gz - gravity_body_0_.x();
      kin_.acc_body(k, 1) += r01 * gx + r11 * gy + r21 * gz - gravity_body_0_.y();
      kin_.acc_body(k, 2) += r02 * gx + r12 * gy + r22 * gz - gravity_body_0_.z();
    }
    auto rotate_row = [&](const Series3& body, Series3& fixed) {
      const double x = body(k, 0), y = body(k, 1), z = body(k, 2);
      fixed(k, 0) = r00 * x + r01 * y + r02 * z;
      fixed(k, 1) = r10 * x + r11 * y + r12 * z;
      fixed(k, 2) = r20 * x + r21 * y + r22 * z;
    };
    rotate_row(kin_.omega_body, kin_.omega_fixed);
    rotate_row(kin_.alpha_body, kin_.alpha_fixed);
    rotate_row(kin_.acc_body, kin_.acc_fixed);
  }

  // (a b).normalized() for unit quaternions a and b, in scalars. |a b|^2 = 1 + e
  // with e a few ulp, and 1/sqrt(1 + e) = 1 - e/2 + 3e^2/8 - ..., so
  // (a b) (3 - |a b|^2) / 2 is the normalized product to round-off, without a
  // square root and a division on the sample-to-sample dependency chain; a
  // product further from unit length is normalized exactly.
  static Eigen::Quaterniond NormalizedProduct(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
    const double w = a.w() * b.w() - a.x() * b.x() - a.y() * b.y() - a.z() * b.z();
    const double x = a.w() * b.x() + a.x() * b.w() + a.y() * b.z() - a.z() * b.y();
    const double y = a.w() * b.y() + a.y() * b.w() + a.z() * b.x() - a.x() * b.z();
    const double z = a.w() * b.z() + a.z() * b.w() + a.x() * b.y() - a.y() * b.x();
    const double norm_sq = w * w + x * x + y * y + z * z;
    const double scale = std::abs(norm_sq - 1.0) > 1e-9 ? 1.0 / std::sqrt(norm_sq) : 1.5 - 0.5 * norm_sq;
    return Eigen::Quaterniond(w * scale, x * scale, y * scale, z * scale);
  }

  // Velocity (from the initial velocity) and position (from 0) by the
  // Hermite rule, the slope of acc_fixed taken on the fly, in one pass.
  // The angles follow in a loop of their own (engine/rotation_angles.h).
  void Finish() {
    ThrowIfCancelled(cancel_);
    OrientationAngles(kin_.quat_fixed_from_body, kin_.roll_pitch_yaw_rad, kin_.dcos_rad,
                      BestAnglesImplementation(), cancel_);
    ThrowIfCancelled(cancel_);
    const Index n = kin_.size();
    if (n == 0) return;
    const Series3& acc = kin_.acc_fixed;
    const double inv_2dt = 0.5 / dt_;
    auto acc_rate = [&](Index k) -> Eigen::RowVector3d {
      if (n == 2) return (acc.row(1) - acc.row(0)) / dt_;
      if (k == 0) return (-3.0 * acc.row(0) + 4.0 * acc.row(1) - acc.row(2)) * inv_2dt;
      if (k == n - 1) return (3.0 * acc.row(n - 1) - 4.0 * acc.row(n - 2) + acc.row(n - 3)) * inv_2dt;
      return (acc.row(k + 1) - acc.row(k - 1)) * inv_2dt;
    };
    if (n == 1) {
      kin_.vel_fixed.row(0) = initial_.velocity_fixed_mps.transpose();
      kin_.pos_fixed.row(0).setZero();
      return;
    }
    // The three components side by side in scalars (their chains overlap),
    // the previous row kept in registers, the interior without branches.
    const double* acc_col[3] = {acc.col(0).data(), acc.col(1).data(), acc.col(2).data()};
    double* vel_col[3] = {kin_.vel_fixed.col(0).data(), kin_.vel_fixed.col(1).data(),
                          kin_.vel_fixed.col(2).data()};
    double* pos_col[3] = {kin_.pos_fixed.col(0).data(), kin_.pos_fixed.col(1).data(),
                          kin_.pos_fixed.col(2).data()};
    double vel_prev[3], pos_prev[3], rate_prev[3], rate[3];
    const Eigen::RowVector3d rate_0 = acc_rate(0);
    for (int c = 0; c < 3; ++c) {
      vel_prev[c] = vel_col[c][0] = initial_.velocity_fixed_mps(c);
      pos_prev[c] = pos_col[c][0] = 0.0;
      rate_prev[c] = rate_0(c);
    }
    auto advance = [&](Index k) {
      for (int c = 0; c < 3; ++c) {
        const double acc_0 = acc_col[c][k - 1], acc_1 = acc_col[c][k];
        const double vel = vel_prev[c] + half_dt_ * (acc_0 + acc_1) + dt2_12_ * (rate_prev[c] - rate[c]);
        const double pos = pos_prev[c] + half_dt_ * (vel_prev[c] + vel) + dt2_12_ * (acc_0 - acc_1);
        vel_col[c][k] = vel_prev[c] = vel;
        pos_col[c][k] = pos_prev[c] = pos;
        rate_prev[c] = rate[c];
      }
    };
    for (Index k = 1; k + 1 < n; ++k) {
      ThrowIfCancelled(cancel_, k);
      for (int c = 0; c < 3; ++c) rate[c] = (acc_col[c][k + 1] - acc_col[c][k - 1]) * inv_2dt;
      advance(k);
    }
    const Eigen::RowVector3d rate_last = acc_rate(n - 1);
    for (int c = 0; c < 3; ++c) rate[c] = rate_last(c);
    advance(n - 1);
  }

 private:
  Kinematics& kin_;
  const std::atomic<bool>* cancel_;
  const GravityOptions& gravity_;
  const InitialState& initial_;
  const Eigen::Matrix3d fixed_from_body_0_;
  const Vector3d gravity_body_0_;
  const double dt_, half_dt_, dt2_12_;
  Eigen::Quaterniond fixed_from_body_;
  Vector3d omega_body_prev_, alpha_body_prev_;  // row k - 1
};

// The centripetal term of linear sensor i is a quadratic form in omega,
//   c_i(omega) = (n_i.omega)(r_i.omega) - (n_i.r_i)|omega|^2 = C_i . Quadratic(omega),
// with the monomials Quadratic(w) = (wx^2, wy^2, wz^2, wx wy, wx wz, wy wz), and so is its rate
//   dc_i/dt = (n_i.alpha)(r_i.omega) + (n_i.omega)(r_i.alpha) - 2 (n_i.r_i)(omega.alpha)
//           = C_i . QuadraticRate(omega, alpha).
// Every linear map of the centripetal terms (the least-squares solution,
// the residual) is thus a fixed 6-column matrix times six monomials.
Vector6d Quadratic(const Vector3d& w) {
  Vector6d monomials;
  monomials << w.x() * w.x(), w.y() * w.y(), w.z() * w.z(), w.x() * w.y(), w.x() * w.z(), w.y() * w.z();
  return monomials;
}

Vector6d QuadraticRate(const Vector3d& w, const Vector3d& a) {
  Vector6d rates;
  rates << 2.0 * w.x() * a.x(), 2.0 * w.y() * a.y(), 2.0 * w.z() * a.z(), w.x() * a.y() + w.y() * a.x(),
      w.x() * a.z() + w.z() * a.x(), w.y() * a.z() + w.z() * a.y();
  return rates;
}

// Rows C_i (L x 6) of the sensors `indices`.
MatrixXd CentripetalCoefficients(const ArrayGeometry& array, const std::vector<std::size_t>& indices) {
  MatrixXd coefficients(static_cast<Index>(indices.size()), 6);
  for (std::size_t i = 0; i < indices.size(); ++i) {
    const Sensor& sensor = array.sensors[indices[i]];
    const Vector3d& n = sensor.axis_body;
    const Vector3d& r = sensor.position_body_m;
    const double n_dot_r = n.dot(r);
    coefficients.row(static_cast<Index>(i)) << n.x() * r.x() - n_dot_r, n.y() * r.y() - n_dot_r,
        n.z() * r.z() - n_dot_r, n.x() * r.y() + n.y() * r.x(), n.x() * r.z() + n.z() * r.x(),
        n.y() * r.z() + n.z() * r.y();
  }
  return coefficients;
}

// The recorded channels of the sensors `indices` (column pointers into
// signals.samples) and their unit factors.
struct SensorColumns {
  std::vector<const double*> columns;
  VectorXd si_per_unit;

  SensorColumns(const ArrayGeometry& array, const std::vector<std::size_t>& indices,
                const TestSignals& signals)
      : si_per_unit(static_cast<Index>(indices.size())) {
    for (std::size_t i = 0; i < indices.size(); ++i) {
      const Sensor& sensor = array.sensors[indices[i]];
      columns.push_back(signals.samples.col(signals.FindSlot(sensor.slot)).data());
      si_per_unit(static_cast<Index>(i)) = sensor.si_per_unit;
    }
  }
};

// Orthonormal basis (rows) of the complement of the column space of `rows`
// (L x 6) as PseudoInverse sees it (singular values above its tolerance):
// the least-squares residual of rhs is |complement * rhs|, since
// I - rows * PseudoInverse(rows) = complement^T complement.
MatrixXd ResidualComplement(const MatrixXd& rows) {
  const Eigen::JacobiSVD<MatrixXd> svd(rows, Eigen::ComputeFullU);
  const VectorXd& sv = svd.singularValues();
  Index rank = 0;
  for (Index i = 0; i < sv.size(); ++i)
    if (sv(i) > kRankRelativeTolerance * sv(0)) ++rank;
  return svd.matrixU().rightCols(rows.rows() - rank).transpose();
}

// kLinear: at each sample the linear sensors give
//   n.a + (r x n).alpha = m - c(omega)            (docs/algorithms.md "Solvers")
// solved by the pseudo-inverse P of the L x 6 rows (factored once; least
// squares for L > 6). omega follows from the implicit Hermite rule
//   omega[k] = omega[k-1] + dt/2 (alpha[k-1] + alpha[k]) + dt^2/12 (alpha'[k-1] - alpha'[k]),
// with alpha' = P_alpha (m' - dc/dt) exact given omega, alpha and the
// measured slope m' (central differences of the record). The rule is fourth
// order; its correction telescopes, so errors in m' at kinks stay local.
// omega[k] is predicted by a Taylor step and corrected by fixed-point
// passes (contraction ~ dt |omega|, so 2-3 passes reach round-off).
//
// The solve is linear in m, so P m, P_alpha m' (the central difference of
// P_alpha m) and the residual's projection of m are formed once per sample;
// each pass only evaluates the 6 x 6 centripetal map P C of the monomials.
// MaxSensors bounds the number of linear sensors (fixed-capacity storage,
// nothing allocated per sample); Eigen::Dynamic for any number. The
// orientation and fixed-frame series of each sample are completed in the
// same loop (KinematicsCompleter).
template <int MaxSensors>
void SolveLinear(const ArrayGeometry& array, const TestSignals& signals, const SolveOptions& options,
                 Kinematics& out) {
  // The residual's complement has at most MaxSensors - 6 rows; with a fixed
  // MaxSensors it is stored with exactly that many, zero-padded (zero rows
  // add exact zeros to the residual norm), so the per-sample sums stay in
  // registers.
  constexpr int kComplementRows = MaxSensors == Eigen::Dynamic ? Eigen::Dynamic : MaxSensors - 6;
  using SixBySensors = Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, MaxSensors>;
  using ComplementBySensors =
      Eigen::Matrix<double, kComplementRows, Eigen::Dynamic, 0, kComplementRows, MaxSensors>;
  using ComplementBySix = Eigen::Matrix<double, kComplementRows, 6>;
  using ComplementVector = Eigen::Matrix<double, kComplementRows, 1>;

  const std::vector<std::size_t> linear = array.LinearIndices();
  const SensorColumns channels(array, linear, signals);
  const auto count = static_cast<Index>(linear.size());
  const Index n = signals.size();
  const double dt = signals.dt_s;
  const MatrixXd rows = LinearRigidBodyRows(array, linear);             // L x 6
  const MatrixXd solve_rows = PseudoInverse(rows);                      // 6 x L
  const MatrixXd centripetal = CentripetalCoefficients(array, linear);  // L x 6
  const MatrixXd complement = ResidualComplement(rows);                 // (L - rank) x L
  if constexpr (kComplementRows != Eigen::Dynamic) {
    // Rows whose unscaled rank is below 6 leave a larger complement.
    if (complement.rows() > kComplementRows) return SolveLinear<Eigen::Dynamic>(array, signals, options, out);
  }
  const Index complement_rows = kComplementRows == Eigen::Dynamic ? complement.rows() : kComplementRows;
  // Per recorded unit: P diag(si) and complement diag(si).
  const SixBySensors solve_recorded = solve_rows * channels.si_per_unit.asDiagonal();
  ComplementBySensors complement_recorded = ComplementBySensors::Zero(complement_rows, count);
  complement_recorded.topRows(complement.rows()) = complement * channels.si_per_unit.asDiagonal();
  const Eigen::Matrix<double, 6, 6> solve_centripetal = solve_rows * centripetal;
  const Eigen::Matrix<double, 3, 6> acc_centripetal = solve_centripetal.topRows<3>();
  const Eigen::Matrix<double, 3, 6> alpha_centripetal = solve_centripetal.bottomRows<3>();
  ComplementBySix complement_centripetal = ComplementBySix::Zero(complement_rows, 6);
  complement_centripetal.topRows(complement.rows()) = complement * centripetal;

  // P m and complement m of sample k in one sweep over the channels, one
  // fixed-size column per sensor: the alpha rows of P m first (so that they
  // start a packet), then its acceleration rows, then complement m.
  constexpr int kStackedRows = MaxSensors;  // 6 + kComplementRows, or Eigen::Dynamic
  using StackedBySensors = Eigen::Matrix<double, kStackedRows, Eigen::Dynamic, 0, kStackedRows, MaxSensors>;
  using StackedVector = Eigen::Matrix<double, kStackedRows, 1>;
  StackedBySensors stacked_recorded(6 + complement_rows, count);
  stacked_recorded.topRows(3) = solve_recorded.bottomRows(3);
  stacked_recorded.middleRows(3, 3) = solve_recorded.topRows(3);
  stacked_recorded.bottomRows(complement_rows) = complement_recorded;
  auto stacked_at = [&](Index k) -> StackedVector {
    StackedVector stacked = StackedVector::Zero(6 + complement_rows);
    for (Index i = 0; i < count; ++i)
      stacked += stacked_recorded.col(i) * channels.columns[static_cast<std::size_t>(i)][k];
    return stacked;
  };
  // The square of the least-squares residual norm given omega and complement m
  // (the square roots are taken after the loop, off the per-sample path).
  auto residual_norm_sq = [&](const ComplementVector& complement_measured,
                              const Vector3d& omega_k) -> double {
    const Vector6d monomials = Quadratic(omega_k);
    ComplementVector residual = complement_measured;
    for (Index j = 0; j < 6; ++j) residual -= complement_centripetal.col(j) * monomials(j);
    return residual.squaredNorm();
  };

  KinematicsCompleter completer(options.initial, options.gravity, dt, out, options.cancel);
  const double half_dt = 0.5 * dt, dt2_12 = dt * dt / 12.0, inv_2dt = 0.5 / dt;
  const int passes = options.corrector_passes;
  // P m of samples k - 2 .. k + 1 (k + 1 while it exists), and P_alpha m' at k.
  Vector3d alpha_projected_km2 = Vector3d::Zero(), alpha_projected_km1 = Vector3d::Zero();
  // complement m of samples k and k + 1.
  const StackedVector stacked_0 = stacked_at(0), stacked_1 = n > 1 ? stacked_at(1) : stacked_0;
  // Three-vectors from the stacked sums one coefficient at a time: a packet
  // load of rows 3 and 4 would span two packet stores of the sums (a
  // store-forwarding stall, perf).
  auto rows_3 = [](const StackedVector& stacked, Index first) {
    return Vector3d(stacked(first), stacked(first + 1), stacked(first + 2));
  };
  Vector3d alpha_projected_k = rows_3(stacked_0, 0), alpha_projected_kp1 = rows_3(stacked_1, 0);
  Vector3d acc_projected_k = rows_3(stacked_0, 3), acc_projected_kp1 = rows_3(stacked_1, 3);
  ComplementVector complement_k = stacked_0.tail(complement_rows),
                   complement_kp1 = stacked_1.tail(complement_rows);
  Vector3d alpha_measured_rate;
  Vector3d omega = options.initial.omega_body_radps, acc, alpha, alpha_rate;
  for (Index k = 0; k < n; ++k) {
    ThrowIfCancelled(options.cancel, k);
    if (k > 0) {
      alpha_projected_km2 = alpha_projected_km1;
      alpha_projected_km1 = alpha_projected_k;
      alpha_projected_k = alpha_projected_kp1;
      acc_projected_k = acc_projected_kp1;
      complement_k = complement_kp1;
      if (k + 1 < n) {
        const StackedVector stacked = stacked_at(k + 1);
        alpha_projected_kp1 = rows_3(stacked, 0);
        acc_projected_kp1 = rows_3(stacked, 3);
        complement_kp1 = stacked.tail(complement_rows);
      }
#if defined(__GNUC__)
      // The channels are read across L columns at once; ask for each
      // column's data a few cache lines ahead of the hardware prefetcher.
      if ((k & 7) == 0 && k + kPrefetchSamples < n)
        for (const double* column : channels.columns) __builtin_prefetch(column + k + kPrefetchSamples);
#endif
    }
    // Second-order differences as DifferentiateSecondOrder takes them.
    if (n < 2) {
      alpha_measured_rate.setZero();
    } else if (n == 2) {
      alpha_measured_rate =
          (k == 0 ? alpha_projected_kp1 - alpha_projected_k : alpha_projected_k - alpha_projected_km1) / dt;
    } else if (k == 0) {
      const Vector3d alpha_projected_2 = stacked_at(2).template head<3>();
      alpha_measured_rate =
          (-3.0 * alpha_projected_k + 4.0 * alpha_projected_kp1 - alpha_projected_2) * inv_2dt;
    } else if (k == n - 1) {
      alpha_measured_rate =
          (3.0 * alpha_projected_k - 4.0 * alpha_projected_km1 + alpha_projected_km2) * inv_2dt;
    } else {
      alpha_measured_rate = (alpha_projected_kp1 - alpha_projected_km1) * inv_2dt;
    }

    if (k > 0) {
      const Vector3d omega_prev = omega, alpha_prev = alpha, alpha_rate_prev = alpha_rate;
      omega = omega_prev + dt * alpha_prev + 0.5 * dt * dt * alpha_rate_prev;  // Taylor predictor
      for (int pass = 0; pass < passes; ++pass) {
        // alpha and alpha' only: the acceleration waits for the final omega.
        const Vector3d alpha_pass = alpha_projected_k - alpha_centripetal * Quadratic(omega);
        const Vector3d alpha_rate_pass =
            alpha_measured_rate - alpha_centripetal * QuadraticRate(omega, alpha_pass);
        const Vector3d corrected =
            omega_prev + half_dt * (alpha_prev + alpha_pass) + dt2_12 * (alpha_rate_prev - alpha_rate_pass);
        // Converged when |change| <= 1e-15 sqrt(1 + |omega|^2) (<= 1e-15 (1 + |omega|)),
        // compared squared: no square root on the sample-to-sample chain.
        const double change_sq = (corrected - omega).squaredNorm();
        omega = corrected;
        if (change_sq <= 1e-30 * (1.0 + omega.squaredNorm())) break;
      }
    }
    // (a, alpha) and alpha' of sample k, consistent with the final omega.
    const Vector6d monomials = Quadratic(omega);
    acc = acc_projected_k - acc_centripetal * monomials;
    alpha = alpha_projected_k - alpha_centripetal * monomials;
    alpha_rate = alpha_measured_rate - alpha_centripetal * QuadraticRate(omega, alpha);
    out.residual(k) = residual_norm_sq(complement_k, omega);
    out.omega_body.row(k) = omega.transpose();
    out.alpha_body.row(k) = alpha.transpose();
    out.acc_body.row(k) = acc.transpose();
    completer.Step(k);
  }
  // |residual| = sqrt(squaredNorm), as Eigen's norm() takes it: the same bits,
  // a packet of square roots at a time.
  out.residual = out.residual.cwiseSqrt();
  completer.Finish();
}

// omega from the angular-rate sensors (least squares over their axes) and
// alpha as its fourth-order derivative (five-point central stencil). The
// rate channels are expected to be filtered (CFC 60 by default) before this.
void OmegaFromRates(const ArrayGeometry& array, const TestSignals& signals, Kinematics& out) {
  const std::vector<std::size_t> rates = array.RateIndices();
  const MatrixXd omega_from_rates = PseudoInverse(SenseAxisRows(array, rates));  // 3 x S
  const MatrixXd omega_by_sample = omega_from_rates * MeasurementsBySample(array, rates, signals);
  out.omega_body = omega_by_sample.transpose();
  out.alpha_body = DifferentiateFourthOrder(out.omega_body, signals.dt_s);
}

// kSixAOmega: omega and alpha known, the linear sensors give
//   n.a = m - (r x n).alpha - c(omega),
// least squares over their (spanning) sense axes.
void SolveSixAOmega(const ArrayGeometry& array, const TestSignals& signals, Kinematics& out,
                    const std::atomic<bool>* cancel) {
  OmegaFromRates(array, signals, out);
  LinearSensors sensors(array, array.LinearIndices());
  const Index count = sensors.size(), n = signals.size();
  const MatrixXd axis_rows = sensors.rows.leftCols<3>();    // L x 3
  const MatrixXd lever_rows = sensors.rows.rightCols<3>();  // L x 3
  const MatrixXd acc_from_rhs = PseudoInverse(axis_rows);   // 3 x L
  const MatrixXd measured = MeasurementsBySample(array, array.LinearIndices(), signals);
  VectorXd centripetal(count), rhs(count), fitted(count), tangential(count);
  Vector3d acc;
  for (Index k = 0; k < n; ++k) {
    ThrowIfCancelled(cancel, k);
    const Vector3d omega = out.omega_body.row(k).transpose();
    const Vector3d alpha = out.alpha_body.row(k).transpose();
    sensors.Centripetal(omega, centripetal);
    tangential.noalias() = lever_rows * alpha;
    rhs = measured.col(k) - tangential - centripetal;
    acc.noalias() = acc_from_rhs * rhs;
    fitted.noalias() = axis_rows * acc;
    out.residual(k) = (fitted - rhs).norm();
    out.acc_body.row(k) = acc.transpose();
  }
}

// kFused: omega from the rate sensors (measured, no integration drift);
// (a, alpha) by weighted least squares of
//   linear rows   n.a + (r x n).alpha = m - c(omega)      weight 1/sigma_linear
//   rate rows     alpha = d omega/dt (five-point)         weight 1/sigma_alpha
// with the nominal sigmas of exact_solver.h. The residual is the weighted
// residual norm times sigma_linear, i.e. in m/s^2 of a linear channel.
void SolveFused(const ArrayGeometry& array, const TestSignals& signals, Kinematics& out,
                const std::atomic<bool>* cancel) {
  OmegaFromRates(array, signals, out);
  LinearSensors sensors(array, array.LinearIndices());
  const Index count = sensors.size(), n = signals.size();
  const double sigma_linear = kFusedLinearSigmaMps2;
  const double sigma_alpha = kFusedRateSigmaRadps * std::sqrt(130.0) / 12.0 / signals.dt_s;
  MatrixXd stacked = MatrixXd::Zero(count + 3, 6);
  stacked.topRows(count) = sensors.rows / sigma_linear;
  stacked.bottomRightCorner<3, 3>() = Eigen::Matrix3d::Identity() / sigma_alpha;
  const MatrixXd solve_rows = PseudoInverse(stacked);  // 6 x (L + 3)
  const MatrixXd measured = MeasurementsBySample(array, array.LinearIndices(), signals);
  VectorXd centripetal(count), rhs(count + 3), fitted(count + 3);
  Vector6d solution;
  for (Index k = 0; k < n; ++k) {
    ThrowIfCancelled(cancel, k);
    const Vector3d omega = out.omega_body.row(k).transpose();
    sensors.Centripetal(omega, centripetal);
    rhs.head(count) = (measured.col(k) - centripetal) / sigma_linear;
    rhs.tail<3>() = out.alpha_body.row(k).transpose() / sigma_alpha;
    solution.noalias() = solve_rows * rhs;
    fitted.noalias() = stacked * solution;
    out.residual(k) = sigma_linear * (fitted - rhs).norm();
    out.acc_body.row(k) = solution.head<3>().transpose();
    out.alpha_body.row(k) = solution.tail<3>().transpose();
  }
}

// kAccelerationOnly: the sensors at the CG read n.a (no lever arm), so a is
// their least-squares solution over their (spanning) sense axes; the other
// sensors are not used. Nothing determines omega: `out` has the shape of
// Kinematics::ResizeWithoutRotation, every series that needs the rotation
// empty, and so is the residual (the rigid-body consistency cannot be judged
// without omega).
void SolveAccelerationOnly(const ArrayGeometry& array, const TestSignals& signals, Kinematics& out) {
  const std::vector<std::size_t> cg = array.CgLinearIndices();
  const MatrixXd acc_from_measured = PseudoInverse(SenseAxisRows(array, cg));  // 3 x C
  out.acc_body = (acc_from_measured * MeasurementsBySample(array, cg, signals)).transpose();
}

}  // namespace

ExactPath ClassifyArray(const ArrayGeometry& array) {
  const bool linear_complete = LinearRigidBodyRank(array, array.LinearIndices()) == 6;
  const bool rates_complete = NumericalRank(SenseAxisRows(array, array.RateIndices())) == 3;
  if (rates_complete) return linear_complete ? ExactPath::kFused : ExactPath::kSixAOmega;
  return linear_complete ? ExactPath::kLinear : ExactPath::kAccelerationOnly;
}

void CompleteKinematics(const InitialState& initial, const GravityOptions& gravity, double dt_s,
                        Kinematics& kin, const std::atomic<bool>* cancel) {
  KinematicsCompleter completer(initial, gravity, dt_s, kin, cancel);
  for (Index k = 0; k < kin.size(); ++k) {
    ThrowIfCancelled(cancel, k);
    completer.Step(k);
  }
  completer.Finish();
}

void SolveExact(const ArrayGeometry& array, const TestSignals& signals, const SolveOptions& options,
                Kinematics& kin) {
  const ExactPath path = ClassifyArray(array);
  // Acceleration-only kinematics hold no series that needs the rotation
  // (engine/kinematics.h HasRotation): a long recording of a 3-channel head
  // holds 4 series rather than 36 (docs/formats.md "Derived-channel storage").
  if (path == ExactPath::kAccelerationOnly)
    kin.ResizeWithoutRotation(signals.size());
  else
    kin.Resize(signals.size());
  for (Index k = 0; k < signals.size(); ++k) kin.time_s(k) = signals.TimeAt(k);
  kin.dt_s = signals.dt_s;
  switch (path) {
    case ExactPath::kLinear: {
      // Completes the kinematics sample by sample. Fixed-capacity storage
      // for up to 9 (NAP) and 16 linear sensors, heap storage beyond.
      const std::size_t linear_count = array.LinearIndices().size();
      if (linear_count <= 9)
        SolveLinear<9>(array, signals, options, kin);
      else if (linear_count <= static_cast<std::size_t>(kMaxFixedSizeSensors))
        SolveLinear<kMaxFixedSizeSensors>(array, signals, options, kin);
      else
        SolveLinear<Eigen::Dynamic>(array, signals, options, kin);
      return;
    }
    case ExactPath::kSixAOmega:
      SolveSixAOmega(array, signals, kin, options.cancel);
      break;
    case ExactPath::kFused:
      SolveFused(array, signals, kin, options.cancel);
      break;
    case ExactPath::kAccelerationOnly:
      if (options.gravity.compensate)
        throw InputError("array '" + array.name +
                         "' cannot determine rotation, so gravity compensation (which needs the head's "
                         "orientation) is impossible; set gravity.compensate to false.");
      ThrowIfCancelled(options.cancel);
      SolveAccelerationOnly(array, signals, kin);
      return;
  }
  ThrowIfCancelled(options.cancel);
  CompleteKinematics(options.initial, options.gravity, signals.dt_s, kin, options.cancel);
}

}  // namespace napkin::engine

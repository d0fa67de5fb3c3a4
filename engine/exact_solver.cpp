#include "engine/exact_solver.h"

#include <cmath>
#include <limits>
#include <vector>

#include "common/error.h"
#include "engine/array_analysis.h"
#include "engine/integration.h"
#include "engine/rotation.h"

namespace napkin::engine {
namespace {

using Eigen::Index;
using Eigen::Matrix3Xd;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;
using Vector6d = Eigen::Matrix<double, 6, 1>;

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
void SolveLinear(const ArrayGeometry& array, const TestSignals& signals, const SolveOptions& options,
                 Kinematics& out) {
  LinearSensors sensors(array, array.LinearIndices());
  const Index count = sensors.size(), n = signals.size();
  const double dt = signals.dt_s;
  const MatrixXd solve_rows = PseudoInverse(sensors.rows);  // 6 x L
  const Eigen::Matrix<double, 3, Eigen::Dynamic> alpha_rows = solve_rows.bottomRows<3>();
  const MatrixXd measured = MeasurementsBySample(array, array.LinearIndices(), signals);
  const MatrixXd measured_rate = DifferentiateSecondOrder(measured.transpose(), dt).transpose();

  VectorXd centripetal(count), rhs(count), fitted(count), rate_rhs(count), centripetal_rate(count);
  Vector6d solution;

  // Solves sample k for (a, alpha) given omega; returns alpha' too.
  auto solve_sample = [&](Index k, const Vector3d& omega, Vector3d& acc, Vector3d& alpha,
                          Vector3d& alpha_rate) {
    sensors.Centripetal(omega, centripetal);
    rhs = measured.col(k) - centripetal;
    solution.noalias() = solve_rows * rhs;
    acc = solution.head<3>();
    alpha = solution.tail<3>();
    sensors.CentripetalRate(omega, alpha, centripetal_rate);
    rate_rhs = measured_rate.col(k) - centripetal_rate;
    alpha_rate.noalias() = alpha_rows * rate_rhs;
  };

  const int passes = options.corrector_passes;
  const double half_dt = 0.5 * dt, dt2_12 = dt * dt / 12.0;
  Vector3d omega = options.initial.omega_body_radps, acc, alpha, alpha_rate;
  solve_sample(0, omega, acc, alpha, alpha_rate);
  for (Index k = 0; k < n; ++k) {
    if (k > 0) {
      const Vector3d omega_prev = omega, alpha_prev = alpha, alpha_rate_prev = alpha_rate;
      omega = omega_prev + dt * alpha_prev + 0.5 * dt * dt * alpha_rate_prev;  // Taylor predictor
      for (int pass = 0; pass < passes; ++pass) {
        solve_sample(k, omega, acc, alpha, alpha_rate);
        const Vector3d corrected =
            omega_prev + half_dt * (alpha_prev + alpha) + dt2_12 * (alpha_rate_prev - alpha_rate);
        const double change = (corrected - omega).norm();
        omega = corrected;
        if (change <= 1e-15 * (1.0 + omega.norm())) break;
      }
      solve_sample(k, omega, acc, alpha, alpha_rate);  // (a, alpha) consistent with the final omega
    }
    fitted.noalias() = sensors.rows * solution;
    out.residual(k) = (fitted - rhs).norm();
    out.omega_body.row(k) = omega.transpose();
    out.alpha_body.row(k) = alpha.transpose();
    out.acc_body.row(k) = acc.transpose();
  }
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
void SolveSixAOmega(const ArrayGeometry& array, const TestSignals& signals, Kinematics& out) {
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
void SolveFused(const ArrayGeometry& array, const TestSignals& signals, Kinematics& out) {
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
// sensors are not used. Nothing determines omega: every series that needs
// the rotation is NaN, and so is the residual (the rigid-body consistency
// cannot be judged without omega).
void SolveAccelerationOnly(const ArrayGeometry& array, const TestSignals& signals, Kinematics& out) {
  const std::vector<std::size_t> cg = array.CgLinearIndices();
  const MatrixXd acc_from_measured = PseudoInverse(SenseAxisRows(array, cg));  // 3 x C
  out.acc_body = (acc_from_measured * MeasurementsBySample(array, cg, signals)).transpose();
  constexpr double kUndetermined = std::numeric_limits<double>::quiet_NaN();
  for (Series3* series :
       {&out.omega_body, &out.alpha_body, &out.omega_fixed, &out.alpha_fixed, &out.acc_fixed, &out.vel_fixed,
        &out.pos_fixed, &out.roll_pitch_yaw_rad, &out.dcos_rad})
    series->setConstant(kUndetermined);
  out.quat_fixed_from_body.setConstant(kUndetermined);
  out.residual.setConstant(kUndetermined);
}

}  // namespace

ExactPath ClassifyArray(const ArrayGeometry& array) {
  const bool linear_complete = LinearRigidBodyRank(array, array.LinearIndices()) == 6;
  const bool rates_complete = NumericalRank(SenseAxisRows(array, array.RateIndices())) == 3;
  if (rates_complete) return linear_complete ? ExactPath::kFused : ExactPath::kSixAOmega;
  return linear_complete ? ExactPath::kLinear : ExactPath::kAccelerationOnly;
}

void CompleteKinematics(const InitialState& initial, const GravityOptions& gravity, double dt_s,
                        Kinematics& kin) {
  const Index n = kin.size();
  const Eigen::Matrix3d fixed_from_body_0 = InitialFixedFromBody(initial.orientation_rad);
  IntegrateOrientation(dt_s, kin.omega_body, kin.alpha_body, Eigen::Quaterniond(fixed_from_body_0),
                       kin.quat_fixed_from_body);
  // docs/algorithms.md "Gravity": zeroed accelerometers read a - (R^T - R0^T) g;
  // add the term back with the integrated orientation.
  const Vector3d gravity_body_0 = fixed_from_body_0.transpose() * gravity.g_fixed_mps2;
  for (Index k = 0; k < n; ++k) {
    const Eigen::Matrix3d fixed_from_body = QuatAt(kin.quat_fixed_from_body, k).toRotationMatrix();
    if (gravity.compensate)
      kin.acc_body.row(k) +=
          (fixed_from_body.transpose() * gravity.g_fixed_mps2 - gravity_body_0).transpose();
    kin.omega_fixed.row(k) = (fixed_from_body * kin.omega_body.row(k).transpose()).transpose();
    kin.alpha_fixed.row(k) = (fixed_from_body * kin.alpha_body.row(k).transpose()).transpose();
    kin.acc_fixed.row(k) = (fixed_from_body * kin.acc_body.row(k).transpose()).transpose();
    kin.roll_pitch_yaw_rad.row(k) = RollPitchYaw(fixed_from_body).transpose();
    kin.dcos_rad.row(k) = DirectionCosineAngles(fixed_from_body).transpose();
  }
  const Series3 acc_fixed_rate = DifferentiateSecondOrder(kin.acc_fixed, dt_s);
  IntegrateHermite(dt_s, kin.acc_fixed, acc_fixed_rate, initial.velocity_fixed_mps, kin.vel_fixed);
  IntegrateHermite(dt_s, kin.vel_fixed, kin.acc_fixed, Vector3d::Zero(), kin.pos_fixed);
}

Kinematics SolveExact(const ArrayGeometry& array, const TestSignals& signals, const SolveOptions& options) {
  Kinematics kin;
  kin.Resize(signals.size());
  for (Index k = 0; k < signals.size(); ++k) kin.time_s(k) = signals.TimeAt(k);
  kin.dt_s = signals.dt_s;
  switch (ClassifyArray(array)) {
    case ExactPath::kLinear:
      SolveLinear(array, signals, options, kin);
      break;
    case ExactPath::kSixAOmega:
      SolveSixAOmega(array, signals, kin);
      break;
    case ExactPath::kFused:
      SolveFused(array, signals, kin);
      break;
    case ExactPath::kAccelerationOnly:
      if (options.gravity.compensate)
        throw InputError("array '" + array.name +
                         "' cannot determine rotation, so gravity compensation (which needs the head's "
                         "orientation) is impossible; set gravity.compensate to false.");
      SolveAccelerationOnly(array, signals, kin);
      return kin;
  }
  CompleteKinematics(options.initial, options.gravity, signals.dt_s, kin);
  return kin;
}

}  // namespace napkin::engine

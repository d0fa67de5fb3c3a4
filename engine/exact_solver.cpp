#include "engine/exact_solver.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <type_traits>
#include <utility>
#include <vector>

#include "common/error.h"
#include "engine/array_analysis.h"
#include "engine/cancellation.h"
#include "engine/integration.h"
#include "engine/kinematics_completer.h"
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

// The centripetal term of linear sensor i is a quadratic form in omega,
//   c_i(omega) = (n_i.omega)(r_i.omega) - (n_i.r_i)|omega|^2 = C_i . Quadratic(omega),
// with the monomials Quadratic(w) = (wx^2, wy^2, wz^2, wx wy, wx wz, wy wz), and so is its rate
//   dc_i/dt = (n_i.alpha)(r_i.omega) + (n_i.omega)(r_i.alpha) - 2 (n_i.r_i)(omega.alpha)
//           = C_i . QuadraticRate(omega, alpha),
// QuadraticRate(w, a) = (2 wx ax, 2 wy ay, 2 wz az, wx ay + wy ax, wx az + wz ax, wy az + wz ay)
// (AlphaOfOmega and AccelerationAndResidual form both). Every linear map of
// the centripetal terms (the least-squares solution, the residual) is thus a
// fixed 6-column matrix times six monomials.
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

// The monomials Quadratic(w) and QuadraticRate(w, a) of the centripetal term
// (above), and a row of a 6-column map applied to them as a balanced tree of
// sums (few steps where it is on the sample-to-sample chain).
void QuadraticOf(double wx, double wy, double wz, double (&monomials)[6]) {
  monomials[0] = wx * wx;
  monomials[1] = wy * wy;
  monomials[2] = wz * wz;
  monomials[3] = wx * wy;
  monomials[4] = wx * wz;
  monomials[5] = wy * wz;
}

void QuadraticRateOf(const double (&w)[3], const double (&a)[3], double (&rates)[6]) {
  rates[0] = 2.0 * w[0] * a[0];
  rates[1] = 2.0 * w[1] * a[1];
  rates[2] = 2.0 * w[2] * a[2];
  rates[3] = w[0] * a[1] + w[1] * a[0];
  rates[4] = w[0] * a[2] + w[2] * a[0];
  rates[5] = w[1] * a[2] + w[2] * a[1];
}

double ApplyRow(const double (&row)[6], const double (&v)[6]) {
  return ((row[0] * v[0] + row[1] * v[1]) + (row[2] * v[2] + row[3] * v[3])) +
         (row[4] * v[4] + row[5] * v[5]);
}

// A 3 x 6 map as rows of plain doubles.
void RowsOf(const Eigen::Matrix<double, 3, 6>& map, double (&rows)[3][6]) {
  for (int c = 0; c < 3; ++c)
    for (int j = 0; j < 6; ++j) rows[c][j] = map(c, j);
}

// alpha = P_alpha m - P_alpha C Quadratic(omega) and
// alpha' = P_alpha m' - P_alpha C QuadraticRate(omega, alpha) of one sample
// (SolveLinear), in scalars: each 6-term sum as a balanced tree, so that an
// evaluation, which is on the sample-to-sample chain, takes few steps.
class AlphaOfOmega {
 public:
  explicit AlphaOfOmega(const Eigen::Matrix<double, 3, 6>& alpha_centripetal) {
    RowsOf(alpha_centripetal, map_);
  }

  void Evaluate(const double (&omega)[3], const double (&projected)[3], const double (&measured_rate)[3],
                double (&alpha)[3], double (&alpha_rate)[3]) const {
    double monomials[6], rates[6];
    QuadraticOf(omega[0], omega[1], omega[2], monomials);
    for (int c = 0; c < 3; ++c) alpha[c] = projected[c] - ApplyRow(map_[c], monomials);
    QuadraticRateOf(omega, alpha, rates);
    for (int c = 0; c < 3; ++c) alpha_rate[c] = measured_rate[c] - ApplyRow(map_[c], rates);
  }

 private:
  double map_[3][6];
};

// The stacked sums of samples [first, first + count) into the columns of
// `sums` (row i: sample first + i; column j: row j of stacked_recorded
// times the sample's channels): for each sample the sum over the sensors in
// their order, from zero, as a sample-by-sample loop forms it; here a loop
// over samples, which the compiler vectorizes. kSensors is the number of
// sensors when it is known at compile time (Eigen::Dynamic otherwise).
template <int kSensors, typename Stacked, typename Sums>
NAPKIN_SAMPLE_LOOP_CLONES void StackedSums(const Stacked& stacked_recorded,
                                           const std::vector<const double*>& columns, Index first,
                                           Index count, Sums& sums) {
  for (Index j = 0; j < stacked_recorded.rows(); ++j) {
    double* __restrict sum = &sums(0, j);
    if constexpr (kSensors != Eigen::Dynamic) {
      double coefficient[kSensors];
      const double* __restrict measured[kSensors];
      for (int i = 0; i < kSensors; ++i) {
        coefficient[i] = stacked_recorded(j, i);
        measured[i] = columns[static_cast<std::size_t>(i)] + first;
      }
      for (Index t = 0; t < count; ++t) {
        double s = 0.0;
        for (int i = 0; i < kSensors; ++i) s += coefficient[i] * measured[i][t];
        sum[t] = s;
      }
    } else {
      for (Index t = 0; t < count; ++t) sum[t] = 0.0;
      for (Index i = 0; i < stacked_recorded.cols(); ++i) {
        const double coefficient = stacked_recorded(j, i);
        const double* __restrict measured = columns[static_cast<std::size_t>(i)] + first;
        for (Index t = 0; t < count; ++t) sum[t] += coefficient * measured[t];
      }
    }
  }
}

// The acceleration P_a (m - c(omega)) and the square of the least-squares
// residual norm |complement (m - c(omega))| of samples [begin, end) of
// SolveLinear, from their final omega (the square roots are taken once the
// record is solved): each sample on its own, in a loop over samples the
// compiler vectorizes. `stacked` holds the block's sums (SolveLinear), row
// s for sample first + s.
template <int kComplementRows, typename Sums, typename ComplementBySix>
NAPKIN_SAMPLE_LOOP_CLONES void AccelerationAndResidual(const Sums& stacked, Index first, Index begin,
                                                       Index end,
                                                       const Eigen::Matrix<double, 3, 6>& acc_centripetal,
                                                       const ComplementBySix& complement_centripetal,
                                                       Kinematics& out) {
  const internal::SeriesColumns<const double> omega = internal::ColumnsOf(std::as_const(out.omega_body));
  const internal::SeriesColumns<double> acc = internal::ColumnsOf(out.acc_body);
  const double* acc_projected[3] = {&stacked(0, 3), &stacked(0, 4), &stacked(0, 5)};
  double* residual_sq = out.residual.data();
  double acc_map[3][6];
  RowsOf(acc_centripetal, acc_map);
  const Index complement_rows = complement_centripetal.rows();
  NAPKIN_INDEPENDENT_SAMPLES
  for (Index k = begin; k < end; ++k) {
    double monomials[6];
    QuadraticOf(omega.x[k], omega.y[k], omega.z[k], monomials);
    acc.x[k] = acc_projected[0][k - first] - ApplyRow(acc_map[0], monomials);
    acc.y[k] = acc_projected[1][k - first] - ApplyRow(acc_map[1], monomials);
    acc.z[k] = acc_projected[2][k - first] - ApplyRow(acc_map[2], monomials);
    double sum_sq = 0.0;
    for (Index r = 0; r < (kComplementRows == Eigen::Dynamic ? complement_rows : kComplementRows); ++r) {
      double residual = stacked(k - first, 6 + r);
      for (int j = 0; j < 6; ++j) residual -= complement_centripetal(r, j) * monomials[j];
      sum_sq += residual * residual;
    }
    residual_sq[k] = sum_sq;
  }
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
// Only omega (and with it alpha and alpha') needs the previous sample, so
// the record is solved in blocks of kCompletionBlock samples: the sums of
// the block, then the chain of omega alone, then the acceleration and the
// residual of every sample of the block, then the block's orientation and
// fixed-frame series (KinematicsCompleter) — every step but the chain a
// loop over samples that the processor runs side by side (and the compiler
// vectorizes), while the block is in cache.
// MaxSensors bounds the number of linear sensors (fixed-capacity storage on
// the stack, nothing allocated per sample or block); Eigen::Dynamic for any
// number.
template <int MaxSensors>
void SolveLinear(const ArrayGeometry& array, const TestSignals& signals, const SolveOptions& options,
                 Kinematics& out) {
  // The residual's complement has at most MaxSensors - 6 rows; with a fixed
  // MaxSensors it is stored with exactly that many, zero-padded (zero rows
  // add exact zeros to the residual norm).
  constexpr int kComplementRows = MaxSensors == Eigen::Dynamic ? Eigen::Dynamic : MaxSensors - 6;
  using SixBySensors = Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, MaxSensors>;
  using ComplementBySensors =
      Eigen::Matrix<double, kComplementRows, Eigen::Dynamic, 0, kComplementRows, MaxSensors>;
  using ComplementBySix = Eigen::Matrix<double, kComplementRows, 6>;

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

  // The stacked map of the recorded channels: the alpha rows of P, its
  // acceleration rows, then the complement.
  constexpr int kStackedRows = MaxSensors;  // 6 + kComplementRows, or Eigen::Dynamic
  const Index stacked_rows = 6 + complement_rows;
  using StackedBySensors = Eigen::Matrix<double, kStackedRows, Eigen::Dynamic, 0, kStackedRows, MaxSensors>;
  StackedBySensors stacked_recorded(stacked_rows, count);
  stacked_recorded.topRows(3) = solve_recorded.bottomRows(3);
  stacked_recorded.middleRows(3, 3) = solve_recorded.topRows(3);
  stacked_recorded.bottomRows(complement_rows) = complement_recorded;
  // The block's scratch: the stacked sums of its samples and of two more on
  // each side (the central differences, the record's ends), one column per
  // stacked row; and P_alpha m' of its samples.
  constexpr Index kScratchSamples = internal::kCompletionBlock + 4;
  using Scratch = std::conditional_t<MaxSensors == Eigen::Dynamic, MatrixXd,
                                     Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kScratchSamples,
                                                   MaxSensors == Eigen::Dynamic ? 1 : MaxSensors>>;
  Scratch stacked(kScratchSamples, stacked_rows);
  alignas(64) double alpha_measured_rate[3][internal::kCompletionBlock];
  const bool nine_sensors = count == 9 && stacked_rows == 9;

  internal::KinematicsCompleter completer(options.initial, options.gravity, dt, out, options.cancel,
                                          options.summary_series_only);
  const double half_dt = 0.5 * dt, dt2_12 = dt * dt / 12.0, inv_2dt = 0.5 / dt;
  const int passes = options.corrector_passes;
  const AlphaOfOmega centripetal_map(alpha_centripetal);
  const double half_dt_sq = 0.5 * dt * dt;
  // The state carried from sample to sample.
  double omega[3] = {options.initial.omega_body_radps.x(), options.initial.omega_body_radps.y(),
                     options.initial.omega_body_radps.z()};
  double alpha[3] = {0.0, 0.0, 0.0}, alpha_rate[3] = {0.0, 0.0, 0.0};
  for (Index begin = 0; begin < n; begin += internal::kCompletionBlock) {
    ThrowIfCancelled(options.cancel);
    const Index end = std::min(n, begin + internal::kCompletionBlock);
    // Scratch row s holds sample first + s.
    const Index first = std::max<Index>(0, begin - 2), last = std::min(n, end + 2);
    if constexpr (MaxSensors != Eigen::Dynamic) {
      if (nine_sensors)
        StackedSums<9>(stacked_recorded, channels.columns, first, last - first, stacked);
      else
        StackedSums<Eigen::Dynamic>(stacked_recorded, channels.columns, first, last - first, stacked);
    } else {
      StackedSums<Eigen::Dynamic>(stacked_recorded, channels.columns, first, last - first, stacked);
    }
    auto projected = [&](Index k, Index row) { return stacked(k - first, row); };

    // P_alpha m' by second-order differences, as DifferentiateSecondOrder takes them.
    for (int c = 0; c < 3; ++c) {
      auto rate = [&](Index k) -> double& { return alpha_measured_rate[c][k - begin]; };
      for (Index k = std::max<Index>(begin, 1); k < std::min(end, n - 1); ++k)
        rate(k) = (projected(k + 1, c) - projected(k - 1, c)) * inv_2dt;
      if (n < 2) {
        rate(0) = 0.0;
      } else if (n == 2) {
        for (Index k = begin; k < end; ++k) rate(k) = (projected(1, c) - projected(0, c)) / dt;
      } else {
        if (begin == 0)
          rate(0) = (-3.0 * projected(0, c) + 4.0 * projected(1, c) - projected(2, c)) * inv_2dt;
        if (end == n)
          rate(n - 1) =
              (3.0 * projected(n - 1, c) - 4.0 * projected(n - 2, c) + projected(n - 3, c)) * inv_2dt;
      }
    }

    // The chain: omega, alpha and alpha' of each sample from the previous
    // one's. At sample k > 0, omega is predicted by a Taylor step; each pass
    // evaluates alpha and alpha' at the current omega and the Hermite rule
    // gives the corrected omega. Once the correction changes omega by no
    // more than round-off (|change| <= 1e-15 sqrt(1 + |omega|^2)), the
    // evaluated point is the sample's omega, with the alpha and alpha'
    // evaluated there: the three agree exactly, and omega satisfies the rule
    // to round-off. Without convergence within the passes, the last
    // corrected omega is evaluated once more.
    for (Index k = begin; k < end; ++k) {
      const Index s = k - first, t = k - begin;
      const double projected_k[3] = {stacked(s, 0), stacked(s, 1), stacked(s, 2)};
      const double measured_rate_k[3] = {alpha_measured_rate[0][t], alpha_measured_rate[1][t],
                                         alpha_measured_rate[2][t]};
      if (k == 0) {
        // The initial omega.
        centripetal_map.Evaluate(omega, projected_k, measured_rate_k, alpha, alpha_rate);
      } else {
        double base[3], point[3];
        for (int c = 0; c < 3; ++c) {
          base[c] = (omega[c] + half_dt * alpha[c]) + dt2_12 * alpha_rate[c];
          point[c] = (omega[c] + dt * alpha[c]) + half_dt_sq * alpha_rate[c];  // Taylor predictor
        }
        bool converged = false;
        for (int pass = 0; pass < passes && !converged; ++pass) {
          centripetal_map.Evaluate(point, projected_k, measured_rate_k, alpha, alpha_rate);
          double change_sq = 0.0, corrected_sq = 0.0;
          double corrected[3];
          for (int c = 0; c < 3; ++c) {
            corrected[c] = (base[c] + half_dt * alpha[c]) - dt2_12 * alpha_rate[c];
            change_sq += (corrected[c] - point[c]) * (corrected[c] - point[c]);
            corrected_sq += corrected[c] * corrected[c];
          }
          // Compared squared: no square root on the sample-to-sample chain.
          converged = change_sq <= 1e-30 * (1.0 + corrected_sq);
          if (!converged)
            for (int c = 0; c < 3; ++c) point[c] = corrected[c];
        }
        if (!converged) centripetal_map.Evaluate(point, projected_k, measured_rate_k, alpha, alpha_rate);
        for (int c = 0; c < 3; ++c) omega[c] = point[c];
      }
      for (int c = 0; c < 3; ++c) {
        out.omega_body(k, c) = omega[c];
        out.alpha_body(k, c) = alpha[c];
      }
    }

    AccelerationAndResidual<kComplementRows>(stacked, first, begin, end, acc_centripetal,
                                             complement_centripetal, out);
    if (!options.body_frame_only) completer.CompleteRows(begin, end);
  }
  // |residual| = sqrt(squared norm), a packet of square roots at a time.
  out.residual = out.residual.cwiseSqrt();
  if (!options.body_frame_only) completer.Finish();
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
                        Kinematics& kin, const std::atomic<bool>* cancel, bool summary_series_only) {
  internal::KinematicsCompleter completer(initial, gravity, dt_s, kin, cancel, summary_series_only);
  for (Index begin = 0; begin < kin.size(); begin += internal::kCompletionBlock) {
    ThrowIfCancelled(cancel);
    completer.CompleteRows(begin, std::min(kin.size(), begin + internal::kCompletionBlock));
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
  else if (options.summary_series_only && !options.body_frame_only)
    kin.ResizeForSummary(signals.size());
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
  if (!options.body_frame_only)
    CompleteKinematics(options.initial, options.gravity, signals.dt_s, kin, options.cancel,
                       options.summary_series_only);
}

}  // namespace napkin::engine

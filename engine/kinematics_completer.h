#pragma once
// The completion of solved body-frame kinematics (CompleteKinematics,
// engine/exact_solver.h) a block of samples at a time, so that a solver can
// complete each block while it is in cache. Internal to the engine.
//
// Each block is done in three passes: the orientation increments of its
// samples (independent of each other), the quaternion chain (the only step
// that needs the previous sample), then the gravity term and the rotation of
// every series to fixed axes (again independent across samples, so the
// compiler vectorizes it over samples). The rules are IntegrateOrientation's,
// DifferentiateSecondOrder's and IntegrateHermite's (engine/integration.h);
// the results equal theirs to round-off, not bit for bit: the quaternions
// are normalized off the chain, and each velocity step adds its increment as
// one term.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <atomic>

#include "engine/kinematics.h"
#include "engine/solver.h"

// The loops over samples of the exact solver and of the completion, in
// which each sample is on its own (the compiler vectorizes them), are also
// compiled for AVX2 and chosen when the program loads (GCC's target_clones):
// the wider vectors do each sample's arithmetic with the same operations in
// the same order, without FMA contraction (engine/CMakeLists.txt), so both
// versions give the same bits.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define NAPKIN_SAMPLE_LOOP_CLONES __attribute__((target_clones("default", "avx2")))
#else
#define NAPKIN_SAMPLE_LOOP_CLONES
#endif

// Before such a loop whose series are distinct arrays: no dependence between
// samples (GCC cannot tell the Eigen columns apart and would otherwise give up).
#if defined(__GNUC__) && !defined(__clang__)
#define NAPKIN_INDEPENDENT_SAMPLES _Pragma("GCC ivdep")
#else
#define NAPKIN_INDEPENDENT_SAMPLES
#endif

namespace napkin::engine::internal {

// The three columns of a series (engine/kinematics.h: each one contiguous),
// for the loops over samples: x[k], y[k], z[k] of row k.
template <typename Scalar>
struct SeriesColumns {
  Scalar* x;
  Scalar* y;
  Scalar* z;
};
inline SeriesColumns<double> ColumnsOf(Series3& series) {
  return {series.col(0).data(), series.col(1).data(), series.col(2).data()};
}
inline SeriesColumns<const double> ColumnsOf(const Series3& series) {
  return {series.col(0).data(), series.col(1).data(), series.col(2).data()};
}

// Samples per block of the exact solver and of the completion: the block's
// scratch (a few series of this many doubles) stays in the first-level cache.
inline constexpr Eigen::Index kCompletionBlock = 256;

class KinematicsCompleter {
 public:
  // With summary_series_only (SolveOptions::summary_series_only), the
  // fixed-frame omega and alpha and the angles are not computed: `kin` has
  // the shape of Kinematics::ResizeForSummary.
  KinematicsCompleter(const InitialState& initial, const GravityOptions& gravity, double dt_s,
                      Kinematics& kin, const std::atomic<bool>* cancel, bool summary_series_only = false);

  // Completes rows [begin, end) (end - begin <= kCompletionBlock) once rows
  // 0 .. end - 1 of omega_body, alpha_body and acc_body are final: the
  // quaternion, the gravity term (added to acc_body) and the fixed-frame
  // omega, alpha and acceleration. Blocks are completed in order, from row 0.
  void CompleteRows(Eigen::Index begin, Eigen::Index end);

  // After the last block: the angles, then velocity (from the initial
  // velocity) and position (from 0) by the Hermite rule.
  void Finish();

 private:
  Kinematics& kin_;
  const std::atomic<bool>* cancel_;
  const GravityOptions& gravity_;
  const InitialState& initial_;
  const Eigen::Matrix3d fixed_from_body_0_;
  const Eigen::Vector3d gravity_body_0_;
  const double dt_, half_dt_, dt2_12_;
  const bool summary_series_only_;
  Eigen::Quaterniond fixed_from_body_;  // of the last completed row
  // The orientation increments QuaternionExp(theta_k) of the block (w, x, y, z).
  alignas(64) double increment_[4][kCompletionBlock];
  alignas(64) double angle_sq_[kCompletionBlock];  // |theta_k|^2, for QuaternionExp's branch
};

}  // namespace napkin::engine::internal

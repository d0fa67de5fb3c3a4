#pragma once
// The `exact` solver (docs/algorithms.md "Solvers", "Orientation"): rigid-body
// least squares for any geometry, with angular-rate sensors when present.
#include "engine/array_geometry.h"
#include "engine/kinematics.h"
#include "engine/signals.h"
#include "engine/solver.h"
#include "engine/units.h"

namespace napkin::engine {

// How the exact solver uses an (already validated) array.
enum class ExactPath {
  // >= 6 linear sensors whose rigid-body rows have rank 6 and fewer than 3
  // independent angular-rate axes: (a, alpha) by least squares, omega by
  // integrating alpha (predictor-corrector, Hermite rule).
  kLinear,
  // Linear rank < 6 but >= 3 independent rate axes (e.g. 3 accelerometers
  // + 3 angular-rate sensors, "6a-omega"): omega from the rate sensors,
  // alpha = d omega / dt, a from the linear sensors with omega, alpha known.
  kSixAOmega,
  // Linear rank 6 and >= 3 independent rate axes (e.g. NAP + 3 ARS):
  // omega from the rate sensors; (a, alpha) by weighted least squares of the
  // linear sensors and the differentiated rates.
  kFused,
  // Linear rank < 6 and fewer than 3 independent rate axes, but linear
  // sensors at the CG along 3 independent axes (e.g. 3a-cg): rotation is
  // undetermined; a by least squares over the CG sensors' sense axes, every
  // rotation-dependent series empty (engine/kinematics.h HasRotation;
  // docs/algorithms.md "Acceleration-only arrays").
  kAccelerationOnly,
};

ExactPath ClassifyArray(const ArrayGeometry& validated_array);

// Nominal noise levels that weight the fused least squares (kFused): each
// row is divided by the standard deviation of its error. A head linear
// accelerometer channel after CFC 1000: about 0.05 g. An angular-rate channel
// after CFC 60: about 0.01 rad/s, which the five-point derivative turns into
// an alpha error of sqrt(130)/12 * 0.01 rad/s / dt (95 rad/s^2 at 10 kHz).
// With arms of ~5 cm the linear sensors thus know alpha ~10x better than the
// differentiated rates; the fusion weights them accordingly.
inline constexpr double kFusedLinearSigmaMps2 = 0.05 * kStandardGravity;
inline constexpr double kFusedRateSigmaRadps = 0.01;

// Solves one test with a validated array and checked signals (Solve() does
// both checks and then calls this), into `out` (its memory reused where a
// series is as long; every series overwritten).
void SolveExact(const ArrayGeometry& validated_array, const TestSignals& signals, const SolveOptions& options,
                Kinematics& out);

// Fills orientation, fixed-frame series, velocity, position and angles from
// kinematics whose time_s, omega_body, alpha_body, acc_body and residual
// are set (shared by every solver path): integrates the orientation from
// R0 = InitialFixedFromBody(initial.orientation_rad), applies the gravity
// compensation a_body += (R^T - R0^T) g_fixed when asked, rotates to fixed
// axes and integrates velocity (from initial.velocity_fixed_mps) and position
// (from 0) with the Hermite rule. Throws Cancelled once `cancel` is set
// (engine/cancellation.h). With summary_series_only (kin shaped by
// Kinematics::ResizeForSummary), the fixed-frame omega and alpha and the
// angles are left out (SolveOptions::summary_series_only).
void CompleteKinematics(const InitialState& initial, const GravityOptions& gravity, double dt_s,
                        Kinematics& kinematics, const std::atomic<bool>* cancel = nullptr,
                        bool summary_series_only = false);

}  // namespace napkin::engine

#pragma once
// From the signals of a head accelerometer array to six-degree-of-freedom
// kinematics. See docs/algorithms.md "Solvers".
#include <array>
#include <atomic>
#include <optional>
#include <string_view>

#include "engine/array_geometry.h"
#include "engine/kinematics.h"
#include "engine/signals.h"
#include "engine/units.h"
#include "engine/vocabulary.h"

namespace napkin::engine {

enum class SolverKind {
  kExact,  // rigid-body least squares for any geometry (default)
  kSeed,   // LC_COMP of report Appendix B, reproduced for legacy comparison
};

// Every solver, in the order their names are offered to users.
inline constexpr std::array<NamedValue<SolverKind>, 2> kSolverNames{
    {{SolverKind::kExact, "exact"}, {SolverKind::kSeed, "seed"}}};
inline constexpr std::array<SolverKind, 2> kSolverKinds = ValuesOf(kSolverNames);

// The one spelling of each solver ("exact", "seed") in processing configs,
// the --solver option and the catalogue's results, and its inverse (nullopt
// for an unknown name).
constexpr const auto& NamesOf(SolverKind) { return kSolverNames; }

struct GravityOptions {
  bool compensate = false;  // add back -(R^T - R0^T) g_fixed (docs/algorithms.md "Gravity")
  Eigen::Vector3d g_fixed_mps2{0.0, 0.0, kStandardGravity};  // SAE: z down
};

inline constexpr int kDefaultCorrectorPasses = 3;

struct SolveOptions {
  SolverKind solver = SolverKind::kExact;
  InitialState initial;
  GravityOptions gravity;
  int corrector_passes = kDefaultCorrectorPasses;  // predictor-corrector passes per sample (exact solver)
  // Set from elsewhere to stop the solve: Solve throws Cancelled (engine/cancellation.h).
  const std::atomic<bool>* cancel = nullptr;
  // The exact solver's body-frame series (omega_body, alpha_body, acc_body),
  // time_s and the residual only: what the trial solves of the consistency
  // screening read (engine/screening.cpp). The orientation, the fixed-frame
  // series, the angles, velocity and position are not computed (their
  // contents are unspecified). Not with the seed solver or gravity
  // compensation (whose term needs the orientation).
  bool body_frame_only = false;
  // The series the summary, the injury criteria and the screening read
  // (engine/pipeline.cpp), bit for bit as the full solve computes them: the
  // exact solver leaves omega_fixed, alpha_fixed, roll_pitch_yaw_rad and
  // dcos_rad empty (0 rows; Kinematics::ResizeForSummary) rather than
  // rotating and converting every sample for nobody. For a run that stores
  // no derived channels (jobs/scheduler.cpp). The seed solver ignores it.
  bool summary_series_only = false;
};

// Solves one test. Throws InputError naming the slot when `signals` lacks a
// channel of `array`, or the data are unusable (fewer than 2 samples,
// non-finite values, non-positive dt), and when `options` asks the seed
// solver for what it cannot do (gravity compensation, corrector passes)
// rather than ignore it. Throws Cancelled once options.cancel is set.
Kinematics Solve(const ArrayGeometry& array, const TestSignals& signals, const SolveOptions& options);

// Solve into `out`, the caller's storage: a series as long as the one it
// had keeps its memory, so a loop over tests of one length that keeps its
// Kinematics maps no new pages whatever the allocator does with freed memory
// (docs/architecture.md "Memory"). Every series is overwritten (the seed
// solver's result is moved in); on a throw `out` holds no result.
void Solve(const ArrayGeometry& array, const TestSignals& signals, const SolveOptions& options,
           Kinematics& out);

}  // namespace napkin::engine

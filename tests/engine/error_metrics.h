#pragma once
// Worst-case errors of solved kinematics against synthetic truth, as the
// accuracy targets of docs/algorithms.md state them.
#include <algorithm>
#include <cstdio>
#include <string>

#include "engine/integration.h"
#include "engine/kinematics.h"
#include "engine/rotation.h"
#include "engine/solver.h"
#include "engine/units.h"
#include "synth/synthetic_tests.h"

namespace napkin::test_support {

struct KinematicsErrors {
  double omega_rel = 0.0;        // max |omega - truth| / max |truth| (body)
  double alpha_rel = 0.0;        // max |alpha - truth| / max |truth| (body)
  double orientation_deg = 0.0;  // max angle between solved and true orientation
  double acc_rel = 0.0;          // max |a_cg - truth| / max |truth| (fixed)
  double vel_rel = 0.0;          // max |v - truth| / max |truth - v0|
  double pos_abs_m = 0.0;        // max |p - truth|

  // Keeps, per measure, the larger of this and `other` (the worst case over a set of motions).
  void KeepWorst(const KinematicsErrors& other) {
    omega_rel = std::max(omega_rel, other.omega_rel);
    alpha_rel = std::max(alpha_rel, other.alpha_rel);
    orientation_deg = std::max(orientation_deg, other.orientation_deg);
    acc_rel = std::max(acc_rel, other.acc_rel);
    vel_rel = std::max(vel_rel, other.vel_rel);
    pos_abs_m = std::max(pos_abs_m, other.pos_abs_m);
  }
};

inline double MaxRowNorm(const engine::Series3& s) { return s.rowwise().norm().maxCoeff(); }

inline KinematicsErrors CompareKinematics(const engine::Kinematics& solved, const engine::Kinematics& truth) {
  KinematicsErrors e;
  e.omega_rel = MaxRowNorm(solved.omega_body - truth.omega_body) / MaxRowNorm(truth.omega_body);
  e.alpha_rel = MaxRowNorm(solved.alpha_body - truth.alpha_body) / MaxRowNorm(truth.alpha_body);
  for (Eigen::Index k = 0; k < truth.size(); ++k)
    e.orientation_deg =
        std::max(e.orientation_deg, engine::AngleBetween(engine::QuatAt(solved.quat_fixed_from_body, k),
                                                         engine::QuatAt(truth.quat_fixed_from_body, k)) *
                                        engine::kDegPerRad);
  e.acc_rel = MaxRowNorm(solved.acc_fixed - truth.acc_fixed) / MaxRowNorm(truth.acc_fixed);
  const engine::Series3 vel_change = truth.vel_fixed.rowwise() - truth.vel_fixed.row(0);
  e.vel_rel = MaxRowNorm(solved.vel_fixed - truth.vel_fixed) / MaxRowNorm(vel_change);
  e.pos_abs_m = MaxRowNorm(solved.pos_fixed - truth.pos_fixed);
  return e;
}

inline void PrintErrors(const std::string& label, const KinematicsErrors& e) {
  std::printf(
      "[errors] %-34s omega %.2e %% | alpha %.2e %% | orient %.2e deg | acc %.2e %% | vel %.2e %% | pos %.2e "
      "m\n",
      label.c_str(), 100 * e.omega_rel, 100 * e.alpha_rel, e.orientation_deg, 100 * e.acc_rel,
      100 * e.vel_rel, e.pos_abs_m);
}

// Solver options that start from a synthetic test's true initial state.
inline engine::SolveOptions OptionsFor(const synth::SyntheticTest& test) {
  engine::SolveOptions options;
  options.initial = test.initial;
  return options;
}

}  // namespace napkin::test_support

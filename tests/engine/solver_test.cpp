// Solve(): input checks, the angular-rate paths (6a-omega, fused), the
// report's sequential rotations, gravity compensation and residuals.
#include "engine/solver.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <ostream>

#include "common/error.h"
#include "engine/exact_solver.h"
#include "engine/report_known_answers.h"
#include "engine/rotation.h"
#include "engine/units.h"
#include "synth/synthetic_tests.h"
#include "tests/engine/error_metrics.h"
#include "tests/support/named_cases.h"
#include "tests/support/reference_arrays.h"

namespace napkin::engine {
namespace {

using test_support::CompareKinematics;
using test_support::KinematicsErrors;
using test_support::OptionsFor;
using test_support::PrintErrors;
using ::testing::HasSubstr;

std::string SolveError(const ArrayGeometry& array, const TestSignals& signals,
                       const SolveOptions& options = {}) {
  try {
    Solve(array, signals, options);
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

TEST(Solver, RejectsUnusableSignals) {
  const synth::SyntheticTest test =
      synth::SynthSeedFixedAxis(test_support::Denton3222(), Eigen::Vector3d::Zero());
  EXPECT_EQ(SolveError(test.array, test.signals), "");

  TestSignals missing = test.signals;
  missing.slots[6] = "something_else";
  EXPECT_THAT(SolveError(test.array, missing),
              HasSubstr("channel 'xarm_y' required by array 'denton-3222' is missing"));

  TestSignals one_sample = test.signals;
  one_sample.samples.conservativeResize(1, Eigen::NoChange);
  EXPECT_THAT(SolveError(test.array, one_sample), HasSubstr("at least 2 are needed"));

  for (double dt : {0.0, -1e-4, std::numeric_limits<double>::quiet_NaN()}) {
    TestSignals bad_dt = test.signals;
    bad_dt.dt_s = dt;
    EXPECT_THAT(SolveError(test.array, bad_dt), HasSubstr("sampling interval must be positive and finite"));
  }

  TestSignals not_finite = test.signals;
  not_finite.samples(41, 4) = std::numeric_limits<double>::infinity();
  EXPECT_THAT(SolveError(test.array, not_finite),
              HasSubstr("channel 'yarm_x' has a non-finite value at row 42 (t = 0.0041 s)"));

  TestSignals ragged = test.signals;
  ragged.slots.pop_back();
  EXPECT_THAT(SolveError(test.array, ragged), HasSubstr("columns but"));

  SolveOptions zero_passes;
  zero_passes.corrector_passes = 0;
  EXPECT_THAT(SolveError(test.array, test.signals, zero_passes),
              HasSubstr("corrector_passes must be at least 1"));

  ArrayGeometry broken = test.array;
  broken.sensors[2].axis_body.setZero();
  EXPECT_THROW(Solve(broken, test.signals, {}), InvalidArrayError);
}

TEST(Solver, ExtraChannelsAndColumnOrderDoNotMatter) {
  const synth::SyntheticTest test =
      synth::SynthSeedFixedAxis(test_support::VolpeTable42(), Eigen::Vector3d(0.5, 0.5, 0.5));
  TestSignals shuffled;
  shuffled.dt_s = test.signals.dt_s;
  shuffled.slots = {"extra"};
  shuffled.samples.resize(test.signals.size(), 10);
  shuffled.samples.col(0).setConstant(std::numeric_limits<double>::quiet_NaN());  // unused, may be anything
  for (int i = 0; i < 9; ++i) {
    shuffled.slots.push_back(test.signals.slots[static_cast<std::size_t>(8 - i)]);
    shuffled.samples.col(i + 1) = test.signals.samples.col(8 - i);
  }
  const Kinematics a = Solve(test.array, test.signals, OptionsFor(test));
  const Kinematics b = Solve(test.array, shuffled, OptionsFor(test));
  EXPECT_EQ(a.omega_body, b.omega_body);
  EXPECT_EQ(a.vel_fixed, b.vel_fixed);
}

// 6a-omega (3 CG accelerometers + 3 rate sensors) and the fused 12-channel
// NAP + ARS on the random motions, sensors displaced up to 0.25 in:
// omega <= 0.05 % of peak, CG acceleration <= 0.1 % of peak.
TEST(Solver, AngularRatePathsMeetAccuracyTargets) {
  for (const ArrayGeometry& nominal : {test_support::SixAOmegaCg(), test_support::NapArs12()}) {
    KinematicsErrors worst;
    for (std::uint64_t seed = 1; seed <= 8; ++seed) {
      SCOPED_TRACE(nominal.name + " seed " + std::to_string(seed));
      synth::RandomMotionOptions motion;
      motion.seed = seed;
      const synth::SyntheticTest test = synth::SynthRandomMotion(
          synth::DisplaceSensors(nominal, 0.25 * kMetresPerInch, 200 + seed), motion);
      const Kinematics solved = Solve(test.array, test.signals, OptionsFor(test));
      const KinematicsErrors e = CompareKinematics(solved, test.truth);
      EXPECT_LE(e.omega_rel, 0.05e-2);
      EXPECT_LE(e.acc_rel, 0.1e-2);
      EXPECT_LE(e.orientation_deg, 0.02);
      EXPECT_LE(e.vel_rel, 0.05e-2);
      // Clean data: the residual stays far below a channel's noise (~0.05 g);
      // what remains in the fused case is the five-point derivative of the
      // rates disagreeing with the linear sensors at the pulses' kinks.
      EXPECT_LT(solved.residual.maxCoeff(), 0.02 * kStandardGravity);
      worst.KeepWorst(e);
    }
    PrintErrors("random x8 " + nominal.name, worst);
  }
}

// Rate sensors in deg/s are converted by the array's unit factor.
TEST(Solver, RateSensorsInDegreesPerSecond) {
  ArrayGeometry array = test_support::SixAOmegaCg();
  for (Sensor& sensor : array.sensors) {
    if (sensor.kind != SensorKind::kAngularRate) continue;
    sensor.unit = "deg/s";
    sensor.si_per_unit = std::numbers::pi / 180.0;
  }
  synth::RandomMotionOptions motion;
  motion.seed = 3;
  const synth::SyntheticTest test = synth::SynthRandomMotion(array, motion);
  const KinematicsErrors e = CompareKinematics(Solve(test.array, test.signals, OptionsFor(test)), test.truth);
  EXPECT_LE(e.omega_rel, 1e-12);
  EXPECT_LE(e.acc_rel, 0.1e-2);
}

// A reference array of every kind the exact solver handles.
struct ReferenceArrayCase {
  const char* name;
  ArrayGeometry (*array)();
};
void PrintTo(const ReferenceArrayCase& reference, std::ostream* os) { *os << reference.name; }

class SequentialRotationsTest : public ::testing::TestWithParam<ReferenceArrayCase> {};

// Report section 4.4: the final orientation is Rx(90) Ry(90) Rz(90).
TEST_P(SequentialRotationsTest, EndAtKnownOrientation) {
  const ArrayGeometry array = GetParam().array();
  const synth::SyntheticTest test = synth::SynthSequential(array);
  const Kinematics solved = Solve(test.array, test.signals, OptionsFor(test));
  const Eigen::Quaterniond final_quat = QuatAt(solved.quat_fixed_from_body, solved.size() - 1);
  const double quarter = report::kSequentialTurnRad;
  const Eigen::Quaterniond expected(Eigen::Matrix3d(Rx(quarter) * Ry(quarter) * Rz(quarter)));
  const double error_deg = AngleBetween(final_quat, expected) * kDegPerRad;
  const KinematicsErrors e = CompareKinematics(solved, test.truth);
  std::printf("[errors] 4.4 %-14s final orientation error %.2e deg (throughout %.2e deg, omega %.2e %%)\n",
              array.name.c_str(), error_deg, e.orientation_deg, 100 * e.omega_rel);
  EXPECT_LE(error_deg, 0.005) << array.name;
  // Final roll/pitch/yaw of Rx(90) Ry(90) Rz(90) = Ry(90) Rx(180)... check via R.
  const Eigen::Vector3d rpy = solved.roll_pitch_yaw_rad.row(solved.size() - 1).transpose();
  EXPECT_LE((Rz(rpy.z()) * Ry(rpy.y()) * Rx(rpy.x()) - expected.toRotationMatrix()).norm(), 1e-3);
}

INSTANTIATE_TEST_SUITE_P(ReferenceArrays, SequentialRotationsTest,
                         ::testing::Values(ReferenceArrayCase{"ideal_3222", &test_support::Ideal3222},
                                           ReferenceArrayCase{"volpe_table4_2", &test_support::VolpeTable42},
                                           ReferenceArrayCase{"denton_3222", &test_support::Denton3222},
                                           ReferenceArrayCase{"six_a_omega_cg", &test_support::SixAOmegaCg},
                                           ReferenceArrayCase{"nap_ars12", &test_support::NapArs12}),
                         test_support::CaseName());

// Gravity (docs/algorithms.md): with compensation the solver recovers the true
// CG acceleration; without it the velocity error is metres per second.
TEST(Solver, GravityCompensationRecoversTruth) {
  synth::RandomMotionOptions motion;
  motion.synth.gravity = true;
  for (std::uint64_t seed : {4, 9}) {
    for (const ArrayGeometry& array :
         {test_support::Denton3222(), test_support::NapArs12(), test_support::SixAOmegaCg()}) {
      motion.seed = seed;
      const synth::SyntheticTest test = synth::SynthRandomMotion(array, motion);
      SolveOptions options = OptionsFor(test);
      options.gravity.compensate = true;
      const KinematicsErrors with = CompareKinematics(Solve(test.array, test.signals, options), test.truth);
      options.gravity.compensate = false;
      const KinematicsErrors without =
          CompareKinematics(Solve(test.array, test.signals, options), test.truth);
      PrintErrors("gravity on " + array.name + " seed " + std::to_string(seed), with);
      EXPECT_LE(with.omega_rel, 0.05e-2);
      EXPECT_LE(with.orientation_deg, 0.02);
      EXPECT_LE(with.acc_rel, 0.1e-2);
      EXPECT_LE(with.vel_rel, 0.05e-2);
      EXPECT_GT(without.vel_rel, 10 * with.vel_rel);  // gravity matters here
    }
  }
}

TEST(Solver, ZeroGravityGivesIdenticalResultsWithAndWithoutCompensation) {
  synth::RandomMotionOptions motion;
  motion.seed = 6;
  for (const ArrayGeometry& array : {test_support::VolpeTable42(), test_support::NapArs12()}) {
    const synth::SyntheticTest test = synth::SynthRandomMotion(array, motion);
    SolveOptions options = OptionsFor(test);
    options.gravity.g_fixed_mps2.setZero();
    options.gravity.compensate = true;
    const Kinematics on = Solve(test.array, test.signals, options);
    options.gravity.compensate = false;
    const Kinematics off = Solve(test.array, test.signals, options);
    EXPECT_EQ(on.acc_body, off.acc_body);
    EXPECT_EQ(on.acc_fixed, off.acc_fixed);
    EXPECT_EQ(on.vel_fixed, off.vel_fixed);
    EXPECT_EQ(on.pos_fixed, off.pos_fixed);
    EXPECT_EQ(on.quat_fixed_from_body, off.quat_fixed_from_body);
  }
}

// The residual is the array's self-consistency: ~0 on clean data, large
// where one channel is corrupted.
TEST(Solver, ResidualFlagsACorruptedChannel) {
  for (const ArrayGeometry& array : {test_support::Denton3222(), test_support::NapArs12()}) {
    const synth::SyntheticTest test = synth::SynthSeedFixedAxis(array, Eigen::Vector3d(0.5, 0.5, 0.5));
    const Kinematics clean = Solve(test.array, test.signals, OptionsFor(test));
    EXPECT_LT(clean.residual.maxCoeff(), 0.005 * kStandardGravity) << array.name;
    TestSignals corrupted = test.signals;
    corrupted.samples.col(4).segment(500, 100).array() += 5.0;  // +5 g on yarm_x for 10 ms
    const Kinematics bad = Solve(test.array, corrupted, OptionsFor(test));
    EXPECT_GT(bad.residual.segment(500, 100).minCoeff(), 1.0) << array.name;  // m/s^2
    EXPECT_LT(bad.residual.head(490).maxCoeff(), 0.005 * kStandardGravity) << array.name;
    std::printf("[errors] residual %-12s clean max %.2e m/s^2, with +5 g on yarm_x min %.2f m/s^2\n",
                array.name.c_str(), clean.residual.maxCoeff(), bad.residual.segment(500, 100).minCoeff());
  }
}

TEST(Solver, InitialVelocityAndOrientationAreHonoured) {
  const synth::SyntheticTest test =
      synth::SynthSeedFixedAxis(test_support::Ideal3222(), Eigen::Vector3d(0.1, -0.2, 0.3));
  SolveOptions options = OptionsFor(test);
  options.initial.velocity_fixed_mps = Eigen::Vector3d(1.0, -2.0, 3.0);
  const Kinematics solved = Solve(test.array, test.signals, options);
  EXPECT_EQ(solved.vel_fixed.row(0), Eigen::RowVector3d(1.0, -2.0, 3.0));
  EXPECT_EQ(solved.pos_fixed.row(0).norm(), 0.0);
  EXPECT_LE((QuatAt(solved.quat_fixed_from_body, 0).toRotationMatrix() -
             InitialFixedFromBody(Eigen::Vector3d(0.1, -0.2, 0.3)))
                .norm(),
            1e-14);
  // A constant initial velocity just adds v0 t to the position.
  const Kinematics still = Solve(test.array, test.signals, OptionsFor(test));
  const double t_end = solved.time_s(solved.size() - 1);
  EXPECT_LE((solved.pos_fixed.row(solved.size() - 1) - still.pos_fixed.row(still.size() - 1) -
             t_end * Eigen::RowVector3d(1.0, -2.0, 3.0))
                .norm(),
            1e-12);
}

}  // namespace
}  // namespace napkin::engine

namespace napkin::engine {
namespace {

// The shortest records (2 to 5 samples) solve with finite results on every
// path: the differentiators fall back to lower-order stencils.
TEST(Solver, ShortRecordsGiveFiniteResults) {
  for (const ArrayGeometry& array :
       {test_support::Denton3222(), test_support::SixAOmegaCg(), test_support::NapArs12()}) {
    const synth::SyntheticTest test = synth::SynthSeedFixedAxis(array, Eigen::Vector3d(0.5, 0.5, 0.5));
    for (Eigen::Index n = 2; n <= 5; ++n) {
      TestSignals shortened = test.signals;
      shortened.samples = test.signals.samples.middleRows(100, n);
      SolveOptions options;
      const Kinematics solved = Solve(test.array, shortened, options);
      ASSERT_EQ(solved.size(), n);
      EXPECT_TRUE(solved.omega_body.allFinite() && solved.vel_fixed.allFinite() &&
                  solved.quat_fixed_from_body.allFinite())
          << array.name << " n = " << n;
    }
  }
}

}  // namespace
}  // namespace napkin::engine

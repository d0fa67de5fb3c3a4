// Acceptance targets of docs/algorithms.md "Accuracy napkin must reach" for the
// exact solver (10 kHz, no noise), against synthetic tests with exact truth.
#include "engine/exact_solver.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <ostream>

#include "common/error.h"
#include "engine/report_known_answers.h"
#include "engine/solver.h"
#include "engine/summary.h"
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

// A 3-2-2-2 NAP geometry of the report (Tables 4-1, 4-2) or of the Denton
// head.
struct NapGeometryCase {
  const char* name;
  ArrayGeometry (*array)();
  std::uint64_t first_random_seed;  // of the 24 random motions on this geometry: 72 distinct in all
};
void PrintTo(const NapGeometryCase& geometry, std::ostream* os) { *os << geometry.name; }

const NapGeometryCase kNapGeometries[] = {
    {"ideal_3222", &test_support::Ideal3222, 1},
    {"volpe_table4_2", &test_support::VolpeTable42, 25},
    {"denton_3222", &test_support::Denton3222, 49},
};

class ExactSolverOnNapTest : public ::testing::TestWithParam<NapGeometryCase> {};

// Report section 4.5 with each 3-2-2-2 geometry processed with its true
// geometry: omega error <= 0.005 % of peak, orientation <= 0.005 deg, fixed
// omega_X, omega_Z <= 0.005 rad/s; known answers of the scenario.
TEST_P(ExactSolverOnNapTest, SeedFixedAxisMeetsReportAccuracy) {
  const ArrayGeometry array = GetParam().array();
  SCOPED_TRACE(array.name);
  const synth::SyntheticTest test = synth::SynthSeedFixedAxis(array, Eigen::Vector3d(0.5, 0.5, 0.5));
  const Kinematics solved = Solve(test.array, test.signals, OptionsFor(test));
  const KinematicsErrors e = CompareKinematics(solved, test.truth);
  PrintErrors("4.5 " + array.name, e);
  EXPECT_LE(e.omega_rel, 0.005e-2);
  EXPECT_LE(e.orientation_deg, 0.005);
  const double max_omega_fixed_x = solved.omega_fixed.col(0).cwiseAbs().maxCoeff();
  const double max_omega_fixed_z = solved.omega_fixed.col(2).cwiseAbs().maxCoeff();
  std::printf("[errors] 4.5 %s fixed omega_X %.2e, omega_Z %.2e rad/s\n", array.name.c_str(),
              max_omega_fixed_x, max_omega_fixed_z);
  EXPECT_LE(max_omega_fixed_x, 0.005);
  EXPECT_LE(max_omega_fixed_z, 0.005);

  // Known answers (docs/algorithms.md table).
  TestSummary summary;
  SummarizeKinematics(solved, summary);
  EXPECT_NEAR(summary.max_rotation_deg, report::kTotalRotationDeg, 0.001);
  const Eigen::Matrix3d turn = solved.quat_fixed_from_body.row(0).norm() > 0
                                   ? Eigen::Matrix3d(QuatAt(solved.quat_fixed_from_body, solved.size() - 1) *
                                                     QuatAt(solved.quat_fixed_from_body, 0).conjugate())
                                   : Eigen::Matrix3d::Identity();
  const Eigen::Vector3d turn_vector = QuaternionLog(Eigen::Quaterniond(turn));
  EXPECT_NEAR(turn_vector.y(), report::kTotalRotationRad, 1e-5);  // about fixed Y
  EXPECT_NEAR(turn_vector.x(), 0.0, 1e-5);
  EXPECT_NEAR(turn_vector.z(), 0.0, 1e-5);
  EXPECT_NEAR(solved.omega_fixed.col(1).maxCoeff(), report::kPeakOmegaFixedYRadps, 1e-3);
  EXPECT_NEAR(summary.peak_alpha_radps2, report::kPeakAlphaRadps2, 0.5);
  EXPECT_NEAR(summary.peak_acc_g, report::kPeakAccG, 0.005);
  EXPECT_LT(summary.max_residual_mps2, 1e-6);
}

// Random smooth 3-D motions with every sensor displaced up to 0.25 in (the
// solver gets the true displaced geometry), random initial orientations and
// velocities: omega <= 0.05 % of peak, orientation <= 0.02 deg, CG velocity
// <= 0.05 % of its peak change.
// 24 distinct motions per geometry (72 in all), each with its own displacement.
TEST_P(ExactSolverOnNapTest, RandomMotionsWithDisplacedSensorsMeetAccuracyTargets) {
  constexpr std::uint64_t kMotionsPerGeometry = 24;
  const std::uint64_t first_seed = GetParam().first_random_seed;
  const ArrayGeometry nominal = GetParam().array();
  KinematicsErrors worst;
  double worst_residual = 0.0;
  for (std::uint64_t seed = first_seed; seed < first_seed + kMotionsPerGeometry; ++seed) {
    SCOPED_TRACE(nominal.name + " seed " + std::to_string(seed));
    const ArrayGeometry displaced = synth::DisplaceSensors(nominal, 0.25 * kMetresPerInch, 100 + seed);
    synth::RandomMotionOptions motion;
    motion.seed = seed;
    const synth::SyntheticTest test = synth::SynthRandomMotion(displaced, motion);
    const Kinematics solved = Solve(test.array, test.signals, OptionsFor(test));
    const KinematicsErrors e = CompareKinematics(solved, test.truth);
    EXPECT_LE(e.omega_rel, 0.05e-2);
    EXPECT_LE(e.orientation_deg, 0.02);
    EXPECT_LE(e.vel_rel, 0.05e-2);
    worst.KeepWorst(e);
    worst_residual = std::max(worst_residual, solved.residual.maxCoeff());
  }
  PrintErrors("random x24 " + nominal.name, worst);
  std::printf("[errors] random x24 %s max residual %.2e m/s^2\n", nominal.name.c_str(), worst_residual);
}

INSTANTIATE_TEST_SUITE_P(NapGeometries, ExactSolverOnNapTest, ::testing::ValuesIn(kNapGeometries),
                         test_support::CaseName());

// The exact solver keeps the per-sample solve of up to 16 linear sensors in
// fixed-capacity storage and larger arrays in heap storage. Every NAP sensor
// duplicated (same position and axis, another slot: 18 sensors) must give
// the 9-sensor least-squares solution (each duplicated row pair is solved
// by its mean, here the same value twice), and each residual component
// appears twice.
TEST(ExactSolver, ArrayBeyondSixteenSensorsGivesTheSameSolutionAsItsNineDistinctSensors) {
  const ArrayGeometry nap = synth::DisplaceSensors(test_support::Denton3222(), 0.25 * kMetresPerInch, 7);
  synth::RandomMotionOptions motion;
  motion.seed = 7;
  const synth::SyntheticTest test = synth::SynthRandomMotion(nap, motion);
  ArrayGeometry doubled = test.array;
  TestSignals doubled_signals = test.signals;
  doubled_signals.samples.conservativeResize(Eigen::NoChange, 2 * test.signals.samples.cols());
  for (const Sensor& sensor : test.array.sensors) {
    Sensor copy = sensor;
    copy.slot = sensor.slot + "_copy";
    doubled.sensors.push_back(copy);
    doubled_signals.slots.push_back(copy.slot);
    doubled_signals.samples.col(static_cast<Eigen::Index>(doubled_signals.slots.size()) - 1) =
        test.signals.samples.col(test.signals.FindSlot(sensor.slot));
  }
  ASSERT_EQ(doubled.sensors.size(), 18u);
  const Kinematics nine = Solve(test.array, test.signals, OptionsFor(test));
  const Kinematics eighteen = Solve(doubled, doubled_signals, OptionsFor(test));
  auto relative = [](const Series3& a, const Series3& b) {
    return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
  };
  EXPECT_LE(relative(eighteen.omega_body, nine.omega_body), 1e-10);
  EXPECT_LE(relative(eighteen.alpha_body, nine.alpha_body), 1e-10);
  EXPECT_LE(relative(eighteen.acc_fixed, nine.acc_fixed), 1e-10);
  EXPECT_LE(relative(eighteen.vel_fixed, nine.vel_fixed), 1e-10);
  EXPECT_LE(relative(eighteen.roll_pitch_yaw_rad, nine.roll_pitch_yaw_rad), 1e-10);
  const KinematicsErrors e = CompareKinematics(eighteen, test.truth);
  EXPECT_LE(e.omega_rel, 0.05e-2);
  EXPECT_LE(e.orientation_deg, 0.02);
  EXPECT_LE(e.vel_rel, 0.05e-2);
  // Each residual component appears twice: sqrt(2) times the 9-sensor residual.
  const double nine_residual = nine.residual.maxCoeff();
  EXPECT_NEAR(eighteen.residual.maxCoeff(), std::sqrt(2.0) * nine_residual, 1e-9 + 1e-6 * nine_residual);
}

}  // namespace
}  // namespace napkin::engine

namespace napkin::engine {
namespace {

// Rows [0, rows) of two series are the same bits; the first difference is
// named.
template <typename Series>
::testing::AssertionResult SameRows(const char* name, const Series& part, const Series& whole,
                                    Eigen::Index rows) {
  for (Eigen::Index k = 0; k < rows; ++k)
    for (Eigen::Index c = 0; c < part.cols(); ++c)
      if (std::memcmp(&part(k, c), &whole(k, c), sizeof(double)) != 0)
        return ::testing::AssertionFailure() << name << " differs at row " << k << " column " << c << ": "
                                             << part(k, c) << " vs " << whole(k, c);
  return ::testing::AssertionSuccess();
}

// The exact solver works through the record in blocks of samples
// (docs/algorithms.md "Solvers"): every sample but the last depends only on
// the samples before it and the next one (central differences), so the solve
// of a prefix of a record must give the same bits as the solve of the whole
// record on every row but the prefix's last (velocity and position: but its
// last two, their slope being the central difference of the acceleration),
// wherever the prefix ends relative to the blocks (256 samples), with and
// without the gravity term. The angles are computed eight or four rows at a
// time where the processor can (engine/rotation_angles.h), the rows beyond
// the last full group by the scalar code, within a few ulp.
TEST(ExactSolver, APrefixOfTheRecordSolvesToTheSameBitsAsTheWholeRecord) {
  const ArrayGeometry nap = synth::DisplaceSensors(test_support::Denton3222(), 0.25 * kMetresPerInch, 11);
  synth::RandomMotionOptions motion;
  motion.seed = 11;
  motion.duration_s = 0.0799;  // 800 samples at 10 kHz
  const synth::SyntheticTest test = synth::SynthRandomMotion(nap, motion);
  ASSERT_EQ(test.signals.size(), 800);
  for (const bool gravity : {false, true}) {
    SolveOptions options = OptionsFor(test);
    options.gravity.compensate = gravity;
    const Kinematics whole = Solve(test.array, test.signals, options);
    for (const Eigen::Index length : {3, 4, 5, 255, 256, 257, 258, 259, 511, 512, 513, 700}) {
      SCOPED_TRACE("gravity " + std::to_string(gravity) + ", first " + std::to_string(length) + " samples");
      TestSignals prefix = test.signals;
      prefix.samples = test.signals.samples.topRows(length);
      const Kinematics part = Solve(test.array, prefix, options);
      ASSERT_EQ(part.size(), length);
      const Eigen::Index rows = length - 1;
      EXPECT_TRUE(SameRows("omega_body", part.omega_body, whole.omega_body, rows));
      EXPECT_TRUE(SameRows("alpha_body", part.alpha_body, whole.alpha_body, rows));
      EXPECT_TRUE(SameRows("acc_body", part.acc_body, whole.acc_body, rows));
      EXPECT_TRUE(SameRows("residual", part.residual, whole.residual, rows));
      EXPECT_TRUE(
          SameRows("quat_fixed_from_body", part.quat_fixed_from_body, whole.quat_fixed_from_body, rows));
      EXPECT_TRUE(SameRows("omega_fixed", part.omega_fixed, whole.omega_fixed, rows));
      EXPECT_TRUE(SameRows("alpha_fixed", part.alpha_fixed, whole.alpha_fixed, rows));
      EXPECT_TRUE(SameRows("acc_fixed", part.acc_fixed, whole.acc_fixed, rows));
      EXPECT_TRUE(SameRows("vel_fixed", part.vel_fixed, whole.vel_fixed, rows - 1));
      EXPECT_TRUE(SameRows("pos_fixed", part.pos_fixed, whole.pos_fixed, rows - 1));
      EXPECT_LE((part.roll_pitch_yaw_rad - whole.roll_pitch_yaw_rad.topRows(length))
                    .topRows(rows)
                    .cwiseAbs()
                    .maxCoeff(),
                2e-15);
      EXPECT_LE((part.dcos_rad - whole.dcos_rad.topRows(length)).topRows(rows).cwiseAbs().maxCoeff(), 2e-15);
    }
  }
}

// The quaternions are normalized off the sample-to-sample chain
// (docs/algorithms.md "Solvers"): every stored one is unit to round-off,
// over a record of many blocks.
TEST(ExactSolver, EveryQuaternionIsUnitToRoundOff) {
  const ArrayGeometry nap = synth::DisplaceSensors(test_support::Denton3222(), 0.25 * kMetresPerInch, 12);
  synth::RandomMotionOptions motion;
  motion.seed = 12;
  motion.duration_s = 0.5;
  const synth::SyntheticTest test = synth::SynthRandomMotion(nap, motion);
  const Kinematics solved = Solve(test.array, test.signals, OptionsFor(test));
  const Eigen::VectorXd norms = solved.quat_fixed_from_body.rowwise().norm();
  EXPECT_LE((norms.array() - 1.0).abs().maxCoeff(), 4e-16);
}

// SolveOptions::body_frame_only (the screening's trial solves) gives the
// body-frame series and the residual of the full solve, bit for bit; it
// refuses what needs the orientation.
TEST(ExactSolver, BodyFrameOnlyGivesTheBodyFrameSeriesOfTheFullSolve) {
  const ArrayGeometry nap = synth::DisplaceSensors(test_support::Denton3222(), 0.25 * kMetresPerInch, 13);
  synth::RandomMotionOptions motion;
  motion.seed = 13;
  const synth::SyntheticTest test = synth::SynthRandomMotion(nap, motion);
  SolveOptions options = OptionsFor(test);
  const Kinematics full = Solve(test.array, test.signals, options);
  options.body_frame_only = true;
  const Kinematics body = Solve(test.array, test.signals, options);
  const Eigen::Index rows = full.size();
  ASSERT_EQ(body.size(), rows);
  EXPECT_TRUE(SameRows("time_s", body.time_s, full.time_s, rows));
  EXPECT_TRUE(SameRows("omega_body", body.omega_body, full.omega_body, rows));
  EXPECT_TRUE(SameRows("alpha_body", body.alpha_body, full.alpha_body, rows));
  EXPECT_TRUE(SameRows("acc_body", body.acc_body, full.acc_body, rows));
  EXPECT_TRUE(SameRows("residual", body.residual, full.residual, rows));

  options.gravity.compensate = true;
  EXPECT_THROW(Solve(test.array, test.signals, options), InputError);
  options.gravity.compensate = false;
  options.solver = SolverKind::kSeed;
  EXPECT_THROW(Solve(test.array, test.signals, options), InputError);
}

}  // namespace
}  // namespace napkin::engine

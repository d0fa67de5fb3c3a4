// Acceptance targets of docs/algorithms.md "Accuracy napkin must reach" for the
// exact solver (10 kHz, no noise), against synthetic tests with exact truth.
#include "engine/exact_solver.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <ostream>

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

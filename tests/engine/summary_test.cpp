#include "engine/summary.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "engine/integration.h"
#include "engine/report_known_answers.h"
#include "engine/rotation.h"
#include "engine/units.h"
#include "synth/synthetic_tests.h"
#include "tests/support/reference_arrays.h"

namespace napkin::engine {
namespace {

TEST(Summary, SeverityNames) {
  EXPECT_STREQ(NameOf(Severity::kInfo), "info");
  EXPECT_STREQ(NameOf(Severity::kWarning), "warning");
  EXPECT_STREQ(NameOf(Severity::kError), "error");
}

// A hand-made three-sample record with every peak at a different sample.
TEST(Summary, PeaksFinalPoseAndResidualOfAHandMadeRecord) {
  Kinematics kin;
  kin.Resize(3);
  kin.time_s << 0.0, 0.1, 0.2;
  kin.omega_body << 1, -7, 2,  //
      3, 4, 0,                 //
      -5, 0, 6;
  kin.alpha_body.setZero();
  kin.alpha_body.row(1) << 30, 40, 0;  // |alpha| = 50
  kin.acc_fixed.setZero();
  kin.acc_fixed.row(2) << 0, 0, -2 * kStandardGravity;
  kin.pos_fixed.setZero();
  kin.pos_fixed.row(2) << 0.1, 0.2, 0.3;
  const Eigen::Quaterniond q0 = Eigen::Quaterniond::Identity();
  const Eigen::Quaterniond q1(Eigen::AngleAxisd(0.9, Eigen::Vector3d::UnitZ()));  // 0.9 rad away
  const Eigen::Quaterniond q2(Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitX()));
  for (int k = 0; k < 3; ++k) {
    const Eigen::Quaterniond& q = k == 0 ? q0 : (k == 1 ? q1 : q2);
    kin.quat_fixed_from_body.row(k) << q.w(), q.x(), q.y(), q.z();
  }
  kin.residual << 0.0, 0.5, 0.25;
  TestSummary summary;
  SummarizeKinematics(kin, summary);
  EXPECT_EQ(summary.peak_omega_body_radps, Eigen::Vector3d(5, 7, 6));
  EXPECT_DOUBLE_EQ(summary.peak_omega_radps, std::sqrt(61.0));  // (-5, 0, 6)
  EXPECT_DOUBLE_EQ(summary.peak_alpha_radps2, 50.0);
  EXPECT_DOUBLE_EQ(summary.peak_acc_g, 2.0);
  EXPECT_NEAR(summary.max_rotation_deg, 0.9 * kDegPerRad, 1e-12);
  EXPECT_EQ(summary.final_pos_fixed_m, Eigen::Vector3d(0.1, 0.2, 0.3));
  EXPECT_LE((summary.final_quat_wxyz - Eigen::Vector4d(q2.w(), q2.x(), q2.y(), q2.z())).norm(), 1e-15);
  EXPECT_LE((summary.final_roll_pitch_yaw_deg - Eigen::Vector3d(0.4 * kDegPerRad, 0, 0)).norm(), 1e-12);
  EXPECT_DOUBLE_EQ(summary.max_residual_mps2, 0.5);
}

// The largest rotation from the initial orientation is the largest
// AngleBetween over the samples, bit for bit: random tumbling through more
// than a half turn (the angle then falls again), a plateau of near-ties,
// and tiny rotations.
TEST(Summary, MaxRotationIsTheLargestAngleFromTheInitialOrientation) {
  std::mt19937_64 rng(42);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (const double step_rad : {1e-10, 1e-3, 0.02}) {
    Kinematics kin;
    kin.Resize(5000);
    kin.omega_body.setZero();
    kin.alpha_body.setZero();
    kin.acc_fixed.setZero();
    kin.pos_fixed.setZero();
    kin.residual.setZero();
    Eigen::Quaterniond q(Eigen::AngleAxisd(normal(rng), Eigen::Vector3d(normal(rng), 1.0, 0.5).normalized()));
    const Eigen::Vector3d axis = Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
    for (Eigen::Index k = 0; k < kin.size(); ++k) {
      kin.quat_fixed_from_body.row(k) << q.w(), q.x(), q.y(), q.z();
      // Mostly about one axis with a random wobble; held still in the middle.
      const Eigen::Vector3d wobble(normal(rng), normal(rng), normal(rng));
      if (k < 2000 || k > 2500)
        q = q * Eigen::Quaterniond(Eigen::AngleAxisd(step_rad, (axis + 0.3 * wobble).normalized()));
    }
    double expected = 0.0;
    for (Eigen::Index k = 0; k < kin.size(); ++k)
      expected = std::max(
          expected, AngleBetween(QuatAt(kin.quat_fixed_from_body, 0), QuatAt(kin.quat_fixed_from_body, k)));
    TestSummary summary;
    SummarizeKinematics(kin, summary);
    EXPECT_EQ(summary.max_rotation_deg, expected * kDegPerRad) << "step " << step_rad;
    EXPECT_GT(expected, 0.0);
  }
}

// Report section 4.5 truth: the summary carries the known answers.
TEST(Summary, SeedFixedAxisKnownAnswers) {
  const synth::SyntheticTest test =
      synth::SynthSeedFixedAxis(test_support::Ideal3222(), Eigen::Vector3d(0.5, 0.5, 0.5));
  TestSummary summary;
  SummarizeKinematics(test.truth, summary);
  EXPECT_NEAR(summary.peak_omega_radps, report::kPeakOmegaFixedYRadps, 1e-12);
  EXPECT_NEAR(summary.peak_alpha_radps2, report::kPeakAlphaRadps2, 0.05);
  EXPECT_NEAR(summary.peak_acc_g, report::kPeakAccG, 0.005);
  EXPECT_NEAR(summary.max_rotation_deg, report::kTotalRotationDeg, 1e-4);
  EXPECT_EQ(summary.max_residual_mps2, 0.0);
  const Eigen::Matrix3d final_r =
      Ry(report::kTotalRotationRad) * InitialFixedFromBody(Eigen::Vector3d(0.5, 0.5, 0.5));
  const Eigen::Vector3d rpy = summary.final_roll_pitch_yaw_deg / kDegPerRad;
  EXPECT_LE((Rz(rpy.z()) * Ry(rpy.y()) * Rx(rpy.x()) - final_r).norm(), 1e-12);
  // The CG ends 10 in from the axis, turned 1.5 rad about fixed Y.
  const double arm = 0.254;
  EXPECT_NEAR(summary.final_pos_fixed_m.x(), -arm * std::sin(report::kTotalRotationRad), 1e-12);
  EXPECT_NEAR(summary.final_pos_fixed_m.z(), arm - arm * std::cos(report::kTotalRotationRad), 1e-12);
}

}  // namespace
}  // namespace napkin::engine

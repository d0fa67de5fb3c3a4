// Acceleration-only arrays (docs/algorithms.md "Acceleration-only arrays"):
// three linear accelerometers at the CG give the CG acceleration and every
// criterion computed from it; everything that needs the rotation is NaN (in
// the summary) or absent (in the kinematics).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "common/error.h"
#include "engine/criteria.h"
#include "engine/injury_risk.h"
#include "engine/pipeline.h"
#include "engine/screening.h"
#include "engine/summary_fields.h"
#include "engine/units.h"
#include "synth/synthetic_tests.h"
#include "tests/support/reference_arrays.h"

namespace napkin::engine {
namespace {

// Raw signals pass through unchanged: no filter, no bias removal.
ProcessingConfig Unconditioned() {
  ProcessingConfig config;
  config.filter.linear_cfc.reset();
  config.filter.angular_rate_cfc.reset();
  config.bias.mode = BiasMode::kNone;
  return config;
}

// A random 3-D head motion sensed by the CG triad (truth: the motion's own
// body-frame CG acceleration).
synth::SyntheticTest RandomMotionAtCg(std::uint64_t seed) {
  synth::RandomMotionOptions motion;
  motion.seed = seed;
  motion.duration_s = 0.1;
  return synth::SynthRandomMotion(test_support::ThreeACg(), motion);
}

// Rotation fields, the residual, and the risks read from BrIC (engine/injury_risk.h).
bool IsRotationField(const SummaryField& field) {
  const std::string name = field.name;
  return field.group == SummaryGroup::kRotation || name == "max_residual_mps2" || name == "bric_p_ais3" ||
         name == "bric_p_ais4";
}

TEST(AccelerationOnly, CgAccelerationAndCriteriaEqualTheTruthAndRotationIsAbsent) {
  const synth::SyntheticTest test = RandomMotionAtCg(7);
  const ProcessedTest processed = ProcessTest(test.array, test.signals, test.initial, Unconditioned());
  const Kinematics& kin = processed.kinematics;
  ASSERT_EQ(kin.size(), test.truth.size());
  EXPECT_FALSE(HasRotation(kin));
  const double peak_mps2 = test.truth.acc_body.cwiseAbs().maxCoeff();
  EXPECT_LE((kin.acc_body - test.truth.acc_body).cwiseAbs().maxCoeff(), 1e-12 * peak_mps2);
  EXPECT_LE((kin.time_s - test.truth.time_s).cwiseAbs().maxCoeff(), 1e-12);
  // The series that need the rotation, and the residual, are not held at
  // all (engine/kinematics.h HasRotation): a long recording holds 4 series.
  for (const Series3* series :
       {&kin.omega_body, &kin.alpha_body, &kin.omega_fixed, &kin.alpha_fixed, &kin.acc_fixed, &kin.vel_fixed,
        &kin.pos_fixed, &kin.roll_pitch_yaw_rad, &kin.dcos_rad})
    EXPECT_EQ(series->rows(), 0);
  EXPECT_EQ(kin.quat_fixed_from_body.rows(), 0);
  EXPECT_EQ(kin.residual.rows(), 0);

  // HIC, peak and a3ms of the truth's resultant, computed independently.
  const double dt = test.signals.dt_s;
  const Eigen::VectorXd truth_g = test.truth.acc_body.rowwise().norm() / kStandardGravity;
  const TestSummary& summary = processed.summary;
  for (const auto& [window, hic] :
       {std::pair{kHic15Window, summary.hic15}, std::pair{kHic36Window, summary.hic36},
        std::pair{kUnlimitedHicWindow, summary.hic}}) {
    HicOptions options;
    options.window_s = window;
    const HicWindow expected = HicExhaustive(truth_g, dt, test.signals.t0_s, options);
    EXPECT_NEAR(hic.value, expected.value, 1e-9 * expected.value) << window;
    EXPECT_NEAR(hic.t1_s, expected.t1_s, 0.5 * dt) << window;
    EXPECT_NEAR(hic.t2_s, expected.t2_s, 0.5 * dt) << window;
  }
  EXPECT_GT(summary.hic15.value, 0.0);
  EXPECT_DOUBLE_EQ(summary.hic_d, HicD(summary.hic36.value));
  EXPECT_NEAR(summary.peak_acc_g, truth_g.maxCoeff(), 1e-12 * truth_g.maxCoeff());
  EXPECT_NEAR(summary.a3ms_g, A3ms(truth_g, dt), 1e-12 * truth_g.maxCoeff());

  // Every rotation-dependent field is NaN (null), every HIC field and HIC risk
  // finite: the HIC risks are those of the HIC values.
  EXPECT_EQ(summary.hic15_p_ais3, NcapHic15Ais3Risk(summary.hic15.value));
  EXPECT_EQ(summary.hic36_p_ais4, PrasadMertzHic36Ais4Risk(summary.hic36.value));
  for (const SummaryField& field : SummaryFields()) {
    if (IsRotationField(field))
      EXPECT_TRUE(std::isnan(field.Get(summary))) << field.name;
    else
      EXPECT_TRUE(std::isfinite(field.Get(summary))) << field.name;
  }
}

TEST(AccelerationOnly, OneInfoFindingAndNoRigidBodyFinding) {
  const synth::SyntheticTest test = RandomMotionAtCg(8);
  const ProcessedTest processed = ProcessTest(test.array, test.signals, test.initial, ProcessingConfig{});
  ASSERT_EQ(processed.summary.findings.size(), 1u);
  const Finding& finding = processed.summary.findings.front();
  EXPECT_EQ(finding.check, "rotation");
  EXPECT_FALSE(finding.channel.has_value());
  EXPECT_EQ(finding.severity, Severity::kInfo);
  EXPECT_NE(finding.detail.find("array 3a-cg cannot determine rotation from its sensors"), std::string::npos)
      << finding.detail;
  EXPECT_EQ(FailingFinding(processed), nullptr);
  EXPECT_EQ(ResidualRedundancy(test.array), 0);
}

TEST(AccelerationOnly, ScreeningStillSeesWhatThreeChannelsShow) {
  // A spike, a clipped run and an offset on the raw channels are found as
  // for any array; no rigid-body finding (polarity, residual) is invented.
  synth::SyntheticTest test = RandomMotionAtCg(9);
  Eigen::MatrixXd& samples = test.signals.samples;
  const Eigen::Index n = samples.rows();
  samples(n / 3, 0) += 80.0;                           // spike on cg_x
  const double top = samples.col(1).maxCoeff() + 1.0;  // cg_y clipped for 8 samples
  samples.col(1).segment(n / 2, 8).setConstant(top);
  samples.col(2).array() += 3.0;  // cg_z offset (no pre-impact data: start level)
  ProcessingConfig config = Unconditioned();
  const ProcessedTest processed = ProcessTest(test.array, test.signals, test.initial, config);
  std::vector<std::string> found;
  for (const Finding& finding : processed.summary.findings)
    found.push_back(finding.check + ":" + finding.channel.value_or("-"));
  EXPECT_NE(std::find(found.begin(), found.end(), "spike:cg_x"), found.end());
  EXPECT_NE(std::find(found.begin(), found.end(), "saturation:cg_y"), found.end());
  EXPECT_NE(std::find(found.begin(), found.end(), "rotation:-"), found.end());
  for (const char* rigid_body : {"polarity", "axis_label", "residual", "consistency"})
    for (const std::string& entry : found) EXPECT_NE(entry.rfind(rigid_body, 0), 0u) << entry;

  // A dropout is fatal as for any array.
  test.signals.samples(10, 2) = std::nan("");
  EXPECT_THROW(ProcessTest(test.array, test.signals, test.initial, config), InputError);
}

TEST(AccelerationOnly, GravityCompensationAndTheSeedSolverAreRefused) {
  const synth::SyntheticTest test = RandomMotionAtCg(10);
  ProcessingConfig gravity;
  gravity.gravity.compensate = true;
  try {
    ProcessTest(test.array, test.signals, test.initial, gravity);
    FAIL() << "gravity compensation accepted";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("cannot determine rotation, so gravity compensation"),
              std::string::npos)
        << error.what();
  }
  ProcessingConfig seed;
  seed.solver = SolverKind::kSeed;
  EXPECT_THROW(ProcessTest(test.array, test.signals, test.initial, seed), InputError);
}

}  // namespace
}  // namespace napkin::engine

// ProcessTest with SeriesKept::kSummary (engine/pipeline.h), what `napkin
// run` asks for when it stores no derived channels: the same summary, bit for
// bit, as the full computation, on every solver path and with gravity
// compensation, and the series nobody reads left empty. Also
// internal::AllFinite (engine/finite_samples.h) against Eigen's allFinite().
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>
#include <vector>

#include "engine/finite_samples.h"
#include "engine/pipeline.h"
#include "engine/summary_fields.h"
#include "synth/synthetic_tests.h"
#include "tests/support/reference_arrays.h"

namespace napkin::engine {
namespace {

synth::SyntheticTest SummaryOnlyRandomMotion(const ArrayGeometry& array) {
  synth::RandomMotionOptions options;
  options.seed = 11;
  options.duration_s = 0.3;
  return synth::SynthRandomMotion(array, options);
}

TEST(SeriesKept, SummaryOnlyGivesTheFullSummaryBitForBit) {
  ProcessingConfig gravity;
  gravity.gravity.compensate = true;
  for (const ProcessingConfig& config : {ProcessingConfig{}, gravity}) {
    for (const ArrayGeometry& array : {test_support::Ideal3222(), test_support::SixAOmegaCg(),
                                       test_support::NapArs12(), test_support::ThreeACg()}) {
      if (config.gravity.compensate && array.name == test_support::ThreeACg().name) continue;  // no rotation
      const synth::SyntheticTest test = SummaryOnlyRandomMotion(array);
      const ProcessedTest full = ProcessTest(test.array, test.signals, test.initial, config);
      Workspace workspace;
      ProcessedTest summary_only;
      ProcessTest(test.array, test.signals, test.initial, config, workspace, summary_only, nullptr,
                  SeriesKept::kSummary);
      EXPECT_THAT(DifferingSummaryFields(full.summary, summary_only.summary), ::testing::IsEmpty())
          << array.name;
      const Kinematics& kept = summary_only.kinematics;
      ASSERT_EQ(kept.size(), full.kinematics.size()) << array.name;
      if (!HasRotation(full.kinematics)) continue;
      EXPECT_EQ(kept.omega_fixed.rows(), 0) << array.name;
      EXPECT_EQ(kept.alpha_fixed.rows(), 0) << array.name;
      EXPECT_EQ(kept.roll_pitch_yaw_rad.rows(), 0) << array.name;
      EXPECT_EQ(kept.dcos_rad.rows(), 0) << array.name;
      // What the summary reads is the full computation's, bit for bit.
      EXPECT_TRUE(kept.acc_fixed == full.kinematics.acc_fixed) << array.name;
      EXPECT_TRUE(kept.quat_fixed_from_body == full.kinematics.quat_fixed_from_body) << array.name;
      EXPECT_TRUE(kept.pos_fixed == full.kinematics.pos_fixed) << array.name;
      EXPECT_TRUE(kept.omega_body == full.kinematics.omega_body) << array.name;
      EXPECT_TRUE(kept.alpha_body == full.kinematics.alpha_body) << array.name;
    }
  }
}

TEST(FiniteSamples, AllFiniteAgreesWithEigenAtEveryPosition) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  const double largest = std::numeric_limits<double>::max();
  for (const Eigen::Index n : {0, 1, 3, 4, 7, 33}) {
    Eigen::VectorXd values = Eigen::VectorXd::LinSpaced(n, -1e300, 1e300);
    if (n > 1) values(0) = -largest;
    if (n > 2) values(n - 1) = largest;
    EXPECT_TRUE(internal::AllFinite(values)) << n;
    for (Eigen::Index k = 0; k < n; ++k)
      for (const double bad : {kInf, -kInf, kNaN}) {
        Eigen::VectorXd with_bad = values;
        with_bad(k) = bad;
        EXPECT_EQ(internal::AllFinite(with_bad), with_bad.allFinite()) << n << " " << k;
        EXPECT_FALSE(internal::AllFinite(with_bad.data(), with_bad.size())) << n << " " << k;
      }
  }
  Series3 series = Series3::Zero(5, 3);
  EXPECT_TRUE(internal::AllFinite(series));
  series(4, 2) = kNaN;
  EXPECT_FALSE(internal::AllFinite(series));
}

}  // namespace
}  // namespace napkin::engine

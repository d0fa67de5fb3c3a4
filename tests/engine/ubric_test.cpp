// UBrIC (Gabler, Crandall, Panzer 2018; engine/ubric.h): known answers of
// simple pulses worked by hand, the limits of the formula, and the criterion
// as a computed summary-field row (FillCriteria, the table, Get and Set).
#include "engine/ubric.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "common/error.h"
#include "engine/criteria.h"
#include "engine/summary_fields.h"

namespace napkin::engine {
namespace {

// One body axis spun up at a constant angular acceleration `alpha` (rad/s²)
// for `duration_s`, then held at that speed; the other axes still.
Kinematics SpinUp(int axis, double alpha, double duration_s, double dt = 1e-4, Eigen::Index n = 501) {
  Kinematics kinematics;
  kinematics.Resize(n);
  kinematics.acc_fixed.setZero();
  kinematics.omega_body.setZero();
  kinematics.alpha_body.setZero();
  for (Eigen::Index k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) * dt;
    kinematics.time_s[k] = t;
    const bool spinning_up = t < duration_s - 1e-12;
    kinematics.alpha_body(k, axis) = spinning_up ? alpha : 0.0;
    kinematics.omega_body(k, axis) = alpha * std::min(t, duration_s);
  }
  return kinematics;
}

TEST(Ubric, CriticalValuesAreThoseOfThePaper) {
  // Gabler et al. 2018, Table 4 (MPS): checked against a public
  // implementation that cites the same table (see docs/algorithms.md).
  EXPECT_EQ(kUbricCriticalOmegaRadps, Eigen::Vector3d(211.0, 171.0, 115.0));
  EXPECT_EQ(kUbricCriticalAlphaRadps2, Eigen::Vector3d(20000.0, 10300.0, 7760.0));
  EXPECT_EQ(kUbricExponent, 2.0);
}

TEST(Ubric, SingleAxisSpinUpByHand) {
  // x: 2000 rad/s² for 20 ms, so max|ω_x| = 40 rad/s: ω* = 40/211, α* = 2000/20000 = 0.1,
  // UBrIC = ω* + (α* − ω*) e^(−α*/ω*) = 0.18957... − 0.08957... × e^(−0.5275) = 0.1367181028189206.
  const Kinematics kinematics = SpinUp(0, 2000.0, 0.02);
  EXPECT_NEAR(kinematics.omega_body.col(0).maxCoeff(), 40.0, 1e-12);
  EXPECT_NEAR(Ubric(kinematics.omega_body, kinematics.alpha_body), 0.1367181028189206, 1e-12);
  // The same pulse reversed (negative rates) gives the same: peaks are of |ω|, |α|.
  EXPECT_NEAR(Ubric(-kinematics.omega_body, -kinematics.alpha_body), 0.1367181028189206, 1e-12);
  EXPECT_EQ(UbricOf(kinematics), Ubric(kinematics.omega_body, kinematics.alpha_body));
}

TEST(Ubric, EqualNormalisedPeaksCombineAsTheEuclideanNorm) {
  // α* = ω* on an axis makes its term ω* exactly (the exponential's factor is
  // 0): ω*_x = α*_x = 0.5, ω*_y = α*_y = 0.3, z still gives √(0.5² + 0.3²).
  Series3 omega = Series3::Zero(2, 3), alpha = Series3::Zero(2, 3);
  omega.row(1) << 0.5 * 211.0, -0.3 * 171.0, 0.0;
  alpha.row(0) << 0.5 * 20000.0, 0.3 * 10300.0, 0.0;
  EXPECT_NEAR(Ubric(omega, alpha), 0.58309518948453, 1e-13);
  EXPECT_EQ(UbricAxisTerm(0.5, 0.5), 0.5);
}

TEST(Ubric, LimitsOfTheFormula) {
  // Short (impulsive) pulse, α*/ω* → ∞: the term is the peak velocity
  // (e^(−1000) is 0 in double precision).
  EXPECT_EQ(UbricAxisTerm(0.2, 200.0), 0.2);
  // Long pulse, α*/ω* → 0: the term vanishes as 2α* − 1.5α*²/ω* (its Taylor series).
  EXPECT_NEAR(UbricAxisTerm(0.5, 1e-6), 2e-6 - 1.5e-12 / 0.5, 1e-15);
  // A still axis contributes nothing, whatever its acceleration.
  EXPECT_EQ(UbricAxisTerm(0.0, 0.0), 0.0);
  EXPECT_EQ(UbricAxisTerm(0.0, 3.0), 0.0);
  // A head spinning at a constant rate from the start has no acceleration:
  // UBrIC is 0 where BrIC is not.
  const Series3 omega = Eigen::RowVector3d(30.0, 0.0, 0.0).replicate(3, 1);
  const Series3 alpha = Series3::Zero(3, 3);
  EXPECT_EQ(Ubric(omega, alpha), 0.0);
  EXPECT_GT(Bric(omega, Eigen::Vector3d(66.25, 56.45, 42.87)), 0.0);
  // No samples: 0, as BrIC.
  EXPECT_EQ(Ubric(Series3(0, 3), Series3(0, 3)), 0.0);
}

TEST(Ubric, NonFiniteSampleIsAnInputError) {
  Series3 omega = Series3::Zero(2, 3), alpha = Series3::Zero(2, 3);
  alpha(1, 2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(Ubric(omega, alpha), InputError);
}

TEST(Ubric, IsAComputedSummaryFieldFilledByFillCriteria) {
  const SummaryField* field = FindSummaryField("ubric");
  ASSERT_NE(field, nullptr);
  EXPECT_EQ(field->group, SummaryGroup::kRotation);
  EXPECT_EQ(field->field, nullptr);
  EXPECT_NE(field->compute, nullptr);
  EXPECT_TRUE(field->log_scale);
  EXPECT_FALSE(field->in_verdict);

  const Kinematics kinematics = SpinUp(1, 1030.0, 0.03);  // y: α* = 0.1, ω* = 30.9/171
  TestSummary summary;
  FillCriteria(kinematics, ProcessingConfig{}, summary);
  const double omega_star = 30.9 / 171.0, alpha_star = 0.1;
  EXPECT_NEAR(field->Get(summary),
              omega_star + (alpha_star - omega_star) * std::exp(-alpha_star / omega_star), 1e-12);
  EXPECT_EQ(summary.computed.at("ubric"), field->Get(summary));

  // Without rotation (an acceleration-only array) it is undetermined, as BrIC is.
  Kinematics acceleration_only;
  acceleration_only.ResizeWithoutRotation(kinematics.size());
  acceleration_only.time_s = kinematics.time_s;
  acceleration_only.acc_body.setZero();
  TestSummary without_rotation;
  FillCriteria(acceleration_only, ProcessingConfig{}, without_rotation);
  EXPECT_TRUE(std::isnan(field->Get(without_rotation)));

  // Get and Set through the table; summaries differing only there differ in "ubric".
  TestSummary other = summary;
  EXPECT_TRUE(DifferingSummaryFields(summary, other).empty());
  field->Set(other, 2.5);
  EXPECT_EQ(field->Get(other), 2.5);
  EXPECT_EQ(DifferingSummaryFields(summary, other), std::vector<std::string>{"ubric"});
  EXPECT_EQ(field->Get(TestSummary{}), 0.0);  // as every field of a new summary
}

}  // namespace
}  // namespace napkin::engine

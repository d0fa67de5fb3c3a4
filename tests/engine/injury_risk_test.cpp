// Injury risk curves (engine/injury_risk.h, docs/algorithms.md "Injury
// risk"): points their sources state, and analytic truths of their forms.
#include "engine/injury_risk.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "engine/summary_fields.h"

namespace napkin::engine {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

TEST(NcapHic15Ais3Risk, IsTheLognormalOfTheNcapNotice) {
  // NHTSA, 73 FR 40016 (2008): P(AIS 3+) = Phi((ln HIC15 - 7.45231) / 0.73998).
  EXPECT_EQ(kNcapHic15Ais3Mu, 7.45231);
  EXPECT_EQ(kNcapHic15Ais3Sigma, 0.73998);
  // The median HIC15, exp(mu) ~ 1726, is a 50 % risk; one sigma below and
  // above are Phi(-1) and Phi(+1) (0.15865525393145705 = erfc(1/sqrt 2) / 2).
  EXPECT_NEAR(NcapHic15Ais3Risk(std::exp(7.45231)), 0.5, 1e-15);
  EXPECT_NEAR(NcapHic15Ais3Risk(std::exp(7.45231 - 0.73998)), 0.15865525393145705, 1e-14);
  EXPECT_NEAR(NcapHic15Ais3Risk(std::exp(7.45231 + 0.73998)), 1.0 - 0.15865525393145705, 1e-14);
  // At the FMVSS 208 limit HIC15 = 700: Phi((ln 700 - 7.45231) / 0.73998)
  // = Phi(-1.217908...) = 0.1116 (11 %).
  EXPECT_NEAR(NcapHic15Ais3Risk(700.0),
              0.5 * std::erfc(-((std::log(700.0) - 7.45231) / 0.73998) / std::sqrt(2.0)), 1e-15);
  EXPECT_NEAR(NcapHic15Ais3Risk(700.0), 0.1116, 5e-5);
}

TEST(PrasadMertzHic36Ais4Risk, HicOf1000IsThe16PercentRiskMertzAndIrwinState) {
  // P(AIS 4+) = 1 / (1 + exp(4.9 + 200 / HIC - 0.00351 HIC)) (Prasad and
  // Mertz 1985). Mertz and Irwin (1994, SAE 941056, abstract) analysed crash
  // tests with "the brain injury risk curve of Prasad and Mertz": "risks
  // greater than 16 percent which corresponds to 15 ms HIC > 1000". The curve
  // gives 16.94 % there: 16 percent in whole percent.
  const double at_1000 = PrasadMertzHic36Ais4Risk(1000.0);
  EXPECT_EQ(std::floor(100.0 * at_1000), 16.0);
  EXPECT_NEAR(at_1000, 1.0 / (1.0 + std::exp(1.59)), 1e-15);
  // Rising with HIC everywhere (4.9 + 200/h - 0.00351 h falls for h > 0).
  double previous = 0.0;
  for (double hic = 10.0; hic <= 4000.0; hic += 10.0) {
    const double risk = PrasadMertzHic36Ais4Risk(hic);
    EXPECT_GT(risk, previous) << hic;
    previous = risk;
  }
}

TEST(TakhountsBricRisk, WeibullCurvesOfTheMpsBasedBric) {
  // Takhounts et al. 2013: P(AIS 3+) = 1 - exp(-(BrIC / 0.987)^2.84),
  // P(AIS 4+) = 1 - exp(-(BrIC / 1.204)^2.84).
  EXPECT_EQ(kTakhountsBricShape, 2.84);
  EXPECT_EQ(kTakhountsBricAis3Scale, 0.987);
  EXPECT_EQ(kTakhountsBricAis4Scale, 1.204);
  // A Weibull at its scale is 1 - 1/e.
  EXPECT_NEAR(TakhountsBricAis3Risk(0.987), 1.0 - std::exp(-1.0), 1e-15);
  EXPECT_NEAR(TakhountsBricAis4Risk(1.204), 1.0 - std::exp(-1.0), 1e-15);
  // BrIC = 1: P(AIS 4+) = 1 - exp(-(1/1.204)^2.84) = 0.4458.
  EXPECT_NEAR(TakhountsBricAis4Risk(1.0), 1.0 - std::exp(-std::pow(1.0 / 1.204, 2.84)), 1e-15);
  EXPECT_NEAR(TakhountsBricAis4Risk(1.0), 0.4458, 5e-5);
  // AIS 4+ is never likelier than AIS 3+.
  for (double bric = 0.05; bric < 3.0; bric += 0.05)
    EXPECT_LT(TakhountsBricAis4Risk(bric), TakhountsBricAis3Risk(bric)) << bric;
}

TEST(InjuryRisk, ZeroCriterionIsNoRiskAndNaNStaysUndetermined) {
  for (const SummaryField* field : RiskFields()) {
    EXPECT_EQ(field->curve->risk(0.0), 0.0) << field->name;
    EXPECT_TRUE(std::isnan(field->curve->risk(kNaN))) << field->name;
    EXPECT_NEAR(field->curve->risk(1e7), 1.0, 1e-12) << field->name;
  }
}

TEST(InjuryRisk, EveryCurveIsARiskSummaryFieldReadingItsCriterion) {
  TestSummary summary;
  summary.hic15.value = 700.0;
  summary.hic36.value = 1000.0;
  summary.bric = 1.0;
  FillInjuryRisks(summary);
  std::size_t risks = 0;
  for (const SummaryField& field : SummaryFields()) {
    if (field.group != SummaryGroup::kRisk) continue;
    ++risks;
    const RiskCurve* curve = field.curve;
    ASSERT_NE(curve, nullptr) << field.name;
    double criterion = kNaN;
    for (const SummaryField& read : SummaryFields())
      if (std::string(read.name) == curve->criterion) criterion = read.Get(summary);
    EXPECT_EQ(field.Get(summary), curve->risk(criterion)) << field.name;
  }
  EXPECT_EQ(risks, RiskFields().size());
  EXPECT_EQ(FindSummaryField("hic15")->curve, nullptr);
  // The table's curves are the engine's functions (engine/injury_risk.h), each once.
  EXPECT_EQ(FindSummaryField("hic15_p_ais3")->curve->risk, &NcapHic15Ais3Risk);
  EXPECT_EQ(FindSummaryField("hic36_p_ais4")->curve->risk, &PrasadMertzHic36Ais4Risk);
  EXPECT_EQ(FindSummaryField("bric_p_ais3")->curve->risk, &TakhountsBricAis3Risk);
  EXPECT_EQ(FindSummaryField("bric_p_ais4")->curve->risk, &TakhountsBricAis4Risk);
  // An acceleration-only array: BrIC undetermined, so are its risks.
  summary.bric = kNaN;
  FillInjuryRisks(summary);
  EXPECT_TRUE(std::isnan(summary.bric_p_ais3));
  EXPECT_TRUE(std::isnan(summary.bric_p_ais4));
  EXPECT_NEAR(summary.hic15_p_ais3, NcapHic15Ais3Risk(700.0), 0.0);
}

}  // namespace
}  // namespace napkin::engine

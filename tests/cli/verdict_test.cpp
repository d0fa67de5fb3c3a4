// The wording rules of the verdict (cli/verdict.h, docs/formats.md
// "Verdict"): significant or not at 0.05, the sign, the p-value's text,
// risks, and the sentences BuildVerdict assembles from compare's rows.
#include "cli/verdict.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "engine/statistics.h"

namespace napkin::cli {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A variant's row with the given difference (percent of `baseline_mean`),
// interval and p; n tests.
ComparisonRow Row(std::size_t n, double baseline_mean, double diff, double ci_low, double ci_high, double p) {
  ComparisonRow row;
  row.description.n = n;
  row.description.mean = baseline_mean + diff;
  row.baseline_mean = baseline_mean;
  const double pct = baseline_mean != 0.0 ? 100.0 * diff / baseline_mean : kNaN;
  row.difference = {diff, pct, kNaN, kNaN, kNaN, ci_low, ci_high, p};
  return row;
}

engine::Description Baseline(std::size_t n, double mean) {
  engine::Description d;
  d.n = n;
  d.mean = mean;
  return d;
}

TEST(VerdictWording, PValues) {
  EXPECT_EQ(PValueText(0.24), "p = 0.24");
  EXPECT_EQ(PValueText(0.0012345), "p = 0.0012");
  EXPECT_EQ(PValueText(0.00009), "p < 0.0001");
  EXPECT_EQ(PValueText(0.0001), "p = 0.0001");
  // Two digits would read 0.05 for a significant p: more digits instead.
  EXPECT_EQ(PValueText(0.0496), "p = 0.0496");
  EXPECT_EQ(PValueText(0.0504), "p = 0.05");
  EXPECT_EQ(PValueText(0.5), "p = 0.5");
}

TEST(VerdictWording, SignificantLoweringReadsAsReductions) {
  // HIC15 1000 -> 560: -44 %, interval [-49, -40] % of the baseline mean.
  const ComparisonRow row = Row(5, 1000.0, -440.0, -490.0, -400.0, 3e-6);
  EXPECT_EQ(CriterionClause("HIC15", row, Baseline(5, 1000.0), true, true),
            "lowers HIC15 by 44 % [40, 49] (p < 0.0001, n = 5 vs 5)");
  EXPECT_EQ(CriterionClause("HIC15", row, Baseline(5, 1000.0), false, false),
            "lowers HIC15 by 44 % [40, 49] (p < 0.0001)");
}

TEST(VerdictWording, SignificantRaise) {
  const ComparisonRow row = Row(4, 100.0, 12.3, 4.4, 20.2, 0.0049);
  EXPECT_EQ(CriterionClause("peak acceleration", row, Baseline(5, 100.0), false, true),
            "raises peak acceleration by 12 % [4, 20] (p = 0.0049, n = 4 vs 5)");
}

TEST(VerdictWording, NotSignificantIsUnchangedWithSignedNumbers) {
  const ComparisonRow row = Row(5, 1.0, -0.09, -0.27, 0.08, 0.24);
  EXPECT_EQ(CriterionClause("BrIC", row, Baseline(5, 1.0), false, false),
            "BrIC unchanged (−9 % [−27, +8], p = 0.24)");
  EXPECT_EQ(CriterionClause("BrIC", row, Baseline(5, 1.0), true, true),
            "leaves BrIC unchanged (−9 % [−27, +8], p = 0.24, n = 5 vs 5)");
  // The same difference with a p just below 0.05 is a lowering, never "unchanged".
  const ComparisonRow just = Row(5, 1.0, -0.09, -0.17, -0.001, 0.0496);
  EXPECT_EQ(CriterionClause("BrIC", just, Baseline(5, 1.0), false, false),
            "lowers BrIC by 9 % [0, 17] (p = 0.0496)");
}

TEST(VerdictWording, SmallPercentagesKeepADecimal) {
  const ComparisonRow row = Row(5, 100.0, -0.42, -0.61, -0.23, 0.003);
  EXPECT_EQ(CriterionClause("HIC15", row, Baseline(5, 100.0), false, false),
            "lowers HIC15 by 0.4 % [0.2, 0.6] (p = 0.003)");
}

TEST(VerdictWording, BaselineMeanZeroUsesTheMetricsUnit) {
  const ComparisonRow row = Row(5, 0.0, 0.125, 0.05, 0.2, 0.01);
  EXPECT_EQ(CriterionClause("DAMAGE", row, Baseline(5, 0.0), false, false),
            "raises DAMAGE by 0.125 [0.05, 0.2] (p = 0.01)");
}

TEST(VerdictWording, NoDifferenceOrNoScatterIsNeverUnchanged) {
  const ComparisonRow small = Row(1, 1000.0, kNaN, kNaN, kNaN, kNaN);
  EXPECT_EQ(CriterionClause("HIC15", small, Baseline(5, 1000.0), true, true),
            "has no HIC15 comparison (n = 1 vs 5: fewer than 2 tests)");
  const ComparisonRow flat = Row(3, 100.0, -10.0, kNaN, kNaN, kNaN);
  EXPECT_EQ(CriterionClause("HIC15", flat, Baseline(3, 100.0), false, false),
            "lowers HIC15 by 10 % (no interval: no scatter, n = 3 vs 3)");
}

TEST(VerdictWording, Risks) {
  EXPECT_EQ(
      RiskClause("P(AIS 3+)", Row(5, 0.113, 0.021 - 0.113, -0.12, -0.06, 0.001), Baseline(5, 0.113), false),
      "P(AIS 3+) from 11.3 % to 2.1 %");
  EXPECT_EQ(RiskClause("P(AIS 3+)", Row(5, 0.113, -0.004, -0.03, 0.02, 0.41), Baseline(5, 0.113), false),
            "P(AIS 3+) unchanged (11.3 % vs 10.9 %, p = 0.41)");
  EXPECT_EQ(RiskClause("P(AIS 4+)", Row(4, 0.0042, 0.0, -0.001, 0.001, 0.9), Baseline(5, 0.0042), true),
            "P(AIS 4+) unchanged (0.42 % vs 0.42 %, p = 0.9, n = 4 vs 5)");
}

TEST(VerdictWording, RiskMetricsByName) {
  const std::vector<std::string> criteria = VerdictCriteria();
  ASSERT_EQ(criteria, (std::vector<std::string>{"hic15", "bric"}));
  const auto hic = IsRiskMetric("hic15_p_ais3", criteria);
  ASSERT_TRUE(hic);
  EXPECT_EQ(hic->ais_level, 3);
  EXPECT_EQ(hic->criterion, "hic15");
  const auto bric = IsRiskMetric("p_ais4_bric", criteria);
  ASSERT_TRUE(bric);
  EXPECT_EQ(bric->ais_level, 4);
  EXPECT_EQ(bric->criterion, "bric");
  const auto other = IsRiskMetric("hic36_ais4plus", criteria);
  ASSERT_TRUE(other);
  EXPECT_EQ(other->ais_level, 4);
  EXPECT_FALSE(other->criterion);
  EXPECT_FALSE(IsRiskMetric("hic15", criteria));
  EXPECT_FALSE(IsRiskMetric("aisle_bric", criteria));
  EXPECT_EQ(MetricLabel("hic15_p_ais3"), "P(AIS 3+)");
  EXPECT_EQ(MetricLabel("bric"), "BrIC");
}

// A by-variant metric comparison of `values` (baseline first), made as
// BuildComparison makes it.
MetricComparison Metric(const std::string& name, const std::vector<std::string>& groups,
                        const std::vector<std::vector<double>>& values) {
  MetricComparison metric;
  metric.metric = name;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    metric.groups.push_back({groups[g], {}, values[g]});
    ComparisonRow& row = metric.rows.emplace_back();
    row.metric = name;
    row.group = groups[g];
    row.baseline = groups[0];
    row.is_baseline = g == 0;
    row.description = engine::Describe(values[g]);
    if (g == 0) {
      row.difference = {kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN};
      continue;
    }
    row.difference = engine::WelchComparison(values[g], values[0]);
    row.baseline_mean = engine::Describe(values[0]).mean;
  }
  return metric;
}

TEST(Verdict, SentencesFollowTheCriteriaWithTheirRisks) {
  const std::vector<std::string> groups = {"production", "foam-b"};
  Comparison comparison;
  comparison.series = "sled";
  comparison.baseline = "production";
  comparison.groups = groups;
  // bric listed before its risk and hic15 after: the verdict orders them itself.
  comparison.metrics.push_back(Metric("bric", groups, {{0.70, 0.80, 0.75, 0.72}, {0.69, 0.71, 0.81, 0.74}}));
  comparison.metrics.push_back(
      Metric("hic15_p_ais3", groups, {{0.10, 0.12, 0.11, 0.13}, {0.020, 0.022, 0.020, 0.022}}));
  comparison.metrics.push_back(Metric("hic15", groups, {{900, 950, 1000, 975}, {500, 540, 520, 530}}));
  comparison.metrics.push_back(Metric("peak_omega_radps", groups, {{}, {}}));  // not a verdict criterion
  comparison.metrics.push_back(Metric("hic36_p_ais4", groups, {{0.05, 0.06}, {0.01, 0.015}}));

  const SeriesVerdict verdict = BuildVerdict(comparison);
  const MetricComparison& bric = comparison.metrics[0];
  const MetricComparison& risk = comparison.metrics[1];
  const MetricComparison& hic = comparison.metrics[2];
  const MetricComparison& other = comparison.metrics[4];
  ASSERT_EQ(verdict.sentences.size(), 1u);
  EXPECT_EQ(verdict.sentences[0],
            "foam-b " + CriterionClause("HIC15", hic.rows[1], hic.rows[0].description, true, true) + "; " +
                RiskClause("P(AIS 3+)", risk.rows[1], risk.rows[0].description, false) + "; " +
                CriterionClause("BrIC", bric.rows[1], bric.rows[0].description, false, false) + "; " +
                RiskClause("P(AIS 4+, HIC36)", other.rows[1], other.rows[0].description, true));
  // The parts, as the rules word them from these numbers.
  EXPECT_EQ(verdict.sentences[0].rfind("foam-b lowers HIC15 by 45 % [", 0), 0u) << verdict.sentences[0];
  EXPECT_NE(verdict.sentences[0].find("; P(AIS 3+) from 11.5 % to 2.1 %; BrIC unchanged ("),
            std::string::npos)
      << verdict.sentences[0];
  EXPECT_NE(verdict.sentences[0].find("n = 2 vs 2)"), std::string::npos) << verdict.sentences[0];

  EXPECT_EQ(verdict.columns,
            (std::vector<std::string>{"variant", "tests", "HIC15 mean ± sd", "P(AIS 3+) HIC15",
                                      "BrIC mean ± sd", "P(AIS 4+) HIC36"}));
  ASSERT_EQ(verdict.rows.size(), 2u);
  EXPECT_EQ(verdict.rows[0][0], "production");
  EXPECT_EQ(verdict.rows[0][1], "4");
  EXPECT_EQ(verdict.rows[0][2], "956.2 ± 42.7");  // mean 956.25, sd 42.696...
  EXPECT_EQ(verdict.rows[1][3], "2.1 %");         // mean 0.021

  const std::string text = FormatVerdict(verdict);
  EXPECT_EQ(text.rfind("verdict on series sled against 'production' (", 0), 0u) << text;
  EXPECT_NE(text.find("\n  " + verdict.sentences[0] + "\n"), std::string::npos) << text;
}

TEST(Verdict, MetricsNoTestHasAreLeftOut) {
  // An acceleration-only series: BrIC has no value anywhere.
  const std::vector<std::string> groups = {"a", "b"};
  Comparison comparison;
  comparison.series = "nhtsa";
  comparison.baseline = "a";
  comparison.groups = groups;
  comparison.metrics.push_back(Metric("hic15", groups, {{400, 420, 410}, {405, 430, 415}}));
  comparison.metrics.push_back(Metric("bric", groups, {{}, {}}));
  const SeriesVerdict verdict = BuildVerdict(comparison);
  ASSERT_EQ(verdict.sentences.size(), 1u);
  EXPECT_EQ(verdict.sentences[0].find("BrIC"), std::string::npos) << verdict.sentences[0];
  EXPECT_EQ(verdict.sentences[0].rfind("b leaves HIC15 unchanged (+", 0), 0u) << verdict.sentences[0];
  EXPECT_EQ(verdict.columns, (std::vector<std::string>{"variant", "tests", "HIC15 mean ± sd"}));
}

}  // namespace
}  // namespace napkin::cli

// The wording rules of the verdict (app/verdict.h, docs/formats.md
// "Verdict"), on series with known answers compared as BuildComparison
// compares them (app::CompareMetric): a large reduction, a non-significant
// difference, an equivalent one, the base/soft series of issue 30, identical
// values, a bound near zero, acceleration-only variants beside full ones,
// limits; and the rules table as docs/formats.md states it.
#include "app/verdict.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>
#include <regex>
#include <string>
#include <vector>

#include "engine/injury_risk.h"
#include "engine/statistics.h"
#include "tests/support/run_command.h"

namespace napkin::app {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Groups named g0, g1, ... with test ids gN-K, values as given (baseline first).
std::vector<GroupValues> Groups(const std::vector<std::string>& names,
                                const std::vector<std::vector<double>>& values) {
  std::vector<GroupValues> groups;
  for (std::size_t g = 0; g < names.size(); ++g) {
    GroupValues& group = groups.emplace_back();
    group.group = names[g];
    group.values = values[g];
    for (std::size_t k = 0; k < values[g].size(); ++k)
      group.test_ids.push_back(names[g] + "-" + std::to_string(k + 1));
  }
  return groups;
}

// A comparison of the given metrics (name, values per group), baseline first.
Comparison Series(const std::vector<std::string>& groups,
                  const std::vector<std::pair<std::string, std::vector<std::vector<double>>>>& metrics) {
  Comparison comparison;
  comparison.series = "sled";
  comparison.baseline = groups.front();
  comparison.groups = groups;
  for (const auto& [name, values] : metrics)
    comparison.metrics.push_back(CompareMetric(name, Groups(groups, values), CompareBy::kVariant,
                                               CompareScale::kLog, kDefaultEquivalencePct));
  return comparison;
}

// HIC15 with its NCAP risk computed from each value, as the engine stores them.
std::vector<std::pair<std::string, std::vector<std::vector<double>>>> HicWithRisk(
    const std::vector<std::vector<double>>& hic15) {
  std::vector<std::vector<double>> risk;
  for (const auto& group : hic15) {
    std::vector<double>& values = risk.emplace_back();
    for (const double hic : group) values.push_back(engine::NcapHic15Ais3Risk(hic));
  }
  return {{"hic15", hic15}, {"hic15_p_ais3", risk}};
}

// The percentages inside the first "[a, b]" of `text`, as numbers.
std::pair<double, double> Bracket(const std::string& text) {
  std::smatch match;
  EXPECT_TRUE(std::regex_search(text, match, std::regex(R"(\[([^,\]]+), ([^\]]+)\])"))) << text;
  const auto number = [](std::string s) {
    const std::string minus = "\xE2\x88\x92";
    if (s.rfind(minus, 0) == 0) s = "-" + s.substr(minus.size());
    return std::stod(s);
  };
  return {number(match[1]), number(match[2])};
}

void ExpectNoUnchanged(const SeriesVerdict& verdict) {
  for (const std::string& sentence : verdict.sentences)
    EXPECT_EQ(sentence.find("unchanged"), std::string::npos) << sentence;
}

TEST(VerdictWording, PValues) {
  EXPECT_EQ(PValueText(0.24), "p = 0.24");
  EXPECT_EQ(PValueText(0.0012345), "p = 0.0012");
  EXPECT_EQ(PValueText(0.00009), "p < 0.0001");
  EXPECT_EQ(PValueText(0.0001), "p = 0.0001");
  // Two digits would read 0.05 for a significant p: more digits instead.
  EXPECT_EQ(PValueText(0.0496), "p = 0.0496");
  EXPECT_EQ(PValueText(0.0504), "p = 0.05");
}

// A risk change is shown with the digits that tell the two risks apart, never "7.7 % → 7.7 %"; the
// table's TOST p of 0.99993 is not "p=1" (issue 42, point 17).
TEST(VerdictWording, ARiskChangeIsNeverShownAsTheSameNumberTwice) {
  ComparisonRow baseline, row;
  baseline.description.mean = 0.0771;
  row.description.mean = 0.0774;
  EXPECT_EQ(RiskConsequence("P(AIS 3+)", ClauseKind::kSignificant, row, baseline),
            "P(AIS 3+) 7.71 % → 7.74 %");
  row.description.mean = 0.07710001;
  EXPECT_EQ(RiskConsequence("P(AIS 3+)", ClauseKind::kNoScatter, row, baseline),
            "P(AIS 3+) 7.71 % in both at the precision shown");
  row.description.mean = 0.30;
  EXPECT_EQ(RiskConsequence("P(AIS 3+)", ClauseKind::kSignificant, row, baseline),
            "P(AIS 3+) 7.7 % → 30.0 %");
  EXPECT_EQ(ComparisonPValueText(0.99993), "p>0.99");
  EXPECT_EQ(ComparisonPValueText(0.41), "p=0.41");
  EXPECT_EQ(ComparisonPValueText(1.0), "p=1");
  EXPECT_EQ(ComparisonPValueText(0.00001), "p<0.0001");
}

TEST(VerdictWording, PercentagesNeverRoundANonZeroBoundToZero) {
  EXPECT_EQ(PercentText(44.4), "44");
  EXPECT_EQ(PercentText(0.3), "0.3");
  EXPECT_EQ(PercentText(0.042), "0.042");
  EXPECT_EQ(PercentText(0.96), "1");
  EXPECT_EQ(PercentText(0.0), "0");
  EXPECT_EQ(PercentText(-4.4),
            "\xE2\x88\x92"
            "4");
}

TEST(VerdictWording, EveryClauseKindHasARuleThatTheDocsState) {
  const std::string docs =
      test_support::ReadText(std::filesystem::path(NAPKIN_SOURCE_DIR) / "docs" / "formats.md");
  for (const ClauseKind kind :
       {ClauseKind::kNotMeasured, ClauseKind::kTooFew, ClauseKind::kIdentical, ClauseKind::kNoScatter,
        ClauseKind::kSignificant, ClauseKind::kEquivalent, ClauseKind::kInconclusive}) {
    const VerdictRule& rule = RuleOf(kind);
    EXPECT_EQ(rule.kind, kind);
    EXPECT_NE(docs.find(std::string(rule.when)), std::string::npos) << "docs/formats.md lacks: " << rule.when;
    EXPECT_NE(docs.find(std::string(rule.example)), std::string::npos)
        << "docs/formats.md lacks: " << rule.example;
  }
}

TEST(Verdict, LargeReductionIsARatioWithItsRiskAsConsequence) {
  const Comparison comparison =
      Series({"production", "foam-b"}, HicWithRisk({{900, 950, 1000, 975, 925}, {500, 540, 520, 530, 510}}));
  const SeriesVerdict verdict = BuildVerdict(comparison);
  ASSERT_EQ(verdict.sentences.size(), 1u);
  const std::string& s = verdict.sentences[0];
  // Ratio of geometric means: exp(mean log b - mean log a) - 1.
  const ComparisonRow& row = comparison.metrics[0].rows[1];
  EXPECT_EQ(row.scale, CompareScale::kLog);
  EXPECT_NEAR(
      row.pct,
      100.0 *
          (std::exp((std::log(500.) + std::log(540.) + std::log(520.) + std::log(530.) + std::log(510.)) / 5 -
                    (std::log(900.) + std::log(950.) + std::log(1000.) + std::log(975.) + std::log(925.)) /
                        5) -
           1.0),
      1e-9);
  EXPECT_EQ(s.rfind("foam-b: lowers HIC15 by 45 % [", 0), 0u) << s;
  const auto [from, to] = Bracket(s);
  EXPECT_GT(from, 0.0);
  EXPECT_LT(to, 100.0);
  EXPECT_NE(s.find("(p < 0.0001, n = 5 vs 5) → P(AIS 3+ | HIC15) "), std::string::npos) << s;
  EXPECT_EQ(s.find("P(AIS 3+ | HIC15)"), s.rfind("P(AIS 3+ | HIC15)")) << "the risk once: " << s;
  EXPECT_EQ(verdict.columns,
            (std::vector<std::string>{"variant", "tests", "HIC15 mean ± sd", "P(AIS 3+ | HIC15)"}));
  ExpectNoUnchanged(verdict);
}

TEST(Verdict, NonSignificantIsWhatTheSeriesCannotTell) {
  const Comparison comparison = Series(
      {"production", "foam-a"}, {{"bric", {{0.70, 0.80, 0.55, 0.62, 0.75}, {0.66, 0.85, 0.50, 0.72, 0.60}}}});
  const ComparisonRow& row = comparison.metrics[0].rows[1];
  ASSERT_GT(row.difference.p_value, 0.05);
  ASSERT_GT(row.equivalence.p_value, 0.05);
  const SeriesVerdict verdict = BuildVerdict(comparison);
  const std::string& s = verdict.sentences.at(0);
  EXPECT_EQ(s.rfind("foam-a: no significant difference in BrIC (", 0), 0u) << s;
  EXPECT_NE(s.find(PValueText(row.difference.p_value) + "; 5 vs 5 tests detect "), std::string::npos) << s;
  EXPECT_NE(s.find(" with 80 % power)"), std::string::npos) << s;
  ExpectNoUnchanged(verdict);
}

TEST(Verdict, EquivalentOnlyWhenTheTwoOneSidedTestsShowIt) {
  const Comparison comparison = Series(
      {"production", "foam-a"}, HicWithRisk({{1000, 1010, 990, 1005, 995}, {1002, 998, 1008, 992, 1001}}));
  const ComparisonRow& row = comparison.metrics[0].rows[1];
  ASSERT_GT(row.difference.p_value, 0.05);
  ASSERT_LT(row.equivalence.p_value, 0.05);
  const std::string s = BuildVerdict(comparison).sentences.at(0);
  EXPECT_EQ(s.rfind("foam-a: HIC15 equivalent within ±10 % (90 % interval ", 0), 0u) << s;
  EXPECT_NE(s.find(" → P(AIS 3+ | HIC15) "), std::string::npos) << s;
  EXPECT_NE(s.find(" vs "), std::string::npos) << "a risk after an equivalence reads 'vs': " << s;
}

TEST(Verdict, BaseAndSoftOfTheIssueNeitherExceedAHundredPercentNorContradict) {
  // Issue 30: "soft lowers HIC15 by 70 % [8, 132] (p = 0.036); P(AIS 3+) unchanged".
  const std::vector<double> base = {720, 551, 1000}, soft = {153, 370, 162};
  for (const bool reverse : {false, true}) {
    const Comparison comparison = reverse ? Series({"soft", "base"}, HicWithRisk({soft, base}))
                                          : Series({"base", "soft"}, HicWithRisk({base, soft}));
    const SeriesVerdict verdict = BuildVerdict(comparison);
    const std::string& s = verdict.sentences.at(0);
    const ComparisonRow& row = comparison.metrics[0].rows[1];
    ExpectNoUnchanged(verdict);
    if (!reverse) {
      const auto [from, to] = Bracket(s);
      EXPECT_LT(to, 100.0) << s;  // a reduction is bounded by 100 %
      EXPECT_GT(from, 0.0) << s;
    }
    // The risk follows the criterion's clause: "→" after a significant one, "vs" otherwise.
    const bool significant = row.difference.p_value < 0.05;
    EXPECT_EQ(s.find(significant ? (reverse ? "base: raises HIC15 by " : "soft: lowers HIC15 by ")
                                 : (reverse ? "base: no significant difference in HIC15"
                                            : "soft: no significant difference in HIC15")),
              0u)
        << s;
    const std::size_t risk = s.find("P(AIS 3+ | HIC15) ");
    ASSERT_NE(risk, std::string::npos) << s;
    EXPECT_EQ(s.find(significant ? " → " : " vs ", risk) != std::string::npos, true) << s;
    EXPECT_EQ(s.find("P(AIS 3+)"), std::string::npos) << s;
  }
}

TEST(Verdict, IdenticalValuesSaySo) {
  const SeriesVerdict verdict =
      BuildVerdict(Series({"a", "b"}, HicWithRisk({{700, 700, 700}, {700, 700, 700}})));
  const std::string& s = verdict.sentences.at(0);
  EXPECT_EQ(s.rfind("b: HIC15 identical in all 6 tests → P(AIS 3+ | HIC15) ", 0), 0u) << s;
  EXPECT_NE(s.find(" in both"), std::string::npos) << s;
  EXPECT_EQ(s.find("0.0 %"), std::string::npos) << s;
}

TEST(Verdict, ABoundNearZeroShowsItsDigits) {
  // A significant lowering whose interval reaches to within 0.3 % of no change.
  ComparisonRow baseline;
  baseline.group = "production";
  baseline.description = engine::Describe(std::vector<double>{900, 950, 1000});
  ComparisonRow row;
  row.group = "foam-a";
  row.description = engine::Describe(std::vector<double>{500, 620, 560});
  row.scale = CompareScale::kLog;
  row.difference = {std::log(0.62), kNaN, 0.1, 4.0, -4.0, std::log(0.25), std::log(0.997), 0.049};
  row.pct = -38.0;
  row.pct_ci_low = -75.0;
  row.pct_ci_high = -0.3;
  row.equivalence = engine::TwoOneSidedTests(row.difference, kNaN, kNaN);
  EXPECT_EQ(CriterionClause("HIC15", row, baseline, false, false),
            "lowers HIC15 by 38 % [0.3, 75] (p = 0.049)");
}

TEST(Verdict, AccelerationOnlyVariantsBesideFullOnesAreNotMeasured) {
  const Comparison comparison = Series(
      {"full", "accel"}, {{"hic15", {{600, 650, 700}, {610, 640, 690}}}, {"bric", {{0.6, 0.7, 0.65}, {}}}});
  const std::string s = BuildVerdict(comparison).sentences.at(0);
  EXPECT_NE(s.find("; BrIC not measured (acceleration-only heads)"), std::string::npos) << s;
  EXPECT_EQ(s.find("fewer than 2"), std::string::npos) << s;
  const Comparison reverse = Series(
      {"accel", "full"}, {{"hic15", {{610, 640, 690}, {600, 650, 700}}}, {"bric", {{}, {0.6, 0.7, 0.65}}}});
  EXPECT_NE(
      BuildVerdict(reverse).sentences.at(0).find("BrIC not measured in accel (acceleration-only heads)"),
      std::string::npos);
  // One test is fewer than 2, not "not measured".
  const Comparison one = Series({"a", "b"}, {{"hic15", {{600, 650, 700}, {610}}}});
  EXPECT_NE(BuildVerdict(one).sentences.at(0).find("no HIC15 comparison (n = 1 vs 3: fewer than 2 tests)"),
            std::string::npos);
}

// `set` checked on the comparison's metrics, as BuildComparison checks a --limits set.
void CheckWith(Comparison& comparison, const LimitSet& set) {
  const std::size_t index = comparison.limit_sets.size();
  comparison.limit_sets.push_back({set, {}});
  for (MetricComparison& metric : comparison.metrics)
    for (const Limit& limit : set.limits) {
      if (limit.metric != metric.metric) continue;
      MetricLimit& checked = metric.limits.emplace_back();
      checked.set = index;
      checked.limit = limit;
      for (const GroupValues& group : metric.groups) checked.checks.push_back(CheckGroupLimit(limit, group));
    }
}

LimitSet OneLimit(const std::string& name, Limit limit) {
  LimitSet set;
  set.name = name;
  set.source = "s";
  set.limits.push_back(std::move(limit));
  return set;
}

Limit Maximum(const std::string& metric, double max) {
  Limit limit;
  limit.metric = metric;
  limit.max = max;
  return limit;
}

// The probabilities of a further test below are scipy's (stats.t.sf on the logs' t, as
// python/tests/test_further_test.py computes them), printed as the verdict prints them.
TEST(Verdict, LimitsClauseCountsTheTestsWithinTheWorstMarginAndAFurtherTest) {
  Comparison comparison = Series({"production", "foam-b"}, {{"hic_d", {{820, 1040, 990}, {515, 563, 540}}}});
  CheckWith(comparison, OneLimit("FMVSS 201U", Maximum("hic_d", 1000.0)));
  const SeriesVerdict verdict = BuildVerdict(comparison);
  ASSERT_EQ(verdict.sentences.size(), 2u);
  // scipy: 36.72 % and 0.3433 %.
  EXPECT_EQ(
      verdict.sentences[0],
      "production (baseline): 2 of 3 production tests meet FMVSS 201U (highest HIC(d) 1040, 4 % over); a "
      "further test exceeds HIC(d) 1000 with probability 36.7 %");
  EXPECT_EQ(
      verdict.sentences[1],
      "foam-b: all 3 foam-b tests meet FMVSS 201U (highest HIC(d) 563, margin 44 %); a further test exceeds "
      "HIC(d) 1000 with probability 0.34 %");
  EXPECT_EQ(verdict.columns.back(), "meet FMVSS 201U");
  EXPECT_EQ(verdict.rows[0].back(), "2 of 3");
}

TEST(Verdict, AFurtherTestIsNotEstimatedFromTwoTestsOrWithoutSpread) {
  Comparison comparison =
      Series({"a", "b", "c"}, {{"hic_d", {{820, 1040, 990}, {515, 563}, {600, 600, 600}}}});
  CheckWith(comparison, OneLimit("FMVSS 201U", Maximum("hic_d", 1000.0)));
  const SeriesVerdict verdict = BuildVerdict(comparison);
  ASSERT_EQ(verdict.sentences.size(), 3u);
  EXPECT_NE(verdict.sentences[1].find("; the chance that a further test exceeds HIC(d) 1000 is not estimated "
                                      "(fewer than 3 tests)"),
            std::string::npos)
      << verdict.sentences[1];
  EXPECT_NE(
      verdict.sentences[2].find("the chance that a further test exceeds HIC(d) 1000 is not estimated (no "
                                "spread)"),
      std::string::npos)
      << verdict.sentences[2];
}

// A sliding scale: the tests' mean points, and a further test's expected points with its 80 %
// prediction interval (scipy: quad over the t density 1.2390; the points of the 90 % and 10 %
// quantiles 0 and 3.0306) and its chance of exceeding the lower performance limit (24.14 %).
TEST(Verdict, AScaleGivesPointsAndAFurtherTestsExpectedPoints) {
  Comparison comparison =
      Series({"production", "foam"}, {{"hic15", {{480, 520, 560, 610}, {600, 650, 700}}}});
  Limit scale;
  scale.metric = "hic15";
  scale.kind = LimitKind::kScale;
  scale.higher_limit = 500.0;
  scale.max = 700.0;
  scale.points = 4.0;
  CheckWith(comparison, OneLimit("Scale", scale));
  const SeriesVerdict verdict = BuildVerdict(comparison);
  const std::string& s = verdict.sentences.at(1);
  EXPECT_NE(s.find("; Scale: HIC15 1.00 points on average; a further test scores 1.24 points expected [0.00, "
                   "3.03] (80 % prediction interval) and exceeds HIC15 700 with probability 24.1 %"),
            std::string::npos)
      << s;
  EXPECT_EQ(verdict.columns.back(), "Scale HIC15 points");
  EXPECT_EQ(verdict.rows[1].back(), "1.00 of 4");
  // scipy: 2.8668 expected, [0.9631, 4], 5.4457 %.
  EXPECT_NE(
      verdict.sentences.at(0).find("HIC15 3.05 points on average; a further test scores 2.87 points "
                                   "expected [0.96, 4.00] (80 % prediction interval) and exceeds HIC15 700 "
                                   "with probability 5.4 %"),
      std::string::npos)
      << verdict.sentences.at(0);
}

// Bands: the tests per band, and a further test's chance of falling beyond the best (scipy: 90.74 %).
TEST(Verdict, BandsGiveTheTestsPerBandAndAFurtherTestBeyondTheBest) {
  Comparison comparison = Series({"production", "foam"}, {{"hic15", {{480, 520, 600}, {610, 640, 690}}}});
  Limit bands;
  bands.metric = "hic15";
  bands.kind = LimitKind::kBands;
  bands.bands = {{"Good", 560.0}, {"Acceptable", 700.0}, {"Marginal", 840.0}, {"Poor", std::nullopt}};
  bands.max = 560.0;
  CheckWith(comparison, OneLimit("IIHS small overlap head", bands));
  const SeriesVerdict verdict = BuildVerdict(comparison);
  EXPECT_NE(
      verdict.sentences.at(1).find("; IIHS small overlap head: HIC15 Acceptable in 3 of 3 (highest 690); a "
                                   "further test is beyond Good (HIC15 > 560) with probability 90.7 %"),
      std::string::npos)
      << verdict.sentences.at(1);
  EXPECT_NE(verdict.sentences.at(0).find("IIHS small overlap head: HIC15 Good in 2, Acceptable in 1 of 3"),
            std::string::npos)
      << verdict.sentences.at(0);
  EXPECT_EQ(verdict.columns.back(), "IIHS small overlap head HIC15");
  EXPECT_EQ(verdict.rows[0].back(), "2 Good, 1 Acceptable");
}

TEST(Verdict, ANegativeValueFallsBackToTheDifferenceOfMeansAndSaysSo) {
  const Comparison comparison = Series({"a", "b"}, {{"hic15", {{0.0, 650, 700}, {300, 320, 310}}}});
  const ComparisonRow& row = comparison.metrics[0].rows[1];
  EXPECT_EQ(row.scale, CompareScale::kLinear);
  EXPECT_TRUE(row.log_fallback);
  const std::string s = BuildVerdict(comparison).sentences.at(0);
  EXPECT_NE(s.find("difference of means: a value ≤ 0"), std::string::npos) << s;
}

TEST(Verdict, FormatVerdictHeadsAndIndentsTheSentences) {
  const SeriesVerdict verdict =
      BuildVerdict(Series({"production", "foam-b"}, HicWithRisk({{900, 950, 1000}, {500, 540, 520}})));
  const std::string text = FormatVerdict(verdict);
  EXPECT_EQ(text.rfind("verdict on series sled against 'production' (", 0), 0u) << text;
  EXPECT_NE(text.find("\n  " + verdict.sentences[0] + "\n"), std::string::npos) << text;
}

}  // namespace
}  // namespace napkin::app

// engine/statistics.h against published numbers (Student's 1908 sleep data as
// R's t.test prints them), against closed forms, and against its
// undefined-value rules (docs/algorithms.md "Comparing groups of tests").
#include "engine/statistics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

namespace napkin::engine {
namespace {

// Student (1908), "The probable error of a mean", Biometrika 6(1), table of
// Cushny & Peebles' additional hours of sleep of ten patients under two
// hypnotics (R's datasets::sleep). R's documented examples
// `t.test(extra ~ group, data = sleep)` and `... paired = TRUE` print:
//   Welch: t = -1.8608, df = 17.776, p-value = 0.07939,
//          95 percent confidence interval: -3.3654832  0.2054832
//   paired: t = -4.0621, df = 9, p-value = 0.002833,
//          95 percent confidence interval: -2.4598858 -0.7001142,
//          mean difference -1.58
// (group 1 minus group 2: the sample is drug 1, the baseline drug 2).
const std::vector<double> kSleepDrug1 = {0.7, -1.6, -0.2, -1.2, -0.1, 3.4, 3.7, 0.8, 0.0, 2.0};
const std::vector<double> kSleepDrug2 = {1.9, 0.8, 1.1, 0.1, -0.1, 4.4, 5.5, 1.6, 4.6, 3.4};

// |actual - printed| within half a unit of the printed last digit.
void ExpectPrinted(double actual, double printed, double last_digit) {
  EXPECT_NEAR(actual, printed, 0.5 * last_digit) << "printed " << printed;
}

TEST(WelchComparison, StudentSleepDataAsPrintedByR) {
  const MeanDifference welch = WelchComparison(kSleepDrug1, kSleepDrug2);
  ExpectPrinted(welch.t, -1.8608, 1e-4);
  ExpectPrinted(welch.df, 17.776, 1e-3);
  ExpectPrinted(welch.p_value, 0.07939, 1e-5);
  ExpectPrinted(welch.ci_low, -3.3654832, 1e-7);
  ExpectPrinted(welch.ci_high, 0.2054832, 1e-7);
  EXPECT_NEAR(welch.diff, 0.75 - 2.33, 1e-12);
  EXPECT_NEAR(welch.diff_pct, 100.0 * (0.75 - 2.33) / 2.33, 1e-10);
}

TEST(PairedComparison, StudentSleepDataAsPrintedByR) {
  std::vector<double> differences;
  for (std::size_t i = 0; i < kSleepDrug1.size(); ++i) differences.push_back(kSleepDrug1[i] - kSleepDrug2[i]);
  const MeanDifference paired = PairedComparison(differences, 2.33);
  ExpectPrinted(paired.diff, -1.58, 1e-2);
  ExpectPrinted(paired.t, -4.0621, 1e-4);
  EXPECT_EQ(paired.df, 9.0);
  ExpectPrinted(paired.p_value, 0.002833, 1e-6);
  ExpectPrinted(paired.ci_low, -2.4598858, 1e-7);
  ExpectPrinted(paired.ci_high, -0.7001142, 1e-7);
}

TEST(Describe, ClosedFormsOfSmallSamples) {
  // 2, 4, 4, 4, 5, 5, 7, 9: mean 5, sum of squares 32, sd sqrt(32/7).
  const std::vector<double> values = {9, 4, 5, 4, 2, 7, 4, 5};
  const Description d = Describe(values);
  EXPECT_EQ(d.n, 8u);
  EXPECT_DOUBLE_EQ(d.mean, 5.0);
  EXPECT_DOUBLE_EQ(d.sd, std::sqrt(32.0 / 7.0));
  EXPECT_DOUBLE_EQ(d.median, 4.5);
  EXPECT_EQ(d.min, 2.0);
  EXPECT_EQ(d.max, 9.0);

  const Description odd = Describe(std::vector<double>{3.0, -1.0, 10.0});
  EXPECT_EQ(odd.median, 3.0);
  EXPECT_DOUBLE_EQ(odd.sd, std::sqrt(((3.0 - 4.0) * (3.0 - 4.0) + 25.0 + 36.0) / 2.0));

  const Description one = Describe(std::vector<double>{7.5});
  EXPECT_EQ(one.n, 1u);
  EXPECT_EQ(one.mean, 7.5);
  EXPECT_EQ(one.median, 7.5);
  EXPECT_EQ(one.min, 7.5);
  EXPECT_EQ(one.max, 7.5);
  EXPECT_TRUE(std::isnan(one.sd));

  const Description none = Describe(std::vector<double>{});
  EXPECT_EQ(none.n, 0u);
  EXPECT_TRUE(std::isnan(none.mean) && std::isnan(none.sd) && std::isnan(none.median) &&
              std::isnan(none.min) && std::isnan(none.max));
}

TEST(WelchComparison, EqualSizesAndVariancesGiveThePooledDegreesOfFreedom) {
  // The same n and variance: Welch's df is 2 (n - 1), here 4 with n = 3.
  // Sample {1, 2, 3} vs {0, 1, 2}: diff 1, variances 1, se sqrt(2/3).
  const MeanDifference welch = WelchComparison(std::vector<double>{1, 2, 3}, std::vector<double>{0, 1, 2});
  EXPECT_DOUBLE_EQ(welch.diff, 1.0);
  EXPECT_DOUBLE_EQ(welch.diff_pct, 100.0);
  EXPECT_DOUBLE_EQ(welch.se, std::sqrt(2.0 / 3.0));
  EXPECT_DOUBLE_EQ(welch.df, 4.0);
  EXPECT_DOUBLE_EQ(welch.t, 1.0 / std::sqrt(2.0 / 3.0));
  // t with 4 degrees of freedom in closed form: P(|T| > t) = 1 - t (6 + t^2) / (4 + t^2)^(3/2).
  const double t = welch.t;
  EXPECT_NEAR(welch.p_value, 1.0 - t * (6.0 + t * t) / std::pow(4.0 + t * t, 1.5), 1e-14);
  // The 97.5 % point of t with 4 degrees of freedom, 2.776445105 (tables).
  EXPECT_NEAR((welch.ci_high - welch.diff) / welch.se, 2.7764451051977987, 1e-12);
  EXPECT_NEAR(welch.ci_low + welch.ci_high, 2.0 * welch.diff, 1e-14);
}

TEST(WelchComparison, TwoDegreesOfFreedomHaveAClosedFormQuantile) {
  // A constant baseline leaves the sample's n - 1 degrees of freedom:
  // {0, 3, 6} vs {1, 1, 1} has v_sample = 9 / 3 = 3, v_baseline = 0, df = 3^2 / (3^2 / 2) = 2.
  const MeanDifference welch = WelchComparison(std::vector<double>{0, 3, 6}, std::vector<double>{1, 1, 1});
  EXPECT_DOUBLE_EQ(welch.df, 2.0);
  EXPECT_DOUBLE_EQ(welch.diff, 2.0);
  EXPECT_DOUBLE_EQ(welch.se, std::sqrt(3.0));
  // t with 2 degrees of freedom: P(|T| > t) = 1 - t / sqrt(2 + t^2); the
  // 97.5 % point is q with q / sqrt(2 + q^2) = 0.95, q = sqrt(2 * 0.95^2 / (1 - 0.95^2)).
  const double t = 2.0 / std::sqrt(3.0);
  EXPECT_NEAR(welch.p_value, 1.0 - t / std::sqrt(2.0 + t * t), 1e-14);
  const double q = std::sqrt(2.0 * 0.95 * 0.95 / (1.0 - 0.95 * 0.95));
  EXPECT_NEAR(welch.ci_low, 2.0 - q * std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(welch.ci_high, 2.0 + q * std::sqrt(3.0), 1e-12);
}

TEST(WelchComparison, UndefinedWhereTheDocumentedRulesSay) {
  const MeanDifference small = WelchComparison(std::vector<double>{1.0}, std::vector<double>{1, 2, 3});
  for (const double value :
       {small.diff, small.diff_pct, small.se, small.df, small.t, small.ci_low, small.ci_high, small.p_value})
    EXPECT_TRUE(std::isnan(value));
  EXPECT_TRUE(std::isnan(WelchComparison(std::vector<double>{1, 2}, std::vector<double>{}).diff));

  // Both constant: diff and diff_pct defined, no interval.
  const MeanDifference constant = WelchComparison(std::vector<double>{3, 3}, std::vector<double>{2, 2, 2});
  EXPECT_EQ(constant.diff, 1.0);
  EXPECT_EQ(constant.diff_pct, 50.0);
  EXPECT_EQ(constant.se, 0.0);
  for (const double value : {constant.df, constant.t, constant.ci_low, constant.ci_high, constant.p_value})
    EXPECT_TRUE(std::isnan(value));

  // Baseline mean 0: no percentage, the rest defined.
  const MeanDifference zero = WelchComparison(std::vector<double>{1, 2}, std::vector<double>{-1, 1});
  EXPECT_TRUE(std::isnan(zero.diff_pct));
  EXPECT_EQ(zero.diff, 1.5);
  EXPECT_TRUE(std::isfinite(zero.p_value));

  EXPECT_THROW(WelchComparison(std::vector<double>{1, NAN}, std::vector<double>{1, 2}),
               std::invalid_argument);
  EXPECT_THROW(Describe(std::vector<double>{INFINITY}), std::invalid_argument);
}

TEST(PairedComparison, ClosedFormsAndUndefinedCases) {
  // Differences {1, 2, 3}: mean 2, sd 1, se 1/sqrt(3), df 2, t = 2 sqrt(3).
  const MeanDifference paired = PairedComparison(std::vector<double>{1, 2, 3}, 8.0);
  EXPECT_DOUBLE_EQ(paired.diff, 2.0);
  EXPECT_DOUBLE_EQ(paired.diff_pct, 25.0);
  EXPECT_DOUBLE_EQ(paired.se, 1.0 / std::sqrt(3.0));
  EXPECT_EQ(paired.df, 2.0);
  const double t = 2.0 * std::sqrt(3.0);
  EXPECT_NEAR(paired.t, t, 1e-14);
  EXPECT_NEAR(paired.p_value, 1.0 - t / std::sqrt(2.0 + t * t), 1e-14);

  const MeanDifference one = PairedComparison(std::vector<double>{5.0}, 1.0);
  EXPECT_TRUE(std::isnan(one.diff) && std::isnan(one.p_value) && std::isnan(one.ci_low));

  const MeanDifference constant = PairedComparison(std::vector<double>{0.5, 0.5, 0.5}, 1.0);
  EXPECT_EQ(constant.diff, 0.5);
  EXPECT_EQ(constant.diff_pct, 50.0);
  EXPECT_EQ(constant.df, 2.0);
  EXPECT_TRUE(std::isnan(constant.t) && std::isnan(constant.ci_low) && std::isnan(constant.ci_high) &&
              std::isnan(constant.p_value));
}

// Issue 19 item 14: three tests with bit-identical HIC15 473.5561725417905
// gave sd 6.96e-14 and a mean below min = max (a plain sum rounds up 3x and
// the division does not undo it), and then p < 0.0001 against another group
// without scatter.
TEST(Describe, IdenticalValuesOfTheIssueHaveTheirOwnMeanAndNoScatter) {
  const std::vector<double> hic15(3, 473.5561725417905);
  const Description d = Describe(hic15);
  EXPECT_EQ(d.mean, 473.5561725417905);
  EXPECT_EQ(d.sd, 0.0);
  EXPECT_EQ(d.min, 473.5561725417905);
  EXPECT_EQ(d.max, 473.5561725417905);
  EXPECT_EQ(d.median, 473.5561725417905);
  // Two groups without scatter: a difference, but no interval and no p.
  const MeanDifference welch = WelchComparison(hic15, std::vector<double>(3, 473.0));
  EXPECT_EQ(welch.diff, 473.5561725417905 - 473.0);
  EXPECT_EQ(welch.se, 0.0);
  EXPECT_TRUE(std::isnan(welch.ci_low) && std::isnan(welch.ci_high) && std::isnan(welch.p_value));
}

// Exact answers a plain left-to-right sum misses: the mean is the exact mean
// of the binary values, correctly rounded (checked with rational arithmetic:
// 0.1 + 0.2 + 0.3 summed in order is 0.6000000000000001, whose third is
// 0.20000000000000004; 1e16 + 1 - 1e16 summed in order is 0).
TEST(Describe, MeanIsTheCorrectlyRoundedExactMean) {
  EXPECT_EQ(Describe(std::vector<double>{0.1, 0.2, 0.3}).mean, 0.2);
  EXPECT_EQ(Describe(std::vector<double>{1e16, 1.0, -1e16}).mean, 1.0 / 3.0);
  // sd of {0.1, 0.2, 0.3}: the exact value 0.0999999999999999916... rounds to
  // the double below 0.1 (Python's statistics.stdev gives the same).
  EXPECT_EQ(Describe(std::vector<double>{0.1, 0.2, 0.3}).sd, 0.09999999999999999);
}

// Property: n identical values of awkward magnitudes (n = 2..50) have that
// value as mean, median, min and max, and sd exactly 0; a paired comparison
// of identical differences has no interval.
TEST(Describe, IdenticalValuesOfAnyMagnitudeHaveSdZeroAndTheirOwnMean) {
  const std::vector<double> awkward = {473.5561725417905,
                                       0.1,
                                       1.0 / 3.0,
                                       -2.0 / 3.0,
                                       9007199254740993.0,  // 2^53 + 1 (rounds to 2^53)
                                       123456789.98765432,
                                       1e-300,
                                       -1e300,
                                       std::numeric_limits<double>::denorm_min(),
                                       std::numeric_limits<double>::min(),
                                       std::nextafter(1000.0, 2000.0),
                                       0.0};
  for (const double value : awkward) {
    for (std::size_t n = 2; n <= 50; ++n) {
      const std::vector<double> values(n, value);
      const Description d = Describe(values);
      EXPECT_EQ(d.mean, value) << "n = " << n << ", value " << value;
      EXPECT_EQ(d.sd, 0.0) << "n = " << n << ", value " << value;
      EXPECT_EQ(d.median, value);
      EXPECT_EQ(d.min, value);
      EXPECT_EQ(d.max, value);
      const MeanDifference paired = PairedComparison(values, 1.0);
      EXPECT_EQ(paired.diff, value) << "n = " << n << ", value " << value;
      EXPECT_EQ(paired.se, 0.0) << "n = " << n << ", value " << value;
      EXPECT_TRUE(std::isnan(paired.p_value) && std::isnan(paired.ci_low));
    }
  }
}

// Property: for samples of values that differ in the last bits (n = 2..50,
// values within a few ulp of awkward magnitudes), min <= mean <= max and
// min <= median <= max, and sd is 0 exactly when all values are equal.
TEST(Describe, MeanAndMedianLieBetweenMinAndMaxForNearlyEqualValues) {
  std::mt19937_64 random(19);
  for (const double base : {473.5561725417905, 0.1, 1e-300, -7.77e250, 1e15 + 0.3}) {
    for (std::size_t n = 2; n <= 50; ++n) {
      std::vector<double> values;
      for (std::size_t i = 0; i < n; ++i) {
        double value = base;
        for (std::uint64_t steps = random() % 4; steps > 0; --steps)
          value = std::nextafter(value, random() % 2 == 0 ? INFINITY : -INFINITY);
        values.push_back(value);
      }
      const Description d = Describe(values);
      EXPECT_LE(d.min, d.mean) << "n = " << n << ", base " << base;
      EXPECT_LE(d.mean, d.max) << "n = " << n << ", base " << base;
      EXPECT_LE(d.min, d.median);
      EXPECT_LE(d.median, d.max);
      EXPECT_GE(d.sd, 0.0);
      EXPECT_EQ(d.sd == 0.0, d.min == d.max) << "n = " << n << ", base " << base;
    }
  }
}

}  // namespace
}  // namespace napkin::engine

namespace napkin::engine {
namespace {

// R 4.x, stats::power.t.test (two-sample, two-sided, strict = FALSE):
//   power.t.test(delta = 1, sd = 1, power = 0.8)  ->  n = 16.71477
//   power.t.test(n = 20, delta = 1)                 ->  power = 0.8689528
//   power.t.test(power = .90, delta = 1)            ->  n = 22.02110
// (the first quoted in docs/algorithms.md "Planning a series"; the other two
// are the examples of R's ?power.t.test). R finds n with uniroot to about
// 1e-4 (its tol is .Machine$double.eps^0.25), hence the tolerance on n.
TEST(PowerForPlanning, AgreesWithRPowerTTest) {
  const PowerModel equal_spreads = WelchPowerModel(1.0, 1.0, 1.0);
  EXPECT_EQ(equal_spreads.variance, 2.0);
  EXPECT_EQ(equal_spreads.df_per_repeat, 2.0);  // Welch with equal n and sd: the pooled 2n - 2
  EXPECT_NEAR(RepeatsForPower(equal_spreads), 16.71477, 2e-4);
  EXPECT_NEAR(TTestPower(equal_spreads, 20.0), 0.8689528, 5e-8);
  EXPECT_NEAR(RepeatsForPower(equal_spreads, 0.9), 22.02110, 2e-4);
  // The n found gives the power asked for.
  EXPECT_NEAR(TTestPower(equal_spreads, RepeatsForPower(equal_spreads)), 0.8, 1e-12);
  EXPECT_EQ(WholeRepeatsForPower(equal_spreads), 17.0);
  // The sign of the difference does not matter.
  EXPECT_EQ(RepeatsForPower(WelchPowerModel(-1.0, 1.0, 1.0)), RepeatsForPower(equal_spreads));
}

TEST(PowerForPlanning, UndefinedWithoutADifferenceOrScatter) {
  EXPECT_TRUE(std::isnan(RepeatsForPower(WelchPowerModel(0.0, 1.0, 2.0))));
  EXPECT_TRUE(std::isnan(RepeatsForPower(WelchPowerModel(1.0, 0.0, 0.0))));
  EXPECT_TRUE(std::isnan(WholeRepeatsForPower(PairedPowerModel(1.0, 0.0))));
  EXPECT_TRUE(std::isnan(WholeRepeatsForPower(WelchPowerModel(std::nan(""), 1.0, 1.0))));
  // A difference large against its scatter needs the fewest tests with a spread.
  EXPECT_EQ(WholeRepeatsForPower(WelchPowerModel(100.0, 1.0, 1.0)), 2.0);
}

TEST(PowerForPlanning, PairedIsTheOneSampleT) {
  // Paired: df = n - 1, non-centrality diff sqrt(n) / sd_d. R:
  // power.t.test(delta = 1, sd = 1, power = 0.8, type = "paired") -> n = 9.937864.
  EXPECT_NEAR(RepeatsForPower(PairedPowerModel(1.0, 1.0)), 9.937864, 2e-4);
  // One spread 0: Welch's df per repeat is 1, the paired case with variance a^2.
  const PowerModel one_sided = WelchPowerModel(1.0, 1.0, 0.0);
  EXPECT_EQ(one_sided.df_per_repeat, 1.0);
  EXPECT_EQ(RepeatsForPower(one_sided), RepeatsForPower(PairedPowerModel(1.0, 1.0)));
}

}  // namespace
}  // namespace napkin::engine

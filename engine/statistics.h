#pragma once
// Descriptive statistics and two-sample comparisons of a metric across tests
// (docs/algorithms.md "Comparing groups of tests"): what `napkin compare` and
// `napkin report` print. The t distribution is Boost.Math's students_t, the
// non-central t of the power computation its non_central_t.
//
// Undefined quantities are NaN (null in the CLI's JSON and CSV):
//  * Describe: every field of an empty sample; sd of a sample of one.
//  * WelchComparison: every field when either sample has n < 2; when both
//    samples have n >= 2 but both sd are 0 (standard error 0), t, df, the
//    interval and p (diff and diff_pct stay defined).
//  * PairedComparison: every field when n < 2; t, the interval and p when the
//    differences have sd 0.
//  * diff_pct: also when the baseline mean is 0.
// Values must be finite (callers drop absent results); a NaN or infinity
// throws std::invalid_argument.
#include <cstddef>
#include <span>

namespace napkin::engine {

// The confidence level of every interval here.
inline constexpr double kConfidenceLevel = 0.95;

struct Description {
  std::size_t n = 0;
  double mean = 0.0;
  double sd = 0.0;      // sample standard deviation (divisor n - 1)
  double median = 0.0;  // mean of the two middle values when n is even
  double min = 0.0;
  double max = 0.0;
};

Description Describe(std::span<const double> values);

// A difference of means against a baseline with its 95 % interval.
struct MeanDifference {
  double diff = 0.0;      // mean(sample) - mean(baseline); for paired data, mean of the differences
  double diff_pct = 0.0;  // 100 diff / mean(baseline)
  double se = 0.0;        // standard error of diff
  double df = 0.0;        // degrees of freedom of t
  double t = 0.0;         // diff / se
  double ci_low = 0.0;    // diff -+ t_{0.975, df} se
  double ci_high = 0.0;
  double p_value = 0.0;  // two-sided: 2 (1 - F_t(|t|; df))
};

// Welch's unequal-variance t (Welch 1947), with the Welch–Satterthwaite
// degrees of freedom.
MeanDifference WelchComparison(std::span<const double> sample, std::span<const double> baseline);

// Paired t on per-test differences d_i = x_i - baseline_i; `baseline_mean`
// (the mean of the baseline values of the same pairs) scales diff_pct.
MeanDifference PairedComparison(std::span<const double> differences, double baseline_mean);

// Planning a series (docs/algorithms.md "Planning a series"): the power of
// the two-sided t test at level alpha to detect a true difference `diff`
// with n tests per group (fractional n allowed), where the standard error is
// sqrt(variance / n) and the degrees of freedom (n - 1) df_per_repeat:
//  * two groups (Welch), standard deviations a and b, n tests each:
//    variance = a^2 + b^2, df_per_repeat = (a^2 + b^2)^2 / (a^4 + b^4)
//    (Welch–Satterthwaite with equal n; 2 when a = b, the pooled t's 2n - 2);
//  * paired, standard deviation d of the differences, n pairs:
//    variance = d^2, df_per_repeat = 1.
// As R's power.t.test (strict = FALSE), power = P(T' > t_{1 - alpha/2, df})
// with T' non-central t (Boost.Math's non_central_t) of non-centrality
// |diff| / sqrt(variance / n); the chance of rejecting in the wrong
// direction is left out.
struct PowerModel {
  double diff = 0.0;
  double variance = 0.0;
  double df_per_repeat = 1.0;
};
PowerModel WelchPowerModel(double diff, double sd_a, double sd_b);
PowerModel PairedPowerModel(double diff, double sd_differences);

// Equivalence by two one-sided tests (TOST, Schuirmann 1987;
// docs/algorithms.md "Equivalence and the smallest detectable difference"):
// given a comparison's diff, se and df (Welch or paired), the hypotheses
// diff <= low and diff >= high are each tested one-sided at level alpha;
// equivalence within (low, high) is shown when both are rejected, that is
// when p_value = max(p_low, p_high) < alpha, which is when the
// (1 - 2 alpha) interval lies inside (low, high). As statsmodels'
// ttost_ind (usevar "unequal") and ttost_paired. NaN where the comparison
// has no se (n < 2, or no scatter) or a bound is not finite.
struct Equivalence {
  double low = 0.0, high = 0.0;  // the margin, in the units of diff
  double ci_low = 0.0;           // diff -+ t_{1 - alpha, df} se: the 90 % interval at alpha 0.05
  double ci_high = 0.0;
  double p_low = 0.0;   // P(T >= (diff - low) / se)
  double p_high = 0.0;  // P(T <= (diff - high) / se)
  double p_value = 0.0;
};
inline constexpr double kEquivalenceAlpha = 0.05;
Equivalence TwoOneSidedTests(const MeanDifference& difference, double low, double high,
                             double alpha = kEquivalenceAlpha);

inline constexpr double kPlanningPower = 0.8;
inline constexpr double kPlanningAlpha = 0.05;

double TTestPower(const PowerModel& model, double n, double alpha = kPlanningAlpha);

// The n (>= 2, fractional, as R's power.t.test reports it) at which
// TTestPower reaches `power`; NaN where no n does: diff 0, variance 0, or
// either not finite.
double RepeatsForPower(const PowerModel& model, double power = kPlanningPower, double alpha = kPlanningAlpha);

// The smallest standardized difference (Cohen's d: difference / sd) that
// the two-sided t test at level alpha detects with `power` given the
// tests already made (docs/algorithms.md "Equivalence and the smallest
// detectable difference"), power counting both tails as statsmodels'
// TTestIndPower and TTestPower do:
//  * two groups of n_a and n_b tests, pooled-variance t: df = n_a + n_b - 2,
//    non-centrality d sqrt(n_a n_b / (n_a + n_b)) (TTestIndPower);
//  * paired, n pairs: df = n - 1, non-centrality d sqrt(n) (TTestPower).
// NaN where a group has fewer than 2 tests. Multiply by the pooled sd (the
// sd of the differences) for the difference in the metric's unit.
double DetectableEffectSize(double n_a, double n_b, double power = kPlanningPower,
                            double alpha = kPlanningAlpha);
double PairedDetectableEffectSize(double n, double power = kPlanningPower, double alpha = kPlanningAlpha);

// The power of those tests at standardized difference d (both tails).
double TwoSamplePower(double d, double n_a, double n_b, double alpha = kPlanningAlpha);
double PairedPower(double d, double n, double alpha = kPlanningAlpha);

// The pooled standard deviation of two groups: sqrt(((n_a - 1) s_a^2 +
// (n_b - 1) s_b^2) / (n_a + n_b - 2)); NaN where a group has n < 2.
double PooledStandardDeviation(const Description& a, const Description& b);

// What `napkin compare` shows: the whole number of repeats per group,
// ceil(RepeatsForPower) (at least 2); NaN where that is NaN.
double WholeRepeatsForPower(const PowerModel& model);

}  // namespace napkin::engine

#include "engine/statistics.h"

#include <algorithm>
#include <boost/math/distributions/non_central_t.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <boost/math/tools/roots.hpp>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace napkin::engine {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void CheckFinite(std::span<const double> values, const char* what) {
  for (std::size_t i = 0; i < values.size(); ++i)
    if (!std::isfinite(values[i]))
      throw std::invalid_argument(std::string(what) + " value " + std::to_string(i) + " is not finite");
}

// Neumaier's compensated sum (Neumaier 1974, "Rundungsfehleranalyse einiger
// Verfahren zur Summation endlicher Summen", ZAMM 54): the rounding error of
// each addition is carried along and added back at the end, so the result
// is the exact sum of the terms correctly rounded in all but pathological
// cases (docs/algorithms.md "Comparing groups of tests").
class CompensatedSum {
 public:
  void Add(double x) {
    const double t = sum_ + x;
    compensation_ += std::abs(sum_) >= std::abs(x) ? (sum_ - t) + x : (x - t) + sum_;
    sum_ = t;
  }
  double Value() const { return sum_ + compensation_; }

 private:
  double sum_ = 0.0;
  double compensation_ = 0.0;
};

// The mean: the compensated sum divided by n, then corrected by the
// compensated mean of the exact deviations from it (each x - mean split by
// Knuth's TwoSum into its rounded value and its rounding error), and kept
// within [min, max]. Identical values give that value exactly: their
// deviations from a first mean a few ulp off are exact, and so is the
// correction. n >= 1.
double MeanOf(std::span<const double> values) {
  const double n = static_cast<double>(values.size());
  CompensatedSum sum;
  for (const double x : values) sum.Add(x);
  double mean = sum.Value() / n;
  if (!std::isfinite(mean)) {  // the sum overflowed: sum x / n instead
    CompensatedSum scaled;
    for (const double x : values) scaled.Add(x / n);
    mean = scaled.Value();
  }
  CompensatedSum deviations;
  for (const double x : values) {
    // Knuth's TwoSum of x and -mean: d + error == x - mean exactly.
    const double d = x - mean;
    const double b_virtual = d - x;
    const double a_virtual = d - b_virtual;
    const double error = (x - a_virtual) + (-mean - b_virtual);
    deviations.Add(d);
    deviations.Add(error);
  }
  mean += deviations.Value() / n;
  const auto [low, high] = std::minmax_element(values.begin(), values.end());
  return std::clamp(mean, *low, *high);
}

// Sample standard deviation (divisor n - 1) about `mean`, two passes with
// the deviations scaled by the largest of them, so squares neither underflow
// (deviations of a few ulp of 1e-300) nor overflow. Exactly 0 when every
// value equals the mean. n >= 2.
double StandardDeviation(std::span<const double> values, double mean) {
  double largest = 0.0;
  for (const double value : values) largest = std::max(largest, std::abs(value - mean));
  if (largest == 0.0) return 0.0;
  CompensatedSum squares_sum;
  for (const double x : values) {
    const double scaled = (x - mean) / largest;
    squares_sum.Add(scaled * scaled);
  }
  const double squares = squares_sum.Value();
  return largest * std::sqrt(squares / static_cast<double>(values.size() - 1));
}

// Squared standard error of the mean: sd^2 / n. n >= 2.
double SquaredStandardError(std::span<const double> values, double mean) {
  const double sd = StandardDeviation(values, mean);
  return sd * sd / static_cast<double>(values.size());
}

double Percent(double diff, double baseline_mean) {
  return baseline_mean != 0.0 ? 100.0 * diff / baseline_mean : kNaN;
}

// Fills t, the interval and p from diff, se and df (docs/algorithms.md
// "Comparing groups of tests"); NaN when se is 0 (Welch's df is then 0/0 = NaN).
void FillInterval(MeanDifference& result) {
  if (!(result.se > 0.0) || !(result.df > 0.0)) {
    result.t = result.ci_low = result.ci_high = result.p_value = kNaN;
    return;
  }
  const boost::math::students_t distribution(result.df);
  const double alpha = 1.0 - kConfidenceLevel;
  const double t_critical = boost::math::quantile(boost::math::complement(distribution, alpha / 2.0));
  result.t = result.diff / result.se;
  result.ci_low = result.diff - t_critical * result.se;
  result.ci_high = result.diff + t_critical * result.se;
  result.p_value = 2.0 * boost::math::cdf(boost::math::complement(distribution, std::abs(result.t)));
}

MeanDifference Undefined() { return {kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN}; }

}  // namespace

Description Describe(std::span<const double> values) {
  CheckFinite(values, "Describe:");
  Description description;
  description.n = values.size();
  if (values.empty()) {
    description.mean = description.sd = description.median = description.min = description.max = kNaN;
    return description;
  }
  std::vector<double> sorted(values.begin(), values.end());
  std::sort(sorted.begin(), sorted.end());
  const std::size_t n = sorted.size();
  description.mean = MeanOf(values);
  description.sd = n >= 2 ? StandardDeviation(values, description.mean) : kNaN;
  // The middle of the two middle values, written so that it neither
  // overflows nor leaves [min, max].
  description.median = n % 2 == 1
                           ? sorted[n / 2]
                           : std::clamp(sorted[n / 2 - 1] + (sorted[n / 2] / 2.0 - sorted[n / 2 - 1] / 2.0),
                                        sorted[n / 2 - 1], sorted[n / 2]);
  description.min = sorted.front();
  description.max = sorted.back();
  return description;
}

MeanDifference WelchComparison(std::span<const double> sample, std::span<const double> baseline) {
  CheckFinite(sample, "WelchComparison: sample");
  CheckFinite(baseline, "WelchComparison: baseline");
  if (sample.size() < 2 || baseline.size() < 2) return Undefined();
  const double n_sample = static_cast<double>(sample.size());
  const double n_baseline = static_cast<double>(baseline.size());
  const double mean_sample = MeanOf(sample);
  const double mean_baseline = MeanOf(baseline);
  // Squared standard errors of the two means.
  const double v_sample = SquaredStandardError(sample, mean_sample);
  const double v_baseline = SquaredStandardError(baseline, mean_baseline);

  MeanDifference result;
  result.diff = mean_sample - mean_baseline;
  result.diff_pct = Percent(result.diff, mean_baseline);
  result.se = std::sqrt(v_sample + v_baseline);
  // Welch–Satterthwaite.
  result.df = (v_sample + v_baseline) * (v_sample + v_baseline) /
              (v_sample * v_sample / (n_sample - 1.0) + v_baseline * v_baseline / (n_baseline - 1.0));
  FillInterval(result);
  return result;
}

MeanDifference PairedComparison(std::span<const double> differences, double baseline_mean) {
  CheckFinite(differences, "PairedComparison: difference");
  if (differences.size() < 2) return Undefined();
  const double n = static_cast<double>(differences.size());
  MeanDifference result;
  result.diff = MeanOf(differences);
  result.diff_pct = Percent(result.diff, baseline_mean);
  result.se = StandardDeviation(differences, result.diff) / std::sqrt(n);
  result.df = n - 1.0;
  FillInterval(result);
  return result;
}

PowerModel WelchPowerModel(double diff, double sd_a, double sd_b) {
  const double a2 = sd_a * sd_a, b2 = sd_b * sd_b;
  const double variance = a2 + b2;
  const double fourth_powers = a2 * a2 + b2 * b2;
  return {diff, variance, fourth_powers > 0.0 ? variance * variance / fourth_powers : kNaN};
}

PowerModel PairedPowerModel(double diff, double sd_differences) {
  return {diff, sd_differences * sd_differences, 1.0};
}

double TTestPower(const PowerModel& model, double n, double alpha) {
  const double df = (n - 1.0) * model.df_per_repeat;
  const double noncentrality = std::abs(model.diff) / std::sqrt(model.variance / n);
  const double t_critical =
      boost::math::quantile(boost::math::complement(boost::math::students_t(df), alpha / 2.0));
  return boost::math::cdf(boost::math::complement(boost::math::non_central_t(df, noncentrality), t_critical));
}

double RepeatsForPower(const PowerModel& model, double power, double alpha) {
  if (!std::isfinite(model.diff) || !std::isfinite(model.variance) || !std::isfinite(model.df_per_repeat) ||
      model.diff == 0.0 || !(model.variance > 0.0))
    return kNaN;
  const auto shortfall = [&](double n) { return TTestPower(model, n, alpha) - power; };
  double low = 2.0;  // the fewest tests with a standard deviation
  if (shortfall(low) >= 0.0) return low;
  // Power grows with n (the non-centrality as sqrt(n), the critical t falls):
  // double the upper end until it is reached, then solve on the bracket.
  double high = 4.0;
  while (shortfall(high) < 0.0) {
    low = high;
    high *= 2.0;
    if (high > 1e12) return kNaN;  // a difference too small against its scatter to plan for
  }
  std::uintmax_t iterations = 200;
  const auto [left, right] = boost::math::tools::toms748_solve(
      shortfall, low, high, boost::math::tools::eps_tolerance<double>(48), iterations);
  return left + (right - left) / 2.0;
}

Equivalence TwoOneSidedTests(const MeanDifference& difference, double low, double high, double alpha) {
  Equivalence result;
  result.low = low;
  result.high = high;
  if (!(difference.se > 0.0) || !(difference.df > 0.0) || !std::isfinite(difference.diff) ||
      !std::isfinite(low) || !std::isfinite(high)) {
    result.ci_low = result.ci_high = result.p_low = result.p_high = result.p_value = kNaN;
    return result;
  }
  const boost::math::students_t distribution(difference.df);
  const double t_critical = boost::math::quantile(boost::math::complement(distribution, alpha));
  result.ci_low = difference.diff - t_critical * difference.se;
  result.ci_high = difference.diff + t_critical * difference.se;
  result.p_low =
      boost::math::cdf(boost::math::complement(distribution, (difference.diff - low) / difference.se));
  result.p_high = boost::math::cdf(distribution, (difference.diff - high) / difference.se);
  result.p_value = std::max(result.p_low, result.p_high);
  return result;
}

namespace {

// P(|T'| > t_{1 - alpha/2, df}) for T' non-central t (both tails), as
// statsmodels' ttest_power with alternative "two-sided".
double TwoSidedPower(double df, double noncentrality, double alpha) {
  const boost::math::students_t central(df);
  const double upper = boost::math::quantile(boost::math::complement(central, alpha / 2.0));
  const boost::math::non_central_t shifted(df, noncentrality);
  return boost::math::cdf(boost::math::complement(shifted, upper)) + boost::math::cdf(shifted, -upper);
}

// The d >= 0 at which power(d) reaches `power`: power grows with d from
// alpha at d = 0, so double the upper end until it is reached, then TOMS 748.
template <typename Power>
double SolveEffectSize(const Power& power_at, double power) {
  const auto shortfall = [&](double d) { return power_at(d) - power; };
  double low = 0.0, high = 1.0;
  while (shortfall(high) < 0.0) {
    low = high;
    high *= 2.0;
    if (high > 1e6) return kNaN;
  }
  std::uintmax_t iterations = 200;
  const auto [left, right] = boost::math::tools::toms748_solve(
      shortfall, low, high, boost::math::tools::eps_tolerance<double>(52), iterations);
  return left + (right - left) / 2.0;
}

}  // namespace

double TwoSamplePower(double d, double n_a, double n_b, double alpha) {
  return TwoSidedPower(n_a + n_b - 2.0, d * std::sqrt(n_a * n_b / (n_a + n_b)), alpha);
}

double PairedPower(double d, double n, double alpha) {
  return TwoSidedPower(n - 1.0, d * std::sqrt(n), alpha);
}

double DetectableEffectSize(double n_a, double n_b, double power, double alpha) {
  if (!(n_a >= 2.0) || !(n_b >= 2.0)) return kNaN;
  return SolveEffectSize([&](double d) { return TwoSamplePower(d, n_a, n_b, alpha); }, power);
}

double PairedDetectableEffectSize(double n, double power, double alpha) {
  if (!(n >= 2.0)) return kNaN;
  return SolveEffectSize([&](double d) { return PairedPower(d, n, alpha); }, power);
}

double PooledStandardDeviation(const Description& a, const Description& b) {
  if (a.n < 2 || b.n < 2) return kNaN;
  const double na = static_cast<double>(a.n), nb = static_cast<double>(b.n);
  return std::sqrt(((na - 1.0) * a.sd * a.sd + (nb - 1.0) * b.sd * b.sd) / (na + nb - 2.0));
}

double WholeRepeatsForPower(const PowerModel& model) {
  const double n = RepeatsForPower(model);
  return std::isnan(n) ? n : std::max(2.0, std::ceil(n));
}

}  // namespace napkin::engine

#include "engine/statistics.h"

#include <algorithm>
#include <boost/math/distributions/students_t.hpp>
#include <cmath>
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

double Mean(std::span<const double> values) {
  double sum = 0.0;
  for (const double value : values) sum += value;
  return sum / static_cast<double>(values.size());
}

// Sample variance (divisor n - 1), two passes; n >= 2.
double Variance(std::span<const double> values, double mean) {
  double sum = 0.0;
  for (const double value : values) sum += (value - mean) * (value - mean);
  return sum / static_cast<double>(values.size() - 1);
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
  description.mean = Mean(values);
  description.sd = n >= 2 ? std::sqrt(Variance(values, description.mean)) : kNaN;
  description.median = n % 2 == 1 ? sorted[n / 2] : (sorted[n / 2 - 1] + sorted[n / 2]) / 2.0;
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
  const double mean_sample = Mean(sample);
  const double mean_baseline = Mean(baseline);
  // Squared standard errors of the two means.
  const double v_sample = Variance(sample, mean_sample) / n_sample;
  const double v_baseline = Variance(baseline, mean_baseline) / n_baseline;

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
  result.diff = Mean(differences);
  result.diff_pct = Percent(result.diff, baseline_mean);
  result.se = std::sqrt(Variance(differences, result.diff) / n);
  result.df = n - 1.0;
  FillInterval(result);
  return result;
}

}  // namespace napkin::engine

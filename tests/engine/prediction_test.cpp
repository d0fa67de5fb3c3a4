// engine/prediction.h against closed forms: Student's t with 2 and 4
// degrees of freedom has an elementary cdf and (2 df) quantile, so the
// chance that a further test exceeds a limit, its quantiles and its expected
// points on a sliding scale have known answers for 3 and 5 tests
// (docs/algorithms.md "A further test").
#include "engine/prediction.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace napkin::engine {
namespace {

// Student's t cdf with 2 and 4 degrees of freedom (Abramowitz & Stegun 26.7.3 for even df).
double Cdf2(double t) { return 0.5 + t / (2.0 * std::sqrt(2.0 + t * t)); }
double Cdf4(double t) {
  const double q = 1.0 + t * t / 4.0;
  return 0.5 + 0.375 * (t / std::sqrt(q)) * (1.0 - t * t / (12.0 * q));
}
// Its quantile with 2 degrees of freedom.
double Quantile2(double p) { return (2.0 * p - 1.0) / std::sqrt(2.0 * p * (1.0 - p)); }

// Three tests whose logs are 0, 1, 2: m = 1, s = 1, the scale sqrt(4/3).
const std::vector<double> kThree = {1.0, std::exp(1.0), std::exp(2.0)};
const double kScaleThree = std::sqrt(4.0 / 3.0);

LogPredictive Fit(const std::vector<double>& values) {
  const PredictiveFit fit = FitLogPredictive(values);
  EXPECT_EQ(fit.gap, PredictionGap::kNone);
  return fit.predictive.value_or(LogPredictive{});
}

TEST(FurtherTest, ExceedProbabilityIsTheUpperTailOfStudentsT) {
  const LogPredictive three = Fit(kThree);
  EXPECT_EQ(three.n, 3u);
  EXPECT_NEAR(three.mean_log, 1.0, 1e-15);
  EXPECT_NEAR(three.sd_log, 1.0, 1e-15);
  EXPECT_NEAR(three.scale, kScaleThree, 1e-15);
  // At the geometric mean: one half.
  EXPECT_NEAR(ExceedProbability(three, std::exp(1.0)), 0.5, 1e-15);
  for (const double log_limit : {-3.0, 0.5, 2.0, 3.0, 6.0}) {
    const double t = (log_limit - 1.0) / kScaleThree;
    EXPECT_NEAR(ExceedProbability(three, std::exp(log_limit)), 1.0 - Cdf2(t), 1e-14) << log_limit;
  }
  // Five tests: 4 degrees of freedom.
  const std::vector<double> five = {610.0, 655.0, 580.0, 702.0, 634.0};
  const LogPredictive fitted = Fit(five);
  double mean = 0.0, squares = 0.0;
  for (const double value : five) mean += std::log(value) / 5.0;
  for (const double value : five) squares += (std::log(value) - mean) * (std::log(value) - mean);
  const double scale = std::sqrt(squares / 4.0) * std::sqrt(1.0 + 1.0 / 5.0);
  for (const double limit : {500.0, 640.0, 700.0, 800.0}) {
    const double t = (std::log(limit) - mean) / scale;
    EXPECT_NEAR(ExceedProbability(fitted, limit), 1.0 - Cdf4(t), 1e-13) << limit;
  }
  // A tail far out keeps its digits (no 1 - cdf cancellation): three tests a thousandth apart on
  // the log scale, a limit 5e5 of their scales above; the 2-df tail in the form without
  // cancellation, 1 / (q (q + t)) with q = sqrt(2 + t^2), is about 2e-12.
  const LogPredictive tight = Fit({1.0, std::exp(0.001), std::exp(0.002)});
  const double t = 5e5;
  const double q = std::sqrt(2.0 + t * t);
  const double tail = ExceedProbability(tight, std::exp(tight.mean_log + t * tight.scale));
  EXPECT_NEAR(tail * q * (q + t), 1.0, 1e-8);
}

TEST(FurtherTest, QuantilesAreThoseOfTheScaledT) {
  const LogPredictive three = Fit(kThree);
  for (const double p : {0.1, 0.5, 0.9, 0.999})
    EXPECT_NEAR(PredictiveQuantile(three, p), std::exp(1.0 + kScaleThree * Quantile2(p)),
                1e-12 * std::exp(1.0 + kScaleThree * Quantile2(p)))
        << p;
  EXPECT_THROW(PredictiveQuantile(three, 0.0), std::invalid_argument);
  EXPECT_THROW(PredictiveQuantile(three, 1.0), std::invalid_argument);
}

// The expected points of a further test by another route: over the probability u of the value's
// quantile, full points below the higher limit's u, none above the lower's, and between them the
// points of the closed-form quantile, by composite Simpson on a grid fine enough for 1e-13.
double ExpectedPointsByQuantiles(double full_at, double zero_at, double points) {
  const double u_full = Cdf2((std::log(full_at) - 1.0) / kScaleThree);
  const double u_zero = Cdf2((std::log(zero_at) - 1.0) / kScaleThree);
  const auto between = [&](double u) {
    const double x = std::exp(1.0 + kScaleThree * Quantile2(u));
    return points * (zero_at - x) / (zero_at - full_at);
  };
  const int intervals = 200000;
  const double h = (u_zero - u_full) / intervals;
  double sum = between(u_full) + between(u_zero);
  for (int i = 1; i < intervals; ++i) sum += (i % 2 == 1 ? 4.0 : 2.0) * between(u_full + i * h);
  return points * u_full + sum * h / 3.0;
}

TEST(FurtherTest, ExpectedPointsOnASlidingScale) {
  const LogPredictive three = Fit(kThree);
  // Limits about the sample (logs 0..2): e^0.8 to e^1.6, and one scale far below and one far above.
  for (const auto& [full_at, zero_at] :
       {std::pair{std::exp(0.8), std::exp(1.6)}, std::pair{std::exp(1.0), std::exp(1.01)},
        std::pair{std::exp(-1.0), std::exp(3.0)}}) {
    const double expected = ExpectedPointsByQuantiles(full_at, zero_at, 4.0);
    EXPECT_NEAR(ExpectedScalePoints(three, full_at, zero_at, 4.0), expected, 1e-10)
        << full_at << " to " << zero_at;
  }
  // A scale far beyond the tests scores (almost) nothing, one far below them (almost) all.
  EXPECT_LT(ExpectedScalePoints(three, std::exp(30.0), std::exp(31.0), 4.0), 4.0);
  EXPECT_GT(ExpectedScalePoints(three, std::exp(30.0), std::exp(31.0), 4.0), 3.99);
  EXPECT_LT(ExpectedScalePoints(three, std::exp(-31.0), std::exp(-30.0), 4.0), 0.01);
  EXPECT_THROW(ExpectedScalePoints(three, 700.0, 500.0, 4.0), std::invalid_argument);
}

TEST(FurtherTest, NoPredictionFromFewTestsAValueAtOrBelowZeroOrNoSpread) {
  EXPECT_EQ(FitLogPredictive(std::vector<double>{}).gap, PredictionGap::kTooFew);
  EXPECT_EQ(FitLogPredictive(std::vector<double>{600.0, 650.0}).gap, PredictionGap::kTooFew);
  EXPECT_EQ(FitLogPredictive(std::vector<double>{600.0, 0.0, 650.0}).gap, PredictionGap::kNotPositive);
  EXPECT_EQ(FitLogPredictive(std::vector<double>{600.0, 600.0, 600.0}).gap, PredictionGap::kNoSpread);
  EXPECT_FALSE(FitLogPredictive(std::vector<double>{600.0, 600.0, 600.0}).predictive);
  EXPECT_EQ(PredictionGapText(PredictionGap::kTooFew), "fewer than 3 tests");
  EXPECT_EQ(PredictionGapText(PredictionGap::kNoSpread), "no spread");
  EXPECT_THROW(FitLogPredictive(std::vector<double>{600.0, std::numeric_limits<double>::quiet_NaN(), 1.0}),
               std::invalid_argument);
  EXPECT_THROW(ExceedProbability(Fit(kThree), 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace napkin::engine

#pragma once
// The chance that a further test of a variant exceeds a limit, and the points
// it would score on a sliding scale (docs/algorithms.md "A further test"):
// the variant's tests on the log scale, the lognormal model `napkin compare`
// compares them on (engine/statistics.h), and the predictive distribution of
// one more test's log,
//   ln X_new = m + s sqrt(1 + 1/n) T,   T ~ Student's t with n - 1 df,
// m and s the mean and sample sd of the n logs (the frequentist prediction
// interval of a normal sample, and the Bayesian posterior predictive under
// the reference prior). The t distribution is Boost.Math's students_t, the
// expected points Boost.Math's Gauss-Kronrod quadrature.
#include <cstddef>
#include <optional>
#include <span>
#include <string_view>

namespace napkin::engine {

// Fewer tests than this give no prediction: with n = 2 the predictive t has
// 1 degree of freedom (a Cauchy: no mean) and one test's luck decides it.
inline constexpr std::size_t kMinPredictionTests = 3;

// Why a sample gives no prediction.
enum class PredictionGap {
  kNone,
  kTooFew,       // fewer than kMinPredictionTests values
  kNotPositive,  // a value <= 0: no log
  kNoSpread,     // every value the same: s = 0, the model says nothing about spread
};

// "fewer than 3 tests", "a value ≤ 0", "no spread", "" for kNone.
std::string_view PredictionGapText(PredictionGap gap);

// The predictive distribution of a further test's value.
struct LogPredictive {
  std::size_t n = 0;
  double mean_log = 0.0;  // m
  double sd_log = 0.0;    // s (sample sd, n - 1)
  double scale = 0.0;     // s sqrt(1 + 1/n)
};

struct PredictiveFit {
  std::optional<LogPredictive> predictive;  // none where `gap` is not kNone
  PredictionGap gap = PredictionGap::kNone;
};

// The predictive distribution from a variant's values (finite; NaN or
// infinity throws std::invalid_argument, as engine::Describe).
PredictiveFit FitLogPredictive(std::span<const double> values);

// P(X_new > limit) = 1 - T_{n-1}((ln limit - m) / (s sqrt(1 + 1/n))), the
// upper tail computed directly (no 1 - cdf cancellation). limit > 0.
double ExceedProbability(const LogPredictive& predictive, double limit);

// The p-quantile of X_new, exp(m + s sqrt(1 + 1/n) t_{p, n-1}); 0 < p < 1.
double PredictiveQuantile(const LogPredictive& predictive, double p);

// The expected points of X_new on a sliding scale: `full_points` at or
// below `full_at`, 0 at or above `zero_at`, linear between (full_at <
// zero_at, both > 0): full_points [P(X <= full_at) + E((zero_at - X) /
// (zero_at - full_at); full_at < X < zero_at)], the second term integrated
// over ln X by adaptive Gauss-Kronrod (61 points) to a relative 1e-12.
double ExpectedScalePoints(const LogPredictive& predictive, double full_at, double zero_at,
                           double full_points);

}  // namespace napkin::engine

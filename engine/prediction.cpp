#include "engine/prediction.h"

#include <boost/math/distributions/students_t.hpp>
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "engine/statistics.h"

namespace napkin::engine {

std::string_view PredictionGapText(PredictionGap gap) {
  switch (gap) {
    case PredictionGap::kNone:
      return "";
    case PredictionGap::kTooFew:
      return "fewer than 3 tests";
    case PredictionGap::kNotPositive:
      return "a value ≤ 0";
    case PredictionGap::kNoSpread:
      return "no spread";
  }
  return "";
}

PredictiveFit FitLogPredictive(std::span<const double> values) {
  PredictiveFit fit;
  for (const double value : values)
    if (!std::isfinite(value)) throw std::invalid_argument("FitLogPredictive: a value is not finite");
  if (values.size() < kMinPredictionTests) {
    fit.gap = PredictionGap::kTooFew;
    return fit;
  }
  std::vector<double> logs;
  logs.reserve(values.size());
  for (const double value : values) {
    if (!(value > 0.0)) {
      fit.gap = PredictionGap::kNotPositive;
      return fit;
    }
    logs.push_back(std::log(value));
  }
  // The compensated mean and sd of `napkin compare` (engine/statistics.h).
  const Description logs_described = Describe(logs);
  if (!(logs_described.sd > 0.0)) {
    fit.gap = PredictionGap::kNoSpread;
    return fit;
  }
  LogPredictive predictive;
  predictive.n = values.size();
  predictive.mean_log = logs_described.mean;
  predictive.sd_log = logs_described.sd;
  predictive.scale = logs_described.sd * std::sqrt(1.0 + 1.0 / static_cast<double>(values.size()));
  fit.predictive = predictive;
  return fit;
}

namespace {

boost::math::students_t PredictiveT(const LogPredictive& predictive) {
  return boost::math::students_t(static_cast<double>(predictive.n - 1));
}

// The standardised t of a value: (ln x - m) / (s sqrt(1 + 1/n)).
double Standardised(const LogPredictive& predictive, double x) {
  return (std::log(x) - predictive.mean_log) / predictive.scale;
}

}  // namespace

double ExceedProbability(const LogPredictive& predictive, double limit) {
  if (!(limit > 0.0)) throw std::invalid_argument("ExceedProbability: the limit must be > 0");
  return boost::math::cdf(boost::math::complement(PredictiveT(predictive), Standardised(predictive, limit)));
}

double PredictiveQuantile(const LogPredictive& predictive, double p) {
  if (!(p > 0.0 && p < 1.0)) throw std::invalid_argument("PredictiveQuantile: p must be in (0, 1)");
  return std::exp(predictive.mean_log + predictive.scale * boost::math::quantile(PredictiveT(predictive), p));
}

double ExpectedScalePoints(const LogPredictive& predictive, double full_at, double zero_at,
                           double full_points) {
  if (!(full_at > 0.0 && zero_at > full_at))
    throw std::invalid_argument("ExpectedScalePoints: needs 0 < full_at < zero_at");
  const boost::math::students_t t = PredictiveT(predictive);
  const double t_full = Standardised(predictive, full_at);
  const double t_zero = Standardised(predictive, zero_at);
  // Between the limits, over the standardised t: the points of the value
  // there, times the t density.
  const auto between = [&](double u) {
    const double x = std::exp(predictive.mean_log + predictive.scale * u);
    return (zero_at - x) / (zero_at - full_at) * boost::math::pdf(t, u);
  };
  double error = 0.0;
  const double partial = boost::math::quadrature::gauss_kronrod<double, 61>::integrate(
      between, t_full, t_zero, 15, 1e-12, &error);
  return full_points * (boost::math::cdf(t, t_full) + partial);
}

}  // namespace napkin::engine

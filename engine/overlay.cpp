#include "engine/overlay.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace napkin::engine {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}  // namespace

std::optional<double> OnsetTime(const Eigen::Ref<const Eigen::VectorXd>& time_s,
                                const Eigen::Ref<const Eigen::VectorXd>& values, double threshold) {
  const Eigen::Index n = std::min(time_s.size(), values.size());
  for (Eigen::Index i = 0; i < n; ++i)
    if (values(i) > threshold) return time_s(i);
  return std::nullopt;
}

Eigen::VectorXd CommonTimeBase(std::span<const TimeSeries> series, Eigen::Index max_points) {
  double first = std::numeric_limits<double>::infinity();
  double last = -first;
  double step = first;
  for (const TimeSeries& one : series) {
    const Eigen::Index n = one.time_s.size();
    if (n < 2) continue;
    first = std::min(first, one.time_s(0));
    last = std::max(last, one.time_s(n - 1));
    step = std::min(step, (one.time_s(n - 1) - one.time_s(0)) / static_cast<double>(n - 1));
  }
  if (!std::isfinite(step) || !(step > 0.0) || max_points < 2) return {};
  // The points of the finest grid that fit, to a rounding error of a step.
  const double intervals = std::floor((last - first) / step + 1e-6);
  if (intervals + 1.0 > static_cast<double>(max_points)) {
    return Eigen::VectorXd::LinSpaced(max_points, first, last);
  }
  const auto points = static_cast<Eigen::Index>(intervals) + 1;
  Eigen::VectorXd base(points);
  for (Eigen::Index k = 0; k < points; ++k) base(k) = first + static_cast<double>(k) * step;
  return base;
}

Eigen::VectorXd ResampleOnto(const TimeSeries& series, const Eigen::Ref<const Eigen::VectorXd>& base) {
  Eigen::VectorXd out = Eigen::VectorXd::Constant(base.size(), kNaN);
  const Eigen::Index n = std::min(series.time_s.size(), series.values.size());
  if (n == 0) return out;
  const double interval =
      n > 1 ? (series.time_s(n - 1) - series.time_s(0)) / static_cast<double>(n - 1) : 0.0;
  const double tolerance = 1e-9 * interval;
  Eigen::Index i = 0;  // series.time_s(i) <= t < series.time_s(i + 1)
  for (Eigen::Index k = 0; k < base.size(); ++k) {
    const double t = base(k);
    if (t < series.time_s(0) - tolerance || t > series.time_s(n - 1) + tolerance) continue;
    while (i + 1 < n && series.time_s(i + 1) <= t + tolerance) ++i;
    if (std::abs(t - series.time_s(i)) <= tolerance || i + 1 == n) {
      out(k) = series.values(i);
      continue;
    }
    const double t0 = series.time_s(i);
    const double t1 = series.time_s(i + 1);
    const double w = (t - t0) / (t1 - t0);
    out(k) = (1.0 - w) * series.values(i) + w * series.values(i + 1);
  }
  return out;
}

Corridor MeanSdCorridor(const Eigen::Ref<const Eigen::MatrixXd>& columns) {
  Corridor corridor{Eigen::VectorXd::Constant(columns.rows(), kNaN),
                    Eigen::VectorXd::Constant(columns.rows(), kNaN)};
  for (Eigen::Index row = 0; row < columns.rows(); ++row) {
    double sum = 0.0;
    int count = 0;
    for (Eigen::Index c = 0; c < columns.cols(); ++c)
      if (std::isfinite(columns(row, c))) {
        sum += columns(row, c);
        ++count;
      }
    if (count < 2) continue;
    const double mean = sum / count;
    double squares = 0.0;
    for (Eigen::Index c = 0; c < columns.cols(); ++c)
      if (std::isfinite(columns(row, c))) squares += (columns(row, c) - mean) * (columns(row, c) - mean);
    const double sd = std::sqrt(squares / (count - 1));
    corridor.low(row) = mean - sd;
    corridor.high(row) = mean + sd;
  }
  return corridor;
}

}  // namespace napkin::engine

#pragma once
// Laying the time histories of many tests over each other (the report's
// overlaid curves, docs/formats.md "HTML report"): aligning each test's time
// axis, resampling every test onto one common time base, and each group's
// mean ± 1 sd corridor on it.
#include <Eigen/Core>
#include <optional>
#include <span>

namespace napkin::engine {

// The time of the first sample whose value exceeds `threshold` (strictly),
// e.g. the impact onset of a resultant acceleration; none when no sample
// does (NaN samples never do).
std::optional<double> OnsetTime(const Eigen::Ref<const Eigen::VectorXd>& time_s,
                                const Eigen::Ref<const Eigen::VectorXd>& values, double threshold);

// A test's samples on its (aligned) time axis, ascending.
struct TimeSeries {
  Eigen::VectorXd time_s;
  Eigen::VectorXd values;
};

// The common time base of `series`: from the earliest first sample to the
// latest last sample, in steps of the finest sample interval among them
// ((last - first) / (n - 1) of each), so series sampled on one grid keep
// every sample; coarsened to at most `max_points` points when the span and
// the finest step would need more. Empty when no series has 2 samples.
Eigen::VectorXd CommonTimeBase(std::span<const TimeSeries> series, Eigen::Index max_points);

// `series` on `base` by linear interpolation between its neighbouring
// samples (a base point on a sample, to 1e-9 of the finest interval, takes
// the sample's value); NaN outside the series' first to last sample.
Eigen::VectorXd ResampleOnto(const TimeSeries& series, const Eigen::Ref<const Eigen::VectorXd>& base);

// Per row of `columns` (one column per test of a group, NaN where a test has
// no sample): mean - sd and mean + sd over the finite values, sd the sample
// standard deviation (divisor n - 1); NaN where fewer than 2 are finite.
struct Corridor {
  Eigen::VectorXd low;
  Eigen::VectorXd high;
};
Corridor MeanSdCorridor(const Eigen::Ref<const Eigen::MatrixXd>& columns);

}  // namespace napkin::engine

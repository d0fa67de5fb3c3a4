#pragma once
// Reducing time histories for display without losing their peaks (the
// report's plots, docs/formats.md "HTML report"): the samples are cut into
// buckets of consecutive samples and, in every bucket, the sample of each
// trace's minimum and of its maximum is kept. A plot of the kept samples
// reaches exactly the extremes of every bucket, so no peak is shaved; the
// full-resolution data stays in the catalogue.
#include <Eigen/Core>
#include <vector>

namespace napkin::engine {

// The sample indices to keep, ascending and without duplicates, for plotting
// the columns of `traces` (one column per trace, one row per sample) against
// a shared time axis with at most `max_points` points. Every sample is kept
// when there are at most `max_points`. Otherwise the first and the last
// sample are kept, and the rows are cut into
//   B = (max_points - 2) / (2 * traces.cols())
// buckets of consecutive rows (bucket b holds rows [b n / B, (b + 1) n / B))
// in each of which, for every trace, the first row of its minimum and the
// first row of its maximum are kept; so every trace's global minimum and
// maximum are kept exactly. Throws std::invalid_argument when max_points is
// smaller than 2 * traces.cols() + 2 (not even one bucket would fit).
std::vector<Eigen::Index> PeakPreservingSamples(const Eigen::Ref<const Eigen::MatrixXd>& traces,
                                                Eigen::Index max_points);

}  // namespace napkin::engine

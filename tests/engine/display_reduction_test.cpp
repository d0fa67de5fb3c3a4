#include "engine/display_reduction.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace napkin::engine {
namespace {

// Three noisy traces of 20,001 samples with one-sample spikes (an impact
// peak that a plain decimation would miss) at odd places.
Eigen::MatrixXd NoisyTracesWithSpikes() {
  const Eigen::Index n = 20001;
  Eigen::MatrixXd traces(n, 3);
  std::mt19937_64 random(20240611);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (Eigen::Index row = 0; row < n; ++row) {
    const double t = static_cast<double>(row) / static_cast<double>(n);
    traces(row, 0) = 50.0 * std::sin(40.0 * t) + noise(random);
    traces(row, 1) = -20.0 * std::exp(-t) + noise(random);
    traces(row, 2) = noise(random);
  }
  traces(7919, 0) = 400.0;    // global maximum of trace 0
  traces(12345, 1) = -300.0;  // global minimum of trace 1
  traces(n - 2, 2) = 99.0;    // global maximum of trace 2, next to the end
  return traces;
}

TEST(PeakPreservingSamples, EveryBucketsExtremesSurviveAndTheGlobalOnesExactly) {
  const Eigen::MatrixXd traces = NoisyTracesWithSpikes();
  const Eigen::Index n = traces.rows();
  const Eigen::Index max_points = 2000;
  const std::vector<Eigen::Index> kept = PeakPreservingSamples(traces, max_points);

  ASSERT_LE(static_cast<Eigen::Index>(kept.size()), max_points);
  ASSERT_GT(kept.size(), 1000u);  // the budget is used, not wasted
  EXPECT_TRUE(std::is_sorted(kept.begin(), kept.end()));
  EXPECT_EQ(std::adjacent_find(kept.begin(), kept.end()), kept.end());  // no duplicates
  EXPECT_EQ(kept.front(), 0);
  EXPECT_EQ(kept.back(), n - 1);

  // Independently: each bucket's minimum and maximum of each trace (by
  // std::minmax_element over the bucket) is among the kept samples of that bucket.
  const Eigen::Index bucket_count = (max_points - 2) / (2 * traces.cols());
  for (Eigen::Index bucket = 0; bucket < bucket_count; ++bucket) {
    const Eigen::Index begin = bucket * n / bucket_count;
    const Eigen::Index end = (bucket + 1) * n / bucket_count;
    for (Eigen::Index trace = 0; trace < traces.cols(); ++trace) {
      const double* column = traces.col(trace).data();
      const auto [lowest, highest] = std::minmax_element(column + begin, column + end);
      double kept_min = INFINITY;
      double kept_max = -INFINITY;
      for (const Eigen::Index row : kept) {
        if (row < begin || row >= end) continue;
        kept_min = std::min(kept_min, traces(row, trace));
        kept_max = std::max(kept_max, traces(row, trace));
      }
      EXPECT_EQ(kept_min, *lowest) << "bucket " << bucket << " trace " << trace;
      EXPECT_EQ(kept_max, *highest) << "bucket " << bucket << " trace " << trace;
    }
  }

  // The global extremes of every trace, exactly, and the planted spikes by index.
  for (Eigen::Index trace = 0; trace < traces.cols(); ++trace) {
    double kept_min = INFINITY;
    double kept_max = -INFINITY;
    for (const Eigen::Index row : kept) {
      kept_min = std::min(kept_min, traces(row, trace));
      kept_max = std::max(kept_max, traces(row, trace));
    }
    EXPECT_EQ(kept_min, traces.col(trace).minCoeff()) << "trace " << trace;
    EXPECT_EQ(kept_max, traces.col(trace).maxCoeff()) << "trace " << trace;
  }
  for (const Eigen::Index spike : {Eigen::Index{7919}, Eigen::Index{12345}, n - 2})
    EXPECT_TRUE(std::binary_search(kept.begin(), kept.end(), spike)) << spike;
}

TEST(PeakPreservingSamples, ShortRecordsAreKeptWhole) {
  Eigen::MatrixXd traces(6, 2);
  traces << 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12;
  EXPECT_EQ(PeakPreservingSamples(traces, 6), (std::vector<Eigen::Index>{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(PeakPreservingSamples(traces.topRows(5), 6), (std::vector<Eigen::Index>{0, 1, 2, 3, 4}));
}

TEST(PeakPreservingSamples, OneBucketKeepsTheEndsAndTheExtremes) {
  // max_points 4, one trace: one bucket; kept are the ends and rows 2 (max) and 4 (min).
  Eigen::MatrixXd traces(7, 1);
  traces << 0.5, 1, 3, 2, -4, -1, 0;
  EXPECT_EQ(PeakPreservingSamples(traces, 4), (std::vector<Eigen::Index>{0, 2, 4, 6}));
}

TEST(PeakPreservingSamples, RefusesABudgetSmallerThanOneBucket) {
  const Eigen::MatrixXd traces = Eigen::MatrixXd::Zero(100, 3);
  EXPECT_THROW(PeakPreservingSamples(traces, 7), std::invalid_argument);
  EXPECT_NO_THROW(PeakPreservingSamples(traces, 8));
}

}  // namespace
}  // namespace napkin::engine

// The overlaid curves' numerics (engine/overlay.h): onset, common time base,
// resampling and the mean ± 1 sd corridor, against values worked by hand.
#include "engine/overlay.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace napkin::engine {
namespace {

constexpr double kQuietNaN = std::numeric_limits<double>::quiet_NaN();

Eigen::VectorXd Vector(std::initializer_list<double> values) {
  Eigen::VectorXd v(static_cast<Eigen::Index>(values.size()));
  Eigen::Index i = 0;
  for (const double value : values) v(i++) = value;
  return v;
}

TEST(Overlay, OnsetIsTheFirstSampleAboveTheThreshold) {
  const Eigen::VectorXd t = Vector({0.0, 0.001, 0.002, 0.003, 0.004});
  EXPECT_EQ(OnsetTime(t, Vector({1, 5, 6, 9, 2}), 5.0), 0.002);  // 5 is not above 5
  EXPECT_EQ(OnsetTime(t, Vector({kQuietNaN, 1, 2, 3, 4}), 5.0), std::nullopt);
}

TEST(Overlay, CommonBaseSpansEveryTestAtTheFinestStep) {
  const std::vector<TimeSeries> series = {{Vector({-0.002, 0.0, 0.002, 0.004}), {}},  // 2 ms steps
                                          {Vector({0.0, 0.001, 0.002, 0.003, 0.004, 0.005}), {}}};
  const Eigen::VectorXd base = CommonTimeBase(series, 100);
  ASSERT_EQ(base.size(), 8);  // -2 ms .. 5 ms in 1 ms steps
  for (Eigen::Index k = 0; k < base.size(); ++k) EXPECT_NEAR(base(k), -0.002 + 0.001 * k, 1e-15);
  // Coarsened to at most 4 points over the same span.
  const Eigen::VectorXd coarse = CommonTimeBase(series, 4);
  ASSERT_EQ(coarse.size(), 4);
  EXPECT_DOUBLE_EQ(coarse(0), -0.002);
  EXPECT_DOUBLE_EQ(coarse(3), 0.005);
  EXPECT_EQ(CommonTimeBase(std::vector<TimeSeries>{{Vector({0.0}), {}}}, 10).size(), 0);
}

TEST(Overlay, ResamplingInterpolatesInsideAndLeavesGapsOutside) {
  const TimeSeries series{Vector({0.0, 0.002, 0.004}), Vector({0.0, 10.0, 4.0})};
  const Eigen::VectorXd out = ResampleOnto(series, Vector({-0.001, 0.0, 0.001, 0.002, 0.003, 0.004, 0.005}));
  EXPECT_TRUE(std::isnan(out(0)));
  EXPECT_EQ(out(1), 0.0);
  EXPECT_DOUBLE_EQ(out(2), 5.0);
  EXPECT_EQ(out(3), 10.0);  // on a sample: the sample itself (the peak kept)
  EXPECT_DOUBLE_EQ(out(4), 7.0);
  EXPECT_EQ(out(5), 4.0);
  EXPECT_TRUE(std::isnan(out(6)));
}

TEST(Overlay, CorridorIsMeanPlusMinusSampleSd) {
  Eigen::MatrixXd columns(3, 3);
  columns << 1.0, 2.0, 3.0,       // mean 2, sd 1
      4.0, kQuietNaN, 8.0,        // mean 6, sd sqrt(8)
      5.0, kQuietNaN, kQuietNaN;  // one value: no corridor
  const Corridor corridor = MeanSdCorridor(columns);
  EXPECT_DOUBLE_EQ(corridor.low(0), 1.0);
  EXPECT_DOUBLE_EQ(corridor.high(0), 3.0);
  EXPECT_DOUBLE_EQ(corridor.low(1), 6.0 - std::sqrt(8.0));
  EXPECT_DOUBLE_EQ(corridor.high(1), 6.0 + std::sqrt(8.0));
  EXPECT_TRUE(std::isnan(corridor.low(2)));
  EXPECT_TRUE(std::isnan(corridor.high(2)));
}

}  // namespace
}  // namespace napkin::engine

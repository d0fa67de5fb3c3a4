// ISO/TS 18571 (engine/iso18571.h): analytic cases with known scores, the
// pruned band warping against the full cost matrix, resampling, errors. The
// agreement with an independent implementation is iso18571_reference_test.cpp.
#include "engine/iso18571.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "common/error.h"

namespace napkin::engine {
namespace {

constexpr double kDt = 1e-4;  // 10 kHz, the standard's rate
constexpr long kN = 1000;     // 0.1 s; max_shift N = 200 samples exactly

// A haversine pulse of `width` samples starting at sample `start` (0 elsewhere).
std::vector<double> IsoPulse(long n, long start, long width, double peak = 50.0) {
  std::vector<double> values(static_cast<std::size_t>(n), 0.0);
  for (long k = start; k < std::min(n, start + width + 1); ++k) {
    if (k < 0) continue;
    const double phase = 2.0 * std::numbers::pi * static_cast<double>(k - start) / static_cast<double>(width);
    values[static_cast<std::size_t>(k)] = 0.5 * peak * (1.0 - std::cos(phase));
  }
  return values;
}

std::vector<double> IsoTransformed(const std::vector<double>& values, double scale, double offset) {
  std::vector<double> out(values.size());
  for (std::size_t k = 0; k < values.size(); ++k) out[k] = scale * values[k] + offset;
  return out;
}

Iso18571Rating IsoRate(const std::vector<double>& reference, const std::vector<double>& candidate,
                       const Iso18571Parameters& parameters = {}) {
  return Iso18571Rate(reference, candidate, kDt, parameters);
}

TEST(Iso18571, IdenticalCurvesScoreOneAndExcellent) {
  const std::vector<double> t = IsoPulse(kN, 200, 300);
  for (Iso18571Edition edition : {Iso18571Edition::k2014, Iso18571Edition::k2024}) {
    const Iso18571Rating r = IsoRate(t, t, Iso18571Parameters::ForEdition(edition));
    EXPECT_EQ(r.corridor, 1.0);
    EXPECT_EQ(r.phase, 1.0);
    EXPECT_EQ(r.magnitude, 1.0);
    EXPECT_EQ(r.slope, 1.0);
    EXPECT_EQ(r.overall, 1.0);
    EXPECT_EQ(r.grade, Iso18571Grade::kExcellent);
    EXPECT_EQ(r.shift_samples, 0);
    EXPECT_EQ(r.correlation, 1.0);
    EXPECT_EQ(r.samples, kN);
    EXPECT_DOUBLE_EQ(r.inner_half_width, 0.05 * 50.0);
    EXPECT_DOUBLE_EQ(r.outer_half_width, 0.5 * 50.0);
  }
}

// The candidate is the reference 50 samples later: the best shift is exactly
// 50 (the pulse lies inside the overlap), the shifted curves coincide, and
// E_P = (0.2 N - 50) / (0.2 N) = 0.75.
TEST(Iso18571, TimeShiftWithinTheAllowedRange) {
  const std::vector<double> t = IsoPulse(kN, 200, 300);
  const std::vector<double> c = IsoPulse(kN, 250, 300);
  const Iso18571Rating r = IsoRate(t, c);
  EXPECT_EQ(r.shift_samples, 50);
  EXPECT_DOUBLE_EQ(r.shift_s, 50 * kDt);
  EXPECT_DOUBLE_EQ(r.phase, 0.75);
  EXPECT_EQ(r.magnitude, 1.0);
  EXPECT_EQ(r.slope, 1.0);
  // The mirror: the candidate leads.
  const Iso18571Rating mirror = IsoRate(c, t);
  EXPECT_EQ(mirror.shift_samples, -50);
  EXPECT_DOUBLE_EQ(mirror.phase, 0.75);
}

// 250 samples later, beyond 0.2 N = 200: the search stops at the largest
// shift allowed, which scores 0.
TEST(Iso18571, TimeShiftBeyondTheAllowedRangeScoresPhaseZero) {
  const std::vector<double> t = IsoPulse(kN, 150, 100);
  const std::vector<double> c = IsoPulse(kN, 400, 100);
  const Iso18571Rating r = IsoRate(t, c);
  EXPECT_EQ(r.shift_samples, 200);
  EXPECT_EQ(r.phase, 0.0);
  EXPECT_LT(r.corridor, 1.0);
}

TEST(Iso18571, CorridorBounds) {
  const std::vector<double> t = IsoPulse(kN, 200, 300);  // T_norm = 50
  const double inner = 0.05 * 50.0, outer = 0.5 * 50.0;
  // Scaled by 1 + a0 / 2: every deviation a0 |T| / 2 is inside the inner corridor.
  EXPECT_EQ(IsoRate(t, IsoTransformed(t, 1.0 + 0.025, 0.0)).corridor, 1.0);
  // Scaled by 1 + 2 a0: only the samples where |T| > T_norm / 2 leave the
  // inner corridor; the peak's deviation 2 a0 T_norm scores ((b0 - 2 a0) / (b0 - a0))^2.
  const Iso18571Rating doubled = IsoRate(t, IsoTransformed(t, 1.1, 0.0));
  double expected = 0.0;
  for (double value : t) {
    const double deviation = 0.1 * value;
    expected += deviation <= inner ? 1.0 : std::pow((outer - deviation) / (outer - inner), 2.0);
  }
  EXPECT_NEAR(doubled.corridor, expected / kN, 1e-12);
  EXPECT_LT(doubled.corridor, 1.0);
  // A constant offset c between the corridors: every sample scores ((δo - c) / (δo - δi))^2.
  for (double c : {inner, 0.3 * outer + 0.7 * inner, 0.5 * (inner + outer), 0.99 * outer}) {
    const Iso18571Rating r = IsoRate(t, IsoTransformed(t, 1.0, c));
    EXPECT_NEAR(r.corridor, std::pow((outer - c) / (outer - inner), 2.0), 1e-12) << c;
    EXPECT_EQ(r.phase, 1.0) << c;  // the coefficient ignores the offset
    EXPECT_EQ(r.shift_samples, 0) << c;
    EXPECT_NEAR(r.slope, 1.0, 1e-12) << c;  // the derivatives are equal (to rounding)
  }
  // Outside the outer corridor everywhere.
  EXPECT_EQ(IsoRate(t, IsoTransformed(t, 1.0, 1.01 * outer)).corridor, 0.0);
  EXPECT_EQ(IsoRate(t, IsoTransformed(t, 1.0, -1.01 * outer)).corridor, 0.0);
}

// A curve scaled by k: no shift, derivatives k T', so eps_slope = |k - 1|
// and E_S = 1 - |k - 1| / eps_s.
TEST(Iso18571, ScaledCurveSlopeScore) {
  const std::vector<double> t = IsoPulse(kN, 200, 300);
  for (double k : {0.5, 0.8, 1.3, 2.5}) {
    const Iso18571Rating r = IsoRate(t, IsoTransformed(t, k, 0.0));
    EXPECT_EQ(r.shift_samples, 0) << k;
    EXPECT_NEAR(r.slope_error, std::abs(k - 1.0), 1e-12) << k;
    EXPECT_NEAR(r.slope, std::max(0.0, 1.0 - std::abs(k - 1.0) / 2.0), 1e-12) << k;
  }
}

// -T against a non-negative T: every warped pair has |-T(a) - T(b)| =
// T(a) + T(b) >= T(b), so eps_mag >= 1 > eps_M and E_M = 0 whatever the
// shift and the path; the corridor counts the samples with 2 |T| inside.
TEST(Iso18571, SignFlipScoresMagnitudeZeroAndPoor) {
  const std::vector<double> t = IsoPulse(kN, 200, 300);
  const Iso18571Rating r = IsoRate(t, IsoTransformed(t, -1.0, 0.0));
  EXPECT_EQ(r.magnitude, 0.0);
  EXPECT_GE(r.magnitude_error, 1.0);
  double expected = 0.0;
  for (double value : t) {
    const double deviation = 2.0 * value;
    expected += deviation <= 2.5 ? 1.0 : deviation < 25.0 ? std::pow((25.0 - deviation) / 22.5, 2.0) : 0.0;
  }
  EXPECT_NEAR(r.corridor, expected / kN, 1e-12);
  EXPECT_EQ(r.grade, Iso18571Grade::kPoor);
  EXPECT_LE(r.overall, 0.58);
}

TEST(Iso18571, Grades) {
  EXPECT_EQ(GradeOf(1.0), Iso18571Grade::kExcellent);
  EXPECT_EQ(GradeOf(0.9400001), Iso18571Grade::kExcellent);
  EXPECT_EQ(GradeOf(0.94), Iso18571Grade::kGood);
  EXPECT_EQ(GradeOf(0.8000001), Iso18571Grade::kGood);
  EXPECT_EQ(GradeOf(0.80), Iso18571Grade::kFair);
  EXPECT_EQ(GradeOf(0.5800001), Iso18571Grade::kFair);
  EXPECT_EQ(GradeOf(0.58), Iso18571Grade::kPoor);
  EXPECT_EQ(GradeOf(0.0), Iso18571Grade::kPoor);
  EXPECT_STREQ(NameOf(Iso18571Grade::kGood), "good");
  EXPECT_EQ(ParseName<Iso18571Edition>("2014"), Iso18571Edition::k2014);
  EXPECT_EQ(ParseName<Iso18571Edition>("2024"), Iso18571Edition::k2024);
  EXPECT_FALSE(ParseName<Iso18571Edition>("2020"));
  for (Iso18571Edition edition : kIso18571Editions)
    EXPECT_EQ(ParseName<Iso18571Edition>(NameOf(edition)), edition);
}

TEST(Iso18571, EditionsDifferInTheWarpingWindowOnly) {
  const Iso18571Parameters p2014 = Iso18571Parameters::ForEdition(Iso18571Edition::k2014);
  const Iso18571Parameters p2024 = Iso18571Parameters::ForEdition(Iso18571Edition::k2024);
  EXPECT_FALSE(p2014.dtw_window.has_value());
  ASSERT_TRUE(p2024.dtw_window.has_value());
  EXPECT_EQ(*p2024.dtw_window, 0.1);
  EXPECT_EQ(Iso18571Parameters{}.edition, Iso18571Edition::k2024);  // the default
  EXPECT_EQ(Iso18571Parameters{}.dtw_window, p2024.dtw_window);
  // A candidate whose features come 15 % later in the middle only: the
  // 2024 window (10 %) cannot warp that far, free warping can.
  const std::vector<double> t = IsoPulse(kN, 100, 200);
  std::vector<double> c = t;
  const std::vector<double> late = IsoPulse(kN, 650, 200, 30.0);
  const std::vector<double> early = IsoPulse(kN, 500, 200, 30.0);
  std::vector<double> t2 = t;
  for (long k = 0; k < kN; ++k) {
    t2[static_cast<std::size_t>(k)] += early[static_cast<std::size_t>(k)];
    c[static_cast<std::size_t>(k)] += late[static_cast<std::size_t>(k)];
  }
  const Iso18571Rating r2014 = IsoRate(t2, c, p2014);
  const Iso18571Rating r2024 = IsoRate(t2, c, p2024);
  EXPECT_EQ(r2014.corridor, r2024.corridor);
  EXPECT_EQ(r2014.phase, r2024.phase);
  EXPECT_EQ(r2014.slope, r2024.slope);
  EXPECT_LT(r2014.magnitude_error, r2024.magnitude_error);
}

// The one-pass pruned band equals the full cost matrix with its backtrack
// on awkward random curves (noise, plateaus, ties), every window.
TEST(Iso18571, PrunedWarpingEqualsTheFullMatrix) {
  std::mt19937_64 random(18571);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::uniform_int_distribution<int> level(-2, 2);
  for (int trial = 0; trial < 60; ++trial) {
    const long n = 20 + trial * 3;
    std::vector<double> t(static_cast<std::size_t>(n)), c(static_cast<std::size_t>(n));
    for (long k = 0; k < n; ++k) {
      const double x = static_cast<double>(k) / static_cast<double>(n);
      if (trial % 3 == 0) {  // integer levels: many equal costs
        t[static_cast<std::size_t>(k)] = level(random);
        c[static_cast<std::size_t>(k)] = level(random);
      } else {
        t[static_cast<std::size_t>(k)] = std::sin(6.0 * x) + 0.1 * noise(random);
        c[static_cast<std::size_t>(k)] = 1.2 * std::sin(6.0 * x - 0.3) + 0.1 * (trial % 5) * noise(random);
      }
    }
    for (std::optional<long> window : {std::optional<long>{}, std::optional<long>{0}, std::optional<long>{1},
                                       std::optional<long>{n / 10}, std::optional<long>{n / 3}}) {
      const double pruned = Iso18571MagnitudeError(t, c, window);
      const double full = Iso18571MagnitudeErrorFullMatrix(t, c, window);
      EXPECT_NEAR(pruned, full, 1e-12 * std::max(1.0, full))
          << "trial " << trial << " window " << (window ? *window : -1);
    }
  }
}

TEST(Iso18571, SmoothedDerivativeOfALineIsItsSlope) {
  std::vector<double> line(50);
  for (std::size_t k = 0; k < line.size(); ++k) line[k] = 3.0 + 2.0 * static_cast<double>(k) * kDt;
  const Eigen::VectorXd d = Iso18571SmoothedDerivative(line, kDt);
  for (Eigen::Index k = 0; k < d.size(); ++k) EXPECT_NEAR(d(k), 2.0, 1e-9) << k;
}

// Two samplings of one pulse resampled onto 10 kHz over their common part:
// at 10 kHz and 20 kHz (every base point a sample of both) the ratings of
// identical curves; at 1 kHz the interpolation's error only.
TEST(Iso18571, RateCurvesResamplesOntoTheCommonInterval) {
  auto sampled = [](double rate_hz, double t0, double t1) {
    const auto n = static_cast<Eigen::Index>(std::llround((t1 - t0) * rate_hz)) + 1;
    TimeSeries s{Eigen::VectorXd(n), Eigen::VectorXd(n)};
    for (Eigen::Index k = 0; k < n; ++k) {
      s.time_s(k) = t0 + static_cast<double>(k) / rate_hz;
      const double x = std::clamp((s.time_s(k) - 0.02) / 0.06, 0.0, 1.0);
      s.values(k) = 40.0 * (1.0 - std::cos(2.0 * std::numbers::pi * x));
    }
    return s;
  };
  const TimeSeries reference = sampled(10000.0, 0.0, 0.12);
  const TimeSeries candidate = sampled(20000.0, 0.01, 0.15);
  const Iso18571Rating r = Iso18571RateCurves(reference, candidate);
  EXPECT_EQ(r.samples, 1101);          // 0.01 s to 0.12 s at 10 kHz
  EXPECT_NEAR(r.overall, 1.0, 1e-12);  // the sample times agree to rounding
  const Iso18571Rating part = Iso18571RateCurves(reference, candidate, {0.02, 0.05});
  EXPECT_EQ(part.samples, 301);
  const Iso18571Rating coarse = Iso18571RateCurves(sampled(1000.0, 0.0, 0.12), candidate);
  EXPECT_EQ(coarse.shift_samples, 0);
  EXPECT_GT(coarse.overall, 0.99);
  try {
    Iso18571RateCurves(reference, candidate, {0.0, 0.05}, {}, "the test", "model.csv");
    FAIL() << "an interval outside the candidate was accepted";
  } catch (const InputError& error) {
    EXPECT_STREQ(
        error.what(),
        "The ISO/TS 18571 evaluation interval from 0 s to 0.05 s reaches outside model.csv (0.01 s to 0.15 "
        "s).");
  }
}

template <typename F>
std::string IsoErrorOf(F&& f) {
  try {
    f();
  } catch (const InputError& error) {
    return error.what();
  }
  return "no error";
}

TEST(Iso18571, RefusesBadInputInOneSentence) {
  const std::vector<double> t = IsoPulse(kN, 200, 300);
  std::vector<double> shorter(t.begin(), t.end() - 1);
  EXPECT_EQ(IsoErrorOf([&] { IsoRate(t, shorter); }),
            "ISO/TS 18571 needs the reference and the candidate on one time base, but they have 1000 and 999 "
            "samples.");
  const std::vector<double> tiny(8, 1.0);
  EXPECT_EQ(IsoErrorOf([&] { IsoRate(tiny, tiny); }),
            "ISO/TS 18571 needs at least 9 samples in the evaluation interval, but it has 8.");
  std::vector<double> bad = t;
  bad[300] = std::nan("");
  EXPECT_EQ(IsoErrorOf([&] { IsoRate(t, bad); }),
            "ISO/TS 18571 cannot rate a curve with a non-finite sample: the candidate's sample 300 (t = 0.03 "
            "s from "
            "the interval's start) is nan.");
  const std::vector<double> zero(kN, 0.0);
  EXPECT_EQ(
      IsoErrorOf([&] { IsoRate(zero, t); }),
      "ISO/TS 18571 cannot rate against a reference that is zero throughout the evaluation interval (its "
      "corridors are fractions of the reference's largest magnitude).");
  Iso18571Parameters p;
  p.b0 = 0.01;
  EXPECT_EQ(IsoErrorOf([&] { IsoRate(t, t, p); }),
            "The ISO/TS 18571 parameter b0 is 0.01, but it must be larger than a0.");
  p = {};
  p.w_phase = 0.3;
  EXPECT_EQ(IsoErrorOf([&] { IsoRate(t, t, p); }),
            "The ISO/TS 18571 parameter weights' sum is 1.1, but it must be 1.");
}

}  // namespace
}  // namespace napkin::engine

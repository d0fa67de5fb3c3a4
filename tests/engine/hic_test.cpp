// HIC: the report's section 4.5 known answers, an independent sine answer,
// an independent naive definition, and fast == exhaustive (bit for bit, with
// the same windows) on hundreds of awkward random signals.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "common/error.h"
#include "engine/criteria.h"
#include "engine/report_known_answers.h"
#include "engine/units.h"

namespace napkin::engine {
namespace {

// Report section 4.5: the CG is 10 in from a fixed axis parallel to Y,
// omega(t) = 25 (1 - cos(2 pi t / 0.06)) rad/s for 0 <= t <= 60 ms, then 0;
// |a| = r sqrt(omega_dot^2 + omega^4). Samples t = 0 .. 0.1 s at 10 kHz.
Eigen::VectorXd SeedFixedAxisAccelerationG(double dt_s = 1e-4) {
  const double radius_m = 10.0 * kMetresPerInch;
  const auto n = static_cast<Eigen::Index>(std::llround(0.1 / dt_s)) + 1;
  Eigen::VectorXd acc_g(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) * dt_s;
    double omega = 0.0, omega_dot = 0.0;
    if (t <= 0.06) {
      omega = 25.0 * (1.0 - std::cos(2.0 * std::numbers::pi * t / 0.06));
      omega_dot = 25.0 * (2.0 * std::numbers::pi / 0.06) * std::sin(2.0 * std::numbers::pi * t / 0.06);
    }
    acc_g[k] = radius_m * std::sqrt(omega_dot * omega_dot + std::pow(omega, 4)) / kStandardGravity;
  }
  return acc_g;
}

HicOptions Window(double window_s, bool from_time_zero = false) {
  HicOptions options;
  options.window_s = window_s;
  options.from_time_zero = from_time_zero;
  return options;
}

TEST(Hic, ReportSection45KnownAnswers) {
  const Eigen::VectorXd acc_g = SeedFixedAxisAccelerationG();
  EXPECT_NEAR(acc_g.maxCoeff(), report::kPeakAccG, 0.005);

  const HicWindow unlimited = Hic(acc_g, 1e-4, 0.0);
  EXPECT_NEAR(unlimited.value, report::kHic, 0.01);
  EXPECT_NEAR(unlimited.t1_s, report::kHicT1S, 0.1e-3 + 1e-12);
  EXPECT_NEAR(unlimited.t2_s, report::kHicT2S, 0.1e-3 + 1e-12);

  const HicWindow hic36 = Hic(acc_g, 1e-4, 0.0, Window(kHic36Window));
  EXPECT_NEAR(hic36.value, report::kHic36, 0.01);
  EXPECT_NEAR(hic36.t1_s, report::kHic36T1S, 1e-9);
  EXPECT_NEAR(hic36.t2_s, report::kHic36T2S, 1e-9);

  // Two equal maxima, mirror images about t = 30 ms (|a| is symmetric
  // there); rounding decides which computed double is larger, so accept
  // either, and check the mirror window scores the same.
  const HicWindow hic15 = Hic(acc_g, 1e-4, 0.0, Window(kHic15Window));
  EXPECT_NEAR(hic15.value, report::kHic15, 0.01);
  EXPECT_NEAR(hic15.t2_s - hic15.t1_s, 0.015, 1e-9);
  EXPECT_GT(std::abs(0.5 * (hic15.t1_s + hic15.t2_s) - 0.03), 1e-3);  // not the centred window
  const auto mirror_i = static_cast<Eigen::Index>(std::llround((0.06 - hic15.t2_s) / 1e-4));
  const auto mirror_j = static_cast<Eigen::Index>(std::llround((0.06 - hic15.t1_s) / 1e-4));
  double mirror_area = 0.0;
  for (Eigen::Index k = mirror_i; k < mirror_j; ++k) mirror_area += 0.5e-4 * (acc_g[k] + acc_g[k + 1]);
  EXPECT_NEAR(0.015 * std::pow(mirror_area / 0.015, 2.5), hic15.value, 1e-9 * hic15.value);

  for (const HicOptions& options :
       {Window(kUnlimitedHicWindow), Window(kHic36Window), Window(kHic15Window)}) {
    const HicWindow fast = Hic(acc_g, 1e-4, 0.0, options);
    const HicWindow exhaustive = HicExhaustive(acc_g, 1e-4, 0.0, options);
    EXPECT_EQ(fast.value, exhaustive.value);
    EXPECT_EQ(fast.t1_s, exhaustive.t1_s);
    EXPECT_EQ(fast.t2_s, exhaustive.t2_s);
  }
}

TEST(Hic, HalfSineKnownAnswer) {
  // a(t) = sin(20 pi t) g, t = 0 .. 0.05 s at 10 kHz: HIC over <= 30 ms is
  // 0.02048 at [0.0100, 0.0400] s (the window centred on the peak).
  Eigen::VectorXd acc_g(501);
  for (Eigen::Index k = 0; k < acc_g.size(); ++k)
    acc_g[k] = std::sin(20.0 * std::numbers::pi * static_cast<double>(k) * 1e-4);
  const HicWindow hic = Hic(acc_g, 1e-4, 0.0, Window(report::kHalfSineHicWindowS));
  EXPECT_NEAR(hic.value, report::kHalfSineHic, 0.000005);
  EXPECT_NEAR(hic.t1_s, report::kHalfSineHicT1S, 1e-9);
  EXPECT_NEAR(hic.t2_s, report::kHalfSineHicT2S, 1e-9);
}

// An independent definition: every window, each integral summed afresh.
HicWindow NaiveHic(const Eigen::VectorXd& a, double dt, double t0, double window_s) {
  HicWindow best;
  bool found = false;
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    double area = 0.0;
    for (Eigen::Index j = i + 1; j < a.size(); ++j) {
      area += 0.5 * dt * (a[j - 1] + a[j]);
      const double duration = static_cast<double>(j - i) * dt;
      if (duration > window_s * (1.0 + 1e-9)) break;
      if (area <= 0.0) continue;
      const double value = duration * std::pow(area / duration, 2.5);
      if (value > best.value * (1.0 + 1e-12) || !found) {
        best = {value, t0 + static_cast<double>(i) * dt, t0 + static_cast<double>(j) * dt};
        found = true;
      }
    }
  }
  return best;
}

TEST(Hic, ExhaustiveMatchesAnIndependentNaiveDefinition) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Index n = 50 + static_cast<Eigen::Index>(uniform(rng) * 250);
    Eigen::VectorXd a(n);
    const double centre = uniform(rng) * n, width = 5 + uniform(rng) * 60, height = 20 + uniform(rng) * 100;
    for (Eigen::Index k = 0; k < n; ++k)
      a[k] = height * std::exp(-0.5 * std::pow((k - centre) / width, 2)) + 3.0 * (uniform(rng) - 0.5);
    const double dt = 1e-4;
    for (const double window : {0.005, 0.015, kUnlimitedHicWindow}) {
      const HicWindow naive = NaiveHic(a, dt, -0.001, window);
      const HicWindow exhaustive = HicExhaustive(a, dt, -0.001, Window(window));
      EXPECT_NEAR(exhaustive.value, naive.value, 1e-9 * naive.value);
      EXPECT_NEAR(exhaustive.t1_s, naive.t1_s, 1e-12);
      EXPECT_NEAR(exhaustive.t2_s, naive.t2_s, 1e-12);
    }
  }
}

// Random signals of many kinds: pulses, noise, negative values, plateaus,
// constants, exactly representable values (exact ties), long windows.
Eigen::VectorXd RandomSignal(std::mt19937_64& rng, int kind, Eigen::Index n, double dt) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::VectorXd a = Eigen::VectorXd::Zero(n);
  switch (kind % 8) {
    case 0: {  // several haversine pulses plus noise
      const int pulses = 1 + static_cast<int>(uniform(rng) * 4);
      for (int p = 0; p < pulses; ++p) {
        const double start = uniform(rng) * n * dt, length = (0.002 + uniform(rng) * 0.03),
                     height = 200 * uniform(rng);
        for (Eigen::Index k = 0; k < n; ++k) {
          const double s = (k * dt - start) / length;
          if (s >= 0 && s <= 1) a[k] += height * 0.5 * (1 - std::cos(2 * std::numbers::pi * s));
        }
      }
      for (Eigen::Index k = 0; k < n; ++k) a[k] = std::abs(a[k] + normal(rng));
      break;
    }
    case 1:  // pure noise around zero (negative values)
      for (Eigen::Index k = 0; k < n; ++k) a[k] = 10.0 * normal(rng);
      break;
    case 2: {  // plateaus of exactly representable levels
      double level = 0.0;
      for (Eigen::Index k = 0; k < n; ++k) {
        if (uniform(rng) < 0.02) level = std::floor(uniform(rng) * 8) * 16.0;
        a[k] = level;
      }
      break;
    }
    case 3:  // a constant
      a.setConstant(std::floor(uniform(rng) * 100.0));
      break;
    case 4: {  // negative-going pulse with a positive rebound
      const double centre = uniform(rng) * n;
      for (Eigen::Index k = 0; k < n; ++k) {
        const double s = (k - centre) / (0.05 * n);
        a[k] = -80.0 * std::exp(-s * s) + 60.0 * std::exp(-std::pow(s - 2.0, 2)) + normal(rng);
      }
      break;
    }
    case 5: {  // symmetric double pulse: exact mirror-image ties
      const Eigen::Index half = n / 2;
      for (Eigen::Index k = 0; k < half; ++k) a[k] = std::floor(uniform(rng) * 4.0) * 32.0;
      for (Eigen::Index k = 0; k < half; ++k) a[n - 1 - k] = a[k];
      break;
    }
    case 6: {  // a rectangular block on a zero background
      const Eigen::Index start = static_cast<Eigen::Index>(uniform(rng) * n);
      const Eigen::Index length = 1 + static_cast<Eigen::Index>(uniform(rng) * n / 3);
      for (Eigen::Index k = start; k < std::min(n, start + length); ++k) a[k] = 64.0;
      break;
    }
    default:  // all negative
      for (Eigen::Index k = 0; k < n; ++k) a[k] = -1.0 - std::abs(normal(rng));
      break;
  }
  return a;
}

TEST(Hic, FastEqualsExhaustiveOnRandomSignals) {
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  int compared = 0;
  for (int trial = 0; trial < 240; ++trial) {
    // Binary fractions make integrals exact (exact ties) in half the trials.
    const double dt = (trial % 2 == 0) ? std::ldexp(1.0, -13) : (trial % 4 == 1 ? 1e-4 : 1.0 / 12500.0);
    const Eigen::Index n = 2 + static_cast<Eigen::Index>(uniform(rng) * 900);
    const Eigen::VectorXd a = RandomSignal(rng, trial, n, dt);
    const double t0 = (trial % 3 == 0) ? -0.0123 * uniform(rng) : 0.0;
    for (const double window : {kHic15Window, kHic36Window, kUnlimitedHicWindow, 0.0013}) {
      for (const bool from_zero : {false, true}) {
        const HicOptions options = Window(window, from_zero);
        const HicWindow fast = Hic(a, dt, t0, options);
        const HicWindow exhaustive = HicExhaustive(a, dt, t0, options);
        ASSERT_EQ(fast.value, exhaustive.value) << "trial " << trial << " window " << window;
        ASSERT_EQ(fast.t1_s, exhaustive.t1_s) << "trial " << trial << " window " << window;
        ASSERT_EQ(fast.t2_s, exhaustive.t2_s) << "trial " << trial << " window " << window;
        ++compared;
      }
    }
  }
  EXPECT_EQ(compared, 240 * 8);
}

// Long records of several overlapping smooth pulses (the resultant of a
// random head motion): the optimal windows are long and many windows come
// within a fraction of a percent of the best, so deep levels of the block
// search are exercised; n spans several powers of two.
TEST(Hic, FastEqualsExhaustiveOnLongMultiPulseSignals) {
  std::mt19937_64 rng(1612);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double dt = 1e-4;
  for (const Eigen::Index n : {1500, 2048, 2049, 2600}) {
    Eigen::VectorXd a = Eigen::VectorXd::Zero(n);
    for (int pulse = 0; pulse < 6; ++pulse) {
      const double start = uniform(rng) * static_cast<double>(n), length = 50.0 + uniform(rng) * 600.0;
      const double height = 10.0 + uniform(rng) * 70.0;
      for (Eigen::Index k = 0; k < n; ++k) {
        const double s = (static_cast<double>(k) - start) / length;
        if (s >= 0.0 && s <= 1.0) a[k] += height * 0.5 * (1.0 - std::cos(2.0 * std::numbers::pi * s));
      }
    }
    for (const double window : {kHic15Window, kHic36Window, kUnlimitedHicWindow}) {
      const HicWindow fast = Hic(a, dt, -0.01, Window(window));
      const HicWindow exhaustive = HicExhaustive(a, dt, -0.01, Window(window));
      EXPECT_GT(exhaustive.value, 0.0);
      EXPECT_EQ(fast.value, exhaustive.value) << "n " << n << " window " << window;
      EXPECT_EQ(fast.t1_s, exhaustive.t1_s) << "n " << n << " window " << window;
      EXPECT_EQ(fast.t2_s, exhaustive.t2_s) << "n " << n << " window " << window;
    }
  }
}

// Several limits at once (each search seeded by a shorter limit's window)
// give Hic's answer for each, in the order asked, ties included.
TEST(Hic, SeveralWindowsAtOnceEqualOneAtATime) {
  std::mt19937_64 rng(77);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const std::vector<double> windows{kUnlimitedHicWindow, kHic15Window, 0.0013, kHic36Window, kHic15Window};
  for (int trial = 0; trial < 80; ++trial) {
    const double dt = (trial % 2 == 0) ? std::ldexp(1.0, -13) : 1e-4;
    const Eigen::Index n = 2 + static_cast<Eigen::Index>(uniform(rng) * 900);
    const Eigen::VectorXd a = RandomSignal(rng, trial, n, dt);
    for (const bool from_zero : {false, true}) {
      const std::vector<HicWindow> together = HicForWindows(a, dt, -0.005, windows, from_zero);
      ASSERT_EQ(together.size(), windows.size());
      for (std::size_t w = 0; w < windows.size(); ++w) {
        const HicWindow alone = Hic(a, dt, -0.005, Window(windows[w], from_zero));
        EXPECT_EQ(together[w].value, alone.value) << "trial " << trial << " window " << windows[w];
        EXPECT_EQ(together[w].t1_s, alone.t1_s) << "trial " << trial << " window " << windows[w];
        EXPECT_EQ(together[w].t2_s, alone.t2_s) << "trial " << trial << " window " << windows[w];
      }
    }
  }
  EXPECT_THROW(HicForWindows(Eigen::VectorXd::Ones(10), 1e-4, 0.0, {kHic15Window, -1.0}), InputError);
}

TEST(Hic, TiesGoToTheEarliestWindow) {
  // A constant with exact arithmetic: every window of the full 15 ms length
  // has the same value; the earliest is reported.
  const double dt = std::ldexp(1.0, -12);  // ~0.244 ms
  const Eigen::VectorXd a = Eigen::VectorXd::Constant(400, 32.0);
  const HicWindow hic = Hic(a, dt, 0.0, Window(kHic15Window));
  const double steps = std::floor(kHic15Window / dt);
  EXPECT_EQ(hic.t1_s, 0.0);
  EXPECT_EQ(hic.t2_s, steps * dt);
  EXPECT_DOUBLE_EQ(hic.value, steps * dt * std::pow(32.0, 2.5));
  // Two identical rectangular pulses: the first one wins.
  Eigen::VectorXd pulses = Eigen::VectorXd::Zero(300);
  pulses.segment(20, 10).setConstant(64.0);
  pulses.segment(200, 10).setConstant(64.0);
  const HicWindow first = Hic(pulses, dt, 0.0, Window(kHic15Window));
  EXPECT_LT(first.t2_s, 100 * dt);
  EXPECT_EQ(first.value, HicExhaustive(pulses, dt, 0.0, Window(kHic15Window)).value);
}

TEST(Hic, WindowsOfExactlyTheLimitAreIncluded) {
  // On a 40 ms plateau HIC grows with the window length, so the best window
  // is exactly 15 ms (150 intervals at 10 kHz); excluding windows of exactly
  // W would give 149 intervals.
  Eigen::VectorXd a = Eigen::VectorXd::Zero(1000);
  a.segment(200, 400).setConstant(100.0);
  const HicWindow hic15 = Hic(a, 1e-4, 0.0, Window(kHic15Window));
  EXPECT_NEAR(hic15.t2_s - hic15.t1_s, 0.015, 1e-12);
  EXPECT_NEAR(hic15.value, 0.015 * std::pow(100.0, 2.5), 1e-9 * hic15.value);
}

TEST(Hic, NonPositiveSignalsScoreZeroAtTheFirstSample) {
  const Eigen::VectorXd negative = -Eigen::VectorXd::LinSpaced(100, 1.0, 5.0);
  for (const HicWindow& hic : {Hic(negative, 1e-4, -0.002), HicExhaustive(negative, 1e-4, -0.002)}) {
    EXPECT_EQ(hic.value, 0.0);
    EXPECT_EQ(hic.t1_s, -0.002);
    EXPECT_EQ(hic.t2_s, -0.002);
  }
  const Eigen::VectorXd one = Eigen::VectorXd::Constant(1, 50.0);
  EXPECT_EQ(Hic(one, 1e-4, 0.0).value, 0.0);
}

TEST(Hic, FromTimeZeroIntegratesMagnitudeAndIgnoresPreImpact) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> normal(0.0, 20.0);
  const double dt = 1e-4, t0 = -0.0050;  // 50 pre-impact samples
  Eigen::VectorXd a(600);
  for (Eigen::Index k = 0; k < a.size(); ++k) a[k] = normal(rng);
  a.head(50).setConstant(500.0);  // a huge pre-impact level that must be ignored
  const HicWindow hic = Hic(a, dt, t0, Window(kHic15Window, true));
  const Eigen::VectorXd magnitude = a.tail(550).cwiseAbs();
  const HicWindow expected = HicExhaustive(magnitude, dt, 0.0, Window(kHic15Window));
  EXPECT_EQ(hic.value, expected.value);
  EXPECT_NEAR(hic.t1_s, expected.t1_s, 1e-15);
  EXPECT_NEAR(hic.t2_s, expected.t2_s, 1e-15);
  EXPECT_GE(hic.t1_s, 0.0);
  // Without the option the pre-impact block dominates.
  EXPECT_LT(Hic(a, dt, t0, Window(kHic15Window)).t1_s, 0.0);
}

TEST(Hic, BadInputIsAnInputError) {
  Eigen::VectorXd a = Eigen::VectorXd::Ones(10);
  EXPECT_THROW(Hic(a, 0.0, 0.0), InputError);
  EXPECT_THROW(Hic(a, 1e-4, 0.0, Window(0.0)), InputError);
  EXPECT_THROW(Hic(a, 1e-4, 0.0, Window(std::nan(""))), InputError);
  a[4] = std::nan("");
  EXPECT_THROW(Hic(a, 1e-4, 0.0), InputError);
  EXPECT_THROW(HicExhaustive(a, 1e-4, 0.0), InputError);
  try {
    Hic(a, 1e-4, 0.0);
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("sample 4"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace napkin::engine

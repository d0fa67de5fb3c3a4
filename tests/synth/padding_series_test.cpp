// The padding series of `napkin synth --scenario padding-series` (and
// `napkin demo`): the HIC15 of its 15 default tests from their exact truth,
// the foams below production trim, and napkin's accuracy on them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "engine/criteria.h"
#include "engine/pipeline.h"
#include "engine/units.h"
#include "synth/synthetic_tests.h"
#include "tests/support/reference_arrays.h"

namespace napkin::engine {
namespace {

double TrueHic15(const synth::SyntheticTest& test) {
  const Eigen::VectorXd acc_g = test.truth.acc_fixed.rowwise().norm() / kStandardGravity;
  HicOptions window;
  window.window_s = kHic15Window;
  return Hic(acc_g, test.signals.dt_s, test.signals.t0_s, window).value;
}

// The default series (seed 1, five repeats per padding) on the ideal 3-2-2-2 array.
struct Series {
  std::vector<synth::ScenarioTest> described;
  std::vector<synth::SyntheticTest> tests;
};

const Series& DefaultSeries() {
  static const Series kSeries = [] {
    Series s;
    synth::ScenarioOptions options;
    options.scenario = synth::SynthScenario::kPaddingSeries;
    options.id_prefix = "padding-series";
    options.count = synth::DefaultCount(synth::SynthScenario::kPaddingSeries);
    s.described = synth::ScenarioTests(options);
    for (const synth::ScenarioTest& test : s.described)
      s.tests.push_back(synth::SynthScenarioTest(test_support::Ideal3222(), options, test));
    return s;
  }();
  return kSeries;
}

TEST(PaddingSeries, Hic15OfProductionTrimAndFoamsFromTheTruth) {
  const Series& series = DefaultSeries();
  ASSERT_EQ(series.tests.size(), 15u);
  std::map<std::string, std::vector<double>> hic15;
  for (std::size_t i = 0; i < series.tests.size(); ++i) {
    hic15[*series.described[i].variant].push_back(TrueHic15(series.tests[i]));
    std::printf("%-28s HIC15 %7.1f\n", series.described[i].external_id.c_str(),
                hic15.at(*series.described[i].variant).back());
  }
  ASSERT_EQ(hic15.size(), 3u);
  auto mean = [](const std::vector<double>& values) {
    double sum = 0.0;
    for (double v : values) sum += v;
    return sum / static_cast<double>(values.size());
  };
  const std::vector<double>& production = hic15.at("production");
  const std::vector<double>& foam_a = hic15.at("foam-a");
  const std::vector<double>& foam_b = hic15.at("foam-b");
  for (double value : production) {
    EXPECT_GE(value, 700.0);
    EXPECT_LE(value, 1100.0);
  }
  // Every repeat pair: softer padding, lower HIC.
  for (std::size_t r = 0; r < production.size(); ++r) {
    EXPECT_LT(foam_a[r], production[r]) << r;
    EXPECT_LT(foam_b[r], production[r]) << r;
  }
  // Foam A about 20-30 % lower, foam B about 35-50 % lower, on average.
  const double foam_a_change = mean(foam_a) / mean(production) - 1.0;
  const double foam_b_change = mean(foam_b) / mean(production) - 1.0;
  std::printf("HIC15 means: production %.1f, foam-a %.1f (%+.1f %%), foam-b %.1f (%+.1f %%)\n",
              mean(production), mean(foam_a), 100 * foam_a_change, mean(foam_b), 100 * foam_b_change);
  EXPECT_LE(foam_a_change, -0.20);
  EXPECT_GE(foam_a_change, -0.30);
  EXPECT_LE(foam_b_change, -0.35);
  EXPECT_GE(foam_b_change, -0.50);
}

TEST(PaddingSeries, HeadPulsesLastTenToTwentyFiveMilliseconds) {
  const Series& series = DefaultSeries();
  std::map<std::string, double> total_s;
  for (std::size_t i = 0; i < series.tests.size(); ++i) {
    const Kinematics& truth = series.tests[i].truth;
    const Eigen::VectorXd acc = truth.acc_fixed.rowwise().norm();
    Eigen::Index first = -1, last = -1;
    for (Eigen::Index k = 0; k < acc.size(); ++k)
      if (acc(k) > 0.0) {
        if (first < 0) first = k;
        last = k;
      }
    ASSERT_GE(first, 0);
    // The samples with force, plus the half intervals to the pulse's ends.
    const double pulse_s = truth.time_s(last) - truth.time_s(first) + series.tests[i].signals.dt_s;
    EXPECT_NEAR(pulse_s, series.described[i].impact->pulse_s, series.tests[i].signals.dt_s);
    EXPECT_GE(pulse_s, 0.010) << series.described[i].external_id;
    EXPECT_LE(pulse_s, 0.025) << series.described[i].external_id;
    total_s[*series.described[i].variant] += pulse_s;
  }
  // Softer padding, longer pulse.
  EXPECT_LT(total_s.at("production"), total_s.at("foam-a"));
  EXPECT_LT(total_s.at("foam-a"), total_s.at("foam-b"));
}

TEST(PaddingSeries, IsDeterministicForASeed) {
  synth::ScenarioOptions options;
  options.scenario = synth::SynthScenario::kPaddingSeries;
  options.id_prefix = "p";
  options.count = 2;
  const synth::ScenarioTest test = synth::ScenarioTests(options)[3];
  const synth::SyntheticTest a = synth::SynthScenarioTest(test_support::Denton3222(), options, test);
  const synth::SyntheticTest b =
      synth::SynthScenarioTest(test_support::Denton3222(), options, synth::ScenarioTests(options)[3]);
  EXPECT_EQ(a.signals.samples, b.signals.samples);
  EXPECT_EQ(a.truth.omega_body, b.truth.omega_body);
  options.seed = 2;
  const synth::SyntheticTest c =
      synth::SynthScenarioTest(test_support::Denton3222(), options, synth::ScenarioTests(options)[3]);
  EXPECT_NE(a.signals.samples, c.signals.samples);
  EXPECT_NE(a.truth.omega_body, c.truth.omega_body);
}

// The targets of the noisy-test acceptance (tests/engine/screening_test.cpp):
// default processing within 2 % of the true peak angular velocity and 1 % of
// the true HIC15, with no finding above info.
TEST(PaddingSeries, DefaultProcessingRecoversPeakOmegaAndHic15) {
  const Series& series = DefaultSeries();
  double worst_omega = 0.0, worst_hic = 0.0;
  double lowest_omega = INFINITY, highest_omega = 0.0;
  // Each test as the series recorded it (ideal 3-2-2-2) and with the NAP
  // array of the report's tests (Denton 3-2-2-2, what `napkin demo` uses).
  synth::ScenarioOptions options;
  options.scenario = synth::SynthScenario::kPaddingSeries;
  std::vector<synth::SyntheticTest> tests = series.tests;
  for (const synth::ScenarioTest& test : series.described)
    tests.push_back(synth::SynthScenarioTest(test_support::Denton3222(), options, test));
  for (const synth::SyntheticTest& test : tests) {
    const ProcessedTest processed = ProcessTest(test.array, test.signals, test.initial, ProcessingConfig{});
    const double true_omega = test.truth.omega_body.rowwise().norm().maxCoeff();
    const double omega_error = std::abs(processed.summary.peak_omega_radps / true_omega - 1.0);
    const double hic_error = std::abs(processed.summary.hic15.value / TrueHic15(test) - 1.0);
    EXPECT_LE(omega_error, 0.02) << test.array.name << " " << test.name;
    EXPECT_LE(hic_error, 0.01) << test.array.name << " " << test.name;
    for (const Finding& finding : processed.summary.findings)
      EXPECT_EQ(finding.severity, Severity::kInfo) << test.name << ": " << finding.detail;
    worst_omega = std::max(worst_omega, omega_error);
    worst_hic = std::max(worst_hic, hic_error);
    lowest_omega = std::min(lowest_omega, true_omega);
    highest_omega = std::max(highest_omega, true_omega);
  }
  std::printf(
      "padding series, %zu tests: true peak omega %.1f-%.1f rad/s; worst peak-omega error %.3f %%, worst "
      "HIC15 error %.3f %%\n",
      tests.size(), lowest_omega, highest_omega, 100.0 * worst_omega, 100.0 * worst_hic);
}

}  // namespace
}  // namespace napkin::engine

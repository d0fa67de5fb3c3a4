// Honest conditioning (docs/algorithms.md "Signal conditioning"): a channel the
// file records as already filtered is not filtered again at the same or a
// wider class, a raw one is filtered as before, and every result says what
// was done to each channel. Also both a3ms definitions against analytic cases.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <random>

#include "common/error.h"
#include "engine/cfc_filter.h"
#include "engine/criteria.h"
#include "engine/pipeline.h"
#include "engine/processing.h"
#include "engine/summary_fields.h"
#include "engine/units.h"
#include "synth/synthetic_tests.h"
#include "tests/support/reference_arrays.h"

namespace napkin::engine {
namespace {

using test_support::OneLinearOneRate;

// cg_x, ars_x: noisy pulses with offsets, from t0 = -5 ms at 10 kHz.
TestSignals NoisySignals() {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 1.0);
  TestSignals signals;
  signals.dt_s = 1e-4;
  signals.t0_s = -0.005;
  signals.slots = {"cg_x", "ars_x"};
  const Eigen::Index n = 400;
  signals.samples.resize(n, 2);
  for (Eigen::Index k = 0; k < n; ++k) {
    const double t = signals.TimeAt(k);
    const double pulse = t > 0.0 && t < 0.02 ? std::sin(std::numbers::pi * t / 0.02) : 0.0;
    signals.samples(k, 0) = 2.5 + 60.0 * pulse + noise(rng);
    signals.samples(k, 1) = -0.75 + 20.0 * pulse + 0.1 * noise(rng);
  }
  return signals;
}

bool BitIdentical(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return a.size() == b.size() &&
         std::memcmp(a.data(), b.data(), static_cast<std::size_t>(a.size()) * sizeof(double)) == 0;
}

TEST(HonestConditioning, ChannelMarkedCfc1000IsNotFilteredAgainBitForBit) {
  ProcessingConfig config;  // CFC 1000 on linear channels
  config.bias.mode = BiasMode::kNone;
  TestSignals signals = NoisySignals();
  signals.prefiltered_cfc = {kCfc1000, std::nullopt};
  const Eigen::VectorXd input = signals.samples.col(0);
  const std::vector<ChannelConditioning> record = ApplyConditioning(OneLinearOneRate(), signals, config);
  EXPECT_TRUE(BitIdentical(signals.samples.col(0), input));
  ASSERT_EQ(record.size(), 2u);
  EXPECT_EQ(record[0].channel, "cg_x");
  EXPECT_FALSE(record[0].filter_cfc.has_value());
  EXPECT_EQ(record[0].prefiltered_cfc, kCfc1000);
  EXPECT_TRUE(record[0].filter_skipped_prefiltered);
  EXPECT_EQ(FilterDescription(record[0]), "none, prefiltered at CFC 1000");

  // A file that records a narrower class (CFC 600) is not filtered at 1000 either.
  TestSignals narrower = NoisySignals();
  narrower.prefiltered_cfc = {kCfc600, std::nullopt};
  ApplyConditioning(OneLinearOneRate(), narrower, config);
  EXPECT_TRUE(BitIdentical(narrower.samples.col(0), input));
}

TEST(HonestConditioning, RawChannelIsFilteredAsToday) {
  ProcessingConfig config;
  config.bias.mode = BiasMode::kNone;
  TestSignals signals = NoisySignals();
  signals.prefiltered_cfc = {kCfc1000, std::nullopt};  // ars_x raw
  Eigen::VectorXd expected_rate = signals.samples.col(1);
  CfcFilter(kCfc60, signals.dt_s, config.filter.variant, config.filter.padding_s).ApplyInPlace(expected_rate);
  const std::vector<ChannelConditioning> record = ApplyConditioning(OneLinearOneRate(), signals, config);
  EXPECT_TRUE(BitIdentical(signals.samples.col(1), expected_rate));
  EXPECT_EQ(record[1].filter_cfc, kCfc60);
  EXPECT_FALSE(record[1].prefiltered_cfc.has_value());
  EXPECT_EQ(FilterDescription(record[1]), "CFC 60");

  // Without any record (CSV): both channels filtered exactly as a plain CfcFilter does.
  TestSignals plain = NoisySignals();
  Eigen::VectorXd expected_linear = plain.samples.col(0);
  CfcFilter(kCfc1000, plain.dt_s, config.filter.variant, config.filter.padding_s)
      .ApplyInPlace(expected_linear);
  ApplyConditioning(OneLinearOneRate(), plain, config);
  EXPECT_TRUE(BitIdentical(plain.samples.col(0), expected_linear));
}

TEST(HonestConditioning, NarrowerRequestedClassIsStillApplied) {
  ProcessingConfig config;
  config.bias.mode = BiasMode::kNone;
  config.filter.linear_cfc = kCfc180;
  TestSignals signals = NoisySignals();
  signals.prefiltered_cfc = {kCfc1000, std::nullopt};
  Eigen::VectorXd expected = signals.samples.col(0);
  CfcFilter(kCfc180, signals.dt_s, config.filter.variant, config.filter.padding_s).ApplyInPlace(expected);
  const std::vector<ChannelConditioning> record = ApplyConditioning(OneLinearOneRate(), signals, config);
  EXPECT_TRUE(BitIdentical(signals.samples.col(0), expected));
  EXPECT_EQ(record[0].filter_cfc, kCfc180);
  EXPECT_FALSE(record[0].filter_skipped_prefiltered);
  const std::vector<Finding> findings = ConditioningFindings(record);
  ASSERT_EQ(findings.size(), 1u);
  EXPECT_EQ(findings[0].check, "prefiltered");
  EXPECT_EQ(findings[0].channel, std::optional<std::string>("cg_x"));
  EXPECT_EQ(findings[0].severity, Severity::kInfo);
  EXPECT_NE(findings[0].detail.find("narrower CFC 180"), std::string::npos) << findings[0].detail;
}

TEST(HonestConditioning, RecordsBiasValueWindowAndShift) {
  ProcessingConfig config;
  config.time.shift_s = 0.001;  // t0 becomes -6 ms: samples -6 ms ... -0.1 ms are before t = 0
  TestSignals signals = NoisySignals();
  // Independent recomputation: the mean of the 60 samples before t = 0 (after the shift).
  const double expected_bias = signals.samples.col(0).head(60).mean();
  const std::vector<ChannelConditioning> record = ApplyConditioning(OneLinearOneRate(), signals, config);
  EXPECT_DOUBLE_EQ(record[0].bias_removed, expected_bias);
  EXPECT_DOUBLE_EQ(record[1].bias_removed, NoisySignals().samples.col(1).head(60).mean());
  ASSERT_TRUE(record[0].bias_window_start_s && record[0].bias_window_end_s);
  EXPECT_NEAR(*record[0].bias_window_start_s, -0.006, 1e-12);
  EXPECT_NEAR(*record[0].bias_window_end_s, -0.0001, 1e-12);
  EXPECT_EQ(record[0].time_shift_s, 0.001);
  EXPECT_EQ(record[0].filter_cfc, kCfc1000);

  // Mode window: the window's own samples.
  ProcessingConfig window = config;
  window.bias.mode = BiasMode::kWindow;
  window.bias.window_start_s = -0.002;
  window.bias.window_end_s = -0.001;
  TestSignals windowed = NoisySignals();
  const double expected_window_bias = windowed.samples.col(0).segment(40, 11).mean();  // -2 ... -1 ms
  const std::vector<ChannelConditioning> window_record =
      ApplyConditioning(OneLinearOneRate(), windowed, window);
  EXPECT_DOUBLE_EQ(window_record[0].bias_removed, expected_window_bias);
  EXPECT_NEAR(*window_record[0].bias_window_start_s, -0.002, 1e-12);
  EXPECT_NEAR(*window_record[0].bias_window_end_s, -0.001, 1e-12);

  // Mode none: no value, no window.
  ProcessingConfig none = config;
  none.bias.mode = BiasMode::kNone;
  TestSignals untouched = NoisySignals();
  const std::vector<ChannelConditioning> none_record = ApplyConditioning(OneLinearOneRate(), untouched, none);
  EXPECT_EQ(none_record[0].bias_removed, 0.0);
  EXPECT_FALSE(none_record[0].bias_window_start_s.has_value());
}

TEST(HonestConditioning, AutoBiasIgnoresTheWindowAndTheConfigRefusesOne) {
  // Mode auto averages every sample before t = 0, not window_s; a config that
  // sets window_s with mode auto is refused rather than silently ignored.
  ProcessingConfig config;
  config.bias.window_start_s = -0.002;
  EXPECT_THROW(config.Check(), InputError);
}

TEST(HonestConditioning, ProcessTestOfPrefilteredTestEqualsUnfilteredRunAndSaysSo) {
  const ArrayGeometry array = test_support::Denton3222();
  synth::HeadImpact impact;
  impact.contact_point_body_m = synth::NominalContactPoint(impact.trajectory_deg);
  synth::SyntheticTest test = synth::SynthHeadImpact(array, impact);
  test.signals.prefiltered_cfc.assign(static_cast<std::size_t>(test.signals.samples.cols()), kCfc1000);
  const ProcessingConfig config;  // CFC 1000
  const ProcessedTest prefiltered = ProcessTest(test.array, test.signals, test.initial, config);

  ProcessingConfig unfiltered = config;
  unfiltered.filter.linear_cfc.reset();
  TestSignals plain = test.signals;
  plain.prefiltered_cfc.clear();
  const ProcessedTest reference = ProcessTest(test.array, plain, test.initial, unfiltered);
  for (const SummaryField& field : SummaryFields()) {
    const double a = field.Get(prefiltered.summary), b = field.Get(reference.summary);
    EXPECT_TRUE(a == b || (std::isnan(a) && std::isnan(b))) << field.name << ": " << a << " vs " << b;
  }
  ASSERT_EQ(prefiltered.summary.conditioning.size(), array.sensors.size());
  int notes = 0;
  for (const Finding& finding : prefiltered.summary.findings) {
    if (finding.check != "prefiltered") continue;
    ++notes;
    EXPECT_EQ(finding.severity, Severity::kInfo);
    EXPECT_NE(finding.detail.find("did not filter it again"), std::string::npos) << finding.detail;
  }
  EXPECT_EQ(notes, static_cast<int>(array.sensors.size()));
  EXPECT_EQ(FailingFinding(prefiltered), nullptr);
}

// a3ms of a half-sine a(t) = A sin(pi t / T): the level held for 3 ms is
// A cos(pi 3 ms / (2 T)) under both definitions (one peak).
TEST(A3msDefinitions, HalfSineAnalytic) {
  const double amplitude = 100.0, duration = 0.010, dt = 1e-6;
  const auto n = static_cast<Eigen::Index>(std::llround(duration / dt)) + 1;
  Eigen::VectorXd acc(n);
  for (Eigen::Index k = 0; k < n; ++k)
    acc[k] = amplitude * std::sin(std::numbers::pi * static_cast<double>(k) * dt / duration);
  const double analytic = amplitude * std::cos(std::numbers::pi * 0.003 / (2.0 * duration));  // 89.1007 g
  // Sampling error: the slope at the level times one sample.
  const double tolerance = amplitude * std::numbers::pi / duration * dt;
  EXPECT_NEAR(A3ms(acc, dt), analytic, tolerance);
  EXPECT_NEAR(A3msContinuous(acc, dt), analytic, tolerance);
}

// Two plateaus: 2 ms at 100 g, a gap at 0, 2 ms at 90 g, and 5 ms at 50 g.
// Cumulative: >= 90 g for 4 ms -> 90. Continuous: only the 50 g plateau
// lasts 3 ms unbroken -> 50.
TEST(A3msDefinitions, InterruptedPulsesSeparateTheDefinitions) {
  const double dt = 1e-4;
  std::vector<double> values;
  const auto append = [&values](int samples, double level) { values.insert(values.end(), samples, level); };
  append(10, 0.0);
  append(20, 100.0);
  append(5, 0.0);
  append(20, 90.0);
  append(5, 0.0);
  append(50, 50.0);
  append(10, 0.0);
  const Eigen::Map<const Eigen::VectorXd> acc(values.data(), static_cast<Eigen::Index>(values.size()));
  EXPECT_EQ(A3ms(acc, dt), 90.0);
  EXPECT_EQ(A3msContinuous(acc, dt), 50.0);
  EXPECT_THROW(A3msContinuous(acc.head(29), dt), InputError);  // shorter than 3 ms
}

TEST(A3msDefinitions, ProcessingConfigChoosesTheDefinition) {
  EXPECT_EQ(ProcessingConfig{}.a3ms.definition, A3msDefinition::kCumulative);
  EXPECT_STREQ(NameOf(A3msDefinition::kContinuous), "continuous");
  EXPECT_EQ(ParseName<A3msDefinition>("cumulative"), A3msDefinition::kCumulative);
  EXPECT_FALSE(ParseName<A3msDefinition>("sliding").has_value());

  const ArrayGeometry array = test_support::Denton3222();
  synth::HeadImpact impact;
  impact.contact_point_body_m = synth::NominalContactPoint(impact.trajectory_deg);
  const synth::SyntheticTest test = synth::SynthHeadImpact(array, impact);
  ProcessingConfig continuous;
  continuous.a3ms.definition = A3msDefinition::kContinuous;
  const ProcessedTest processed = ProcessTest(test.array, test.signals, test.initial, continuous);
  const Eigen::VectorXd acc_g = processed.kinematics.acc_fixed.rowwise().norm() / kStandardGravity;
  const double dt = processed.kinematics.time_s[1] - processed.kinematics.time_s[0];
  EXPECT_EQ(processed.summary.a3ms_g, A3msContinuous(acc_g, dt));
  EXPECT_LE(processed.summary.a3ms_g, A3ms(acc_g, dt));
}

}  // namespace
}  // namespace napkin::engine

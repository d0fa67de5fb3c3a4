// Processing configuration checks and signal conditioning: shift, bias
// removal, per-kind filtering and cropping.
#include "engine/processing.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "common/error.h"
#include "engine/units.h"
#include "tests/support/reference_arrays.h"

namespace napkin::engine {
namespace {

using test_support::OneLinearOneRate;

// Columns cg_x, ars_x, extra (not in the array); noisy pulses plus offsets.
TestSignals NoisySignals(double t0, Eigen::Index n, double dt = 1e-4) {
  std::mt19937_64 rng(99);
  std::normal_distribution<double> noise(0.0, 1.0);
  TestSignals signals;
  signals.dt_s = dt;
  signals.t0_s = t0;
  signals.slots = {"cg_x", "ars_x", "extra"};
  signals.samples.resize(n, 3);
  for (Eigen::Index k = 0; k < n; ++k) {
    const double t = signals.TimeAt(k);
    const double pulse = t > 0.0 && t < 0.02 ? std::sin(std::numbers::pi * t / 0.02) : 0.0;
    signals.samples(k, 0) = 2.5 + 60.0 * pulse + noise(rng);
    signals.samples(k, 1) = -0.75 + 20.0 * pulse + 0.1 * noise(rng);
    signals.samples(k, 2) = 1.0 + noise(rng);
  }
  return signals;
}

ProcessingConfig NoFilter() {
  ProcessingConfig config;
  config.filter.linear_cfc.reset();
  config.filter.angular_rate_cfc.reset();
  return config;
}

TEST(ProcessingConfig, DefaultsAreValidAndDocumentedValues) {
  const ProcessingConfig config;
  EXPECT_NO_THROW(config.Check());
  EXPECT_EQ(config.solver, SolverKind::kExact);
  EXPECT_EQ(*config.filter.linear_cfc, 1000.0);
  EXPECT_EQ(*config.filter.angular_rate_cfc, 60.0);
  EXPECT_EQ(config.filter.variant, CfcVariant::kSaeJ211);
  EXPECT_EQ(config.bias.mode, BiasMode::kAuto);
  EXPECT_FALSE(config.gravity.compensate);
  EXPECT_EQ(config.gravity.g_fixed_mps2, Eigen::Vector3d(0.0, 0.0, 9.80665));
  EXPECT_FALSE(config.hic.from_time_zero);
  EXPECT_EQ(config.bric.critical_radps, Eigen::Vector3d(66.25, 56.45, 42.87));
}

TEST(ProcessingConfig, CheckNamesTheBadField) {
  const auto message_of = [](const ProcessingConfig& config) {
    try {
      config.Check();
    } catch (const InputError& error) {
      return std::string(error.what());
    }
    return std::string();
  };
  ProcessingConfig config;
  config.filter.linear_cfc = -5.0;
  EXPECT_NE(message_of(config).find("filter.linear_cfc"), std::string::npos);
  config = {};
  config.bric.critical_radps[2] = 0.0;
  EXPECT_NE(message_of(config).find("bric.critical_radps[2]"), std::string::npos);
  config = {};
  config.time.start_s = 0.05;
  config.time.end_s = 0.01;
  EXPECT_NE(message_of(config).find("time.end_s"), std::string::npos);
  config = {};
  config.bias.window_start_s = 0.0;
  config.bias.window_end_s = -0.01;
  EXPECT_NE(message_of(config).find("bias.window_s"), std::string::npos);
  config = {};
  config.screening.saturation_run_samples = 1;
  EXPECT_NE(message_of(config).find("screening.saturation_run_samples"), std::string::npos);
  config = {};
  config.gravity.g_fixed_mps2[1] = std::nan("");
  EXPECT_NE(message_of(config).find("gravity.g_fixed[1]"), std::string::npos);
}

TEST(ProcessingConfig, MakeSolveOptionsCarriesSolverAndGravity) {
  ProcessingConfig config;
  config.solver = SolverKind::kSeed;
  config.gravity.compensate = true;
  InitialState initial;
  initial.orientation_rad = Eigen::Vector3d(0.5, 0.5, 0.5);
  const SolveOptions options = MakeSolveOptions(config, initial);
  EXPECT_EQ(options.solver, SolverKind::kSeed);
  EXPECT_TRUE(options.gravity.compensate);
  EXPECT_EQ(options.initial.orientation_rad, initial.orientation_rad);
}

TEST(Conditioning, AutoBiasUsesPreImpactSamplesWhenThereIsAtLeastOneMillisecond) {
  const ArrayGeometry array = OneLinearOneRate();
  TestSignals signals = NoisySignals(-0.005, 600);
  const Eigen::MatrixXd raw = signals.samples;
  ApplyConditioning(array, signals, NoFilter());
  for (Eigen::Index c = 0; c < 3; ++c) {
    const double pre_impact_mean = raw.col(c).head(50).mean();  // t < 0: 50 samples
    EXPECT_NEAR((raw.col(c).array() - pre_impact_mean - signals.samples.col(c).array()).abs().maxCoeff(), 0.0,
                1e-12);
    EXPECT_NEAR(signals.samples.col(c).head(50).mean(), 0.0, 1e-12);
  }
  // Only 0.5 ms before t = 0: left alone.
  TestSignals short_pre = NoisySignals(-0.0005, 600);
  const Eigen::MatrixXd short_raw = short_pre.samples;
  ApplyConditioning(array, short_pre, NoFilter());
  EXPECT_EQ(short_pre.samples, short_raw);
  // Exactly 1 ms (10 samples): used.
  TestSignals one_ms = NoisySignals(-0.001, 600);
  const Eigen::MatrixXd one_ms_raw = one_ms.samples;
  ApplyConditioning(array, one_ms, NoFilter());
  EXPECT_NEAR(one_ms.samples(300, 0), one_ms_raw(300, 0) - one_ms_raw.col(0).head(10).mean(), 1e-12);
}

TEST(Conditioning, WindowAndNoneBiasModes) {
  const ArrayGeometry array = OneLinearOneRate();
  ProcessingConfig config = NoFilter();
  config.bias.mode = BiasMode::kWindow;
  config.bias.window_start_s = 0.030;
  config.bias.window_end_s = 0.040;
  TestSignals signals = NoisySignals(0.0, 600);
  const Eigen::MatrixXd raw = signals.samples;
  ApplyConditioning(array, signals, config);
  const double mean = raw.col(1).segment(300, 101).mean();  // t = 30.0 .. 40.0 ms inclusive
  EXPECT_NEAR(signals.samples(10, 1), raw(10, 1) - mean, 1e-12);

  config.bias.window_start_s = 0.5;
  config.bias.window_end_s = 0.6;
  TestSignals outside = NoisySignals(0.0, 600);
  EXPECT_THROW(ApplyConditioning(array, outside, config), InputError);

  config.bias = {};  // mode "none" with a window set is refused (Check: the window would be ignored)
  config.bias.mode = BiasMode::kNone;
  TestSignals untouched = NoisySignals(-0.01, 600);
  const Eigen::MatrixXd untouched_raw = untouched.samples;
  ApplyConditioning(array, untouched, config);
  EXPECT_EQ(untouched.samples, untouched_raw);
}

TEST(Conditioning, FiltersEachSensorKindWithItsClassAndLeavesOtherColumns) {
  const ArrayGeometry array = OneLinearOneRate();
  ProcessingConfig config;
  config.bias.mode = BiasMode::kNone;
  config.filter.variant = CfcVariant::kIso6487;
  config.filter.linear_cfc = 180.0;
  TestSignals signals = NoisySignals(0.0, 800);
  const Eigen::MatrixXd raw = signals.samples;
  ApplyConditioning(array, signals, config);
  Eigen::VectorXd expected(800);
  CfcFilter(180.0, 1e-4, CfcVariant::kIso6487).Apply(raw.col(0), expected);
  EXPECT_EQ(signals.samples.col(0), expected);
  CfcFilter(60.0, 1e-4, CfcVariant::kIso6487).Apply(raw.col(1), expected);
  EXPECT_EQ(signals.samples.col(1), expected);
  EXPECT_EQ(signals.samples.col(2), raw.col(2));  // not an array slot

  config.filter.angular_rate_cfc.reset();  // "none"
  TestSignals no_rate_filter = NoisySignals(0.0, 800);
  ApplyConditioning(array, no_rate_filter, config);
  EXPECT_EQ(no_rate_filter.samples.col(1), raw.col(1));
}

TEST(Conditioning, ShiftThenCropKeepsTheRequestedSpan) {
  const ArrayGeometry array = OneLinearOneRate();
  ProcessingConfig config = NoFilter();
  config.bias.mode = BiasMode::kNone;
  config.time.shift_s = 0.012;  // the pulse started at 12 ms
  config.time.start_s = -0.002;
  config.time.end_s = 0.050;
  TestSignals signals = NoisySignals(0.0, 1000);
  const Eigen::MatrixXd raw = signals.samples;
  ApplyConditioning(array, signals, config);
  EXPECT_NEAR(signals.t0_s, -0.002, 1e-12);
  EXPECT_EQ(signals.size(), 521);                   // -2 .. 50 ms inclusive
  EXPECT_EQ(signals.samples.row(0), raw.row(100));  // raw t = 10 ms
  EXPECT_EQ(signals.samples.row(520), raw.row(620));

  // Shift alone moves the time base only.
  ProcessingConfig shift_only = NoFilter();
  shift_only.bias.mode = BiasMode::kNone;
  shift_only.time.shift_s = -0.003;
  TestSignals shifted = NoisySignals(0.0, 100);
  ApplyConditioning(array, shifted, shift_only);
  EXPECT_NEAR(shifted.t0_s, 0.003, 1e-15);

  config.time.start_s = 0.2;
  config.time.end_s = 0.3;
  TestSignals empty = NoisySignals(0.0, 1000);
  EXPECT_THROW(ApplyConditioning(array, empty, config), InputError);
}

TEST(Conditioning, FilteringHappensBeforeTheCrop) {
  // Cropping after filtering means the crop edges see real neighbours.
  const ArrayGeometry array = OneLinearOneRate();
  ProcessingConfig config;
  config.bias.mode = BiasMode::kNone;
  config.time.start_s = 0.005;
  config.time.end_s = 0.015;
  TestSignals signals = NoisySignals(0.0, 400);
  const Eigen::MatrixXd raw = signals.samples;
  ApplyConditioning(array, signals, config);
  Eigen::VectorXd full(400);
  CfcFilter(1000.0, 1e-4).Apply(raw.col(0), full);
  EXPECT_EQ(signals.samples.col(0), full.segment(50, 101));
}

TEST(Conditioning, NonFiniteSampleNamesTheChannel) {
  const ArrayGeometry array = OneLinearOneRate();
  TestSignals signals = NoisySignals(0.0, 100);
  signals.samples(42, 1) = std::nan("");
  try {
    ApplyConditioning(array, signals, ProcessingConfig{});
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("ars_x"), std::string::npos) << message;
    EXPECT_NE(message.find("42"), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace napkin::engine

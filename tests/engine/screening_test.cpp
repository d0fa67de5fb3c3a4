// Data screening (report sections 2.2 and 3.4): each fault injected into an
// otherwise clean synthetic test is caught by the right check naming the
// right channel(s); clean tests (exact, noisy and filtered, displaced
// sensors with their true geometry) raise nothing above info. Also the noise
// acceptance test of the default processing (issue 3).
#include "engine/screening.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "common/error.h"
#include "engine/criteria.h"
#include "engine/pipeline.h"
#include "engine/units.h"
#include "synth/synthetic_tests.h"
#include "tests/support/reference_arrays.h"

namespace napkin::engine {
namespace {

using Eigen::Index;

const Eigen::Vector3d kTiltedOrientation(0.3, -0.4, 0.8);

synth::SyntheticTest RandomTest(const ArrayGeometry& array, std::uint64_t seed) {
  synth::RandomMotionOptions options;
  options.seed = seed;
  return synth::SynthRandomMotion(array, options);
}

// White noise of `rms_g` on every linear channel (seeded).
void AddLinearNoise(synth::SyntheticTest& test, double rms_g, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (std::size_t i = 0; i < test.array.sensors.size(); ++i) {
    const Sensor& sensor = test.array.sensors[i];
    if (sensor.kind != SensorKind::kLinear) continue;
    const double rms = rms_g * kStandardGravity / sensor.si_per_unit;
    auto column = test.signals.samples.col(test.signals.FindSlot(sensor.slot));
    for (Index k = 0; k < column.size(); ++k) column(k) += rms * noise(rng);
  }
}

Eigen::Ref<Eigen::VectorXd> Column(synth::SyntheticTest& test, const std::string& slot) {
  const int column = test.signals.FindSlot(slot);
  EXPECT_GE(column, 0) << slot;
  return test.signals.samples.col(column);
}

std::vector<Finding> ProcessFindings(const synth::SyntheticTest& test, const ProcessingConfig& config = {}) {
  return ProcessTest(test.array, test.signals, test.initial, config).summary.findings;
}

std::string DescribeFindings(const std::vector<Finding>& findings);

// The findings ProcessTest has gathered (default config) when it stops on
// diverged kinematics: the raw-signal checks, then the rigid-body checks on
// the exact solve of the conditioned signals.
std::vector<Finding> FindingsBeforeDivergence(const synth::SyntheticTest& test) {
  const ProcessingConfig config;
  std::vector<Finding> findings = ScreenSignals(test.array, test.signals, test.initial, config);
  TestSignals conditioned = test.signals;
  ApplyConditioning(test.array, conditioned, config);
  const SolveOptions exact_options = MakeSolveOptions(config, test.initial);
  EXPECT_EQ(exact_options.solver, SolverKind::kExact);
  const Kinematics kinematics = Solve(test.array, conditioned, exact_options);
  AppendFindings(ScreenConsistency(test.array, conditioned, kinematics, exact_options, config.screening),
                 findings);
  return findings;
}

// Findings of ProcessTest on a faulty test. A fault that makes the solved
// kinematics diverge stops ProcessTest with an InputError that must name
// the channel at fault; the findings then come from the screening checks
// ProcessTest ran before it stopped.
std::vector<Finding> FaultFindings(const synth::SyntheticTest& test, const std::string& slot) {
  try {
    return ProcessFindings(test);
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("diverge"), std::string::npos) << message;
    EXPECT_NE(message.find(slot), std::string::npos) << message;
    return FindingsBeforeDivergence(test);
  }
}

std::string DescribeFindings(const std::vector<Finding>& findings) {
  std::string text;
  for (const Finding& f : findings)
    text += std::string("  [") + NameOf(f.severity) + "] " + f.check + " " + f.channel.value_or("-") + ": " +
            f.detail + "\n";
  return text;
}

std::vector<Finding> AboveInfo(const std::vector<Finding>& findings) {
  std::vector<Finding> serious;
  for (const Finding& f : findings)
    if (f.severity != Severity::kInfo) serious.push_back(f);
  return serious;
}

const Finding* FindCheck(const std::vector<Finding>& findings, const std::string& check,
                         const std::string& channel) {
  for (const Finding& f : findings)
    if (f.check == check && f.channel == channel) return &f;
  return nullptr;
}

// The check fired for `channel` with `severity`, and the same check named no
// other channel.
void ExpectOnly(const std::vector<Finding>& findings, const std::string& check,
                const std::vector<std::string>& channels, Severity severity, const std::string& context) {
  for (const std::string& channel : channels) {
    const Finding* finding = FindCheck(findings, check, channel);
    ASSERT_NE(finding, nullptr) << context << ": no " << check << " finding for " << channel << "\n"
                                << DescribeFindings(findings);
    EXPECT_EQ(finding->severity, severity) << context;
    EXPECT_NE(finding->detail.find(channel), std::string::npos) << finding->detail;
  }
  for (const Finding& f : findings) {
    if (f.check != check) continue;
    EXPECT_TRUE(f.channel && std::find(channels.begin(), channels.end(), *f.channel) != channels.end())
        << context << ": " << check << " also names " << f.channel.value_or("none") << "\n"
        << DescribeFindings(findings);
  }
}

// Clean tests over the report's arrays: random motions and the section 4.5
// fixed-axis rotation (tilted, so every NAP channel carries signal).
std::vector<synth::SyntheticTest> FaultHosts() {
  std::vector<synth::SyntheticTest> hosts;
  for (std::uint64_t seed : {1, 2, 3}) hosts.push_back(RandomTest(test_support::Denton3222(), seed));
  hosts.push_back(RandomTest(test_support::Ideal3222(), 4));
  hosts.push_back(synth::SynthSeedFixedAxis(test_support::Denton3222(), kTiltedOrientation));
  return hosts;
}

TEST(Screening, CleanTestsRaiseNothingAboveInfo) {
  std::vector<std::pair<std::string, synth::SyntheticTest>> tests;
  for (std::uint64_t seed = 1; seed <= 6; ++seed)
    tests.emplace_back("denton", RandomTest(test_support::Denton3222(), seed));
  for (std::uint64_t seed = 7; seed <= 9; ++seed)
    tests.emplace_back("ideal", RandomTest(test_support::Ideal3222(), seed));
  for (std::uint64_t seed = 10; seed <= 12; ++seed)
    tests.emplace_back("ars12", RandomTest(test_support::NapArs12(), seed));
  for (std::uint64_t seed = 13; seed <= 14; ++seed)
    tests.emplace_back("6aw", RandomTest(test_support::SixAOmegaCg(), seed));
  tests.emplace_back("fixed-axis", synth::SynthSeedFixedAxis(test_support::Denton3222(), kTiltedOrientation));
  tests.emplace_back("fixed-axis-upright",
                     synth::SynthSeedFixedAxis(test_support::Ideal3222(), Eigen::Vector3d::Zero()));
  tests.emplace_back("sequential", synth::SynthSequential(test_support::Denton3222()));
  // Noisy (0.5 g RMS) and conditioned with the defaults.
  for (std::uint64_t seed = 21; seed <= 26; ++seed) {
    synth::SyntheticTest test =
        RandomTest(seed % 2 ? test_support::Denton3222() : test_support::NapArs12(), seed);
    AddLinearNoise(test, 0.5, 100 + seed);
    tests.emplace_back("noisy", std::move(test));
  }
  // Sensors displaced up to 5 mm, processed with their true geometry.
  for (std::uint64_t seed = 31; seed <= 33; ++seed)
    tests.emplace_back("displaced",
                       RandomTest(synth::DisplaceSensors(test_support::Denton3222(), 0.005, seed), seed));
  ASSERT_GE(tests.size(), 20u);
  for (const auto& [kind, test] : tests) {
    const std::vector<Finding> findings = ProcessFindings(test);
    EXPECT_TRUE(AboveInfo(findings).empty()) << kind << " " << test.name << "\n"
                                             << DescribeFindings(findings);
  }
}

TEST(Screening, ArrayWithoutRedundancySaysSoAtInfo) {
  const synth::SyntheticTest test = RandomTest(test_support::SixAOmegaCg(), 3);
  EXPECT_EQ(ResidualRedundancy(test.array), 0);
  EXPECT_EQ(ResidualRedundancy(test_support::Denton3222()), 3);
  EXPECT_EQ(ResidualRedundancy(test_support::NapArs12()), 6);
  const std::vector<Finding> findings = ProcessFindings(test);
  ASSERT_EQ(findings.size(), 1u) << DescribeFindings(findings);
  EXPECT_EQ(findings[0].check, "consistency");
  EXPECT_EQ(findings[0].severity, Severity::kInfo);
  EXPECT_FALSE(findings[0].channel.has_value());
}

TEST(Screening, FlippedSignIsAPolarityError) {
  int host_index = 0;
  for (const synth::SyntheticTest& host : FaultHosts()) {
    ++host_index;
    for (const std::string slot : {"cg_x", "cg_z", "yarm_z", "yarm_x", "xarm_y", "zarm_x", "zarm_y"}) {
      synth::SyntheticTest test = host;
      Column(test, slot) *= -1.0;
      const std::vector<Finding> findings = FaultFindings(test, slot);
      ExpectOnly(findings, "polarity", {slot}, Severity::kError, test.name + " flipped " + slot);
      EXPECT_EQ(FindCheck(findings, "axis_label", slot), nullptr) << DescribeFindings(findings);
    }
  }
  EXPECT_EQ(host_index, 5);
}

TEST(Screening, SwappedChannelsAreAnAxisLabelError) {
  const std::vector<std::pair<std::string, std::string>> pairs = {
      {"yarm_z", "yarm_x"}, {"xarm_z", "xarm_y"}, {"zarm_x", "zarm_y"}, {"cg_x", "cg_y"}, {"cg_z", "xarm_z"}};
  for (const synth::SyntheticTest& host : FaultHosts()) {
    for (const auto& [first, second] : pairs) {
      synth::SyntheticTest test = host;
      Column(test, first).swap(Column(test, second));
      const std::vector<Finding> findings = FaultFindings(test, first);
      std::string what = test.name;
      what.append(" swapped ").append(first).append("/").append(second);
      ExpectOnly(findings, "axis_label", {first, second}, Severity::kError, what);
      EXPECT_EQ(FindCheck(findings, "polarity", first), nullptr) << DescribeFindings(findings);
    }
  }
}

TEST(Screening, ClippedChannelIsASaturationError) {
  for (const synth::SyntheticTest& host : FaultHosts()) {
    for (const std::string slot : {"cg_y", "yarm_x", "xarm_z", "zarm_y"}) {
      synth::SyntheticTest test = host;
      auto column = Column(test, slot);
      const double clip = 0.8 * column.cwiseAbs().maxCoeff();
      column = column.cwiseMax(-clip).cwiseMin(clip);
      const std::vector<Finding> findings = FaultFindings(test, slot);
      ExpectOnly(findings, "saturation", {slot}, Severity::kError, test.name + " clipped " + slot);
    }
  }
}

TEST(Screening, SpikeIsAWarningAtItsSample) {
  std::mt19937_64 rng(7);
  for (const synth::SyntheticTest& host : FaultHosts()) {
    for (const std::string slot : {"cg_x", "yarm_z", "xarm_y", "zarm_x"}) {
      synth::SyntheticTest test = host;
      auto column = Column(test, slot);
      std::uniform_int_distribution<Index> where(10, column.size() - 10);
      const Index k = where(rng);
      column(k) += (k % 2 ? 100.0 : -100.0);  // g
      const std::vector<Finding> findings = FaultFindings(test, slot);
      ExpectOnly(findings, "spike", {slot}, Severity::kWarning, test.name + " spike on " + slot);
      const Finding* spike = FindCheck(findings, "spike", slot);
      ASSERT_NE(spike, nullptr);
      EXPECT_NE(spike->detail.find("at sample " + std::to_string(k) + " "), std::string::npos)
          << spike->detail;
    }
  }
}

TEST(Screening, SpikeOnTheCrashPulseOfANoisyRecordIsFoundWithoutFalseAlarms) {
  synth::SyntheticTest test = RandomTest(test_support::Denton3222(), 8);
  AddLinearNoise(test, 0.5, 808);
  auto column = Column(test, "yarm_x");
  Index peak_at = 0;
  column.cwiseAbs().maxCoeff(&peak_at);
  column(peak_at) += (column(peak_at) > 0 ? 80.0 : -80.0);
  const std::vector<Finding> findings = ProcessFindings(test);
  ExpectOnly(findings, "spike", {"yarm_x"}, Severity::kWarning, "spike at the peak");
}

TEST(Screening, TwoGBiasWithoutPreImpactDataIsAWarning) {
  for (const synth::SyntheticTest& host : FaultHosts()) {
    for (const std::string slot : {"cg_x", "cg_y", "yarm_z", "xarm_z", "zarm_y"}) {
      synth::SyntheticTest test = host;
      Column(test, slot).array() += 2.0;
      ExpectOnly(FaultFindings(test, slot), "bias", {slot}, Severity::kWarning,
                 test.name + " bias on " + slot);
    }
  }
}

// The record starts 10 ms before the impact (head at rest, zeroed channels
// reading 0), noisy: a 2 g offset shows in the pre-impact mean.
TEST(Screening, TwoGBiasInThePreImpactMeanIsAWarning) {
  for (std::uint64_t seed : {1, 2}) {
    for (const std::string slot : {"cg_z", "yarm_x", "zarm_y"}) {
      synth::SyntheticTest test = RandomTest(test_support::Denton3222(), seed);
      const Index pre = 100;
      Eigen::MatrixXd samples = Eigen::MatrixXd::Zero(pre + test.signals.size(), test.signals.samples.cols());
      samples.bottomRows(test.signals.size()) = test.signals.samples;
      test.signals.samples = samples;
      test.signals.t0_s = -static_cast<double>(pre) * test.signals.dt_s;
      test.initial.velocity_fixed_mps.setZero();  // the head rests before the impact
      AddLinearNoise(test, 0.5, seed);
      const std::vector<Finding> clean = ProcessFindings(test);
      EXPECT_TRUE(AboveInfo(clean).empty()) << DescribeFindings(clean);
      Column(test, slot).array() += 2.0;
      const std::vector<Finding> findings = ProcessFindings(test);
      ExpectOnly(findings, "bias", {slot}, Severity::kWarning, test.name + " pre-impact bias on " + slot);
      const Finding* bias = FindCheck(findings, "bias", slot);
      ASSERT_NE(bias, nullptr);
      EXPECT_NE(bias->detail.find("pre-impact mean"), std::string::npos) << bias->detail;
      EXPECT_NE(bias->detail.find("subtracts it"), std::string::npos) << bias->detail;
      // The default bias removal subtracts it, so the array stays rigid.
      EXPECT_EQ(std::count_if(findings.begin(), findings.end(),
                              [](const Finding& f) { return f.check == "residual"; }),
                0)
          << DescribeFindings(findings);
    }
  }
}

TEST(Screening, NanDropoutIsAnErrorAndStopsProcessingNamingSlotAndSample) {
  for (const synth::SyntheticTest& host : FaultHosts()) {
    for (const std::string slot : {"cg_y", "yarm_x", "zarm_x"}) {
      synth::SyntheticTest test = host;
      auto column = Column(test, slot);
      const Index first = column.size() / 3;
      column.segment(first, 25).setConstant(std::nan(""));
      const std::vector<Finding> findings =
          ScreenSignals(test.array, test.signals, test.initial, ProcessingConfig{});
      ExpectOnly(findings, "non_finite", {slot}, Severity::kError, test.name + " NaN in " + slot);
      try {
        ProcessTest(test.array, test.signals, test.initial, ProcessingConfig{});
        ADD_FAILURE() << "no InputError for a NaN dropout in " << slot;
      } catch (const InputError& error) {
        const std::string message = error.what();
        EXPECT_NE(message.find("channel " + slot + " "), std::string::npos) << message;
        EXPECT_NE(message.find("25 non-finite samples"), std::string::npos) << message;
        EXPECT_NE(message.find("sample " + std::to_string(first) + " "), std::string::npos) << message;
        EXPECT_NE(message.find("sample " + std::to_string(first + 24) + " "), std::string::npos) << message;
      }
    }
  }
}

TEST(Screening, MissingChannelIsAnErrorNamingTheSlot) {
  synth::SyntheticTest test = RandomTest(test_support::Denton3222(), 1);
  test.signals.slots[4] = "not_a_slot";
  const std::vector<Finding> findings =
      ScreenSignals(test.array, test.signals, test.initial, ProcessingConfig{});
  ExpectOnly(findings, "missing", {"yarm_x"}, Severity::kError, "missing yarm_x");
  try {
    ProcessTest(test.array, test.signals, test.initial, ProcessingConfig{});
    ADD_FAILURE() << "no InputError for a missing channel";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("yarm_x"), std::string::npos) << error.what();
  }
}

// Report section 2.2 also names scale-factor errors: a channel reading 50 %
// high is inconsistent with a rigid body; the residual names it.
TEST(Screening, ScaleFactorErrorShowsInTheResidualNamingTheChannel) {
  for (const synth::SyntheticTest& host : FaultHosts()) {
    for (const std::string slot : {"cg_x", "yarm_z", "xarm_y"}) {
      synth::SyntheticTest test = host;
      Column(test, slot) *= 1.5;
      const std::vector<Finding> findings = FaultFindings(test, slot);
      ExpectOnly(findings, "residual", {slot}, Severity::kWarning, test.name + " gain error on " + slot);
      EXPECT_TRUE(std::none_of(findings.begin(), findings.end(), [](const Finding& f) {
        return f.check == "polarity" || f.check == "axis_label";
      })) << DescribeFindings(findings);
    }
  }
}

TEST(Screening, SeedSolverRunsAreScreenedWithTheExactResidual) {
  synth::SyntheticTest test = synth::SynthSeedFixedAxis(test_support::Ideal3222(), kTiltedOrientation);
  Column(test, "yarm_x") *= -1.0;
  ProcessingConfig config;
  config.solver = SolverKind::kSeed;
  ExpectOnly(ProcessFindings(test, config), "polarity", {"yarm_x"}, Severity::kError,
             "seed solver, flipped yarm_x");
}

// The verdict beside ProcessTest: a clean test and one with warnings only
// pass; the first error-severity finding fails the test with its sentence.
TEST(Verdict, FirstErrorFindingFailsTheTest) {
  const synth::SyntheticTest clean = RandomTest(test_support::NapArs12(), 3);
  EXPECT_EQ(FailingFinding(ProcessTest(clean.array, clean.signals, clean.initial, {})), nullptr);

  // A spike the rigid body pins on one channel is a faulty channel (issue 41):
  // the spike warning and a `fault` error; salvage repairs it.
  synth::SyntheticTest spiked = clean;
  Column(spiked, "yarm_z")(700) += 100.0;  // g
  const ProcessedTest warned = ProcessTest(spiked.array, spiked.signals, spiked.initial, {});
  ExpectOnly(warned.summary.findings, "spike", {"yarm_z"}, Severity::kWarning, "spike on yarm_z");
  ASSERT_NE(FailingFinding(warned), nullptr) << DescribeFindings(warned.summary.findings);
  EXPECT_EQ(FailingFinding(warned)->check, "fault");
  EXPECT_EQ(FailingFinding(warned)->channel, "yarm_z");
  ProcessingConfig repair;
  repair.screening.salvage = SalvageMode::kRepair;
  const ProcessedTest repaired = ProcessTest(spiked.array, spiked.signals, spiked.initial, repair);
  EXPECT_EQ(FailingFinding(repaired), nullptr) << DescribeFindings(repaired.summary.findings);
  EXPECT_TRUE(repaired.summary.salvage.has_value());

  synth::SyntheticTest flipped = clean;
  Column(flipped, "yarm_z") *= -1.0;
  const ProcessedTest failed = ProcessTest(flipped.array, flipped.signals, flipped.initial, {});
  const Finding* failing = FailingFinding(failed);
  ASSERT_NE(failing, nullptr) << DescribeFindings(failed.summary.findings);
  EXPECT_EQ(failing->check, "polarity");
  EXPECT_EQ(failing->channel, "yarm_z");
  EXPECT_EQ(failing->severity, Severity::kError);
  for (const Finding& f : failed.summary.findings) {
    if (&f == failing) break;
    EXPECT_NE(f.severity, Severity::kError) << "not the first error finding\n"
                                            << DescribeFindings(failed.summary.findings);
  }
}

TEST(Screening, FlatChannelIsInfo) {
  synth::SyntheticTest test = RandomTest(test_support::Denton3222(), 2);
  const std::vector<Finding> clean =
      ScreenSignals(test.array, test.signals, test.initial, ProcessingConfig{});
  EXPECT_TRUE(clean.empty()) << DescribeFindings(clean);
  Column(test, "cg_z").setConstant(0.25);
  const std::vector<Finding> findings =
      ScreenSignals(test.array, test.signals, test.initial, ProcessingConfig{});
  ExpectOnly(findings, "flat", {"cg_z"}, Severity::kInfo, "flat cg_z");
}

// Issue 3 acceptance: white noise of 0.5 g RMS on every channel at 10 kHz,
// default processing: the exact solver stays within 2 % of the true peak
// angular velocity and 1 % of the true HIC15 over >= 10 random motions.
TEST(Screening, NoisyTestsWithDefaultFilteringKeepPeakOmegaAndHic15) {
  double worst_omega = 0.0, worst_hic = 0.0;
  int motions = 0;
  for (const ArrayGeometry& array : {test_support::Denton3222(), test_support::Ideal3222()}) {
    for (std::uint64_t seed = 1; seed <= 6; ++seed) {
      synth::SyntheticTest test = RandomTest(array, seed);
      ASSERT_DOUBLE_EQ(test.signals.dt_s, 1e-4);
      AddLinearNoise(test, 0.5, 1000 + seed);
      const ProcessedTest processed = ProcessTest(test.array, test.signals, test.initial, ProcessingConfig{});
      const double true_omega = test.truth.omega_body.rowwise().norm().maxCoeff();
      const Eigen::VectorXd true_acc_g = test.truth.acc_fixed.rowwise().norm() / kStandardGravity;
      HicOptions window;
      window.window_s = kHic15Window;
      const double true_hic15 = Hic(true_acc_g, test.signals.dt_s, test.signals.t0_s, window).value;
      const double omega_error = std::abs(processed.summary.peak_omega_radps / true_omega - 1.0);
      const double hic_error = std::abs(processed.summary.hic15.value / true_hic15 - 1.0);
      EXPECT_LE(omega_error, 0.02) << array.name << " seed " << seed;
      EXPECT_LE(hic_error, 0.01) << array.name << " seed " << seed;
      worst_omega = std::max(worst_omega, omega_error);
      worst_hic = std::max(worst_hic, hic_error);
      ++motions;
    }
  }
  EXPECT_GE(motions, 10);
  std::printf("noise 0.5 g RMS, %d motions: worst peak-omega error %.3f %%, worst HIC15 error %.3f %%\n",
              motions, 100.0 * worst_omega, 100.0 * worst_hic);
}

}  // namespace
}  // namespace napkin::engine

// The transform of one test without a catalogue (app/transform.h), called
// directly: signals from samples in memory read back bit for bit and are
// refused naming the sample and channel or the time at fault; ProcessSignals
// is engine::ProcessTest's answer; RunTransform reads a signals CSV to the same
// samples, computes the same kinematics and writes the derived-channel CSV that
// reads back to them (to its 12 significant digits, docs/formats.md "Derived channels");
// an unknown solver is refused and nothing written.
#include "app/transform.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "common/error.h"
#include "engine/summary_fields.h"
#include "formats/array_json.h"
#include "formats/csv.h"
#include "formats/model_curves.h"
#include "synth/synthetic_tests.h"
#include "tests/app/app_test_util.h"
#include "tests/jobs/jobs_test_helpers.h"
#include "tests/support/test_support.h"

namespace napkin::app {
namespace {

namespace fs = std::filesystem;

synth::SyntheticTest RandomTest() {
  synth::RandomMotionOptions options;
  options.seed = 7;
  options.duration_s = 0.05;
  return synth::SynthRandomMotion(formats::LoadArray("ideal-3222"), options);
}

TEST(SignalsFromSamples, ReadBackBitForBitAndRefuseWhatTheCsvReaderRefuses) {
  const synth::SyntheticTest test = RandomTest();
  const engine::TestSignals signals =
      SignalsFromSamples(test.signals.samples, test.array, test.signals.dt_s, "memory");
  EXPECT_EQ(signals.samples, test.signals.samples);
  EXPECT_EQ(signals.dt_s, test.signals.dt_s);
  EXPECT_EQ(signals.t0_s, 0.0);
  ASSERT_EQ(signals.slots.size(), test.array.sensors.size());
  for (std::size_t s = 0; s < signals.slots.size(); ++s)
    EXPECT_EQ(signals.slots[s], test.array.sensors[s].slot);
  // One time per sample, uniformly spaced from 0.25 s.
  std::vector<double> times;
  for (Eigen::Index k = 0; k < test.signals.samples.rows(); ++k)
    times.push_back(0.25 + 1e-4 * static_cast<double>(k));
  const engine::TestSignals timed =
      SignalsFromSamples(test.signals.samples, test.array, std::span<const double>(times), "memory");
  EXPECT_NEAR(timed.t0_s, 0.25, 1e-15);
  EXPECT_NEAR(timed.dt_s, 1e-4, 1e-15);

  Eigen::MatrixXd bad = test.signals.samples;
  bad(5, 2) = std::nan("");
  const std::string nan =
      test_support::ErrorText<InputError>([&] { SignalsFromSamples(bad, test.array, 1e-4, "memory"); });
  EXPECT_NE(nan.find("memory: sample 5, channel \"" + test.array.sensors[2].slot + "\""), std::string::npos)
      << nan;
  times[3] += 5e-5;  // half a step late
  const std::string late = test_support::ErrorText<InputError>([&] {
    SignalsFromSamples(test.signals.samples, test.array, std::span<const double>(times), "memory");
  });
  EXPECT_NE(late.find("memory: "), std::string::npos) << late;
  EXPECT_NE(late.find("time_s["), std::string::npos) << late;
  const std::string one = test_support::ErrorText<InputError>(
      [&] { SignalsFromSamples(test.signals.samples.topRows(1), test.array, 1e-4, "memory"); });
  EXPECT_EQ(one.rfind("memory", 0), 0u) << one;
}

TEST(ProcessSignals, IsTheEnginesProcessing) {
  const synth::SyntheticTest test = RandomTest();
  const engine::ProcessingConfig config;
  const engine::ProcessedTest processed =
      ProcessSignals(test.array, test.signals, test.initial, config, "memory");
  const engine::ProcessedTest engine_answer =
      engine::ProcessTest(test.array, test.signals, test.initial, config);
  test_support::ExpectSameKinematics(processed.kinematics, engine_answer.kinematics, "memory");
  EXPECT_TRUE(engine::DifferingSummaryFields(processed.summary, engine_answer.summary).empty());
}

class RunTransformTest : public ::testing::Test {
 protected:
  void SetUp() override {
    test_ = RandomTest();
    input_ = dir_ / "signals.csv";
    formats::WriteSignalsCsv(test_.signals, input_);
    options_.input.path = input_.string();
    options_.input.array = "ideal-3222";
    options_.orientation_rad = {test_.initial.orientation_rad.x(), test_.initial.orientation_rad.y(),
                                test_.initial.orientation_rad.z()};
    options_.initial_velocity_mps = {test_.initial.velocity_fixed_mps.x(),
                                     test_.initial.velocity_fixed_mps.y(),
                                     test_.initial.velocity_fixed_mps.z()};
  }
  test_support::TempDir dir_;
  synth::SyntheticTest test_;
  fs::path input_;
  TransformOptions options_;
};

TEST_F(RunTransformTest, TheFilesSamplesTheEnginesKinematicsAndADerivedCsvThatReadsBack) {
  options_.out = (dir_ / "derived.csv").string();
  options_.summary = (dir_ / "summary.json").string();
  const TransformReport report = RunTransform(options_);

  const TestFile read = ReadTestFile(options_.input);
  EXPECT_EQ(read.signals.samples, test_.signals.samples);  // the CSV holds every digit
  engine::InitialState initial;
  initial.orientation_rad = test_.initial.orientation_rad;
  initial.velocity_fixed_mps = test_.initial.velocity_fixed_mps;
  const engine::ProcessedTest processed =
      ProcessSignals(read.array, read.signals, initial, engine::ProcessingConfig{}, input_.string());
  test_support::ExpectSameKinematics(report.kinematics, processed.kinematics, "signals.csv");
  EXPECT_TRUE(engine::DifferingSummaryFields(report.summary, processed.summary).empty());
  EXPECT_TRUE(fs::exists(dir_ / "summary.json"));

  // The derived-channel CSV is a model CSV: its omega_body_y_radps is the kinematics' to 12 digits.
  const std::vector<formats::ModelCurve> columns = formats::ReadModelCsv(dir_ / "derived.csv");
  const auto omega = std::find_if(columns.begin(), columns.end(), [](const formats::ModelCurve& c) {
    return c.name == "omega_body_y_radps";
  });
  ASSERT_NE(omega, columns.end());
  ASSERT_EQ(omega->series.values.size(), report.kinematics.omega_body.rows());
  ASSERT_GT(report.kinematics.omega_body.col(1).cwiseAbs().maxCoeff(), 1.0);
  for (Eigen::Index k = 0; k < omega->series.values.size(); ++k)
    ASSERT_LE(std::abs(omega->series.values(k) - report.kinematics.omega_body(k, 1)),
              5.01e-12 * std::abs(report.kinematics.omega_body(k, 1)))
        << k;
}

// An unknown solver is an error, never the exact solver (issue 8), and nothing is written.
TEST_F(RunTransformTest, AnUnknownSolverIsRefusedAndNothingWritten) {
  options_.solver = "fast";
  options_.out = (dir_ / "fast.csv").string();
  const std::string message = test_support::ErrorText<InputError>([&] { RunTransform(options_); });
  EXPECT_NE(message.find("unknown solver \"fast\""), std::string::npos) << message;
  EXPECT_NE(message.find("exact or seed"), std::string::npos) << message;
  EXPECT_FALSE(fs::exists(dir_ / "fast.csv"));
}

}  // namespace
}  // namespace napkin::app

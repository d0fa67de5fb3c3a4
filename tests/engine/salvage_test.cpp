// Faulty channels (engine/salvage.h, docs/algorithms.md "Faulty channels"):
// a channel broken the way channels break in real tests (a dropout to zero,
// a stuck reading, a clipped top, spikes, a flipped sign, two swapped
// channels) is never published: with salvage off the test fails naming the
// channel and saying what salvage would do; with salvage exclude or repair
// the result equals the synthetic truth within the documented accuracy,
// with the record of what was done. Clean and noisy tests raise no fault
// and give bit-identical results under every salvage mode.
#include "engine/salvage.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "engine/criteria.h"
#include "engine/pipeline.h"
#include "engine/units.h"
#include "synth/synthetic_tests.h"
#include "tests/engine/error_metrics.h"
#include "tests/support/reference_arrays.h"

namespace napkin::engine::salvage_test {
namespace {

using Eigen::Index;

enum class Fault { kDropout, kStuck, kClipped, kSpikes, kFlipped, kSwapped };

const char* NameOfFault(Fault fault) {
  switch (fault) {
    case Fault::kDropout:
      return "dropout";
    case Fault::kStuck:
      return "stuck";
    case Fault::kClipped:
      return "clipped";
    case Fault::kSpikes:
      return "spikes";
    case Fault::kFlipped:
      return "flipped";
    case Fault::kSwapped:
      return "swapped";
  }
  return "?";
}

Eigen::Ref<Eigen::VectorXd> Column(synth::SyntheticTest& test, const std::string& slot) {
  return test.signals.samples.col(test.signals.FindSlot(slot));
}

// The sample where the channel's own reading peaks in magnitude: a fault
// there is what a cable torn at impact does.
Index PeakOf(const Eigen::Ref<const Eigen::VectorXd>& x) {
  Index at = 0;
  x.cwiseAbs().maxCoeff(&at);
  return at;
}

// Breaks `slot` of `test` as `fault` says (`partner` for a swap).
void Inject(synth::SyntheticTest& test, Fault fault, const std::string& slot,
            const std::string& partner = "") {
  auto x = Column(test, slot);
  const Index n = x.size();
  const Index peak = PeakOf(x);
  const auto samples_of = [&test](double seconds) { return std::llround(seconds / test.signals.dt_s); };
  switch (fault) {
    case Fault::kDropout: {  // 2 ms of zeros at the channel's peak
      const Index half = samples_of(0.001);
      for (Index k = std::max<Index>(0, peak - half); k < std::min<Index>(n, peak + half); ++k) x(k) = 0.0;
      break;
    }
    case Fault::kStuck: {  // a flat line for 6 ms across the peak
      const Index start = std::max<Index>(0, peak - samples_of(0.003));
      const double held = x(start);
      for (Index k = start; k < std::min<Index>(n, start + samples_of(0.006)); ++k) x(k) = held;
      break;
    }
    case Fault::kClipped: {  // the amplifier saturates at 60 % of the peak
      const double limit = 0.6 * std::abs(x(peak));
      for (Index k = 0; k < n; ++k) x(k) = std::clamp(x(k), -limit, limit);
      break;
    }
    case Fault::kSpikes: {  // three one-sample spikes of 60 g
      for (const Index k : {n / 4, n / 2, peak}) x(std::min(k, n - 2)) += 60.0 * kStandardGravity / 9.80665;
      break;
    }
    case Fault::kFlipped:
      x *= -1.0;
      break;
    case Fault::kSwapped: {
      const Eigen::VectorXd copy = x;
      auto y = Column(test, partner);
      x = y;
      y = copy;
      break;
    }
  }
}

ProcessingConfig WithSalvage(SalvageMode mode) {
  ProcessingConfig config;
  config.screening.salvage = mode;
  return config;
}

double TrueHic15(const synth::SyntheticTest& test) {
  const Eigen::VectorXd acc_g = test.truth.acc_fixed.rowwise().norm() / kStandardGravity;
  HicOptions window;
  window.window_s = kHic15Window;
  return Hic(acc_g, test.signals.dt_s, test.signals.t0_s, window).value;
}

// How far a published result is from the truth.
struct Accuracy {
  double omega_rel = 0.0;  // max |omega - truth| / max |truth|
  double hic15_rel = 0.0;
  double orientation_deg = 0.0;
};

Accuracy AccuracyOf(const ProcessedTest& processed, const synth::SyntheticTest& test) {
  const test_support::KinematicsErrors errors =
      test_support::CompareKinematics(processed.kinematics, test.truth);
  return {errors.omega_rel, std::abs(processed.summary.hic15.value / TrueHic15(test) - 1.0),
          errors.orientation_deg};
}

std::string Describe(const std::vector<Finding>& findings) {
  std::string text;
  for (const Finding& f : findings)
    text += std::string("  [") + NameOf(f.severity) + "] " + f.check + " " + f.channel.value_or("-") + ": " +
            f.detail + "\n";
  return text;
}

synth::SyntheticTest RandomTest(const ArrayGeometry& array, std::uint64_t seed) {
  synth::RandomMotionOptions options;
  options.seed = seed;
  return synth::SynthRandomMotion(array, options);
}

// White noise of `rms_g` on every linear channel (seeded).
void AddLinearNoise(synth::SyntheticTest& test, double rms_g, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (const Sensor& sensor : test.array.sensors) {
    if (sensor.kind != SensorKind::kLinear) continue;
    const double rms = rms_g * kStandardGravity / sensor.si_per_unit;
    auto column = Column(test, sensor.slot);
    for (Index k = 0; k < column.size(); ++k) column(k) += rms * noise(rng);
  }
}

// The largest fault of a reproduction of the issue: the default config
// fails the test on an error finding naming the channel and saying what
// salvage would do; exclude and repair publish the truth with the record.
void ExpectFailsThenSalvaged(const synth::SyntheticTest& faulty, const std::string& slot,
                             const std::string& context) {
  const ProcessedTest failed = ProcessTest(faulty.array, faulty.signals, faulty.initial, ProcessingConfig{});
  const Finding* failing = FailingFinding(failed);
  ASSERT_NE(failing, nullptr) << context << " was published:\n" << Describe(failed.summary.findings);
  EXPECT_EQ(failing->channel.value_or(""), slot) << context << "\n" << Describe(failed.summary.findings);
  EXPECT_NE(failing->detail.find("--config salvage"), std::string::npos) << failing->detail;
  EXPECT_FALSE(failed.summary.salvage.has_value());
  for (const auto& [mode, tolerance, orientation_deg] :
       {std::tuple{SalvageMode::kExclude, 0.005, 0.1}, std::tuple{SalvageMode::kRepair, 0.01, 0.2}}) {
    const ProcessedTest salvaged =
        ProcessTest(faulty.array, faulty.signals, faulty.initial, WithSalvage(mode));
    const std::string label = context + " salvage " + NameOf(mode);
    ASSERT_EQ(FailingFinding(salvaged), nullptr) << label << ":\n" << Describe(salvaged.summary.findings);
    ASSERT_TRUE(salvaged.summary.salvage.has_value()) << label;
    const SalvageAudit& record = *salvaged.summary.salvage;
    EXPECT_EQ(record.mode, NameOf(mode));
    ASSERT_FALSE(record.channels.empty());
    EXPECT_EQ(record.channels.front().channel, slot) << label;
    EXPECT_LT(record.rms_residual_after_mps2, 0.1 * record.rms_residual_before_mps2) << label;
    const Accuracy accuracy = AccuracyOf(salvaged, faulty);
    EXPECT_LE(accuracy.omega_rel, tolerance) << label;
    EXPECT_LE(accuracy.hic15_rel, tolerance) << label;
    EXPECT_LE(accuracy.orientation_deg, orientation_deg) << label;
    if (mode == SalvageMode::kRepair) {
      EXPECT_GT(record.channels.front().samples_replaced +
                    (record.channels.front().action != SalvageAction::kReplaced),
                0);
      // The repaired channel is kept whole: its good samples are the recorded ones.
      const std::vector<double>& repaired = record.channels.front().repaired_samples;
      ASSERT_EQ(static_cast<Eigen::Index>(repaired.size()), faulty.signals.size()) << label;
      const Eigen::Index column = faulty.signals.FindSlot(slot);
      Eigen::Index kept = 0;
      for (Eigen::Index k = 0; k < faulty.signals.size(); ++k)
        kept += repaired[static_cast<std::size_t>(k)] == faulty.signals.samples(k, column);
      if (record.channels.front().action == SalvageAction::kReplaced) {
        EXPECT_EQ(kept + record.channels.front().samples_replaced, faulty.signals.size()) << label;
      }
    }
  }
}

// The first reproduction: a 2 ms dropout (zeros) on zarm_y at the
// impact peak of a NAP test (47 % of peak omega off, exit 0, before).
TEST(Salvage, DropoutOnZarmYAtThePeakFailsThenIsSalvaged) {
  synth::SyntheticTest test = RandomTest(test_support::Denton3222(), 1);
  Inject(test, Fault::kDropout, "zarm_y");
  ExpectFailsThenSalvaged(test, "zarm_y", "dropout zarm_y");
}

// The second: zarm_x stuck across the peak (24 % of omega off, exit 0).
TEST(Salvage, StuckZarmXAcrossThePeakFailsThenIsSalvaged) {
  synth::SyntheticTest test = RandomTest(test_support::Denton3222(), 2);
  Inject(test, Fault::kStuck, "zarm_x");
  ExpectFailsThenSalvaged(test, "zarm_x", "stuck zarm_x");
}

// The third: a padding-series head impact with cg_x stuck for 11 ms at its
// value at the pulse (HIC15 published 25 % low, before).
TEST(Salvage, PaddingTestWithCgXStuckFor11MsFailsThenRepairsHic15) {
  synth::HeadImpact impact = synth::ScatteredImpact(synth::kPaddingVariants[0], 1);
  synth::SyntheticTest test = synth::SynthHeadImpact(test_support::Denton3222(), impact);
  const ProcessedTest intact = ProcessTest(test.array, test.signals, test.initial, ProcessingConfig{});
  ASSERT_EQ(FailingFinding(intact), nullptr) << Describe(intact.summary.findings);
  auto x = Column(test, "cg_x");
  const Index peak = PeakOf(x);
  const Index start = peak - std::llround(0.004 / test.signals.dt_s);
  for (Index k = start; k < start + std::llround(0.011 / test.signals.dt_s); ++k) x(k) = x(start);
  const ProcessedTest failed = ProcessTest(test.array, test.signals, test.initial, ProcessingConfig{});
  ASSERT_NE(FailingFinding(failed), nullptr) << Describe(failed.summary.findings);
  EXPECT_EQ(FailingFinding(failed)->channel.value_or(""), "cg_x");
  const ProcessedTest repaired =
      ProcessTest(test.array, test.signals, test.initial, WithSalvage(SalvageMode::kRepair));
  ASSERT_EQ(FailingFinding(repaired), nullptr) << Describe(repaired.summary.findings);
  EXPECT_NEAR(repaired.summary.hic15.value / intact.summary.hic15.value, 1.0, 0.01);
  ASSERT_TRUE(repaired.summary.salvage.has_value());
  EXPECT_EQ(repaired.summary.salvage->channels.front().channel, "cg_x");
  EXPECT_EQ(repaired.summary.salvage->channels.front().fault, FaultKind::kStuck);
  // The fault's interval covers the stuck stretch (times of the raw samples).
  EXPECT_LE(repaired.summary.salvage->channels.front().t1_s, test.signals.TimeAt(start + 10));
  EXPECT_GE(repaired.summary.salvage->channels.front().t2_s,
            test.signals.TimeAt(start + std::llround(0.010 / test.signals.dt_s)));
}

// Every fault kind at every channel position of the report's arrays and of
// NAP + ARS: a published result (fault found and salvaged, or too small to
// matter) equals the truth within 0.5 % (exclude) / 1 % (repair) of peak
// omega and of HIC15 and 0.1 / 0.2 deg of orientation; the default config
// publishes nothing farther from the truth than repair's tolerance.
TEST(Salvage, EveryFaultKindAtEveryChannelIsFailedOrPublishedTrue) {
  struct Host {
    ArrayGeometry array;
    std::uint64_t seed;
  };
  const std::vector<Host> hosts = {
      {test_support::Denton3222(), 3}, {test_support::Ideal3222(), 4}, {test_support::NapArs12(), 5}};
  int salvaged_count = 0, failed_default = 0, cases = 0, refused_confounded = 0;
  for (const Host& host : hosts) {
    const synth::SyntheticTest clean = RandomTest(host.array, host.seed);
    // The method's own error on the intact test (filtering: CFC 60 on the
    // rate channels of NAP + ARS costs a few percent of peak omega on these
    // fast motions); salvage may add at most the tolerance to it.
    const Accuracy intact =
        AccuracyOf(ProcessTest(clean.array, clean.signals, clean.initial, ProcessingConfig{}), clean);
    for (const Sensor& sensor : host.array.sensors) {
      // A channel the others cannot predict (the array without it no
      // longer determines the motion) cannot be checked: its fault goes
      // into alpha unseen (docs/algorithms.md "Faulty channels").
      std::string why;
      if (!ArrayWithout(host.array, {sensor.slot}, why)) continue;
      for (const Fault fault : {Fault::kDropout, Fault::kStuck, Fault::kClipped, Fault::kSpikes,
                                Fault::kFlipped, Fault::kSwapped}) {
        std::string partner;
        if (fault == Fault::kSwapped) {
          // The next channel of the same kind (wrapping round).
          const auto& sensors = host.array.sensors;
          const auto self = std::find_if(sensors.begin(), sensors.end(),
                                         [&](const Sensor& s) { return s.slot == sensor.slot; });
          for (auto it = self + 1;; ++it) {
            if (it == sensors.end()) it = sensors.begin();
            if (it == self) break;
            if (it->kind == sensor.kind) {
              partner = it->slot;
              break;
            }
          }
          if (partner.empty()) continue;
        }
        synth::SyntheticTest test = clean;
        Inject(test, fault, sensor.slot, partner);
        const std::string context = host.array.name + " " + NameOfFault(fault) + " " + sensor.slot +
                                    (partner.empty() ? "" : "/" + partner);
        ++cases;
        for (const auto& [mode, tolerance, orientation_deg] :
             {std::tuple{SalvageMode::kOff, 0.01, 0.2}, std::tuple{SalvageMode::kExclude, 0.005, 0.1},
              std::tuple{SalvageMode::kRepair, 0.01, 0.2}}) {
          ProcessedTest processed;
          try {
            processed = ProcessTest(test.array, test.signals, test.initial, WithSalvage(mode));
          } catch (const ScreeningFailure& failure) {
            // Salvage recovers every single fault of these arrays, except
            // one of two confounded channels, which it refuses to guess at.
            const std::string sentence = failure.what();
            const bool confounded = sentence.find("cannot be told apart") != std::string::npos;
            EXPECT_TRUE(mode == SalvageMode::kOff || confounded)
                << context << " salvage " << NameOf(mode) << ": " << sentence;
            if (mode == SalvageMode::kOff) ++failed_default;
            if (confounded && mode != SalvageMode::kOff) ++refused_confounded;
            continue;
          }
          if (FailingFinding(processed) != nullptr) {
            EXPECT_EQ(mode, SalvageMode::kOff) << context << " salvage " << NameOf(mode) << ":\n"
                                               << Describe(processed.summary.findings);
            if (mode == SalvageMode::kOff) ++failed_default;
            continue;
          }
          const Accuracy accuracy = AccuracyOf(processed, test);
          EXPECT_LE(accuracy.omega_rel, intact.omega_rel + tolerance)
              << context << " salvage " << NameOf(mode) << "\n"
              << Describe(processed.summary.findings);
          EXPECT_LE(accuracy.hic15_rel, intact.hic15_rel + tolerance)
              << context << " salvage " << NameOf(mode);
          EXPECT_LE(accuracy.orientation_deg, intact.orientation_deg + orientation_deg)
              << context << " salvage " << NameOf(mode);
          if (processed.summary.salvage) ++salvaged_count;
        }
      }
    }
  }
  std::printf("%d faulty tests: %d failed with salvage off, %d salvaged results, %d refused as confounded\n",
              cases, failed_default, salvaged_count, refused_confounded);
  // Confounded pairs are the exception: the ideal array's xarm_y/yarm_x.
  EXPECT_LE(refused_confounded, 2 * 6 * 2);
  // Every injected fault is found, and salvaged by both modes (or refused
  // as confounded).
  EXPECT_EQ(failed_default, cases);
  EXPECT_EQ(salvaged_count + refused_confounded, 2 * cases);
}

// No false alarms: the clean tests of the report's arrays and NAP + ARS, and
// tests with 0.5 g RMS noise on every linear channel, raise no fault and
// give bit-identical results under every salvage mode.
TEST(Salvage, CleanAndNoisyTestsRaiseNoFaultAndAreIdenticalUnderEveryMode) {
  std::vector<synth::SyntheticTest> tests;
  for (std::uint64_t seed : {1, 2, 3}) tests.push_back(RandomTest(test_support::Denton3222(), seed));
  tests.push_back(RandomTest(test_support::Ideal3222(), 4));
  tests.push_back(RandomTest(test_support::NapArs12(), 5));
  tests.push_back(synth::SynthSeedFixedAxis(test_support::Denton3222(), Eigen::Vector3d(0.3, -0.4, 0.8)));
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    synth::SyntheticTest noisy =
        RandomTest(seed % 2 == 0 ? test_support::Ideal3222() : test_support::Denton3222(), seed);
    AddLinearNoise(noisy, 0.5, 2000 + seed);
    tests.push_back(noisy);
  }
  for (const synth::SyntheticTest& test : tests) {
    const ProcessedTest off = ProcessTest(test.array, test.signals, test.initial, ProcessingConfig{});
    EXPECT_EQ(FailingFinding(off), nullptr) << test.name << ":\n" << Describe(off.summary.findings);
    EXPECT_TRUE(std::none_of(off.summary.findings.begin(), off.summary.findings.end(),
                             [](const Finding& f) { return f.check == "fault"; }))
        << test.name << ":\n"
        << Describe(off.summary.findings);
    for (const SalvageMode mode : {SalvageMode::kExclude, SalvageMode::kRepair}) {
      const ProcessedTest salvaged = ProcessTest(test.array, test.signals, test.initial, WithSalvage(mode));
      EXPECT_FALSE(salvaged.summary.salvage.has_value()) << test.name;
      EXPECT_EQ(salvaged.summary.hic15.value, off.summary.hic15.value) << test.name;
      EXPECT_TRUE(salvaged.kinematics.omega_body.cwiseEqual(off.kinematics.omega_body).all()) << test.name;
      EXPECT_TRUE(
          salvaged.kinematics.quat_fixed_from_body.cwiseEqual(off.kinematics.quat_fixed_from_body).all())
          << test.name;
      EXPECT_EQ(salvaged.summary.findings.size(), off.summary.findings.size()) << test.name;
    }
  }
}

// On noisy tests (0.5 g RMS on every linear channel) the salvaged error is
// at most 1.5x the intact test's.
// On noisy tests (0.5 g RMS on every linear channel) the salvaged error is
// at most 1.5x the intact test's. Judged on the mean over 6 motions and 3
// channel positions: a single test's error of 0.1 % is itself a draw of the
// noise (the intact errors here range from 0.08 % to 0.4 % of HIC15), and
// the claim is about the error salvage adds, not about one draw.
TEST(Salvage, NoisySalvagedErrorIsAtMostOneAndAHalfTimesTheIntactError) {
  struct Sums {
    double omega = 0.0, hic15 = 0.0;
  };
  Sums intact_sum, exclude_sum, repair_sum;
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    synth::SyntheticTest intact = RandomTest(test_support::Denton3222(), seed);
    AddLinearNoise(intact, 0.5, 3000 + seed);
    const Accuracy intact_accuracy =
        AccuracyOf(ProcessTest(intact.array, intact.signals, intact.initial, ProcessingConfig{}), intact);
    for (const std::string slot : {"zarm_y", "xarm_z", "cg_y"}) {
      intact_sum.omega += intact_accuracy.omega_rel;
      intact_sum.hic15 += intact_accuracy.hic15_rel;
      synth::SyntheticTest faulty = intact;
      Inject(faulty, Fault::kDropout, slot);
      for (const SalvageMode mode : {SalvageMode::kExclude, SalvageMode::kRepair}) {
        const ProcessedTest salvaged =
            ProcessTest(faulty.array, faulty.signals, faulty.initial, WithSalvage(mode));
        const std::string label = "seed " + std::to_string(seed) + " " + slot + " " + NameOf(mode);
        ASSERT_EQ(FailingFinding(salvaged), nullptr) << label << "\n" << Describe(salvaged.summary.findings);
        ASSERT_TRUE(salvaged.summary.salvage.has_value()) << label;
        EXPECT_EQ(salvaged.summary.salvage->channels.front().channel, slot) << label;
        const Accuracy accuracy = AccuracyOf(salvaged, faulty);
        Sums& sum = mode == SalvageMode::kExclude ? exclude_sum : repair_sum;
        sum.omega += accuracy.omega_rel;
        sum.hic15 += accuracy.hic15_rel;
      }
    }
  }
  std::printf(
      "noisy salvage, mean error / intact mean error: exclude omega %.2f HIC15 %.2f, repair omega %.2f "
      "HIC15 %.2f\n",
      exclude_sum.omega / intact_sum.omega, exclude_sum.hic15 / intact_sum.hic15,
      repair_sum.omega / intact_sum.omega, repair_sum.hic15 / intact_sum.hic15);
  for (const Sums* sum : {&exclude_sum, &repair_sum}) {
    EXPECT_LE(sum->omega, 1.5 * intact_sum.omega);
    EXPECT_LE(sum->hic15, 1.5 * intact_sum.hic15);
  }
}

// 6aw (three accelerometers and three rate sensors at the CG) has no
// redundant channel: nothing can be excluded, and the sentence says so.
// Two faulty channels of a 3-2-2-2 array are found and left out together.
TEST(Salvage, ArraysSurviveTheLossesTheDocsSay) {
  std::string why;
  EXPECT_FALSE(ArrayWithout(test_support::SixAOmegaCg(), {"ars_x"}, why).has_value());
  EXPECT_NE(why.find("5 of 6"), std::string::npos) << why;
  for (const char* slot : kNapSlots) {
    EXPECT_TRUE(ArrayWithout(test_support::Denton3222(), {slot}, why).has_value()) << slot << ": " << why;
    EXPECT_TRUE(ArrayWithout(test_support::NapArs12(), {slot, "ars_x"}, why).has_value())
        << slot << ": " << why;
  }

  synth::SyntheticTest test = RandomTest(test_support::Denton3222(), 6);
  Inject(test, Fault::kDropout, "zarm_y");
  Inject(test, Fault::kStuck, "cg_z");
  const ProcessedTest failed = ProcessTest(test.array, test.signals, test.initial, ProcessingConfig{});
  ASSERT_NE(FailingFinding(failed), nullptr) << Describe(failed.summary.findings);
  const ProcessedTest excluded =
      ProcessTest(test.array, test.signals, test.initial, WithSalvage(SalvageMode::kExclude));
  ASSERT_EQ(FailingFinding(excluded), nullptr) << Describe(excluded.summary.findings);
  ASSERT_TRUE(excluded.summary.salvage.has_value());
  EXPECT_EQ(excluded.summary.salvage->channels.size(), 2u);
  EXPECT_EQ(excluded.summary.salvage->channels_used, 7);
  const Accuracy accuracy = AccuracyOf(excluded, test);
  EXPECT_LE(accuracy.omega_rel, 0.005);
  EXPECT_LE(accuracy.hic15_rel, 0.005);
}

}  // namespace
}  // namespace napkin::engine::salvage_test

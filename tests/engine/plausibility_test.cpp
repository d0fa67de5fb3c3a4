// Issue 11, items 3 and 10: physically absurd input fails the test with an
// `implausible` error finding naming channel, time and value (never a result
// published as done); a corrupt time base or initial state is refused up
// front with a sentence naming it; HIC windows do not depend on where the
// record's clock starts.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <string>

#include "common/error.h"
#include "engine/criteria.h"
#include "engine/pipeline.h"
#include "engine/screening.h"
#include "engine/units.h"
#include "synth/synthetic_tests.h"
#include "tests/support/reference_arrays.h"

namespace napkin::engine {
namespace {

using ::testing::HasSubstr;

synth::SyntheticTest CleanTest(const ArrayGeometry& array, std::uint64_t seed = 3) {
  synth::RandomMotionOptions options;
  options.seed = seed;
  return synth::SynthRandomMotion(array, options);
}

std::string ErrorOf(const synth::SyntheticTest& test, const ProcessingConfig& config = {}) {
  try {
    ProcessTest(test.array, test.signals, test.initial, config);
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

// Issue 11, item 3: one sample of cg_x at 1e6 g was published as done with
// HIC15 = 1.47e14. Now the test fails on an `implausible` error naming the
// channel, the sample's time and the value.
TEST(Plausibility, OneSampleAtAMillionGFailsTheTestNamingChannelTimeAndValue) {
  for (const ArrayGeometry& array : {test_support::Ideal3222(), test_support::SixAOmegaCg()}) {
    synth::SyntheticTest test = CleanTest(array);
    const Sensor& sensor = array.sensors.front();
    ASSERT_EQ(sensor.kind, SensorKind::kLinear);
    const Eigen::Index k = test.signals.size() / 2;
    test.signals.samples(k, test.signals.FindSlot(sensor.slot)) = 1e6 * kStandardGravity / sensor.si_per_unit;
    std::string verdict;
    try {
      const ProcessedTest processed = ProcessTest(test.array, test.signals, test.initial, ProcessingConfig{});
      const Finding* failing = FailingFinding(processed);
      ASSERT_NE(failing, nullptr) << array.name << ": a 1e6 g sample must fail the test";
      EXPECT_EQ(failing->check, "implausible");
      EXPECT_EQ(failing->channel, sensor.slot);
      verdict = failing->detail;
    } catch (const InputError& error) {
      verdict = error.what();  // the solve diverged: the message quotes the screening error
    }
    EXPECT_THAT(verdict, HasSubstr("channel " + sensor.slot + " reads 1e+06 g")) << array.name;
    EXPECT_THAT(verdict, HasSubstr("sample " + std::to_string(k))) << array.name;
    std::ostringstream time;
    time << "t = " << std::setprecision(6) << test.signals.TimeAt(k) << " s";
    EXPECT_THAT(verdict, HasSubstr(time.str())) << array.name;
    EXPECT_THAT(verdict, HasSubstr("plausibility limit of 2000 g")) << array.name;
  }
}

TEST(Plausibility, AngularRateBeyondTheLimitFailsTheTest) {
  synth::SyntheticTest test = CleanTest(test_support::SixAOmegaCg());
  const Sensor* rate = nullptr;
  for (const Sensor& sensor : test.array.sensors)
    if (sensor.kind == SensorKind::kAngularRate) rate = &sensor;
  ASSERT_NE(rate, nullptr);
  test.signals.samples(100, test.signals.FindSlot(rate->slot)) = 5000.0 / rate->si_per_unit;  // rad/s
  const ProcessedTest processed = ProcessTest(test.array, test.signals, test.initial, ProcessingConfig{});
  const Finding* failing = FailingFinding(processed);
  ASSERT_NE(failing, nullptr);
  EXPECT_EQ(failing->check, "implausible");
  EXPECT_THAT(failing->detail, HasSubstr("channel " + rate->slot + " reads 5000 rad/s at sample 100"));
}

// The limits are configuration: raising them lets the same data through
// (with its warnings), so nothing else fails the test.
TEST(Plausibility, LimitsComeFromTheProcessingConfig) {
  synth::SyntheticTest test = CleanTest(test_support::Ideal3222());
  test.signals.samples(50, 0) += 3000.0 * kStandardGravity / test.array.sensors[0].si_per_unit;
  ProcessingConfig config;
  const Finding* failing = nullptr;
  const ProcessedTest strict = ProcessTest(test.array, test.signals, test.initial, config);
  failing = FailingFinding(strict);
  ASSERT_NE(failing, nullptr);
  EXPECT_EQ(failing->check, "implausible");
  config.plausibility.max_acceleration_g = 1e5;
  config.plausibility.max_residual_factor = 1e5;
  const ProcessedTest lenient = ProcessTest(test.array, test.signals, test.initial, config);
  for (const Finding& finding : lenient.summary.findings) EXPECT_NE(finding.check, "implausible");
}

// Clean synthetic tests of every reference array, including the padding
// series' impacts, trip none of the default limits.
TEST(Plausibility, CleanTestsTripNothing) {
  for (const ArrayGeometry& array : {test_support::Ideal3222(), test_support::Denton3222(),
                                     test_support::SixAOmegaCg(), test_support::NapArs12()})
    for (std::uint64_t seed = 1; seed <= 3; ++seed) {
      const synth::SyntheticTest test = CleanTest(array, seed);
      const ProcessedTest processed = ProcessTest(test.array, test.signals, test.initial, ProcessingConfig{});
      for (const Finding& finding : processed.summary.findings)
        EXPECT_NE(finding.check, "implausible") << array.name << " seed " << seed << ": " << finding.detail;
    }
}

TEST(Plausibility, ConfigChecksTheLimits) {
  ProcessingConfig config;
  config.plausibility.max_acceleration_g = -1.0;
  try {
    config.Check();
    ADD_FAILURE() << "a negative limit must be refused";
  } catch (const InputError& error) {
    EXPECT_THAT(std::string(error.what()), HasSubstr("plausibility.max_acceleration_g"));
  }
}

// Issue 11, item 10: an initial velocity of 1e308 or a time step of 1e-320
// was blamed on "channels inconsistent with a rigid body"; "sampling interval
// inf s is not positive".
TEST(TimeBaseAndInitialState, AbsurdValuesAreRefusedUpFrontNamingThem) {
  synth::SyntheticTest test = CleanTest(test_support::Ideal3222());
  {
    synth::SyntheticTest fast = test;
    fast.initial.velocity_fixed_mps = Eigen::Vector3d(1e308, 0.0, 0.0);
    const std::string error = ErrorOf(fast);
    EXPECT_THAT(error, HasSubstr("initial velocity"));
    EXPECT_THAT(error, HasSubstr("plausibility limit of 1000 m/s"));
    EXPECT_EQ(error.find("rigid"), std::string::npos) << error;
  }
  {
    synth::SyntheticTest tiny = test;
    tiny.signals.dt_s = 1e-320;
    const std::string error = ErrorOf(tiny);
    EXPECT_THAT(error, HasSubstr("sampling interval 9.99989e-321 s is below 1e-09 s"));
    EXPECT_EQ(error.find("rigid"), std::string::npos) << error;
  }
  {
    synth::SyntheticTest infinite = test;
    infinite.signals.dt_s = std::numeric_limits<double>::infinity();
    EXPECT_EQ(ErrorOf(infinite), "the sampling interval inf s is not a finite positive number.");
  }
}

// Issue 11, item 10: a UDS-1992 test starting at NFP ~ 2.1e9 (t0 ~ 2.1e5 s)
// got a 0.0149 s HIC15 window: the sampling interval was taken from the
// difference of two absolute times. Windows and values must not depend on
// where the clock starts.
TEST(HicWindows, DoNotDependOnTheRecordsStartTime) {
  // A long, low pulse, so the HIC15 window is limited by its 15 ms (150
  // samples): with dt from the difference of two absolute times near 2.1e5 s
  // it shrank to 149 samples.
  synth::HeadImpact impact;
  impact.contact_point_body_m = synth::NominalContactPoint(impact.trajectory_deg);
  impact.pulse_s = 0.05;
  const synth::SyntheticTest test = synth::SynthHeadImpact(test_support::Denton3222(), impact);
  const ProcessedTest at_zero = ProcessTest(test.array, test.signals, test.initial, ProcessingConfig{});
  ASSERT_GT(at_zero.summary.hic15.value, 10.0);
  ASSERT_NEAR(at_zero.summary.hic15.t2_s - at_zero.summary.hic15.t1_s, kHic15Window, 1e-12);
  for (const double nfp : {2.1e9, 2'147'483'000.0, 123456789.0}) {
    synth::SyntheticTest shifted = test;
    shifted.signals.t0_s = test.signals.t0_s + nfp * test.signals.dt_s;
    const ProcessedTest late =
        ProcessTest(shifted.array, shifted.signals, shifted.initial, ProcessingConfig{});
    const double duration_at_zero = at_zero.summary.hic15.t2_s - at_zero.summary.hic15.t1_s;
    const double duration_late = late.summary.hic15.t2_s - late.summary.hic15.t1_s;
    EXPECT_NEAR(duration_late, duration_at_zero, 1e-9) << "NFP " << nfp;
    EXPECT_NEAR(late.summary.hic15.t1_s - shifted.signals.t0_s,
                at_zero.summary.hic15.t1_s - test.signals.t0_s, 1e-9)
        << "NFP " << nfp;
    EXPECT_NEAR(late.summary.hic15.value, at_zero.summary.hic15.value, 1e-9 * at_zero.summary.hic15.value)
        << "NFP " << nfp;
    EXPECT_NEAR(late.summary.hic36.value, at_zero.summary.hic36.value, 1e-9 * at_zero.summary.hic36.value)
        << "NFP " << nfp;
  }
}

}  // namespace
}  // namespace napkin::engine

// The scenarios of `napkin synth`: names, ids, seeds and paddings.
#include <gtest/gtest.h>

#include "engine/synth.h"

namespace napkin::engine {
namespace {

TEST(SynthScenarioTest, NamesRoundTrip) {
  for (const SynthScenario scenario : kSynthScenarios)
    EXPECT_EQ(ParseSynthScenario(SynthScenarioName(scenario)), scenario);
  EXPECT_FALSE(ParseSynthScenario("Random"));
  EXPECT_TRUE(HasChosenDuration(SynthScenario::kRandom));
  EXPECT_TRUE(HasChosenDuration(SynthScenario::kPaddingVariants));
  EXPECT_FALSE(HasChosenDuration(SynthScenario::kSeedFixedAxis));
  EXPECT_FALSE(HasChosenDuration(SynthScenario::kSeedSequential));
}

TEST(SynthScenarioTest, ReportScenariosAreOneTestNamedByThePrefix) {
  ScenarioOptions options;
  options.scenario = SynthScenario::kSeedFixedAxis;
  options.id_prefix = "fixed";
  options.count = 5;
  const std::vector<ScenarioTest> tests = ScenarioTests(options);
  ASSERT_EQ(tests.size(), 1u);
  EXPECT_EQ(tests[0].external_id, "fixed");
  EXPECT_FALSE(tests[0].seed);
  EXPECT_FALSE(tests[0].variant);
}

TEST(SynthScenarioTest, RandomTestsAreNumberedWithConsecutiveSeeds) {
  ScenarioOptions options;
  options.scenario = SynthScenario::kRandom;
  options.id_prefix = "r";
  options.count = 12345;
  options.seed = 10;
  options.duration_s = 0.05;
  const std::vector<ScenarioTest> tests = ScenarioTests(options);
  ASSERT_EQ(tests.size(), 12345u);
  EXPECT_EQ(tests[0].external_id, "r-00001");
  EXPECT_EQ(tests.back().external_id, "r-12345");
  EXPECT_EQ(tests[0].seed, 10u);
  EXPECT_EQ(tests.back().motion.seed, 10u + 12344u);
  EXPECT_EQ(tests.back().motion.duration_s, 0.05);
  options.count = 3;
  EXPECT_EQ(ScenarioTests(options)[2].external_id, "r-0003");
}

TEST(SynthScenarioTest, PaddingVariantsScaleTheSameImpacts) {
  ScenarioOptions options;
  options.scenario = SynthScenario::kPaddingVariants;
  options.id_prefix = "pad";
  options.count = 2;
  options.seed = 4;
  const std::vector<ScenarioTest> tests = ScenarioTests(options);
  ASSERT_EQ(tests.size(), 6u);
  const RandomMotionOptions defaults;
  const char* ids[] = {"pad-production-01", "pad-production-02", "pad-foam-a-01",
                       "pad-foam-a-02",     "pad-foam-b-01",     "pad-foam-b-02"};
  const double factors[] = {1.0, 1.0, 0.8, 0.8, 0.65, 0.65};
  for (std::size_t i = 0; i < tests.size(); ++i) {
    EXPECT_EQ(tests[i].external_id, ids[i]);
    EXPECT_EQ(tests[i].load_factor, factors[i]);
    EXPECT_EQ(tests[i].seed, 4u + i % 2);
    EXPECT_EQ(tests[i].motion.peak_acc_g, defaults.peak_acc_g * factors[i]);
    EXPECT_EQ(tests[i].motion.peak_omega_radps, defaults.peak_omega_radps * factors[i]);
  }
  EXPECT_EQ(tests[2].variant, "foam-a");
}

}  // namespace
}  // namespace napkin::engine

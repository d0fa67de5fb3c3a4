// The scenarios of `napkin synth`: names, ids, seeds, paddings and impacts.
#include <gtest/gtest.h>

#include <cmath>

#include "synth/synthetic_tests.h"

namespace napkin::engine {
namespace {

TEST(SynthScenarioTest, NamesRoundTrip) {
  for (const synth::SynthScenario scenario : synth::kSynthScenarios)
    EXPECT_EQ(synth::ParseSynthScenario(synth::SynthScenarioName(scenario)), scenario);
  EXPECT_FALSE(synth::ParseSynthScenario("Random"));
  EXPECT_TRUE(synth::HasChosenDuration(synth::SynthScenario::kRandom));
  EXPECT_FALSE(synth::HasChosenDuration(synth::SynthScenario::kPaddingSeries));
  EXPECT_FALSE(synth::HasChosenDuration(synth::SynthScenario::kSeedFixedAxis));
  EXPECT_FALSE(synth::HasChosenDuration(synth::SynthScenario::kSeedSequential));
}

TEST(SynthScenarioTest, ReportScenariosAreOneTestNamedByThePrefix) {
  synth::ScenarioOptions options;
  options.scenario = synth::SynthScenario::kSeedFixedAxis;
  options.id_prefix = "fixed";
  options.count = 5;
  const std::vector<synth::ScenarioTest> tests = synth::ScenarioTests(options);
  ASSERT_EQ(tests.size(), 1u);
  EXPECT_EQ(tests[0].external_id, "fixed");
  EXPECT_FALSE(tests[0].seed);
  EXPECT_FALSE(tests[0].variant);
}

TEST(SynthScenarioTest, RandomTestsAreNumberedWithConsecutiveSeeds) {
  synth::ScenarioOptions options;
  options.scenario = synth::SynthScenario::kRandom;
  options.id_prefix = "r";
  options.count = 12345;
  options.seed = 10;
  options.duration_s = 0.05;
  const std::vector<synth::ScenarioTest> tests = synth::ScenarioTests(options);
  ASSERT_EQ(tests.size(), 12345u);
  EXPECT_EQ(tests[0].external_id, "r-00001");
  EXPECT_EQ(tests.back().external_id, "r-12345");
  EXPECT_EQ(tests[0].seed, 10u);
  EXPECT_EQ(tests.back().motion.seed, 10u + 12344u);
  EXPECT_EQ(tests.back().motion.duration_s, 0.05);
  options.count = 3;
  EXPECT_EQ(synth::ScenarioTests(options)[2].external_id, "r-0003");
}

TEST(SynthScenarioTest, PaddingSeriesNumbersEachVariantsRepeatsWithConsecutiveSeeds) {
  synth::ScenarioOptions options;
  options.scenario = synth::SynthScenario::kPaddingSeries;
  options.id_prefix = "pad";
  options.count = 2;
  options.seed = 4;
  const std::vector<synth::ScenarioTest> tests = synth::ScenarioTests(options);
  ASSERT_EQ(tests.size(), 6u);
  const char* ids[] = {"pad-production-01", "pad-production-02", "pad-foam-a-01",
                       "pad-foam-a-02",     "pad-foam-b-01",     "pad-foam-b-02"};
  for (std::size_t i = 0; i < tests.size(); ++i) {
    EXPECT_EQ(tests[i].external_id, ids[i]);
    EXPECT_EQ(tests[i].seed, 4u + i);
    const synth::PaddingVariant& variant = synth::kPaddingVariants[i / 2];
    EXPECT_EQ(tests[i].variant, variant.name);
    ASSERT_TRUE(tests[i].impact);
    const synth::HeadImpact& impact = *tests[i].impact;
    EXPECT_EQ(impact.noise_seed, 4u + i);
    EXPECT_EQ(impact.restitution, variant.restitution);
    // The scatter, truncated at 3 sigma.
    EXPECT_LE(std::abs(impact.pulse_s / variant.pulse_s - 1.0), 3 * 0.02);
    EXPECT_LE(std::abs(impact.speed_mps / synth::HeadImpact{}.speed_mps - 1.0), 3 * 0.015);
    EXPECT_LE(std::abs(impact.trajectory_deg - 36.0), 3 * 1.5);
    EXPECT_LE((impact.contact_point_body_m - synth::NominalContactPoint(impact.trajectory_deg))
                  .cwiseAbs()
                  .maxCoeff(),
              3 * 0.002);
  }
  EXPECT_NE(tests[0].impact->speed_mps, tests[1].impact->speed_mps);
  EXPECT_EQ(synth::DefaultCount(synth::SynthScenario::kPaddingSeries), 5);
  EXPECT_EQ(synth::DefaultCount(synth::SynthScenario::kRandom), 1);
}

}  // namespace
}  // namespace napkin::engine

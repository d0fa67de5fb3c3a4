// A recomputation equals the stored result bit for bit (records/test_inputs.h,
// docs/formats.md "Derived-channel storage"): `napkin run` stores a result,
// records::RecomputeResult (what `export` and `report` do for a config that
// stores no derived channels, and what `napkin_catalogue_io verify` checks)
// reads the same inputs back, decodes the config from its stored record and
// computes the same result -- every derived sample and every summary field.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "engine/summary_fields.h"
#include "records/test_inputs.h"
#include "tests/jobs/jobs_test_helpers.h"
#include "tests/support/test_support.h"

namespace napkin::jobs {
namespace {

using test_support::ExpectSameKinematics;

// A config away from the defaults in fields whose decimal form does not
// round-trip by accident (a value lost or rounded by the stored JSON would
// change the numbers), with the storage choice `storage`.
engine::ProcessingConfig UnusualConfig(engine::DerivedStorage storage) {
  engine::ProcessingConfig config;
  config.filter.padding_s = 0.0123456789012345;
  config.filter.angular_rate_cfc = 180.0;
  config.time.shift_s = 1.0 / 30000.0;
  config.gravity.compensate = true;
  config.screening.residual_limit_g = 4.321098765432109;
  config.storage.derived_channels = storage;
  return config;
}

RunOptions TwoThreads() {
  RunOptions options;
  options.threads = 2;
  options.poll_interval_s = 0.05;
  return options;
}

TEST(Recomputation, EqualsTheStoredFloat64ResultBitForBit) {
  napkin::test_support::TempDir dir;
  const std::string path = dir / "catalogue.db";
  test_support::AddRandomTests(path, 6, 1200);
  const RunReport report = RunScheduler(
      path, test_support::Processing(UnusualConfig(engine::DerivedStorage::kFloat64)), TwoThreads());
  ASSERT_EQ(report.done, 6);

  db::Catalogue catalogue = db::Catalogue::Open(path);
  for (const db::TestRow& test : catalogue.ReadAllTests()) {
    const auto kinematics = catalogue.ReadKinematics(test.id, report.config);
    const auto summary = catalogue.ReadSummary(test.id, report.config);
    ASSERT_TRUE(kinematics && summary) << test.external_id;
    const engine::ProcessedTest recomputed = records::RecomputeResult(catalogue, test.id, report.config);
    ExpectSameKinematics(*kinematics, recomputed.kinematics, test.external_id);
    EXPECT_THAT(engine::DifferingSummaryFields(*summary, recomputed.summary), ::testing::IsEmpty())
        << test.external_id;
  }
}

// Storage "none": nothing stored, so export and report recompute; the
// recomputation equals the kinematics a float64 run of the same processing
// stored, and the summary the "none" run stored.
TEST(Recomputation, OfANoneResultEqualsTheFloat64StoredKinematicsBitForBit) {
  napkin::test_support::TempDir dir;
  const std::string path = dir / "catalogue.db";
  test_support::AddRandomTests(path, 4, 1000);
  const RunReport float64 = RunScheduler(
      path, test_support::Processing(UnusualConfig(engine::DerivedStorage::kFloat64)), TwoThreads());
  const RunReport none = RunScheduler(
      path, test_support::Processing(UnusualConfig(engine::DerivedStorage::kNone)), TwoThreads());
  ASSERT_EQ(float64.done, 4);
  ASSERT_EQ(none.done, 4);
  ASSERT_NE(float64.config, none.config);

  db::Catalogue catalogue = db::Catalogue::Open(path);
  for (const db::TestRow& test : catalogue.ReadAllTests()) {
    EXPECT_FALSE(catalogue.ReadKinematics(test.id, none.config)) << test.external_id;
    const auto stored = catalogue.ReadKinematics(test.id, float64.config);
    const auto summary = catalogue.ReadSummary(test.id, none.config);
    ASSERT_TRUE(stored && summary) << test.external_id;
    const engine::ProcessedTest recomputed = records::RecomputeResult(catalogue, test.id, none.config);
    ExpectSameKinematics(*stored, recomputed.kinematics, test.external_id);
    EXPECT_THAT(engine::DifferingSummaryFields(*summary, recomputed.summary), ::testing::IsEmpty())
        << test.external_id;
  }
}

}  // namespace
}  // namespace napkin::jobs

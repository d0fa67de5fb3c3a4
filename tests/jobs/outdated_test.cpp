// `run --outdated` (README "Batch runs"): the overnight job after an upgrade recomputes
// the results another napkin version computed, bit for bit the same values under this
// version, and leaves this version's results alone.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <map>

#include "common/version.h"
#include "db/job_queue.h"
#include "engine/summary_fields.h"
#include "tests/jobs/jobs_test_helpers.h"
#include "tests/support/db/catalogue_inspector.h"
#include "tests/support/test_support.h"

namespace napkin::jobs {
namespace {

using test_support::AddRandomTests;
using test_support::Processing;
using test_support::TestName;
using ::testing::IsEmpty;
using ::testing::Optional;

constexpr const char* kOldVersion = "0.0.9+g0123456";

// Every derived channel of `a` equals `b`'s bit for bit (Eigen's == compares exactly).
bool SameKinematics(const engine::Kinematics& a, const engine::Kinematics& b) {
  return a.time_s == b.time_s && a.omega_body == b.omega_body && a.alpha_body == b.alpha_body &&
         a.omega_fixed == b.omega_fixed && a.alpha_fixed == b.alpha_fixed && a.acc_body == b.acc_body &&
         a.acc_fixed == b.acc_fixed && a.vel_fixed == b.vel_fixed && a.pos_fixed == b.pos_fixed &&
         a.quat_fixed_from_body == b.quat_fixed_from_body && a.roll_pitch_yaw_rad == b.roll_pitch_yaw_rad &&
         a.dcos_rad == b.dcos_rad && a.residual == b.residual;
}

TEST(OutdatedRunTest, RecomputesExactlyTheResultsOfAnotherVersionBitForBit) {
  napkin::test_support::TempDir dir;
  const std::string path = dir / "catalogue.db";
  AddRandomTests(path, 6, 800);
  RunOptions options;
  options.threads = 2;
  options.poll_interval_s = 0.05;
  const RunReport first = RunScheduler(path, Processing(), options);
  ASSERT_EQ(first.done, 6);

  // r0001 and r0004 stand for results of an older napkin, r0003 for one from before
  // version tracking (NULL).
  const std::map<std::string, std::optional<std::string>> older = {
      {TestName(1), kOldVersion}, {TestName(3), std::nullopt}, {TestName(4), kOldVersion}};
  std::map<std::string, engine::TestSummary> summaries;
  std::map<std::string, engine::Kinematics> kinematics;
  std::map<std::string, std::int64_t> attempts;
  {
    db::Catalogue catalogue = db::Catalogue::Open(path);
    db::CatalogueInspector inspector(catalogue);
    for (const auto& [id, version] : older)
      inspector.SetResultVersion(*catalogue.FindTestByExternalId(id), first.config, version);
    for (const db::TestRow& test : catalogue.ReadAllTests()) {
      summaries[test.external_id] = *catalogue.ReadSummary(test.id, first.config);
      kinematics[test.external_id] = *catalogue.ReadKinematics(test.id, first.config);
    }
    const std::vector<std::int64_t> job_attempts = inspector.ReadJobAttempts(first.config);
    ASSERT_EQ(job_attempts.size(), 6u);
    for (int i = 0; i < 6; ++i) attempts[TestName(i)] = job_attempts[static_cast<std::size_t>(i)];
  }

  // Without --outdated a run finds everything up to date.
  const RunReport plain = RunScheduler(path, Processing(), options);
  EXPECT_EQ(plain.total, 0);
  EXPECT_EQ(plain.done, 0);
  EXPECT_EQ(plain.skipped, 6);

  RunOptions outdated = options;
  outdated.outdated = true;
  const RunReport report = RunScheduler(path, Processing(), outdated);
  EXPECT_EQ(report.config, first.config);
  EXPECT_EQ(report.total, 3);
  EXPECT_EQ(report.done, 3);
  EXPECT_EQ(report.skipped, 3);
  EXPECT_EQ(report.failed, 0);

  db::Catalogue catalogue = db::Catalogue::Open(path);
  db::CatalogueInspector inspector(catalogue);
  const std::vector<std::int64_t> job_attempts = inspector.ReadJobAttempts(first.config);
  for (int i = 0; i < 6; ++i) {
    const std::string id = TestName(i);
    const db::TestId test = *catalogue.FindTestByExternalId(id);
    const bool recomputed = older.count(id) > 0;
    EXPECT_EQ(job_attempts[static_cast<std::size_t>(i)], attempts[id] + (recomputed ? 1 : 0))
        << id << (recomputed ? ": recomputed once" : ": left alone");
    EXPECT_THAT(inspector.ReadResultVersion(test, first.config), Optional(napkin::Version())) << id;
    EXPECT_THAT(engine::DifferingSummaryFields(*catalogue.ReadSummary(test, first.config), summaries[id]),
                IsEmpty())
        << id;
    EXPECT_TRUE(SameKinematics(*catalogue.ReadKinematics(test, first.config), kinematics[id])) << id;
  }
  EXPECT_EQ(inspector.CountRows("results"), 6);

  // Everything is of this version now: --outdated has nothing left to do.
  const RunReport again = RunScheduler(path, Processing(), outdated);
  EXPECT_EQ(again.total, 0);
  EXPECT_EQ(again.skipped, 6);
}

}  // namespace
}  // namespace napkin::jobs

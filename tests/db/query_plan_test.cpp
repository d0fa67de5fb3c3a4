// The statements of the job queue whose cost must not grow with the catalogue
// (issue 45; docs/architecture.md "Catalogues of a million tests"): SQLite's
// plan (EXPLAIN QUERY PLAN) of the claim and of the up-to-date check reads
// jobs, results and tests through their indexes, never a walk of the table,
// so that a claim costs what it takes and `run` stays flat per test.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "db/catalogue.h"
#include "db/catalogue_internal.h"
#include "db/job_queue.h"
#include "tests/db/db_test_helpers.h"
#include "tests/support/db/catalogue_inspector.h"
#include "tests/support/test_support.h"

namespace napkin::db {
namespace {

// The lines of SQLite's plan of `sql` (its parameters unbound).
std::vector<std::string> PlanOfStatement(Connection& connection, const std::string& sql) {
  auto explain = connection.Prepare("EXPLAIN QUERY PLAN " + sql);
  std::vector<std::string> lines;
  while (explain->Step()) lines.push_back(explain->ColumnText(3));
  return lines;
}

// The lines of `plan` that walk one of `tables` whole: "SCAN <name or alias>"
// (with an index or without: both read every row).
std::vector<std::string> TableWalksInPlan(const std::vector<std::string>& plan,
                                          const std::vector<std::string>& tables) {
  std::vector<std::string> scans;
  for (const std::string& line : plan)
    for (const std::string& table : tables)
      if (line == "SCAN " + table || line.rfind("SCAN " + table + " ", 0) == 0) scans.push_back(line);
  return scans;
}

std::string PlanText(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) text += line + "\n";
  return text;
}

// The names the statements give jobs, results and tests.
const std::vector<std::string> kJobsNames = {"jobs", "j"};
const std::vector<std::string> kResultsNames = {"results", "r"};
const std::vector<std::string> kTestsNames = {"tests", "t"};

class QueryPlanTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // Rows in every table the statements read: two series of tests, a
    // config, jobs in each state and results.
    const ArrayId array = catalogue_.WriteArray(test_support::IdealArray());
    for (int i = 0; i < 40; ++i)
      test_support::AddTest(catalogue_, array, "t" + std::to_string(100 + i), i % 2 == 0 ? "S" : "R",
                            i % 4 < 2 ? "A" : "B");
    config_ = catalogue_.WriteConfig(test_support::DefaultConfig());
    JobQueue queue(catalogue_);
    queue.EnqueueMissing(config_);
    const std::vector<Job> claimed = queue.ClaimJobs(config_, "w", 10, 60.0);
    for (std::size_t i = 0; i < 5; ++i) {
      catalogue_.WriteResult(claimed[i].test_id, config_, engine::TestSummary{}, "exact");
      queue.CompleteJob(claimed[i].id, "w");
    }
    queue.FailJob(claimed[5].id, "w", "test 'x' has no channel 'cg_x'.");
  }

  // Every shape of scope run takes: the whole catalogue, --series, a
  // variant, --test, --shard, and their combinations.
  static std::vector<std::pair<std::string, JobScope>> Scopes() {
    std::vector<std::pair<std::string, JobScope>> scopes;
    scopes.emplace_back("the whole catalogue", JobScope{});
    JobScope series;
    series.tests.series = {"S"};
    scopes.emplace_back("a series", series);
    JobScope two_series;
    two_series.tests.series = {"S", "T"};
    scopes.emplace_back("two series", two_series);
    JobScope variant;
    variant.tests.variants = {"A"};
    scopes.emplace_back("a variant", variant);
    JobScope series_variant = series;
    series_variant.tests.variants = {"B"};
    scopes.emplace_back("a series and variant", series_variant);
    JobScope named;
    named.tests.external_ids = {"t101", "t117"};
    scopes.emplace_back("named tests", named);
    JobScope shard;
    shard.shard = Shard{1, 4};
    scopes.emplace_back("a shard", shard);
    JobScope series_shard = series;
    series_shard.shard = Shard{0, 3};
    scopes.emplace_back("a shard of a series", series_shard);
    return scopes;
  }

  test_support::TempDir dir_;
  Catalogue catalogue_ = Catalogue::Open(dir_ / "plans.db");
  ConfigId config_{};
};

TEST_F(QueryPlanTest, AClaimReadsTheQueueInKeyOrderThroughItsIndex) {
  Connection& connection = CatalogueInspector(catalogue_).connection();
  for (const auto& [name, scope] : Scopes()) {
    const std::vector<std::string> plan = PlanOfStatement(connection, internal::ClaimSql(scope));
    for (const auto& tables : {kJobsNames, kResultsNames, kTestsNames})
      EXPECT_THAT(TableWalksInPlan(plan, tables), ::testing::IsEmpty()) << name << ":\n" << PlanText(plan);
    // The queued jobs of the config, from the cursor on, in key order: no
    // sort of the queue, so the walk stops after the jobs it takes.
    EXPECT_THAT(plan,
                ::testing::Contains(::testing::AllOf(
                    ::testing::StartsWith("SEARCH j USING "),
                    ::testing::EndsWith("INDEX jobs_by_config_state (config_id=? AND state=? AND rowid>?)"))))
        << name << ":\n"
        << PlanText(plan);
  }
}

TEST_F(QueryPlanTest, TheUpToDateCheckLooksUpEachTestsJobAndResult) {
  Connection& connection = CatalogueInspector(catalogue_).connection();
  for (const auto& [name, scope] : Scopes()) {
    for (const std::string& sql : internal::EnqueueSql(scope)) {
      const std::vector<std::string> plan = PlanOfStatement(connection, sql);
      // Each test of the scope looks up its job and its result.
      for (const auto& tables : {kJobsNames, kResultsNames})
        EXPECT_THAT(TableWalksInPlan(plan, tables), ::testing::IsEmpty()) << name << ":\n" << PlanText(plan);
      // The scope itself is read through the indexes when it names tests or
      // a series; the whole catalogue, a shard or a variant alone (which no
      // index holds) are one walk of the tests, once a run.
      const bool indexed = !scope.tests.external_ids.empty() || !scope.tests.series.empty();
      if (indexed) {
        EXPECT_THAT(TableWalksInPlan(plan, kTestsNames), ::testing::IsEmpty()) << name << ":\n"
                                                                               << PlanText(plan);
      }
    }
  }
}

TEST_F(QueryPlanTest, ClaimsTakeWhatIsClaimableBeforeTheCursorToo) {
  JobQueue queue(catalogue_);
  // 30 queued jobs after SetUp: take 20, fail the first of them and queue
  // it again with SetUp's failure: both lie before the cursor.
  const std::vector<Job> first = queue.ClaimJobs(config_, "w", 20, 60.0);
  ASSERT_EQ(first.size(), 20u);
  ASSERT_TRUE(queue.FailJob(first.front().id, "w", "test 'x' is bad."));
  EXPECT_EQ(queue.EnqueueMissing(config_), 2) << "the two failures";
  const std::vector<Job> second = queue.ClaimJobs(config_, "w", 20, 60.0);
  ASSERT_EQ(second.size(), 12u) << "the 10 queued after the cursor and the 2 queued again before it";
  std::vector<JobId> ids;
  for (const Job& job : second) ids.push_back(job.id);
  EXPECT_THAT(ids, ::testing::Contains(first.front().id));
  EXPECT_TRUE(std::is_sorted(ids.begin(), ids.end()));
  EXPECT_TRUE(queue.ClaimJobs(config_, "w", 20, 60.0).empty());
  EXPECT_EQ(queue.ReadStatusCounts(config_).running, 4 + 20 - 1 + 12) << "SetUp's 4 and these";
}

}  // namespace
}  // namespace napkin::db

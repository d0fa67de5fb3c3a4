// The job queue: enqueueing, atomic claims, leases, status counts.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <memory>
#include <set>
#include <thread>

#include "common/error.h"
#include "db/catalogue.h"
#include "db/job_queue.h"
#include "tests/db/db_test_helpers.h"
#include "tests/support/db/catalogue_inspector.h"
#include "tests/support/test_support.h"

namespace napkin::db {
namespace {

using ::testing::ElementsAre;

// A clock the test advances by hand, shared by several catalogues.
struct ManualClock {
  std::shared_ptr<double> now_s = std::make_shared<double>(1.7e9);
  std::function<double()> Function() const {
    return [now = now_s] { return *now; };
  }
  void Advance(double seconds) const { *now_s += seconds; }
};

class JobsTest : public ::testing::Test {
 protected:
  Catalogue OpenCatalogue() {
    CatalogueOptions options;
    options.clock = clock_.Function();
    return Catalogue::Open(path_, options);
  }
  // n tests "t000".."t<n-1>" in series "S", variants alternating A/B.
  void AddTests(Catalogue& catalogue, int n) {
    const ArrayId array = catalogue.WriteArray(test_support::IdealArray());
    for (int i = 0; i < n; ++i) {
      char name[16];  // "t" and any int: 12 bytes (GCC's -Wformat-truncation at -O0 counts them)
      std::snprintf(name, sizeof name, "t%03d", i);
      test_support::AddTest(catalogue, array, name, "S", i % 2 == 0 ? "A" : "B");
    }
  }

  napkin::test_support::TempDir dir_;
  std::string path_ = dir_ / "jobs.db";
  ManualClock clock_;
};

TEST_F(JobsTest, EnqueueClaimCompleteAndCount) {
  Catalogue catalogue = OpenCatalogue();
  JobQueue queue(catalogue);
  AddTests(catalogue, 5);
  const ConfigId config = catalogue.WriteConfig(test_support::DefaultConfig());
  StatusCounts counts = queue.ReadStatusCounts(config);
  EXPECT_EQ(counts.tests, 5);
  EXPECT_EQ(counts.pending, 5);

  EXPECT_EQ(queue.EnqueueMissing(config), 5);
  EXPECT_EQ(queue.EnqueueMissing(config), 0) << "enqueueing is idempotent";

  const auto jobs = queue.ClaimJobs(config, "worker-1", 3, 60.0);
  ASSERT_EQ(jobs.size(), 3u);
  for (const Job& job : jobs) EXPECT_EQ(job.attempts, 1);
  counts = queue.ReadStatusCounts(config);
  EXPECT_EQ(counts.running, 3);
  EXPECT_EQ(counts.pending, 2);

  clock_.Advance(2.5);
  catalogue.WriteResult(jobs[0].test_id, config, engine::TestSummary{}, "exact");
  EXPECT_TRUE(queue.CompleteJob(jobs[0].id, "worker-1"));
  EXPECT_FALSE(queue.CompleteJob(jobs[0].id, "worker-1")) << "already done";
  EXPECT_FALSE(queue.CompleteJob(jobs[1].id, "worker-2")) << "not the lease owner";
  EXPECT_TRUE(queue.FailJob(jobs[1].id, "worker-1", "channel 'cg_x' of test 't001' is missing."));

  counts = queue.ReadStatusCounts(config);
  EXPECT_EQ(counts.tests, 5);
  EXPECT_EQ(counts.done, 1);
  EXPECT_EQ(counts.failed, 1);
  EXPECT_EQ(counts.running, 1);
  EXPECT_EQ(counts.pending, 2);
  ASSERT_EQ(counts.failures.size(), 1u);
  EXPECT_EQ(counts.failures[0].test_id, catalogue.ReadTest(jobs[1].test_id).external_id);
  EXPECT_EQ(counts.failures[0].error, "channel 'cg_x' of test 't001' is missing.");

  auto timing =
      CatalogueInspector(catalogue).connection().Prepare("SELECT duration_s FROM jobs WHERE id = ?1");
  timing->Bind(1, jobs[0].id);
  ASSERT_TRUE(timing->Step());
  EXPECT_DOUBLE_EQ(timing->ColumnDouble(0), 2.5);

  // A re-run retries the failure (and counts the attempt), not the done test.
  EXPECT_EQ(queue.EnqueueMissing(config), 1);
  const auto retried = queue.ClaimJobs(config, "worker-1", 10, 60.0);
  std::vector<TestId> retried_tests;
  retried_tests.reserve(retried.size());
  for (const Job& job : retried) retried_tests.push_back(job.test_id);
  EXPECT_THAT(retried_tests, ::testing::Contains(jobs[1].test_id));
  for (const Job& job : retried) {
    if (job.test_id == jobs[1].test_id) {
      EXPECT_EQ(job.attempts, 2);
    }
  }
  EXPECT_EQ(retried.size(), 3u)
      << "the failed one and the two never claimed; the running one holds its lease";
}

TEST_F(JobsTest, TwoConnectionsClaimDisjointJobSets) {
  constexpr int kTests = 120;
  {
    Catalogue catalogue = OpenCatalogue();
    JobQueue queue(catalogue);
    AddTests(catalogue, kTests);
    queue.EnqueueMissing(catalogue.WriteConfig(test_support::DefaultConfig()));
  }
  std::vector<std::vector<std::int64_t>> claimed(2);
  std::atomic<int> errors = 0;
  std::vector<std::thread> workers;
  workers.reserve(2);
  for (int w = 0; w < 2; ++w) {
    workers.emplace_back([&, w] {
      try {
        CatalogueOptions options;  // own connection on the same file, real clock
        Catalogue catalogue = Catalogue::Open(path_, options);
        JobQueue queue(catalogue);
        const ConfigId config = *catalogue.FindConfigByHash(test_support::DefaultConfig().config_hash);
        const std::string owner = "worker-" + std::to_string(w);
        for (;;) {
          const auto jobs = queue.ClaimJobs(config, owner, 3, 600.0);
          if (jobs.empty()) break;
          for (const Job& job : jobs) {
            claimed[w].push_back(static_cast<std::int64_t>(job.id));
            if (!queue.CompleteJob(job.id, owner)) ++errors;
          }
        }
      } catch (...) {
        ++errors;
      }
    });
  }
  for (std::thread& worker : workers) worker.join();
  EXPECT_EQ(errors, 0);
  std::set<std::int64_t> all(claimed[0].begin(), claimed[0].end());
  for (const std::int64_t id : claimed[1])
    EXPECT_TRUE(all.insert(id).second) << "job " << id << " claimed twice";
  EXPECT_EQ(all.size(), static_cast<std::size_t>(kTests));
  EXPECT_EQ(claimed[0].size() + claimed[1].size(), static_cast<std::size_t>(kTests));
}

TEST_F(JobsTest, ExpiredLeaseIsReclaimedAndTheOldOwnerLosesIt) {
  Catalogue first = OpenCatalogue();
  AddTests(first, 4);
  const ConfigId config = first.WriteConfig(test_support::DefaultConfig());
  JobQueue first_queue(first);
  first_queue.EnqueueMissing(config);
  Catalogue second = OpenCatalogue();
  JobQueue second_queue(second);

  const auto crashed = first_queue.ClaimJobs(config, "crashed-worker", 2, 10.0);
  ASSERT_EQ(crashed.size(), 2u);
  const auto others = second_queue.ClaimJobs(config, "worker-2", 10, 10.0);
  ASSERT_EQ(others.size(), 2u);
  EXPECT_TRUE(std::none_of(others.begin(), others.end(), [&](const Job& job) {
    return job.id == crashed[0].id || job.id == crashed[1].id;
  }));

  clock_.Advance(9.0);
  EXPECT_TRUE(second_queue.ClaimJobs(config, "worker-2", 10, 10.0).empty()) << "leases still valid";
  EXPECT_TRUE(second_queue.RenewLease(others[0].id, "worker-2", 10.0));
  clock_.Advance(1.5);  // crashed-worker's leases (and others[1]'s) have expired
  const auto reclaimed = second_queue.ClaimJobs(config, "worker-2", 10, 10.0);
  std::vector<std::int64_t> reclaimed_ids;
  reclaimed_ids.reserve(reclaimed.size());
  for (const Job& job : reclaimed) reclaimed_ids.push_back(static_cast<std::int64_t>(job.id));
  std::vector<std::int64_t> expected = {static_cast<std::int64_t>(crashed[0].id),
                                        static_cast<std::int64_t>(crashed[1].id),
                                        static_cast<std::int64_t>(others[1].id)};
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(reclaimed_ids, expected);
  for (const Job& job : reclaimed) EXPECT_EQ(job.attempts, 2);

  EXPECT_FALSE(first_queue.CompleteJob(crashed[0].id, "crashed-worker")) << "its lease was taken over";
  EXPECT_FALSE(first_queue.FailJob(crashed[1].id, "crashed-worker", "late"));
  EXPECT_TRUE(second_queue.CompleteJob(crashed[0].id, "worker-2"));
  EXPECT_EQ(second_queue.ReadStatusCounts(config).running, 3);
}

TEST_F(JobsTest, ChangedConfigReenqueuesWithoutDeletingEarlierResults) {
  Catalogue catalogue = OpenCatalogue();
  JobQueue queue(catalogue);
  AddTests(catalogue, 3);
  const ConfigId old_config = catalogue.WriteConfig(test_support::DefaultConfig(R"({"filter":"cfc1000"})"));
  queue.EnqueueMissing(old_config);
  for (const Job& job : queue.ClaimJobs(old_config, "w", 10, 60.0)) {
    engine::TestSummary summary;
    summary.hic15.value = 100.0 + static_cast<double>(job.id);
    catalogue.WriteResult(job.test_id, old_config, summary, "exact");
    ASSERT_TRUE(queue.CompleteJob(job.id, "w"));
  }
  EXPECT_EQ(queue.ReadStatusCounts(old_config).done, 3);
  EXPECT_EQ(queue.EnqueueMissing(old_config), 0) << "nothing missing or stale";

  // The config file changed: new canonical JSON, new hash.
  const ConfigId new_config = catalogue.WriteConfig(test_support::DefaultConfig(R"({"filter":"cfc180"})"));
  ASSERT_NE(new_config, old_config);
  StatusCounts counts = queue.ReadStatusCounts(new_config);
  EXPECT_EQ(counts.pending, 3);
  EXPECT_EQ(counts.done, 0);
  EXPECT_EQ(queue.EnqueueMissing(new_config), 3);
  for (const TestRow& test : catalogue.ReadAllTests())
    EXPECT_TRUE(catalogue.ReadSummary(test.id, old_config).has_value()) << test.external_id;
  EXPECT_EQ(queue.ReadStatusCounts(old_config).done, 3);
  EXPECT_EQ(catalogue.Query(QueryKind::kHic).rows.size(), 3u) << "old results stay queryable";
}

TEST_F(JobsTest, DoneJobWhoseResultVanishedIsMissingAgain) {
  Catalogue catalogue = OpenCatalogue();
  JobQueue queue(catalogue);
  AddTests(catalogue, 2);
  const ConfigId config = catalogue.WriteConfig(test_support::DefaultConfig());
  queue.EnqueueMissing(config);
  for (const Job& job : queue.ClaimJobs(config, "w", 10, 60.0)) {
    catalogue.WriteResult(job.test_id, config, engine::TestSummary{}, "exact");
    queue.CompleteJob(job.id, "w");
  }
  CatalogueInspector(catalogue).connection().Execute(
      "DELETE FROM results WHERE test_id = (SELECT min(test_id) FROM results)");
  StatusCounts counts = queue.ReadStatusCounts(config);
  EXPECT_EQ(counts.done, 1);
  EXPECT_EQ(counts.pending, 1);
  EXPECT_EQ(queue.EnqueueMissing(config), 1);
  EXPECT_EQ(queue.EnqueueMissing(config, {}, /*force=*/true), 1) << "force re-queues the done one too";
  EXPECT_EQ(queue.ReadStatusCounts(config).pending, 2);
}

TEST_F(JobsTest, ScopesSelectBySeriesVariantIdsAndShard) {
  Catalogue catalogue = OpenCatalogue();
  JobQueue queue(catalogue);
  AddTests(catalogue, 10);
  test_support::AddTest(catalogue, catalogue.WriteArray(test_support::IdealArray()), "other", "T", "A");
  const ConfigId config = catalogue.WriteConfig(test_support::DefaultConfig());

  JobScope variant_a;
  variant_a.tests = {{"S"}, {"A"}, {}};
  EXPECT_EQ(queue.ReadStatusCounts(config, variant_a).tests, 5);
  JobScope two_ids;
  two_ids.tests.external_ids = {"t003", "other", "absent"};
  EXPECT_EQ(queue.ReadStatusCounts(config, two_ids).tests, 2);

  // Shards partition the catalogue exactly.
  std::int64_t total = 0;
  for (int index = 0; index < 3; ++index) {
    JobScope shard;
    shard.shard = Shard{index, 3};
    total += queue.EnqueueMissing(config, shard);
  }
  EXPECT_EQ(total, 11);
  JobScope bad;
  bad.shard = Shard{3, 3};
  EXPECT_THROW(queue.EnqueueMissing(config, bad), InputError);

  EXPECT_EQ(queue.ReadStatusCounts(config).pending, 11);
  const auto claimed = queue.ClaimJobs(config, "w", 100, 60.0);
  EXPECT_EQ(claimed.size(), 11u);
}

TEST_F(JobsTest, ClaimsOnlyTheRequestedConfig) {
  Catalogue catalogue = OpenCatalogue();
  JobQueue queue(catalogue);
  AddTests(catalogue, 2);
  const ConfigId a = catalogue.WriteConfig(test_support::DefaultConfig("{\"a\":1}"));
  const ConfigId b = catalogue.WriteConfig(test_support::DefaultConfig("{\"b\":1}"));
  queue.EnqueueMissing(a);
  EXPECT_TRUE(queue.ClaimJobs(b, "w", 10, 60.0).empty());
  const auto jobs = queue.ClaimJobs(a, "w", 10, 60.0);
  ASSERT_EQ(jobs.size(), 2u);
  EXPECT_THAT(std::vector<ConfigId>({jobs[0].config_id, jobs[1].config_id}), ElementsAre(a, a));
}

TEST_F(JobsTest, ClaimsStayInTheirScopeAndReleasedLeasesAreClaimableAtOnce) {
  Catalogue catalogue = OpenCatalogue();
  JobQueue queue(catalogue);
  AddTests(catalogue, 6);  // variants A: t000, t002, t004; B: t001, t003, t005
  const ConfigId config = catalogue.WriteConfig(test_support::DefaultConfig());
  EXPECT_EQ(queue.EnqueueMissing(config), 6);

  JobScope variant_b;
  variant_b.tests.variants = {"B"};
  const auto b_jobs = queue.ClaimJobs(config, "dead", 10, 600.0, variant_b);
  ASSERT_EQ(b_jobs.size(), 3u);
  for (const Job& job : b_jobs) EXPECT_EQ(catalogue.ReadTest(job.test_id).variant, "B");
  EXPECT_TRUE(queue.ClaimJobs(config, "alive", 10, 600.0, variant_b).empty()) << "leases hold";
  JobScope one;
  one.tests.external_ids = {"t002"};
  const auto a_jobs = queue.ClaimJobs(config, "alive", 10, 600.0, one);
  ASSERT_EQ(a_jobs.size(), 1u);

  EXPECT_THAT(queue.ReadLeaseOwners(config), ElementsAre("alive", "dead"));
  EXPECT_THAT(queue.ReadLeaseOwners(config, variant_b), ElementsAre("dead"));
  EXPECT_EQ(queue.ReleaseLeases(config, "dead"), 3);
  EXPECT_THAT(queue.ReadLeaseOwners(config), ElementsAre("alive"));
  EXPECT_FALSE(queue.CompleteJob(b_jobs[0].id, "dead")) << "the released lease is gone";
  const auto reclaimed = queue.ClaimJobs(config, "alive", 10, 600.0, variant_b);
  ASSERT_EQ(reclaimed.size(), 3u);
  for (const Job& job : reclaimed) EXPECT_EQ(job.attempts, 2) << "the released claim stays counted";
  EXPECT_EQ(queue.ReadStatusCounts(config).pending, 2);
}

}  // namespace
}  // namespace napkin::db

// Provenance (schema/007_provenance.sql, docs/formats.md "Version string"): results and
// finished jobs record the napkin version, `run --outdated` queues the results of other
// versions only, `status` counts results by version, merge carries the version.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "common/version.h"
#include "db/catalogue.h"
#include "db/job_queue.h"
#include "tests/db/db_test_helpers.h"
#include "tests/support/db/catalogue_inspector.h"
#include "tests/support/test_support.h"

namespace napkin::db {
namespace {

using ::testing::ElementsAre;
using ::testing::Optional;

constexpr const char* kOldVersion = "0.0.9+g0123456";
constexpr const char* kNewVersion = "0.2.0+gfedcba9-dirty";

// The tests of these external ids.
JobScope Only(std::vector<std::string> external_ids) {
  JobScope scope;
  scope.tests.external_ids = std::move(external_ids);
  return scope;
}

class ProvenanceTest : public ::testing::Test {
 protected:
  // The catalogue as the napkin of `version` opens it (empty: this build).
  Catalogue Open(const std::string& version = "") {
    CatalogueOptions options;
    options.napkin_version = version;
    options.clock = [this] { return now_s_ += 1.0; };  // every write a second later
    return Catalogue::Open(path_, options);
  }
  // Computes the queued jobs of `config` as `catalogue`'s napkin would: HIC15 is
  // 100 + the test's number, except that the tests in `failing` fail.
  static std::vector<std::string> Process(Catalogue& catalogue, ConfigId config,
                                          const std::vector<std::string>& failing = {}) {
    JobQueue queue(catalogue);
    std::vector<std::string> processed;
    for (const Job& job : queue.ClaimJobs(config, "worker", 100, 600.0)) {
      const std::string id = catalogue.ReadTest(job.test_id).external_id;
      processed.push_back(id);
      if (std::find(failing.begin(), failing.end(), id) != failing.end()) {
        EXPECT_TRUE(queue.FailJob(job.id, "worker", "channel 'cg_y' of test '" + id + "' is missing."));
        continue;
      }
      engine::TestSummary summary;
      summary.hic15.value = 100.0 + std::stod(id.substr(1));
      auto transaction = catalogue.BeginTransaction();
      catalogue.WriteResult(job.test_id, config, summary, "exact");
      EXPECT_TRUE(queue.CompleteJob(job.id, "worker"));
      transaction.Commit();
    }
    std::sort(processed.begin(), processed.end());
    return processed;
  }
  TestId Test(Catalogue& catalogue, const std::string& id) { return *catalogue.FindTestByExternalId(id); }

  napkin::test_support::TempDir dir_;
  std::string path_ = dir_ / "provenance.db";
  double now_s_ = 1.7e9;
};

TEST_F(ProvenanceTest, ResultsAndFinishedJobsRecordTheNapkinVersionThatComputedThem) {
  {
    Catalogue catalogue = Open();
    EXPECT_EQ(catalogue.napkin_version(), napkin::Version()) << "default: this build's version";
    const ArrayId array = catalogue.WriteArray(test_support::IdealArray());
    for (const char* id : {"t0", "t1", "t2"}) test_support::AddTest(catalogue, array, id);
    const ConfigId config = catalogue.WriteConfig(test_support::DefaultConfig());
    JobQueue(catalogue).EnqueueMissing(config);
    EXPECT_THAT(Process(catalogue, config, {"t1"}), ElementsAre("t0", "t1", "t2"));
    CatalogueInspector inspector(catalogue);
    EXPECT_THAT(inspector.ReadResultVersion(Test(catalogue, "t0"), config), Optional(napkin::Version()));
    EXPECT_THAT(inspector.ReadJobVersion(Test(catalogue, "t0"), config), Optional(napkin::Version()));
    EXPECT_THAT(inspector.ReadJobVersion(Test(catalogue, "t1"), config), Optional(napkin::Version()))
        << "a failure names the version it happened under";
  }
  // Another napkin (here standing in through CatalogueOptions) records its own.
  Catalogue catalogue = Open(kNewVersion);
  EXPECT_EQ(catalogue.napkin_version(), kNewVersion);
  const ConfigId config = *catalogue.FindConfigByHash(test_support::DefaultConfig().config_hash);
  EXPECT_THAT(Process(catalogue, config), ElementsAre()) << "nothing queued";
  JobQueue(catalogue).EnqueueMissing(config, {}, /*force=*/true);
  EXPECT_THAT(Process(catalogue, config), ElementsAre("t0", "t1", "t2"));
  CatalogueInspector inspector(catalogue);
  for (const char* id : {"t0", "t1", "t2"}) {
    EXPECT_THAT(inspector.ReadResultVersion(Test(catalogue, id), config), Optional(std::string(kNewVersion)))
        << id;
    EXPECT_THAT(inspector.ReadJobVersion(Test(catalogue, id), config), Optional(std::string(kNewVersion)))
        << id;
  }
}

// The overnight job after an upgrade: results of the old version (and of before version
// tracking) are queued with --outdated; results of this version, and the results of
// other configs, are left alone; missing and failed ones are queued as always.
TEST_F(ProvenanceTest, OutdatedQueuesExactlyTheResultsOfAnotherVersion) {
  ConfigId config{};
  ConfigId other_config{};
  {
    Catalogue old = Open(kOldVersion);
    const ArrayId array = old.WriteArray(test_support::IdealArray());
    for (const char* id : {"t0", "t1", "t2", "t3", "t4", "t5", "t6", "t7"})
      test_support::AddTest(old, array, id);
    config = old.WriteConfig(test_support::DefaultConfig());
    other_config = old.WriteConfig(test_support::DefaultConfig(R"({"solver":"seed"})"));
    JobQueue(old).EnqueueMissing(config, Only({"t0", "t1", "t2", "t3", "t4"}));
    EXPECT_THAT(Process(old, config, {"t4"}), ElementsAre("t0", "t1", "t2", "t3", "t4"));
    JobQueue(old).EnqueueMissing(other_config);
    EXPECT_EQ(Process(old, other_config).size(), 8u);
    // t1: a result from before version tracking. t7: a result without a job (merged
    // from a shard catalogue), of the old version.
    CatalogueInspector(old).SetResultVersion(Test(old, "t1"), config, std::nullopt);
    old.WriteResult(Test(old, "t7"), config, engine::TestSummary{}, "exact");
  }
  Catalogue catalogue = Open(kNewVersion);
  JobQueue queue(catalogue);
  queue.EnqueueMissing(config, Only({"t5"}));
  EXPECT_THAT(Process(catalogue, config), ElementsAre("t5")) << "t5: computed by this version";

  // t4 failed, t6 was never computed: any run queues them.
  EXPECT_EQ(queue.EnqueueMissing(config), 2);
  EXPECT_THAT(Process(catalogue, config), ElementsAre("t4", "t6"));
  // t0, t2, t3 (old version), t1 (unknown version), t7 (old, no job) with --outdated;
  // t5, t4, t6 (this version) stay.
  EXPECT_EQ(queue.EnqueueMissing(config, {}, /*force=*/false, /*outdated=*/true), 5);
  EXPECT_EQ(queue.EnqueueMissing(config, {}, false, true), 0) << "enqueueing is idempotent";
  EXPECT_THAT(Process(catalogue, config), ElementsAre("t0", "t1", "t2", "t3", "t7"));
  EXPECT_EQ(queue.EnqueueMissing(config, {}, false, true), 0) << "every result is of this version now";

  CatalogueInspector inspector(catalogue);
  for (const TestRow& test : catalogue.ReadAllTests()) {
    EXPECT_THAT(inspector.ReadResultVersion(test.id, config), Optional(std::string(kNewVersion)))
        << test.external_id;
    EXPECT_THAT(inspector.ReadResultVersion(test.id, other_config), Optional(std::string(kOldVersion)))
        << test.external_id << ": another config's results are not this run's";
  }
  // The scope limits --outdated as it limits a run.
  EXPECT_EQ(queue.EnqueueMissing(other_config, Only({"t2"}), false, true), 1);
  EXPECT_THAT(Process(catalogue, other_config), ElementsAre("t2"));
}

TEST_F(ProvenanceTest, VersionCountsGroupResultsAndFailuresByConfigAndVersion) {
  ConfigId config{};
  {
    Catalogue old = Open(kOldVersion);
    const ArrayId array = old.WriteArray(test_support::IdealArray());
    for (const char* id : {"t0", "t1", "t2", "t3"}) test_support::AddTest(old, array, id, "S");
    config = old.WriteConfig(test_support::DefaultConfig());
    JobQueue(old).EnqueueMissing(config);
    Process(old, config, {"t3"});
    CatalogueInspector(old).SetResultVersion(Test(old, "t0"), config, std::nullopt);
  }
  Catalogue catalogue = Open(kNewVersion);
  const ConfigId seed = catalogue.WriteConfig(test_support::DefaultConfig(R"({"solver":"seed"})"));
  JobQueue queue(catalogue);
  queue.EnqueueMissing(seed);
  Process(catalogue, seed, {"t2"});

  const std::vector<VersionCount> counts = queue.ReadVersionCounts();
  ASSERT_EQ(counts.size(), 3u);
  // Config order, then the unknown version first.
  EXPECT_EQ(counts[0].config_id, config);
  EXPECT_EQ(counts[0].config_name, "default");
  EXPECT_EQ(counts[0].config_hash, test_support::DefaultConfig().config_hash);
  EXPECT_EQ(counts[0].napkin_version, std::nullopt);
  EXPECT_EQ(counts[0].results, 1);  // t0
  EXPECT_EQ(counts[0].failed, 0);
  EXPECT_EQ(counts[1].config_id, config);
  EXPECT_EQ(counts[1].napkin_version, kOldVersion);
  EXPECT_EQ(counts[1].results, 2);  // t1, t2
  EXPECT_EQ(counts[1].failed, 1);   // t3
  EXPECT_EQ(counts[2].config_id, seed);
  EXPECT_EQ(counts[2].napkin_version, kNewVersion);
  EXPECT_EQ(counts[2].results, 3);
  EXPECT_EQ(counts[2].failed, 1);

  // The scope counts its tests only.
  const std::vector<VersionCount> t1 = queue.ReadVersionCounts(Only({"t1"}));
  ASSERT_EQ(t1.size(), 2u);
  EXPECT_EQ(t1[0].napkin_version, kOldVersion);
  EXPECT_EQ(t1[0].results, 1);
  EXPECT_EQ(t1[1].napkin_version, kNewVersion);
  EXPECT_EQ(t1[1].results, 1);
  JobScope no_tests;
  no_tests.tests.series = {"none"};
  EXPECT_TRUE(queue.ReadVersionCounts(no_tests).empty());
}

// A shard reprocessed by a newer napkin: its results come with their version, and the
// same values under another version are no conflict.
TEST_F(ProvenanceTest, MergeCarriesTheVersionAndAVersionDifferenceAloneIsNoConflict) {
  ConfigId config{};
  {
    Catalogue old = Open(kOldVersion);
    const ArrayId array = old.WriteArray(test_support::IdealArray());
    for (const char* id : {"t0", "t1", "t2"}) test_support::AddTest(old, array, id);
    config = old.WriteConfig(test_support::DefaultConfig());
    JobQueue(old).EnqueueMissing(config);
    Process(old, config, {"t2"});
  }
  const std::string shard_path = dir_ / "shard.db";
  std::filesystem::copy_file(path_, shard_path);
  {
    CatalogueOptions options;
    options.napkin_version = kNewVersion;
    options.clock = [this] { return now_s_ += 1.0; };
    Catalogue shard = Catalogue::Open(shard_path, options);
    JobQueue shard_queue(shard);
    EXPECT_EQ(shard_queue.EnqueueMissing(config, {}, false, /*outdated=*/true), 3);
    EXPECT_THAT(Process(shard, config, {"t2"}), ElementsAre("t0", "t1", "t2"));
  }
  Catalogue catalogue = Open(kOldVersion);
  const MergeReport merged = catalogue.MergeShard(shard_path);
  EXPECT_EQ(merged.results_merged, 2) << "same values, newer computation";
  EXPECT_EQ(merged.failures_merged, 1) << "the same failure, under the shard's version";
  CatalogueInspector inspector(catalogue);
  for (const char* id : {"t0", "t1"}) {
    EXPECT_THAT(inspector.ReadResultVersion(Test(catalogue, id), config), Optional(std::string(kNewVersion)))
        << id;
    EXPECT_THAT(inspector.ReadJobVersion(Test(catalogue, id), config), Optional(std::string(kNewVersion)))
        << id;
    EXPECT_EQ(catalogue.ReadSummary(Test(catalogue, id), config)->hic15.value, 100.0 + std::stod(id + 1));
  }
  EXPECT_THAT(inspector.ReadJobVersion(Test(catalogue, "t2"), config), Optional(std::string(kNewVersion)));
  const std::string before = inspector.Dump();
  EXPECT_EQ(catalogue.MergeShard(shard_path).failures_merged, 0);
  EXPECT_EQ(inspector.Dump(), before) << "merging again changes nothing";
  // For the shard's napkin the merged results are up to date; only the failure is queued.
  Catalogue as_new = Open(kNewVersion);
  EXPECT_EQ(JobQueue(as_new).EnqueueMissing(config, {}, false, /*outdated=*/true), 1);
}

}  // namespace
}  // namespace napkin::db

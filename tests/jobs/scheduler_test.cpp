// The batch scheduler: parallel results equal the transform core's, failures
// are recorded and the run goes on, stop, bounded memory, concurrent runs,
// leases of dead workers, stale results.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "common/error.h"
#include "db/job_queue.h"
#include "engine/pipeline.h"
#include "engine/summary_fields.h"
#include "tests/jobs/jobs_test_helpers.h"
#include "tests/support/db/catalogue_inspector.h"
#include "tests/support/test_support.h"

namespace napkin::jobs {
namespace {

using test_support::AddRandomTests;
using test_support::Processing;
using test_support::TestName;

using test_support::ExpectSameKinematics;

class SchedulerTest : public ::testing::Test {
 protected:
  RunOptions Options(int threads = 2) const {
    RunOptions options;
    options.threads = threads;
    options.poll_interval_s = 0.05;
    return options;
  }

  napkin::test_support::TempDir dir_;
  std::string path_ = dir_ / "catalogue.db";
};

TEST_F(SchedulerTest, ParallelResultsEqualTheTransformCoreBitForBit) {
  AddRandomTests(path_, 12, 1500);
  // Stored bit-exact (the default float32 storage rounds; docs/formats.md "Derived-channel storage").
  engine::ProcessingConfig config;
  config.storage.derived_channels = engine::DerivedStorage::kFloat64;
  const records::ResolvedConfig processing = Processing(config);
  std::vector<RunProgress> progress;
  const RunReport report =
      RunScheduler(path_, processing, Options(2), [&](const RunProgress& p) { progress.push_back(p); });
  EXPECT_EQ(report.total, 12);
  EXPECT_EQ(report.done, 12);
  EXPECT_EQ(report.failed, 0);
  EXPECT_EQ(report.samples, 12 * 1500 * 9);
  EXPECT_FALSE(report.stopped);
  ASSERT_FALSE(progress.empty());
  EXPECT_EQ(progress.back().done, 12);
  EXPECT_EQ(progress.back().total, 12);

  db::Catalogue catalogue = db::Catalogue::Open(path_);
  for (const db::TestRow& test : catalogue.ReadAllTests()) {
    const engine::ArrayGeometry array = records::DecodeArrayRecord(catalogue.ReadArray(test.array_id));
    const engine::ProcessedTest expected =
        engine::ProcessTest(array, catalogue.ReadTestSignals(test.id), test.initial_state, processing.config);
    const auto kinematics = catalogue.ReadKinematics(test.id, report.config);
    const auto summary = catalogue.ReadSummary(test.id, report.config);
    ASSERT_TRUE(kinematics && summary) << test.external_id;
    ExpectSameKinematics(*kinematics, expected.kinematics, test.external_id);
    EXPECT_THAT(engine::DifferingSummaryFields(*summary, expected.summary), ::testing::IsEmpty())
        << test.external_id;
    EXPECT_EQ(db::CatalogueInspector(catalogue).ReadResultSolver(test.id, report.config), "exact");
  }
  EXPECT_THAT(db::CatalogueInspector(catalogue).ReadJobAttempts(report.config), ::testing::Each(1));
  const db::StatusCounts counts = db::JobQueue(catalogue).ReadStatusCounts(report.config);
  EXPECT_EQ(counts.done, 12);
  EXPECT_EQ(counts.running + counts.pending + counts.failed, 0);

  // Nothing left: a second run is a no-op.
  const RunReport again = RunScheduler(path_, processing, Options(2));
  EXPECT_EQ(again.total, 0);
  EXPECT_EQ(again.skipped, 12);
  EXPECT_EQ(again.done, 0);
}

TEST_F(SchedulerTest, FailedTestsAreRecordedWithTheirReasonAndTheRunGoesOn) {
  AddRandomTests(path_, 6, 800);
  std::string nan_error, missing_error;
  {
    db::Catalogue catalogue = db::Catalogue::Open(path_);
    const engine::ArrayGeometry array = formats::LoadArray("ideal-3222");
    synth::RandomMotionOptions motion;
    motion.duration_s = 0.05;
    synth::SyntheticTest bad = synth::SynthRandomMotion(array, motion);
    bad.signals.samples(200, 4) = std::numeric_limits<double>::quiet_NaN();
    test_support::StoreTest(catalogue, bad, "bad-nan");
    synth::SyntheticTest short_of_one = synth::SynthRandomMotion(array, motion);
    short_of_one.signals.slots.pop_back();  // "zarm_y" is missing
    short_of_one.signals.samples.conservativeResize(Eigen::NoChange, 8);
    test_support::StoreTest(catalogue, short_of_one, "missing-channel");
    // The errors the transform core gives for these inputs.
    for (auto [test, error] : {std::pair{&bad, &nan_error}, std::pair{&short_of_one, &missing_error}}) {
      try {
        engine::ProcessTest(array, test->signals, test->initial, {});
        ADD_FAILURE() << "ProcessTest accepted a bad test";
      } catch (const InputError& e) {
        *error = e.what();
      }
    }
  }
  const RunReport report = RunScheduler(path_, Processing(), Options(2));
  EXPECT_EQ(report.done, 6);
  EXPECT_EQ(report.failed, 2);

  db::Catalogue catalogue = db::Catalogue::Open(path_);
  const db::StatusCounts counts = db::JobQueue(catalogue).ReadStatusCounts(report.config);
  EXPECT_EQ(counts.tests, 8);
  EXPECT_EQ(counts.done, 6);
  EXPECT_EQ(counts.failed, 2);
  ASSERT_EQ(counts.failures.size(), 2u);
  EXPECT_EQ(counts.failures[0].test_id, "bad-nan");
  EXPECT_EQ(counts.failures[0].error, nan_error);
  EXPECT_EQ(counts.failures[1].test_id, "missing-channel");
  EXPECT_EQ(counts.failures[1].error, missing_error);
  EXPECT_FALSE(catalogue.ReadSummary(*catalogue.FindTestByExternalId("bad-nan"), report.config));

  // A new run retries the failures (and fails them again).
  const RunReport retry = RunScheduler(path_, Processing(), Options(1));
  EXPECT_EQ(retry.total, 2);
  EXPECT_EQ(retry.failed, 2);
  EXPECT_EQ(retry.done, 0);
}

TEST_F(SchedulerTest, AnUndecodableArrayFailsItsTestsOnly) {
  AddRandomTests(path_, 3, 500);
  // Three more tests whose stored array cannot be solved (no sensors).
  const db::ArrayRow broken{
      {}, "broken", R"({"name":"broken","length_unit":"m","sensors":[]})", "broken-hash"};
  std::string decode_error;
  try {
    records::DecodeArrayRecord(broken);
    ADD_FAILURE() << "DecodeArrayRecord accepted an array without sensors";
  } catch (const InputError& e) {
    decode_error = e.what();
  }
  {
    db::Catalogue catalogue = db::Catalogue::Open(path_);
    synth::RandomMotionOptions motion;
    motion.duration_s = 0.05;
    const synth::SyntheticTest test = synth::SynthRandomMotion(formats::LoadArray("ideal-3222"), motion);
    for (int i = 0; i < 3; ++i)
      test_support::StoreTest(catalogue, test, "broken-" + std::to_string(i), "synthetic", &broken);
  }
  const RunReport report = RunScheduler(path_, Processing(), Options(2));
  EXPECT_EQ(report.done, 3);
  EXPECT_EQ(report.failed, 3);
  db::Catalogue catalogue = db::Catalogue::Open(path_);
  const db::StatusCounts counts = db::JobQueue(catalogue).ReadStatusCounts(report.config);
  ASSERT_EQ(counts.failures.size(), 3u);
  EXPECT_EQ(counts.failures[0].test_id, "broken-0");
  EXPECT_EQ(counts.failures[0].error, decode_error);
  EXPECT_NE(decode_error.find("array 'broken'"), std::string::npos) << decode_error;
}

TEST_F(SchedulerTest, StopEndsAfterTheTestsInFlightAndTheNextRunFinishes) {
  AddRandomTests(path_, 30, 500);
  RunOptions options = Options(1);
  options.commit_batch = 2;
  std::atomic<bool> stop{false};
  const RunReport stopped = RunScheduler(
      path_, Processing(), options, [&](const RunProgress&) { stop.store(true); }, &stop);
  EXPECT_TRUE(stopped.stopped);
  EXPECT_GE(stopped.done, 2);
  EXPECT_LT(stopped.done, 30);
  {
    db::Catalogue catalogue = db::Catalogue::Open(path_);
    const db::StatusCounts counts = db::JobQueue(catalogue).ReadStatusCounts(stopped.config);
    EXPECT_EQ(counts.done, stopped.done);
    EXPECT_EQ(counts.running, 0) << "claimed jobs went back to the queue";
    EXPECT_EQ(counts.pending, 30 - stopped.done);
    EXPECT_EQ(db::CatalogueInspector(catalogue).CountRows("results"), stopped.done);
  }
  const RunReport rest = RunScheduler(path_, Processing(), Options(2));
  EXPECT_EQ(rest.total, 30 - stopped.done);
  EXPECT_EQ(rest.skipped, stopped.done);
  EXPECT_EQ(rest.done, 30 - stopped.done);
  // The resumed run read the signals of the tests left only (9 channels x 500 samples each).
  EXPECT_EQ(rest.samples, (30 - stopped.done) * 9 * 500);
  db::Catalogue catalogue = db::Catalogue::Open(path_);
  EXPECT_EQ(db::CatalogueInspector(catalogue).CountRows("results"), 30);
  EXPECT_EQ(db::CatalogueInspector(catalogue).CountRows("derived_channels"), 30 * 36);
}

TEST_F(SchedulerTest, TestsInMemoryAreBoundedByTheTokensAndTheBatch) {
  AddRandomTests(path_, 40, 400);
  RunOptions options = Options(2);
  options.tests_in_flight_per_thread = 2;
  options.commit_batch = 3;
  const RunReport report = RunScheduler(path_, Processing(), options);
  EXPECT_EQ(report.done, 40);
  EXPECT_EQ(report.max_tests_in_flight, 4);
  EXPECT_GE(report.peak_tests_in_memory, 1);
  EXPECT_LE(report.peak_tests_in_memory, report.max_tests_in_flight + options.commit_batch);
}

TEST_F(SchedulerTest, ConcurrentSchedulersOnOneFileProcessEachTestOnce) {
  AddRandomTests(path_, 40, 400);
  RunReport first, second;
  {
    std::jthread a([&] { first = RunScheduler(path_, Processing(), Options(1)); });
    std::jthread b([&] { second = RunScheduler(path_, Processing(), Options(1)); });
  }
  EXPECT_NE(first.owner, second.owner);
  EXPECT_EQ(first.done + second.done, 40);
  EXPECT_EQ(first.lost + second.lost, 0);
  db::Catalogue catalogue = db::Catalogue::Open(path_);
  EXPECT_THAT(db::CatalogueInspector(catalogue).ReadJobAttempts(first.config),
              ::testing::AllOf(::testing::SizeIs(40), ::testing::Each(1)));
  EXPECT_EQ(db::CatalogueInspector(catalogue).CountRows("results"), 40);
}

TEST_F(SchedulerTest, JobsOfADeadLocalWorkerAreReclaimedAtOnce) {
  AddRandomTests(path_, 6, 400);
  const records::ResolvedConfig processing = Processing();
  // A worker on this host that claimed jobs and died (its pid is reaped).
  const pid_t child = fork();
  if (child == 0) _exit(0);
  waitpid(child, nullptr, 0);
  char host[256] = {};
  gethostname(host, sizeof host - 1);
  const std::string dead_owner = std::string(host) + ":" + std::to_string(child) + ":0123456789abcdef";
  EXPECT_TRUE(IsDeadLocalOwner(dead_owner));
  {
    db::Catalogue catalogue = db::Catalogue::Open(path_);
    const db::ConfigId config = catalogue.WriteConfig(processing.record);
    db::JobQueue queue(catalogue);
    queue.EnqueueMissing(config);
    ASSERT_EQ(queue.ClaimJobs(config, dead_owner, 4, 3600.0).size(), 4u);
  }
  const auto start = std::chrono::steady_clock::now();
  const RunReport report = RunScheduler(path_, processing, Options(2));
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 60.0);
  EXPECT_EQ(report.done, 6);
  EXPECT_EQ(report.reclaimed, 4);
  db::Catalogue catalogue = db::Catalogue::Open(path_);
  EXPECT_THAT(db::CatalogueInspector(catalogue).ReadJobAttempts(report.config),
              ::testing::ElementsAre(2, 2, 2, 2, 1, 1));
}

TEST_F(SchedulerTest, JobsOfAForeignWorkerAreTakenWhenTheirLeaseExpires) {
  AddRandomTests(path_, 4, 400);
  const records::ResolvedConfig processing = Processing();
  const std::string foreign = "another-host:1:0123456789abcdef";
  EXPECT_FALSE(IsDeadLocalOwner(foreign)) << "no way to know: wait for the lease";
  {
    db::Catalogue catalogue = db::Catalogue::Open(path_);
    const db::ConfigId config = catalogue.WriteConfig(processing.record);
    db::JobQueue queue(catalogue);
    queue.EnqueueMissing(config);
    ASSERT_EQ(queue.ClaimJobs(config, foreign, 2, 1.0).size(), 2u);
  }
  const RunReport report = RunScheduler(path_, processing, Options(2));
  EXPECT_EQ(report.done, 4) << "the run waited for the foreign lease and took its jobs";
  db::Catalogue catalogue = db::Catalogue::Open(path_);
  EXPECT_EQ(db::JobQueue(catalogue).ReadStatusCounts(report.config).done, 4);
}

TEST_F(SchedulerTest, AChangedConfigMakesResultsStaleWithoutDeletingThem) {
  AddRandomTests(path_, 4, 600);
  const RunReport first = RunScheduler(path_, Processing(), Options(2));
  EXPECT_EQ(first.done, 4);

  engine::ProcessingConfig seed_config;
  seed_config.solver = engine::SolverKind::kSeed;
  const RunReport second = RunScheduler(path_, Processing(seed_config), Options(2));
  EXPECT_NE(second.config, first.config);
  EXPECT_EQ(second.total, 4) << "every result is stale for the new config";
  EXPECT_EQ(second.done, 4);

  db::Catalogue catalogue = db::Catalogue::Open(path_);
  db::CatalogueInspector inspector(catalogue);
  const db::TestId test = *catalogue.FindTestByExternalId(TestName(0));
  EXPECT_EQ(inspector.ReadResultSolver(test, first.config), "exact") << "earlier result kept";
  EXPECT_EQ(inspector.ReadResultSolver(test, second.config), "seed");
  EXPECT_EQ(inspector.CountRows("results"), 8);

  // --force recomputes the current config's results and replaces them.
  RunOptions force = Options(2);
  force.force = true;
  const RunReport forced = RunScheduler(path_, Processing(seed_config), force);
  EXPECT_EQ(forced.total, 4);
  EXPECT_EQ(forced.done, 4);
  EXPECT_EQ(inspector.CountRows("results"), 8);
  EXPECT_THAT(inspector.ReadJobAttempts(second.config), ::testing::Each(2));
}

TEST_F(SchedulerTest, ScopeAndShardSelectTheirTestsOnly) {
  AddRandomTests(path_, 9, 400);
  RunOptions options = Options(2);
  options.scope.tests.external_ids = {TestName(2), TestName(5)};
  const RunReport some = RunScheduler(path_, Processing(), options);
  EXPECT_EQ(some.done, 2);
  options = Options(2);
  options.scope.shard = db::Shard{1, 3};
  const RunReport shard = RunScheduler(path_, Processing(), options);
  // Keys 1..9; shard 1/3 holds 1, 4, 7 (r0000, r0003, r0006), none done yet.
  EXPECT_EQ(shard.total, 3);
  EXPECT_EQ(shard.done, 3);
  db::Catalogue catalogue = db::Catalogue::Open(path_);
  EXPECT_EQ(db::JobQueue(catalogue).ReadStatusCounts(shard.config).done, 5);
}

TEST_F(SchedulerTest, OwnerIdsAreUniqueAndNameThisProcess) {
  const std::string a = MakeOwnerId(), b = MakeOwnerId();
  EXPECT_NE(a, b);
  EXPECT_THAT(a, ::testing::HasSubstr(":" + std::to_string(getpid()) + ":"));
  // `a` is this process's pid but no running scheduler's id: a dead process
  // whose pid was reused.
  EXPECT_TRUE(IsDeadLocalOwner(a));
  EXPECT_FALSE(IsDeadLocalOwner("garbage"));
  EXPECT_FALSE(IsDeadLocalOwner("host:notapid:x"));
}

TEST_F(SchedulerTest, OptionsOutOfRangeAreRejected) {
  RunOptions options;
  options.commit_batch = 0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = RunOptions{};
  options.lease_s = 0.0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  EXPECT_NO_THROW(RunOptions{}.Check());
}

}  // namespace
}  // namespace napkin::jobs

// Merging shard catalogues processed on other machines.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

#include "common/error.h"
#include "db/catalogue.h"
#include "db/job_queue.h"
#include "engine/summary_fields.h"
#include "tests/db/db_test_helpers.h"
#include "tests/support/db/catalogue_inspector.h"
#include "tests/support/test_support.h"

namespace napkin::db {
namespace {

using ::testing::HasSubstr;
using ::testing::IsEmpty;
using ::testing::StrEq;
using ::testing::ThrowsMessage;

engine::Kinematics RampKinematics(Eigen::Index n, double scale) {
  engine::Kinematics kinematics;
  kinematics.Resize(n);
  kinematics.time_s.setLinSpaced(n, 0.0, 1e-4 * static_cast<double>(n - 1));
  for (auto* series :
       {&kinematics.omega_body, &kinematics.alpha_body, &kinematics.omega_fixed, &kinematics.alpha_fixed,
        &kinematics.acc_body, &kinematics.acc_fixed, &kinematics.vel_fixed, &kinematics.pos_fixed,
        &kinematics.roll_pitch_yaw_rad, &kinematics.dcos_rad})
    series->setConstant(scale);
  kinematics.quat_fixed_from_body.setConstant(0.5);
  kinematics.residual.setConstant(scale / 3.0);
  return kinematics;
}

class MergeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    Catalogue main = Catalogue::Open(main_path_);
    const ArrayId array = main.WriteArray(test_support::IdealArray());
    for (const char* id : {"t0", "t1", "t2", "t3", "t4", "t5"}) {
      const TestId test = test_support::AddTest(main, array, id, "S", "A");
      engine::TestSignals signals;
      signals.slots = {"cg_x"};
      signals.samples = Eigen::MatrixXd::Constant(8, 1, 1.0);
      main.WriteRawChannels(test, signals, std::vector<std::string>{"g"});
    }
    main.WriteConfig(test_support::DefaultConfig());
  }  // closing checkpoints the WAL: the file alone is the catalogue

  // The summary ProcessShard writes for test `external_id` ("t<k>").
  static engine::TestSummary ShardSummary(const std::string& external_id) {
    engine::TestSummary summary;
    summary.hic15.value = 100.0 + std::stod(external_id.substr(1));
    summary.findings = {{"bias", "cg_x", engine::Severity::kInfo, "Offset removed."}};
    return summary;
  }

  // Copies the catalogue to a shard file, processes shard `index` of `count`
  // there (test t<k> gets HIC15 = 100 + k; "t3" fails).
  std::string ProcessShard(int index, int count) {
    std::string path = dir_ / ("shard" + std::to_string(index) + ".db");
    std::filesystem::copy_file(main_path_, path);
    Catalogue shard = Catalogue::Open(path);
    JobQueue queue(shard);
    const ConfigId config = *shard.FindConfigByHash(test_support::DefaultConfig().config_hash);
    JobScope scope;
    scope.shard = Shard{index, count};
    queue.EnqueueMissing(config, scope);
    const std::string owner = "node" + std::to_string(index);
    for (const Job& job : queue.ClaimJobs(config, owner, 100, 600.0)) {
      const std::string external_id = shard.ReadTest(job.test_id).external_id;
      if (external_id == "t3") {
        EXPECT_TRUE(queue.FailJob(job.id, owner, "channel 'cg_y' of test 't3' is missing."));
        continue;
      }
      const engine::TestSummary summary = ShardSummary(external_id);
      const engine::Kinematics kinematics = RampKinematics(16, summary.hic15.value);
      auto transaction = shard.BeginTransaction();
      shard.WriteResult(job.test_id, config, summary, "exact", &kinematics);
      EXPECT_TRUE(queue.CompleteJob(job.id, owner));
      transaction.Commit();
    }
    return path;
  }

  napkin::test_support::TempDir dir_;
  std::string main_path_ = dir_ / "main.db";
};

TEST_F(MergeTest, ShardsMergeIntoTheCompleteCatalogue) {
  const std::string shard0 = ProcessShard(0, 2);
  const std::string shard1 = ProcessShard(1, 2);
  Catalogue main = Catalogue::Open(main_path_);
  const ConfigId config = *main.FindConfigByHash(test_support::DefaultConfig().config_hash);

  const MergeReport first = main.MergeShard(shard0);
  const MergeReport second = main.MergeShard(shard1);
  JobQueue queue(main);
  EXPECT_EQ(first.tests_added + second.tests_added, 0);
  EXPECT_EQ(first.results_merged + second.results_merged, 5);
  EXPECT_EQ(first.failures_merged + second.failures_merged, 1);

  const StatusCounts counts = queue.ReadStatusCounts(config);
  EXPECT_EQ(counts.tests, 6);
  EXPECT_EQ(counts.done, 5);
  EXPECT_EQ(counts.failed, 1);
  ASSERT_EQ(counts.failures.size(), 1u);
  EXPECT_EQ(counts.failures[0].test_id, "t3");
  EXPECT_EQ(counts.failures[0].error, "channel 'cg_y' of test 't3' is missing.");

  for (const TestRow& test : main.ReadAllTests()) {
    if (test.external_id == "t3") continue;
    const auto summary = main.ReadSummary(test.id, config);
    ASSERT_TRUE(summary.has_value()) << test.external_id;
    const double expected = 100.0 + std::stod(test.external_id.substr(1));
    EXPECT_EQ(summary->hic15.value, expected);
    EXPECT_THAT(engine::DifferingSummaryFields(*summary, ShardSummary(test.external_id)), IsEmpty())
        << test.external_id;
    const auto kinematics = main.ReadKinematics(test.id, config);
    ASSERT_TRUE(kinematics.has_value());
    EXPECT_EQ(kinematics->omega_body, RampKinematics(16, expected).omega_body);
  }
  EXPECT_EQ(queue.EnqueueMissing(config), 1) << "only the failure is left to retry";

  // Merging again changes nothing.
  const std::string before = CatalogueInspector(main).Dump();
  const MergeReport again = main.MergeShard(shard1);
  EXPECT_EQ(again.results_merged, 0);
  EXPECT_EQ(again.failures_merged, 0);
  EXPECT_EQ(CatalogueInspector(main).Dump(), before);
}

TEST_F(MergeTest, TestsImportedInAShardAreAddedWithTheirChannels) {
  const std::string shard_path = dir_ / "extra.db";
  std::filesystem::copy_file(main_path_, shard_path);
  {
    Catalogue shard = Catalogue::Open(shard_path);
    // A new array and series on the shard shift its keys away from main's.
    ArrayRow other_array = test_support::IdealArray();
    other_array.definition_hash = "other";
    other_array.definition_json = "{\"other\":true}";
    const ArrayId array = shard.WriteArray(other_array);
    const TestId test = test_support::AddTest(shard, array, "t9", "new-series", "B");
    engine::TestSignals signals;
    signals.slots = {"cg_x", "cg_y"};
    signals.samples = Eigen::MatrixXd::Random(5, 2);
    shard.WriteRawChannels(test, signals, std::vector<std::string>{"g", "g"});
  }
  Catalogue main = Catalogue::Open(main_path_);
  const MergeReport report = main.MergeShard(shard_path);
  EXPECT_EQ(report.tests_added, 1);
  const auto added = main.FindTestByExternalId("t9");
  ASSERT_TRUE(added.has_value());
  const TestRow test = main.ReadTest(*added);
  EXPECT_EQ(test.series, "new-series");
  EXPECT_EQ(main.ReadArray(test.array_id).definition_hash, "other");
  Catalogue shard = Catalogue::Open(shard_path);
  EXPECT_EQ(main.ReadTestSignals(*added).samples,
            shard.ReadTestSignals(*shard.FindTestByExternalId("t9")).samples);
}

TEST_F(MergeTest, ConflictingTestIdsAndForeignFilesAreRefused) {
  const std::string shard_path = dir_ / "conflict.db";
  std::filesystem::copy_file(main_path_, shard_path);
  {
    Catalogue main = Catalogue::Open(main_path_);
    test_support::AddTest(main, main.WriteArray(test_support::IdealArray()), "t9");
  }
  {
    Catalogue shard = Catalogue::Open(shard_path);
    TestRow clash;
    clash.external_id = "t9";
    clash.array_id = shard.WriteArray(test_support::IdealArray());
    clash.source_path = "/other/t9.csv";
    clash.content_hash = "different content";
    shard.WriteTest(clash);
  }
  Catalogue main = Catalogue::Open(main_path_);
  const std::string before = CatalogueInspector(main).Dump();
  EXPECT_THAT(
      [&] { main.MergeShard(shard_path); },
      ThrowsMessage<InputError>(StrEq("test 't9' in shard '" + shard_path +
                                      "' has different content from the catalogue's test of that id.")));
  EXPECT_EQ(CatalogueInspector(main).Dump(), before);

  const std::string text = dir_ / "notes.txt";
  std::ofstream(text) << "not a catalogue\n";
  EXPECT_THAT([&] { main.MergeShard(text); }, ThrowsMessage<InputError>(HasSubstr("not an SQLite database")));
  // The connection is still usable afterwards (the shard was detached).
  EXPECT_EQ(main.ReadAllTests().size(), 7u);
}

TEST_F(MergeTest, ADifferentResultForTheSameTestAndConfigIsRefused) {
  const std::string shard0 = ProcessShard(0, 2);
  Catalogue::Open(main_path_).MergeShard(shard0);  // closing checkpoints the WAL
  // The same shard processed again elsewhere gives the same values: merging
  // it is no conflict.
  const std::string again = dir_ / "again.db";
  std::filesystem::copy_file(main_path_, again);
  {
    Catalogue copy = Catalogue::Open(again);
    const ConfigId config = *copy.FindConfigByHash(test_support::DefaultConfig().config_hash);
    // Shard 0 of 2 holds the keys 2, 4, 6: t1, t3 (failed) and t5.
    const TestId t1 = *copy.FindTestByExternalId("t1");
    const engine::Kinematics kinematics = *copy.ReadKinematics(t1, config);
    engine::TestSummary summary = *copy.ReadSummary(t1, config);
    copy.WriteResult(t1, config, summary, "exact", &kinematics);
    summary.hic15.value += 1e-9;  // t5 is another story
    copy.WriteResult(*copy.FindTestByExternalId("t5"), config, summary, "exact", &kinematics);
  }
  Catalogue main = Catalogue::Open(main_path_);
  const std::string before = CatalogueInspector(main).Dump();
  EXPECT_THAT([&] { main.MergeShard(again); },
              ThrowsMessage<InputError>(StrEq("test 't5' has a result for config 'default' in shard '" +
                                              again + "' that differs from the catalogue's result.")));
  EXPECT_EQ(CatalogueInspector(main).Dump(), before);
}

// Derived channels keep their encoding through a merge (schema 6): a result
// stored as float32 in the shard reads back the same rounded values here.
TEST_F(MergeTest, MergedDerivedChannelsKeepTheirEncoding) {
  const std::string shard0 = ProcessShard(0, 2);
  {
    Catalogue shard = Catalogue::Open(shard0);
    const ConfigId config = *shard.FindConfigByHash(test_support::DefaultConfig().config_hash);
    const TestId t1 = *shard.FindTestByExternalId("t1");
    const engine::Kinematics kinematics = RampKinematics(16, ShardSummary("t1").hic15.value);
    shard.WriteResult(t1, config, ShardSummary("t1"), "exact", &kinematics, engine::DerivedStorage::kFloat32);
  }
  Catalogue main = Catalogue::Open(main_path_);
  main.MergeShard(shard0);
  const ConfigId config = *main.FindConfigByHash(test_support::DefaultConfig().config_hash);
  const engine::Kinematics exact = RampKinematics(16, ShardSummary("t1").hic15.value);
  const engine::Kinematics t1 = *main.ReadKinematics(*main.FindTestByExternalId("t1"), config);
  EXPECT_EQ(t1.time_s, exact.time_s);  // the time base stays float64
  EXPECT_NE(t1.residual, exact.residual);
  EXPECT_EQ(t1.residual,
            exact.residual.unaryExpr([](double r) { return static_cast<double>(static_cast<float>(r)); }));
  const engine::Kinematics t5 = *main.ReadKinematics(*main.FindTestByExternalId("t5"), config);
  EXPECT_EQ(t5.time_s, RampKinematics(16, ShardSummary("t5").hic15.value).time_s);  // float64: bit-exact
  auto encodings = CatalogueInspector(main).connection().Prepare(
      "SELECT sum(encoding = 'float32'), sum(encoding = 'float64') FROM derived_channels");
  ASSERT_TRUE(encodings->Step());
  EXPECT_EQ(encodings->ColumnInt64(0), 35);      // t1 but its time_s
  EXPECT_EQ(encodings->ColumnInt64(1), 36 + 1);  // t5, and t1's time_s
}

// schema/013_repaired_channels.sql: a salvage record and its repaired
// channel (bit for bit, NaN and -0 included) round-trip and come with a
// merged result; an excluded channel keeps none.
TEST_F(MergeTest, MergedSalvageAuditsKeepTheirRepairedChannels) {
  engine::SalvageAudit record;
  record.mode = "repair";
  record.channels_used = record.channels_total = 9;
  record.rms_residual_before_mps2 = 30.0;
  record.rms_residual_after_mps2 = 1e-3;
  engine::SalvagedChannel replaced;
  replaced.channel = "cg_x";
  replaced.fault = engine::FaultKind::kDropout;
  replaced.action = engine::SalvageAction::kReplaced;
  replaced.t1_s = 0.0002;
  replaced.t2_s = 0.0004;
  replaced.samples_replaced = 3;
  replaced.repaired_samples = {1.0,    -0.0, 2.5, std::numeric_limits<double>::quiet_NaN(),
                               1e-310, 4.0,  5.0, 6.0};
  record.channels.push_back(replaced);
  engine::SalvagedChannel& excluded = record.channels.emplace_back();
  excluded.channel = "cg_y";
  excluded.fault = engine::FaultKind::kStuck;
  excluded.action = engine::SalvageAction::kExcluded;
  const std::string shard0 = ProcessShard(0, 2);
  {
    Catalogue shard = Catalogue::Open(shard0);
    const ConfigId config = *shard.FindConfigByHash(test_support::DefaultConfig().config_hash);
    engine::TestSummary summary = ShardSummary("t1");
    summary.salvage = record;
    shard.WriteResult(*shard.FindTestByExternalId("t1"), config, summary, "exact");
  }
  Catalogue main = Catalogue::Open(main_path_);
  main.MergeShard(shard0);
  const ConfigId config = *main.FindConfigByHash(test_support::DefaultConfig().config_hash);
  const std::optional<engine::TestSummary> merged =
      main.ReadSummary(*main.FindTestByExternalId("t1"), config);
  ASSERT_TRUE(merged && merged->salvage);
  ASSERT_EQ(merged->salvage->channels.size(), 2u);
  const std::vector<double>& samples = merged->salvage->channels[0].repaired_samples;
  ASSERT_EQ(samples.size(), replaced.repaired_samples.size());
  EXPECT_EQ(std::memcmp(samples.data(), replaced.repaired_samples.data(), samples.size() * sizeof(double)),
            0);
  EXPECT_TRUE(merged->salvage->channels[1].repaired_samples.empty());
  auto nulls = CatalogueInspector(main).connection().Prepare(
      "SELECT count(*) FROM result_salvage WHERE repaired_samples IS NULL AND channel = 'cg_y'");
  ASSERT_TRUE(nulls->Step());
  EXPECT_EQ(nulls->ColumnInt64(0), 1);
}

}  // namespace
}  // namespace napkin::db

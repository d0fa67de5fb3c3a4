// Results files (db/results_file.h): the shared catalogue opened immutable,
// test rows copied with their keys and without raw channels, and merged back.
#include "db/results_file.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <vector>

#include "common/error.h"
#include "db/catalogue.h"
#include "db/job_queue.h"
#include "tests/db/db_test_helpers.h"
#include "tests/support/db/catalogue_inspector.h"
#include "tests/support/db/results_dump.h"
#include "tests/support/test_support.h"

namespace napkin::db {
namespace {

namespace fs = std::filesystem;
using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

std::vector<std::string> FilesIn(const fs::path& directory) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(directory)) names.push_back(entry.path().filename());
  std::sort(names.begin(), names.end());
  return names;
}

class ResultsFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::create_directories(dir_ / "shared");
    Catalogue main = Catalogue::Open(main_path_);
    const ArrayId array = main.WriteArray(test_support::IdealArray());
    for (const char* id : {"t1", "t2", "t3", "t4", "t5", "t6"}) {
      const TestId test = test_support::AddTest(main, array, id, "S", "A");
      engine::TestSignals signals;
      signals.slots = {"cg_x"};
      signals.samples = Eigen::MatrixXd::Constant(8, 1, 1.0);
      main.WriteRawChannels(test, signals, std::vector<std::string>{"g"});
    }
  }  // closing checkpoints the WAL: the file alone is the catalogue

  // Processes the jobs of `results` as the scheduler would, reading tests
  // from `catalogue`: HIC15 = 100 + k for test t<k>, "t3" fails with a finding.
  static void Process(Catalogue& catalogue, Catalogue& results, const JobScope& scope) {
    const ConfigId config = results.WriteConfig(test_support::DefaultConfig());
    JobQueue queue(results);
    queue.EnqueueMissing(config, scope);
    for (const Job& job : queue.ClaimJobs(config, "node", 100, 600.0, scope)) {
      const std::string external_id = catalogue.ReadTest(job.test_id).external_id;
      EXPECT_EQ(catalogue.ReadTestSignals(job.test_id).samples.rows(), 8);
      auto transaction = results.BeginTransaction();
      if (external_id == "t3") {
        const engine::Finding finding{"saturation", "cg_x", engine::Severity::kError, "cg_x is clipped."};
        results.WriteFindings(job.test_id, config, std::span(&finding, 1));
        EXPECT_TRUE(queue.FailJob(job.id, "node", "cg_x is clipped."));
      } else {
        engine::TestSummary summary;
        summary.hic15.value = 100.0 + std::stod(external_id.substr(1));
        results.WriteResult(job.test_id, config, summary, "exact");
        EXPECT_TRUE(queue.CompleteJob(job.id, "node"));
      }
      transaction.Commit();
    }
  }

  napkin::test_support::TempDir dir_;
  std::string main_path_ = dir_ / "shared" / "main.db";
};

TEST_F(ResultsFileTest, TheSharedCatalogueIsReadWithoutAnyFileBesideIt) {
  {
    Catalogue shared = ResultsFile::OpenSharedCatalogue(main_path_);
    EXPECT_EQ(shared.ReadAllTests().size(), 6u);
    EXPECT_EQ(shared.ReadTestSignals(*shared.FindTestByExternalId("t2")).samples.rows(), 8);
    EXPECT_EQ(FilesIn(dir_ / "shared"), std::vector<std::string>{"main.db"});
    // A writer may still open it meanwhile (no lock is held) ...
    Catalogue writer = Catalogue::Open(main_path_);
    writer.WriteSeries("written-meanwhile");
    // ... but a new shared reader refuses the changes it could not see.
    EXPECT_THAT([&] { ResultsFile::OpenSharedCatalogue(main_path_); },
                ThrowsMessage<InputError>(AllOf(HasSubstr("main.db-wal"), HasSubstr("wal_checkpoint"))));
  }
  // Checkpointed (the writer closed): readable again.
  EXPECT_TRUE(ResultsFile::OpenSharedCatalogue(main_path_).ReadSeries("written-meanwhile").has_value());
  EXPECT_THAT([&] { ResultsFile::OpenSharedCatalogue((dir_ / "missing.db").string()); },
              ThrowsMessage<InputError>(HasSubstr("does not exist")));
}

TEST_F(ResultsFileTest, TestsAreCopiedWithTheirKeysAndWithoutRawChannels) {
  Catalogue shared = ResultsFile::OpenSharedCatalogue(main_path_);
  const std::string results_path = dir_ / "r.db";
  Catalogue results = ResultsFile::Open(results_path, shared);
  JobScope scope;
  scope.shard = Shard{1, 2};
  EXPECT_EQ(ResultsFile::CopyTests(shared, results, scope), 3);
  EXPECT_EQ(ResultsFile::CopyTests(shared, results, scope), 0) << "rows already there are kept";
  std::vector<std::string> copied;
  for (const TestRow& test : results.ReadAllTests()) {
    const TestRow original = shared.ReadTest(test.id);  // same key
    EXPECT_EQ(test.external_id, original.external_id);
    EXPECT_EQ(test.content_hash, original.content_hash);
    EXPECT_EQ(test.series, original.series);
    EXPECT_EQ(results.ReadArray(test.array_id).definition_hash,
              shared.ReadArray(original.array_id).definition_hash);
    EXPECT_TRUE(results.ReadRawChannelInfo(test.id).empty());
    copied.push_back(test.external_id);
  }
  EXPECT_EQ(copied, (std::vector<std::string>{"t1", "t3", "t5"}));  // keys 1, 3, 5: key % 2 == 1

  // A results file written for another catalogue (other content at the same key) is refused.
  const std::string other_path = dir_ / "other.db";
  {
    Catalogue other = Catalogue::Open(other_path);
    const ArrayId array = other.WriteArray(test_support::IdealArray());
    test_support::AddTest(other, array, "x1", "S", "A");
  }
  Catalogue other = ResultsFile::Open(other_path, shared);
  EXPECT_THAT([&] { ResultsFile::CopyTests(shared, other, scope); },
              ThrowsMessage<InputError>(AllOf(HasSubstr("other.db"), HasSubstr("another catalogue"),
                                              HasSubstr("main.db"), HasSubstr("its test 't1' differs"))));
}

TEST_F(ResultsFileTest, TheCatalogueItselfOrADirectoryIsNotAResultsFile) {
  Catalogue shared = ResultsFile::OpenSharedCatalogue(main_path_);
  fs::create_symlink(main_path_, dir_ / "alias.db");
  for (const std::string& itself : {main_path_, std::string(dir_ / "alias.db")})
    EXPECT_THAT([&] { ResultsFile::Open(itself, shared); },
                ThrowsMessage<InputError>(AllOf(HasSubstr("is the catalogue"), HasSubstr("itself"))));
  EXPECT_THAT([&] { ResultsFile::Open(dir_ / "shared", shared); },
              ThrowsMessage<InputError>(HasSubstr("is a directory")));
  EXPECT_EQ(FilesIn(dir_ / "shared"), std::vector<std::string>{"main.db"});
}

TEST_F(ResultsFileTest, ResultsFilesMergeLikeShardCopiesAndCannotAddTests) {
  // The whole catalogue processed in place, for comparison.
  const std::string whole_path = dir_ / "whole.db";
  fs::copy_file(main_path_, whole_path);
  {
    Catalogue whole = Catalogue::Open(whole_path);
    Process(whole, whole, {});
  }
  std::vector<std::string> files;
  {
    Catalogue shared = ResultsFile::OpenSharedCatalogue(main_path_);
    for (int i = 0; i < 2; ++i) {
      files.push_back(dir_ / ("r" + std::to_string(i) + ".db"));
      Catalogue results = ResultsFile::Open(files.back(), shared);
      JobScope scope;
      scope.shard = Shard{i, 2};
      ResultsFile::CopyTests(shared, results, scope);
      Process(shared, results, scope);
    }
  }
  const std::string merged_path = dir_ / "merged.db";
  fs::copy_file(main_path_, merged_path);
  Catalogue merged = Catalogue::Open(merged_path);
  for (const std::string& file : files) {
    const MergeReport report = merged.MergeShard(file);
    EXPECT_EQ(report.tests_added, 0);
    EXPECT_EQ(report.results_merged + report.failures_merged, 3);
  }
  const std::string expected = CanonicalResultsDump(whole_path);
  EXPECT_NE(expected.find("findings|test_id='t3'"), std::string::npos) << "the failure's finding";
  EXPECT_EQ(CanonicalResultsDump(merged_path), expected);
  const std::string before = CatalogueInspector(merged).Dump();
  merged.MergeShard(files[1]);
  EXPECT_EQ(CatalogueInspector(merged).Dump(), before) << "merging again changes nothing";

  // Into a catalogue without t1 (a results file carries no raw channels).
  const std::string small_path = dir_ / "small.db";
  {
    Catalogue small = Catalogue::Open(small_path);
    const ArrayId array = small.WriteArray(test_support::IdealArray());
    test_support::AddTest(small, array, "t2", "S", "A");
  }
  Catalogue small = Catalogue::Open(small_path);
  const std::string small_before = CatalogueInspector(small).Dump();
  EXPECT_THAT([&] { small.MergeShard(files[1]); },
              ThrowsMessage<InputError>(AllOf(HasSubstr("test 't1'"), HasSubstr("r1.db"),
                                              HasSubstr("not in the catalogue"), HasSubstr("raw channels"))));
  EXPECT_EQ(CatalogueInspector(small).Dump(), small_before);
}

}  // namespace
}  // namespace napkin::db

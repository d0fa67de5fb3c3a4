// `napkin run --shard I/N --results FILE.db` end to end (README "Batch runs",
// docs/formats.md "Results files"): shards read one catalogue that nobody
// may write (folder and file read-only, opened immutable: no file appears
// beside it), each writes its results file, `napkin merge` takes them back
// into a copy of the original, which then equals an unsharded run of it bit
// for bit (db::CanonicalResultsDump). Resuming, a catalogue with an
// un-checkpointed -wal, bad --results paths and a results file of tests the
// catalogue lacks are one-sentence refusals.
#include <gtest/gtest.h>
#include <pwd.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "db/catalogue.h"
#include "tests/cli/cli_test_util.h"
#include "tests/support/db/catalogue_inspector.h"
#include "tests/support/db/results_dump.h"
#include "tests/support/test_support.h"

namespace napkin {
namespace {

namespace fs = std::filesystem;
using test_support::CommandResult;
using test_support::ExpectOneSentenceError;
using test_support::ReadText;

constexpr int kTests = 12;
constexpr int kShards = 3;
// The test whose channel is clipped: screening fails it (an error finding).
constexpr const char* kClippedTest = "random-0005";

std::vector<std::string> Concat(std::vector<std::string> head, const std::vector<std::string>& tail) {
  head.insert(head.end(), tail.begin(), tail.end());
  return head;
}

std::vector<std::string> FilesIn(const fs::path& directory) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(directory)) names.push_back(entry.path().filename());
  std::sort(names.begin(), names.end());
  return names;
}

// Lines of a canonical dump that start with `prefix`.
int CountLines(const std::string& dump, const std::string& prefix) {
  int count = 0;
  for (const std::string& line : test_support::Lines(dump)) count += line.rfind(prefix, 0) == 0 ? 1 : 0;
  return count;
}

class ResultsFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    base_ = dir_ / "base.db";
    ASSERT_EQ(Napkin({"--db", base_, "synth", "--scenario", "random", "--count", std::to_string(kTests),
                      "--samples", "1000"})
                  .exit_code,
              0);
    // Clip one channel of one test at 80 % of its peak: a saturated channel,
    // an error-severity finding, a failed test with its findings stored.
    db::Catalogue catalogue = db::Catalogue::Open(base_);
    const db::TestId clipped = *catalogue.FindTestByExternalId(kClippedTest);
    engine::TestSignals signals = catalogue.ReadTestSignals(clipped);
    std::vector<std::string> units;
    for (const db::RawChannelInfo& channel : catalogue.ReadRawChannelInfo(clipped))
      units.push_back(channel.unit);
    auto column = signals.samples.col(0);
    const double clip = 0.8 * column.cwiseAbs().maxCoeff();
    column = column.cwiseMax(-clip).cwiseMin(clip);
    catalogue.WriteRawChannels(clipped, signals, units);
  }

  void TearDown() override {
    // Let the temporary folder be removed whoever runs the tests.
    for (const fs::path& locked : locked_)
      if (fs::exists(locked)) fs::permissions(locked, fs::perms::owner_all, fs::perm_options::add);
  }

  CommandResult Napkin(const std::vector<std::string>& args) {
    return test_support::RunNapkin(dir_.path(), args);
  }

  // Whether napkin can run as a user who may not write the read-only
  // folders: any user but root, or root through setpriv(1) as nobody.
  bool CanDropRoot() const {
    return geteuid() != 0 || (getpwnam("nobody") != nullptr && fs::exists("/usr/bin/setpriv"));
  }
  // Runs napkin as that user (as root without setpriv: as root, for whom
  // the folders are not read-only, but the catalogue is still opened immutable).
  CommandResult NapkinAsUser(const std::vector<std::string>& args) {
    if (geteuid() != 0 || !CanDropRoot()) return Napkin(args);
    const passwd* nobody = getpwnam("nobody");
    return test_support::RunProgram(
        "/usr/bin/setpriv",
        Concat({"--reuid=" + std::to_string(nobody->pw_uid), "--regid=" + std::to_string(nobody->pw_gid),
                "--clear-groups", NAPKIN_BINARY},
               args),
        dir_.path());
  }

  // A copy of the base catalogue in folder `name`, file and folder made
  // read-only for everyone (nobody reaches it through dir_).
  fs::path ReadOnlyCopy(const std::string& name) {
    const fs::path folder = dir_ / name;
    fs::create_directories(folder);
    fs::path copy = folder / "catalogue.db";
    fs::copy_file(base_, copy);
    const auto read_only = fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read;
    fs::permissions(copy, read_only);
    fs::permissions(folder,
                    read_only | fs::perms::owner_exec | fs::perms::group_exec | fs::perms::others_exec);
    fs::permissions(dir_.path(), fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec |
                                     fs::perms::others_read | fs::perms::others_exec);
    locked_.push_back(folder);
    return copy;
  }

  // A folder anyone may write, for the results files.
  fs::path OpenFolder(const std::string& name) {
    fs::path folder = dir_ / name;
    fs::create_directories(folder);
    fs::permissions(folder, fs::perms::all);
    return folder;
  }

  nlohmann::json Status(const fs::path& db) {
    const CommandResult status = Napkin({"--db", db, "status", "--format", "json"});
    EXPECT_EQ(status.exit_code, 0) << status.err;
    // The counts, without the file they are of (the JSON's "path"): two catalogues are compared.
    nlohmann::json counts = nlohmann::json::parse(status.out);
    counts.erase("path");
    return counts;
  }

  test_support::TempDir dir_;
  fs::path base_;
  std::vector<fs::path> locked_;
};

TEST_F(ResultsFileTest, ShardsFromAReadOnlyCatalogueMergeToExactlyTheUnshardedRun) {
  const fs::path whole = dir_ / "whole.db";
  fs::copy_file(base_, whole);
  const CommandResult unsharded = Napkin({"--db", whole, "--quiet", "run", "--threads", "2"});
  ASSERT_EQ(unsharded.exit_code, 3) << "one test fails screening: " << unsharded.err;

  const fs::path shared = ReadOnlyCopy("shared");
  const std::string shared_bytes = ReadText(shared);
  const fs::path out = OpenFolder("out");
  std::vector<std::string> merge = {"--db", dir_ / "merged.db", "merge"};
  int failed_shards = 0;
  for (int i = 0; i < kShards; ++i) {
    const std::string results = out / ("results-" + std::to_string(i) + ".db");
    const CommandResult run =
        NapkinAsUser({"--db", shared, "--quiet", "run", "--threads", "2", "--shard",
                      std::to_string(i) + "/" + std::to_string(kShards), "--results", results});
    EXPECT_TRUE(run.exit_code == 0 || run.exit_code == 3) << run.err;
    failed_shards += run.exit_code == 3 ? 1 : 0;
    // Nothing beside the shared catalogue: no -wal, -shm or journal.
    EXPECT_EQ(FilesIn(shared.parent_path()), std::vector<std::string>{"catalogue.db"}) << "after shard " << i;
    merge.push_back(results);
  }
  EXPECT_EQ(failed_shards, 1) << "the clipped test fails in its shard";
  EXPECT_EQ(ReadText(shared), shared_bytes) << "the shared catalogue is never written";
  // A results file holds no raw channels.
  {
    db::Catalogue results = test_support::OpenForReading(out / "results-0.db");
    db::CatalogueInspector inspector(results);
    EXPECT_EQ(inspector.CountRows("raw_channels"), 0);
    EXPECT_EQ(inspector.CountRows("tests"), kTests / kShards);
    EXPECT_EQ(inspector.CountRows("jobs"), kTests / kShards);
  }

  fs::copy_file(base_, dir_ / "merged.db");
  const CommandResult merged = Napkin(merge);
  ASSERT_EQ(merged.exit_code, 0) << merged.err;
  EXPECT_NE(merged.out.find("0 tests added"), std::string::npos) << merged.out;

  const std::string expected = db::CanonicalResultsDump(whole);
  EXPECT_EQ(CountLines(expected, "results|"), kTests - 1);
  EXPECT_EQ(CountLines(expected, "jobs|"), kTests);
  EXPECT_EQ(CountLines(expected, "derived_channels|"), (kTests - 1) * 36);
  EXPECT_GT(CountLines(expected, "result_conditioning|"), 0);
  EXPECT_NE(expected.find("test_id='" + std::string(kClippedTest) + "'|config_id="), std::string::npos);
  EXPECT_EQ(db::CanonicalResultsDump(dir_ / "merged.db"), expected);
  EXPECT_EQ(Status(dir_ / "merged.db"), Status(whole));

  // Running a shard again resumes: nothing new is computed, the results file
  // keeps its rows (a failed test is retried and fails the same way).
  for (int i = 0; i < kShards; ++i) {
    const fs::path results = out / ("results-" + std::to_string(i) + ".db");
    const std::string before = test_support::DumpCatalogue(results);
    const std::string canonical_before = db::CanonicalResultsDump(results);
    const CommandResult again =
        NapkinAsUser({"--db", shared, "run", "--shard", std::to_string(i) + "/" + std::to_string(kShards),
                      "--results", results});
    EXPECT_TRUE(again.exit_code == 0 || again.exit_code == 3) << again.err;
    EXPECT_EQ(db::CanonicalResultsDump(results), canonical_before) << "shard " << i;
    if (again.exit_code == 0) {
      EXPECT_NE(again.err.find("0 tests done, 0 failed, 4 up to date"), std::string::npos) << again.err;
      EXPECT_EQ(test_support::DumpCatalogue(results), before) << "shard " << i << " unchanged";
    }
  }
  // Merging the files again changes nothing.
  const std::string merged_before = test_support::DumpCatalogue(dir_ / "merged.db");
  ASSERT_EQ(Napkin(merge).exit_code, 0);
  EXPECT_EQ(db::CanonicalResultsDump(dir_ / "merged.db"), expected);
  EXPECT_EQ(FilesIn(shared.parent_path()), std::vector<std::string>{"catalogue.db"});
}

TEST_F(ResultsFileTest, AnInterruptedShardResumesWithoutDuplicates) {
  const fs::path whole = dir_ / "whole.db";
  fs::copy_file(base_, whole);
  ASSERT_EQ(Napkin({"--db", whole, "--quiet", "run", "--shard", "1/3"}).exit_code, 0);
  const fs::path shared = ReadOnlyCopy("shared");
  const fs::path out = OpenFolder("out");
  const std::string results = out / "results.db";
  // First part of the shard only (as a run stopped early would leave it), then all of it.
  const CommandResult part = NapkinAsUser(
      {"--db", shared, "--quiet", "run", "--shard", "1/3", "--test", "random-0001", "--results", results});
  ASSERT_EQ(part.exit_code, 0) << part.err;
  const CommandResult rest = NapkinAsUser({"--db", shared, "run", "--shard", "1/3", "--results", results});
  ASSERT_EQ(rest.exit_code, 0) << rest.err;
  EXPECT_NE(rest.err.find("3 tests done, 0 failed, 1 up to date"), std::string::npos) << rest.err;
  db::Catalogue catalogue = test_support::OpenForReading(results);
  db::CatalogueInspector inspector(catalogue);
  EXPECT_EQ(inspector.CountRows("results"), 4);
  EXPECT_EQ(inspector.CountRows("jobs"), 4);
  EXPECT_EQ(inspector.CountDoneJobsClaimedOnce(), 4);
  EXPECT_EQ(inspector.CountRows("derived_channels"), 4 * 36);
  // The shard's results equal those of the same shard run in a catalogue.
  fs::copy_file(base_, dir_ / "merged.db");
  ASSERT_EQ(Napkin({"--db", dir_ / "merged.db", "merge", results}).exit_code, 0);
  EXPECT_EQ(db::CanonicalResultsDump(dir_ / "merged.db"), db::CanonicalResultsDump(whole));
}

TEST_F(ResultsFileTest, ACatalogueWithUncheckpointedChangesIsRefusedInOneSentence) {
  const fs::path copy = dir_ / "busy.db";
  fs::copy_file(base_, copy);
  // A writer that has committed into the write-ahead log and is still open.
  db::Catalogue writer = db::Catalogue::Open(copy);
  writer.WriteSeries("added-while-running");
  ASSERT_GT(fs::file_size(copy.string() + "-wal"), 0u);
  const fs::path results = dir_ / "results.db";
  const CommandResult run = Napkin({"--db", copy, "run", "--shard", "0/2", "--results", results});
  EXPECT_EQ(run.exit_code, 1);
  ExpectOneSentenceError(run, {"busy.db", "busy.db-wal", "wal_checkpoint"});
  EXPECT_FALSE(fs::exists(results));
}

TEST_F(ResultsFileTest, BadResultsPathsAreRefusedInOneSentence) {
  const fs::path shared = ReadOnlyCopy("shared");
  auto run = [&](const std::string& results) {
    return NapkinAsUser({"--db", shared, "run", "--shard", "0/2", "--results", results});
  };
  fs::create_directories(dir_ / "folder");
  const CommandResult folder = run(dir_ / "folder");
  EXPECT_EQ(folder.exit_code, 1);
  ExpectOneSentenceError(folder, {"folder", "is a directory"});

  const CommandResult missing = run(dir_ / "no-such-folder" / "r.db");
  EXPECT_EQ(missing.exit_code, 1);
  ExpectOneSentenceError(missing, {"no-such-folder", "does not exist"});

  // The catalogue itself, by its name, a relative name and a hard link.
  fs::create_hard_link(shared, dir_ / "link.db");
  for (const std::string& itself :
       {shared.string(), std::string("shared/catalogue.db"), std::string("link.db")}) {
    const CommandResult same = run(itself);
    EXPECT_EQ(same.exit_code, 1) << itself;
    ExpectOneSentenceError(same, {"is the catalogue", "itself"});
  }
  if (CanDropRoot()) {
    const CommandResult unwritable = run(shared.parent_path() / "r.db");
    EXPECT_EQ(unwritable.exit_code, 1);
    ExpectOneSentenceError(unwritable, {"r.db", "read-only"});
  }
  EXPECT_EQ(FilesIn(shared.parent_path()), std::vector<std::string>{"catalogue.db"});
}

TEST_F(ResultsFileTest, AResultsFileOfATestTheCatalogueLacksIsRefused) {
  const fs::path results = dir_ / "results.db";
  const CommandResult run = Napkin(
      {"--db", base_, "--quiet", "run", "--shard", "0/1", "--test", "random-0008", "--results", results});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const fs::path smaller = dir_ / "smaller.db";
  ASSERT_EQ(Napkin({"--db", smaller, "synth", "--scenario", "random", "--count", "3", "--samples", "1000"})
                .exit_code,
            0);
  const std::string before = test_support::DumpCatalogue(smaller);
  const CommandResult merge = Napkin({"--db", smaller, "merge", results});
  EXPECT_EQ(merge.exit_code, 1);
  ExpectOneSentenceError(merge, {"test 'random-0008'", "results.db", "not in the catalogue", "raw channels"});
  EXPECT_EQ(test_support::DumpCatalogue(smaller), before);
}

}  // namespace
}  // namespace napkin

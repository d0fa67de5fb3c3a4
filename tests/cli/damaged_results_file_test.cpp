// Issue 19 item 6: a results file (or shard) cut short in copying was blamed
// on the catalogue: `merge trunc.db` and `run --shard ... --results trunc.db`
// said "catalogue 't.db' is damaged ...; restore it from a backup", telling
// the user to throw away a sound catalogue. The sentence names the damaged
// file, and neither the catalogue nor the damaged file is written.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "tests/cli/cli_test_util.h"
#include "tests/support/test_support.h"

namespace napkin {
namespace {

namespace fs = std::filesystem;
using test_support::CommandResult;
using test_support::ExpectOneSentenceError;
using test_support::ReadText;

class DamagedResultsFile : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(
        Napkin({"--db", "base.db", "synth", "--scenario", "random", "--count", "6", "--samples", "2000"})
            .exit_code,
        0);
    const CommandResult shard = Napkin({"--db", "base.db", "run", "--shard", "0/2", "--results", "r.db"});
    ASSERT_EQ(shard.exit_code, 0) << shard.err;
    ASSERT_FALSE(fs::exists(dir_ / "r.db-wal") && fs::file_size(dir_ / "r.db-wal") > 0);
    // A copy cut off in the middle, as an interrupted transfer leaves it.
    fs::copy_file(dir_ / "r.db", dir_ / "trunc.db");
    fs::resize_file(dir_ / "trunc.db", fs::file_size(dir_ / "r.db") / 2);
    catalogue_before_ = test_support::DumpCatalogue(dir_ / "base.db");
    truncated_before_ = ReadText(dir_ / "trunc.db");
  }

  CommandResult Napkin(const std::vector<std::string>& args) {
    return test_support::RunNapkin(dir_.path(), args);
  }

  // One sentence naming the damaged file, never the catalogue as damaged nor
  // "restore it from a backup"; nothing written.
  void ExpectBlamesTheTruncatedFile(const CommandResult& refused) {
    EXPECT_EQ(refused.exit_code, 1) << refused.out;
    ExpectOneSentenceError(refused, {"'trunc.db' is damaged"});
    EXPECT_EQ(refused.err.find("catalogue 'base.db' is damaged"), std::string::npos) << refused.err;
    EXPECT_EQ(refused.err.find("backup"), std::string::npos) << refused.err;
    EXPECT_EQ(refused.err.find(".cpp"), std::string::npos) << refused.err;
    EXPECT_EQ(test_support::DumpCatalogue(dir_ / "base.db"), catalogue_before_);
    EXPECT_EQ(ReadText(dir_ / "trunc.db"), truncated_before_) << "the damaged file was written";
  }

  test_support::TempDir dir_;
  std::string catalogue_before_;
  std::string truncated_before_;
};

TEST_F(DamagedResultsFile, MergeNamesTheTruncatedShardNotTheCatalogue) {
  ExpectBlamesTheTruncatedFile(Napkin({"--db", "base.db", "merge", "trunc.db"}));
  // The sound results file still merges afterwards.
  const CommandResult merged = Napkin({"--db", "base.db", "merge", "r.db"});
  EXPECT_EQ(merged.exit_code, 0) << merged.err;
}

TEST_F(DamagedResultsFile, RunIntoATruncatedResultsFileNamesIt) {
  ExpectBlamesTheTruncatedFile(Napkin({"--db", "base.db", "run", "--shard", "0/2", "--results", "trunc.db"}));
}

}  // namespace
}  // namespace napkin

// `napkin import` of real lab tests: several dummies (TEST/11, TEST/13,
// --position), the position and test information in `query tests`, the
// ambiguous-position refusal, and CSV columns named with --column (import
// and transform).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "tests/cli/cli_test_util.h"
#include "tests/support/isomme_generator.h"
#include "tests/support/test_support.h"

namespace napkin::cli {
namespace {

using napkin::test_support::ExpectOneSentenceError;
using napkin::test_support::Lines;
using napkin::test_support::RunNapkin;
using napkin::test_support::RunResult;

class CliImportPositions : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(RunNapkin(dir_.path(), {"init"}).exit_code, 0);
    generated_ = napkin::test_support::WriteMultiDummyIsoMme(dir_ / "MD0001", {.samples = 300});
  }
  RunResult Napkin(std::vector<std::string> args) {
    args.insert(args.begin(), {"--db", "napkin.db"});
    return RunNapkin(dir_.path(), args);
  }

  napkin::test_support::TempDir dir_;
  napkin::test_support::GeneratedIsoMme generated_;
};

TEST_F(CliImportPositions, EachDummyHeadIsATestAndTheTestsQueryShowsItsInformation) {
  const RunResult import =
      Napkin({"import", "--array", "6aw-cg", "--series", "frontal", "MD0001", "--quiet"});
  ASSERT_EQ(import.exit_code, 0) << import.err;
  EXPECT_EQ(Lines(import.out).back(), "imported 2 tests, skipped 0 already present.");

  const RunResult query = Napkin({"query", "tests", "--where", "position=13", "--format", "json"});
  ASSERT_EQ(query.exit_code, 0) << query.err;
  const nlohmann::json rows = nlohmann::json::parse(query.out);
  ASSERT_EQ(rows.size(), 1U);
  EXPECT_EQ(rows[0]["test_id"], "MD0001/13");
  EXPECT_EQ(rows[0]["series"], "frontal");
  EXPECT_EQ(rows[0]["position"], "13");
  EXPECT_EQ(rows[0]["test_number"], "MD0001");
  EXPECT_EQ(rows[0]["title"], generated_.title);
  EXPECT_EQ(rows[0]["vehicle"], generated_.vehicle);
  EXPECT_EQ(rows[0]["dummy"], "HF");
  EXPECT_EQ(rows[0]["test_date"], "2019-05-21");
  EXPECT_EQ(rows[0]["laboratory"], generated_.laboratory);

  const RunResult csv = Napkin({"query", "tests", "--sort", "position:desc", "--format", "csv"});
  ASSERT_EQ(csv.exit_code, 0) << csv.err;
  const std::vector<std::string> lines = Lines(csv.out);
  ASSERT_EQ(lines.size(), 3U);
  EXPECT_EQ(
      lines[0],
      "test_id,series,variant,array,source_path,content_hash,imported_at,position,test_number,title,vehicle,"
      "dummy,test_date,laboratory,salvaged");
  EXPECT_EQ(lines[1].rfind("MD0001/13,", 0), 0U);
  EXPECT_EQ(lines[2].rfind("MD0001/11,", 0), 0U);
}

TEST_F(CliImportPositions, AnAmbiguousPositionIsOneSentenceAndChangesNothing) {
  const std::string before = napkin::test_support::DumpCatalogue(dir_ / "napkin.db");
  const RunResult import =
      Napkin({"import", "--array", "6aw-cg", "--test-id", "driver", "MD0001", "--quiet"});
  EXPECT_EQ(import.exit_code, 1);
  ExpectOneSentenceError(import, {"holds dummy heads at positions 11 and 13", "give --position to take one"});
  EXPECT_EQ(napkin::test_support::DumpCatalogue(dir_ / "napkin.db"), before);

  const RunResult driver =
      Napkin({"import", "--array", "6aw-cg", "--test-id", "driver", "--position", "11", "MD0001", "--quiet"});
  ASSERT_EQ(driver.exit_code, 0) << driver.err;
  const RunResult query = Napkin({"query", "tests", "--format", "json"});
  const nlohmann::json rows = nlohmann::json::parse(query.out);
  ASSERT_EQ(rows.size(), 1U);
  EXPECT_EQ(rows[0]["test_id"], "driver");
  EXPECT_EQ(rows[0]["position"], "11");
  EXPECT_EQ(rows[0]["dummy"], "H3");
}

TEST_F(CliImportPositions, ColumnOptionsNameTheCsvColumnsOnImportAndTransform) {
  // 100 samples at 10 kHz under the lab's own column names.
  std::string lab_csv = "Time,AX,AY,AZ,RX,RY,RZ\n";
  for (int i = 0; i < 100; ++i)
    lab_csv += std::to_string(i * 1e-4) + "," + std::to_string(i % 7) + ",0,0,0,0,0\n";
  napkin::test_support::WriteText(dir_ / "lab.csv", lab_csv);
  const std::vector<std::string> columns = {"--column", "time_s=Time", "--column", "cg_x=AX",  "--column",
                                            "cg_y=AY",  "--column",    "cg_z=AZ",  "--column", "ars_x=RX",
                                            "--column", "ars_y=RY",    "--column", "ars_z=RZ"};
  std::vector<std::string> import = {"import", "--array", "6aw-cg", "lab.csv", "--quiet"};
  import.insert(import.end(), columns.begin(), columns.end());
  const RunResult imported = Napkin(import);
  ASSERT_EQ(imported.exit_code, 0) << imported.err;
  EXPECT_EQ(Lines(imported.out).back(), "imported 1 test, skipped 0 already present.");

  std::vector<std::string> transform = {"transform", "--array", "6aw-cg", "lab.csv", "--out", "lab_out.csv"};
  transform.insert(transform.end(), columns.begin(), columns.end());
  const RunResult transformed = RunNapkin(dir_.path(), transform);
  ASSERT_EQ(transformed.exit_code, 0) << transformed.err;
  // One derived row per input sample: the columns were found by their mapped names.
  EXPECT_EQ(Lines(napkin::test_support::ReadText(dir_ / "lab_out.csv")).size(), 101U);

  const RunResult without =
      RunNapkin(dir_.path(), {"transform", "--array", "6aw-cg", "lab.csv", "--out", "x.csv"});
  EXPECT_EQ(without.exit_code, 1);
  ExpectOneSentenceError(without, {"lab.csv", "no time_s column"});

  const RunResult bad = Napkin({"import", "--array", "6aw-cg", "lab.csv", "--column", "cg_x"});
  EXPECT_EQ(bad.exit_code, 2);
  ExpectOneSentenceError(bad, {"--column takes SLOT=NAME"});
}

}  // namespace
}  // namespace napkin::cli

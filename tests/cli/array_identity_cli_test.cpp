// The stored geometry is the test's geometry (issue 29 point 6): a test
// imported with an edited copy of a preset (same name, other arm positions)
// is computed with that copy, and `query tests` tells it from the preset
// (docs/formats.md "Array names in the catalogue"). The Python half
// (Catalogue.test_inputs recomputes the stored HIC) is
// python/tests/test_array_identity.py.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "records/test_inputs.h"
#include "tests/cli/cli_test_util.h"
#include "tests/support/test_support.h"

namespace napkin::test_support {
namespace {

class ArrayIdentityCliTest : public ::testing::Test {
 protected:
  // `preset`'s JSON with its name kept and `slots` moved by `shift_in` along
  // their arm (y for yarm_*), written to `file`.
  fs::path EditedPreset(const std::string& preset, const std::string& file, double shift_in) {
    nlohmann::json json =
        nlohmann::json::parse(std::ifstream(SourceDir() / "config" / "arrays" / (preset + ".json")));
    for (nlohmann::json& sensor : json["sensors"])
      if (sensor["slot"] == "yarm_z" || sensor["slot"] == "yarm_x")
        sensor["position"][1] = sensor["position"][1].get<double>() + shift_in;
    const fs::path path = dir_ / file;
    WriteText(path, json.dump(2));
    return path;
  }

  // A random-motion test recorded by `array` (its true geometry), as CSV.
  fs::path RecordedCsv(const fs::path& array, std::uint64_t seed, const std::string& file) {
    synth::RandomMotionOptions options;
    options.seed = seed;
    options.duration_s = 0.1;
    const synth::SyntheticTest test = synth::SynthRandomMotion(formats::ReadArrayJson(array), options);
    const fs::path path = dir_ / file;
    formats::WriteSignalsCsv(test.signals, path);
    return path;
  }

  RunResult Napkin(std::vector<std::string> args) {
    args.insert(args.begin(), {"--db", db_.string()});
    return RunNapkin(dir_.path(), args);
  }

  // test_id -> the query's rows as JSON objects.
  std::map<std::string, nlohmann::json> Query(const std::string& kind) {
    const RunResult query = Napkin({"query", kind, "--format", "json"});
    EXPECT_EQ(query.exit_code, 0) << query.err;
    std::map<std::string, nlohmann::json> rows;
    for (const nlohmann::json& row : nlohmann::json::parse(query.out)) rows[row["test_id"]] = row;
    return rows;
  }

  // hic15 of `napkin transform --array ARRAY CSV`.
  double TransformHic15(const std::string& array, const fs::path& csv) {
    const fs::path summary = dir_ / "summary.json";
    fs::remove(summary);
    const RunResult run =
        RunNapkin(dir_.path(), {"transform", "--array", array, csv.string(), "--out",
                                (dir_ / "out.csv").string(), "--summary", summary.string()});
    EXPECT_EQ(run.exit_code, 0) << run.err;
    fs::remove(dir_ / "out.csv");
    return nlohmann::json::parse(std::ifstream(summary))["hic15"].get<double>();
  }

  static std::string Hash12(const fs::path& array) {
    return records::MakeArrayRecord(formats::ReadArrayJson(array)).definition_hash.substr(0, 12);
  }

  TempDir dir_;
  fs::path db_ = dir_ / "lab.db";
};

TEST_F(ArrayIdentityCliTest, AnEditedPresetIsStoredAndShownAsItself) {
  const fs::path preset = SourceDir() / "config" / "arrays" / "denton-3222.json";
  const fs::path edited = EditedPreset("denton-3222", "my-denton.json", 0.4);
  const fs::path preset_csv = RecordedCsv(preset, 11, "preset.csv");
  const fs::path edited_csv = RecordedCsv(edited, 12, "edited.csv");
  ASSERT_EQ(Napkin({"init"}).exit_code, 0);
  RunResult import =
      Napkin({"import", "--array", "denton-3222", "--test-id", "t-preset", preset_csv.string()});
  ASSERT_EQ(import.exit_code, 0) << import.err;
  import = Napkin({"import", "--array", edited.string(), "--test-id", "t-edited", edited_csv.string()});
  ASSERT_EQ(import.exit_code, 0) << import.err;
  const RunResult run = Napkin({"run"});
  ASSERT_EQ(run.exit_code, 0) << run.err;

  // `query tests` tells the two geometries apart: the preset by its name, the
  // edited copy by its name and hash.
  std::map<std::string, nlohmann::json> tests = Query("tests");
  EXPECT_EQ(tests["t-preset"]["array"], "denton-3222");
  EXPECT_EQ(tests["t-edited"]["array"], "denton-3222@" + Hash12(edited));
  const RunResult selected =
      Napkin({"query", "tests", "--where", "array=denton-3222@" + Hash12(edited), "--format", "csv"});
  EXPECT_EQ(Lines(selected.out).size(), 2U) << selected.out << selected.err;

  // The stored HIC is the edited geometry's: the catalogue's recomputation
  // and `napkin transform` with the edited JSON give it, the preset does not.
  std::map<std::string, nlohmann::json> hic = Query("hic");
  const double stored = hic["t-edited"]["hic15"].get<double>();
  {
    db::Catalogue catalogue = OpenForReading(db_);
    const db::TestId test = *catalogue.FindTestByExternalId("t-edited");
    const db::ConfigId config = *catalogue.ReadLatestResultConfig(test);
    EXPECT_EQ(records::RecomputeResult(catalogue, test, config).summary.hic15.value, stored);
    EXPECT_EQ(catalogue.ReadArray(catalogue.ReadTest(test).array_id).name, "denton-3222@" + Hash12(edited));
  }
  EXPECT_EQ(TransformHic15(edited.string(), edited_csv), stored);
  EXPECT_NE(TransformHic15("denton-3222", edited_csv), stored);
  EXPECT_EQ(hic["t-preset"]["hic15"].get<double>(), TransformHic15("denton-3222", preset_csv));

  // Importing the edited copy again reuses its record and name.
  import = Napkin({"import", "--array", edited.string(), "--test-id", "t-edited-2",
                   RecordedCsv(edited, 13, "edited2.csv").string()});
  ASSERT_EQ(import.exit_code, 0) << import.err;
  EXPECT_EQ(Query("tests")["t-edited-2"]["array"], "denton-3222@" + Hash12(edited));
}

// A name no preset has: the first geometry stored under it keeps it, a
// different one gets its hash (db::Catalogue::WriteArray).
TEST_F(ArrayIdentityCliTest, ASecondGeometryUnderOneNameIsShownWithItsHash) {
  nlohmann::json json =
      nlohmann::json::parse(std::ifstream(SourceDir() / "config" / "arrays" / "denton-3222.json"));
  json["name"] = "rig-7";
  const fs::path first = dir_ / "rig-7-a.json";
  WriteText(first, json.dump());
  json["sensors"][3]["position"][1] = 2.0;  // yarm_z
  json["sensors"][4]["position"][1] = 2.0;  // yarm_x
  const fs::path second = dir_ / "rig-7-b.json";
  WriteText(second, json.dump());
  ASSERT_EQ(Napkin({"init"}).exit_code, 0);
  RunResult import = Napkin(
      {"import", "--array", first.string(), "--test-id", "a", RecordedCsv(first, 1, "a.csv").string()});
  ASSERT_EQ(import.exit_code, 0) << import.err;
  import = Napkin(
      {"import", "--array", second.string(), "--test-id", "b", RecordedCsv(second, 2, "b.csv").string()});
  ASSERT_EQ(import.exit_code, 0) << import.err;
  std::map<std::string, nlohmann::json> tests = Query("tests");
  EXPECT_EQ(tests["a"]["array"], "rig-7");
  EXPECT_EQ(tests["b"]["array"], "rig-7@" + Hash12(second));
}

}  // namespace
}  // namespace napkin::test_support

// Derived-channel storage (docs/formats.md "Derived-channel storage"): the
// same tests run under configs identical except storage.derived_channels.
// "none" stores nothing and `napkin export` recomputes: byte for byte the
// files of the "float64" run (csv, isomme, uds). "float32" stores each value
// but the time base rounded to float: its export is the float64 kinematics
// rounded to float, within float32 rounding of the float64 export.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "db/catalogue.h"
#include "formats/csv.h"
#include "records/config_record.h"
#include "tests/cli/cli_test_util.h"
#include "tests/support/db/catalogue_inspector.h"
#include "tests/support/test_support.h"

namespace napkin {
namespace {

namespace fs = std::filesystem;
using test_support::RunNapkin;
using test_support::WriteText;
using CliResult = test_support::CommandResult;

constexpr int kStorageTests = 3;

// Every file of `folder` (name -> bytes).
std::map<std::string, std::string> FolderFiles(const fs::path& folder) {
  std::map<std::string, std::string> files;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder))
    files[entry.path().filename().string()] = test_support::ReadText(entry.path());
  return files;
}

// `kinematics` with every value but the time base (stored float64) rounded
// to the nearest float.
engine::Kinematics RoundedToFloat(engine::Kinematics kinematics) {
  const auto round = [](auto& matrix) {
    matrix = matrix.unaryExpr([](double value) { return static_cast<double>(static_cast<float>(value)); });
  };
  round(kinematics.omega_body);
  round(kinematics.alpha_body);
  round(kinematics.omega_fixed);
  round(kinematics.alpha_fixed);
  round(kinematics.acc_body);
  round(kinematics.acc_fixed);
  round(kinematics.vel_fixed);
  round(kinematics.pos_fixed);
  round(kinematics.quat_fixed_from_body);
  round(kinematics.roll_pitch_yaw_rad);
  round(kinematics.dcos_rad);
  round(kinematics.residual);
  return kinematics;
}

// The numeric cells of a derived-channel CSV, row by row.
std::vector<std::vector<double>> CsvNumbers(const std::string& text) {
  std::vector<std::vector<double>> rows;
  const std::vector<std::string> lines = test_support::Lines(text);
  for (std::size_t l = 1; l < lines.size(); ++l) {
    std::vector<double>& row = rows.emplace_back();
    std::size_t start = 0;
    for (;;) {
      const std::size_t comma = lines[l].find(',', start);
      row.push_back(std::strtod(lines[l].substr(start, comma - start).c_str(), nullptr));
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
  }
  return rows;
}

class StorageCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(RunNapkin(dir_.path(), {"init"}).exit_code, 0);
    const CliResult synth = RunNapkin(dir_.path(), {"synth", "--scenario", "random", "--count",
                                                    std::to_string(kStorageTests), "--samples", "1500"});
    ASSERT_EQ(synth.exit_code, 0) << synth.err;
    for (const char* storage : {"float64", "float32", "none"}) {
      WriteText(dir_ / (std::string(storage) + ".json"), std::string(R"({"name": ")") + storage +
                                                             R"(", "storage": {"derived_channels": ")" +
                                                             storage + "\"}}");
      const CliResult run = RunNapkin(dir_.path(), {"run", "--config", std::string(storage) + ".json"});
      ASSERT_EQ(run.exit_code, 0) << storage << ": " << run.err;
    }
  }

  CliResult Export(const std::string& test, const std::string& storage, const std::string& format,
                   const std::string& out) {
    return RunNapkin(dir_.path(), {"export", "--test", test, "--config", storage + ".json", "--format",
                                   format, "--out", out});
  }

  // The config written to STORAGE.json in SetUp.
  records::ResolvedConfig Resolve(const std::string& storage) {
    return records::ResolveConfig((dir_ / (storage + ".json")).string());
  }

  std::vector<std::string> TestIds() {
    db::Catalogue catalogue = test_support::OpenForReading(dir_ / "napkin.db");
    std::vector<std::string> ids;
    for (const db::TestRow& test : catalogue.ReadAllTests()) ids.push_back(test.external_id);
    return ids;
  }

  test_support::TempDir dir_;
};

TEST_F(StorageCliTest, NoneStoresNothingAndItsExportEqualsTheFloat64ExportByteForByte) {
  const std::vector<std::string> ids = TestIds();
  ASSERT_EQ(ids.size(), static_cast<std::size_t>(kStorageTests));
  {
    db::Catalogue catalogue = test_support::OpenForReading(dir_ / "napkin.db");
    const auto none = catalogue.FindConfigByHash(Resolve("none").record.config_hash);
    const auto float64 = catalogue.FindConfigByHash(Resolve("float64").record.config_hash);
    ASSERT_TRUE(none && float64);
    for (const db::TestRow& test : catalogue.ReadAllTests()) {
      EXPECT_TRUE(catalogue.ReadSummary(test.id, *none).has_value()) << test.external_id;
      EXPECT_FALSE(catalogue.ReadKinematics(test.id, *none).has_value()) << test.external_id;
      EXPECT_TRUE(catalogue.ReadKinematics(test.id, *float64).has_value()) << test.external_id;
    }
    // Three configs, derived channels for two of them.
    EXPECT_EQ(db::CatalogueInspector(catalogue).CountRows("derived_channels"), 2 * kStorageTests * 36);
  }
  for (const std::string& id : ids) {
    for (const char* storage : {"float64", "none"}) {
      const std::string prefix = id + "." + storage;
      for (const auto& [format, out] :
           {std::pair{"csv", ".csv"}, std::pair{"isomme", ".isomme"}, std::pair{"uds", ".uds"}}) {
        const CliResult exported = Export(id, storage, format, prefix + out);
        ASSERT_EQ(exported.exit_code, 0) << prefix << " " << format << ": " << exported.err;
      }
    }
    const std::string csv = test_support::ReadText(dir_ / (id + ".float64.csv"));
    EXPECT_GT(test_support::Lines(csv).size(), 1000u);
    EXPECT_EQ(test_support::ReadText(dir_ / (id + ".none.csv")), csv) << id;
    for (const char* folder : {".isomme", ".uds"}) {
      const auto float64 = FolderFiles(dir_ / (id + ".float64" + folder));
      EXPECT_GE(float64.size(), 2u) << id << folder;
      EXPECT_EQ(FolderFiles(dir_ / (id + ".none" + folder)), float64) << id << folder;
    }
  }
}

TEST_F(StorageCliTest, Float32HoldsTheFloat64ValuesRoundedToFloat) {
  db::Catalogue catalogue = test_support::OpenForReading(dir_ / "napkin.db");
  const auto float32 = catalogue.FindConfigByHash(Resolve("float32").record.config_hash);
  const auto float64 = catalogue.FindConfigByHash(Resolve("float64").record.config_hash);
  ASSERT_TRUE(float32 && float64);
  // The default preset is float32 and has the same hash as float32.json but for the name.
  EXPECT_EQ(Resolve("float32").record.config_hash, records::ResolveConfig("default").record.config_hash);
  for (const db::TestRow& test : catalogue.ReadAllTests()) {
    const auto exact = catalogue.ReadKinematics(test.id, *float64);
    const auto rounded = catalogue.ReadKinematics(test.id, *float32);
    ASSERT_TRUE(exact && rounded) << test.external_id;
    const engine::Kinematics expected = RoundedToFloat(*exact);
    EXPECT_EQ(rounded->time_s, exact->time_s) << test.external_id;
    EXPECT_EQ(rounded->omega_body, expected.omega_body) << test.external_id;
    EXPECT_EQ(rounded->acc_fixed, expected.acc_fixed) << test.external_id;
    EXPECT_EQ(rounded->quat_fixed_from_body, expected.quat_fixed_from_body) << test.external_id;
    EXPECT_EQ(rounded->pos_fixed, expected.pos_fixed) << test.external_id;
    EXPECT_NE(rounded->omega_body, exact->omega_body) << test.external_id;  // rounding happened

    // The export is the CSV of the rounded float64 kinematics, byte for byte,
    // and each number is within float32 rounding (2^-24 relative) of the
    // float64 export's (2^-150 absolute among float subnormals), plus the
    // CSV's 12 significant digits.
    const std::string id = test.external_id;
    ASSERT_EQ(Export(id, "float32", "csv", id + ".float32.csv").exit_code, 0);
    ASSERT_EQ(Export(id, "float64", "csv", id + ".float64.csv").exit_code, 0);
    formats::WriteDerivedCsv(expected, dir_ / (id + ".expected.csv"));
    const std::string csv32 = test_support::ReadText(dir_ / (id + ".float32.csv"));
    EXPECT_EQ(csv32, test_support::ReadText(dir_ / (id + ".expected.csv"))) << id;
    const auto numbers32 = CsvNumbers(csv32);
    const auto numbers64 = CsvNumbers(test_support::ReadText(dir_ / (id + ".float64.csv")));
    ASSERT_EQ(numbers32.size(), numbers64.size());
    ASSERT_GT(numbers64.size(), 1000u);
    std::size_t differing = 0;
    for (std::size_t r = 0; r < numbers64.size(); ++r) {
      ASSERT_EQ(numbers32[r].size(), numbers64[r].size());
      for (std::size_t c = 0; c < numbers64[r].size(); ++c) {
        const double a = numbers32[r][c], b = numbers64[r][c];
        ASSERT_LE(std::abs(a - b), std::ldexp(std::abs(b), -24) + std::ldexp(1.0, -150) +
                                       1e-11 * std::max(std::abs(a), std::abs(b)))
            << id << " row " << r << " column " << c;
        differing += a != b;
      }
    }
    EXPECT_GT(differing, 0u);
  }
}

TEST_F(StorageCliTest, ReportRecomputesTheKinematicsOfANoneResult) {
  // The latest result of every test is the "none" run's (SetUp runs it last).
  const CliResult report = RunNapkin(dir_.path(), {"report", "--out", "report.html"});
  ASSERT_EQ(report.exit_code, 0) << report.err;
  EXPECT_NE(report.out.find(std::to_string(kStorageTests) + " tests"), std::string::npos) << report.out;
  EXPECT_TRUE(fs::exists(dir_ / "report.html"));
}

}  // namespace
}  // namespace napkin

namespace napkin {
namespace {

// A results file (run --results) holds no raw channels: a "none" result in it
// cannot be recomputed, and export says so in one sentence naming the test.
TEST_F(StorageCliTest, NoneResultInAResultsFileCannotBeRecomputedAndExportSaysWhy) {
  const CliResult run =
      RunNapkin(dir_.path(), {"run", "--config", "none.json", "--force", "--results", "r.db"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string id = TestIds().front();
  const CliResult exported = RunNapkin(dir_.path(), {"--db", "r.db", "export", "--test", id, "--config",
                                                     "none.json", "--format", "csv", "--out", "x.csv"});
  EXPECT_EQ(exported.exit_code, 1);
  EXPECT_EQ(exported.err, "napkin: test '" + id +
                              "' has no stored derived channels (its config stores none) and no raw channels "
                              "to recompute them from (a results file of `run --results` holds none); export "
                              "it from the catalogue the results were merged into.\n");
  EXPECT_FALSE(fs::exists(dir_ / "x.csv"));
}

}  // namespace
}  // namespace napkin

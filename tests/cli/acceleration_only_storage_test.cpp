// What `napkin run` stores for a test of an acceleration-only array (3a-cg):
// only the derived channels that have data, time_s and acc_body_* (docs/
// formats.md "Derived-channel storage"), and every reader of stored results
// (export, report, a results file merged back) copes with the absent ones:
// the csv export keeps its documented columns, with the rotation cells empty.
#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "formats/csv.h"
#include "records/config_record.h"
#include "tests/cli/cli_test_util.h"
#include "tests/support/test_support.h"

namespace napkin::cli {
namespace {

using namespace napkin::test_support;
using ChannelSizes = std::vector<std::pair<std::string, std::int64_t>>;

// The cells of a csv line without quoting (napkin's derived csv quotes none).
std::vector<std::string> Cells(const std::string& line) {
  std::vector<std::string> cells(1);
  for (const char c : line) {
    if (c == ',')
      cells.emplace_back();
    else
      cells.back() += c;
  }
  return cells;
}

class AccelerationOnlyStorage : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(RunNapkin(dir_.path(), {"init"}).exit_code, 0);
    synth::RandomMotionOptions motion;
    motion.seed = 1912;
    motion.duration_s = 0.05;
    fs::create_directories(dir_ / "heads");
    formats::WriteSignalsCsv(synth::SynthRandomMotion(formats::LoadArray("3a-cg"), motion).signals,
                             dir_ / "heads" / "h1.csv");
    const RunResult import = Napkin({"import", "--array", "3a-cg", "--series", "heads", "heads"});
    ASSERT_EQ(import.exit_code, 0) << import.err;
    for (const char* storage : {"float64", "none"})
      WriteText(dir_ / (std::string(storage) + ".json"),
                std::string(R"({"storage": {"derived_channels": ")") + storage + "\"}}");
  }

  RunResult Napkin(const std::vector<std::string>& args) { return RunNapkin(dir_.path(), args); }

  // The stored derived channels (name, bytes) of test h1 under the config
  // `config` ("default" or a JSON file of dir_), and its sample count.
  std::pair<ChannelSizes, std::int64_t> Stored(const fs::path& db_path, const std::string& config) {
    db::Catalogue catalogue = OpenForReading(db_path);
    const std::string resolved = config == "default" ? config : (dir_ / config).string();
    const auto config_id = catalogue.FindConfigByHash(records::ResolveConfig(resolved).record.config_hash);
    const auto test = catalogue.FindTestByExternalId("h1");
    if (!config_id || !test) return {};
    const std::int64_t samples = catalogue.ReadSummary(*test, *config_id) ? n_ : -1;
    return {db::CatalogueInspector(catalogue).ReadDerivedChannelSizes(*test, *config_id), samples};
  }

  // Rows of the test's signals (the sample count of its derived channels).
  std::int64_t SampleCount() {
    db::Catalogue catalogue = OpenForReading(dir_ / "napkin.db");
    return catalogue.ReadTestSignals(*catalogue.FindTestByExternalId("h1")).size();
  }

  TempDir dir_;
  std::int64_t n_ = 0;
};

TEST_F(AccelerationOnlyStorage, StoresTimeAndTheCgAccelerationOnly) {
  n_ = SampleCount();
  ASSERT_GT(n_, 100);
  ASSERT_EQ(Napkin({"run"}).exit_code, 0);
  ASSERT_EQ(Napkin({"run", "--config", "float64.json"}).exit_code, 0);

  // Default (float32): time_s float64, the three CG components float32.
  const auto [float32, float32_samples] = Stored(dir_ / "napkin.db", "default");
  EXPECT_EQ(float32_samples, n_);
  EXPECT_EQ(float32, (ChannelSizes{{"acc_body_x_mps2", 4 * n_},
                                   {"acc_body_y_mps2", 4 * n_},
                                   {"acc_body_z_mps2", 4 * n_},
                                   {"time_s", 8 * n_}}));
  const auto [float64, float64_samples] = Stored(dir_ / "napkin.db", "float64.json");
  EXPECT_EQ(float64_samples, n_);
  EXPECT_EQ(float64, (ChannelSizes{{"acc_body_x_mps2", 8 * n_},
                                   {"acc_body_y_mps2", 8 * n_},
                                   {"acc_body_z_mps2", 8 * n_},
                                   {"time_s", 8 * n_}}));
}

TEST_F(AccelerationOnlyStorage, ReadersKeepTheDocumentedColumns) {
  ASSERT_EQ(Napkin({"run", "--config", "float64.json"}).exit_code, 0);
  ASSERT_EQ(Napkin({"run", "--config", "none.json"}).exit_code, 0);
  // Stored (4 channels) and recomputed (none stored) give the same file, the
  // one `transform` writes: every documented column, rotation cells empty.
  for (const char* config : {"float64.json", "none.json"}) {
    const RunResult exported = Napkin({"export", "--test", "h1", "--config", config, "--format", "csv",
                                       "--out", config + std::string(".csv")});
    ASSERT_EQ(exported.exit_code, 0) << config << ": " << exported.err;
  }
  const RunResult transform = Napkin({"transform", "--array", "3a-cg", "heads/h1.csv", "--out", "t.csv"});
  ASSERT_EQ(transform.exit_code, 0) << transform.err;
  const std::string csv = ReadText(dir_ / "float64.json.csv");
  EXPECT_EQ(ReadText(dir_ / "none.json.csv"), csv);
  EXPECT_EQ(ReadText(dir_ / "t.csv"), csv);
  const std::vector<std::string> lines = Lines(csv);
  ASSERT_GT(lines.size(), 100u);
  std::string header;
  for (const std::string& column : formats::DerivedCsvColumns())
    header += (header.empty() ? "" : ",") + column;
  EXPECT_EQ(lines.front(), header);
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const std::vector<std::string> cells = Cells(lines[i]);
    ASSERT_EQ(cells.size(), formats::DerivedCsvColumns().size()) << lines[i];
    for (std::size_t c = 0; c < cells.size(); ++c) {
      const std::string& column = formats::DerivedCsvColumns()[c];
      const bool filled = column == "time_s" || column.rfind("acc_body_", 0) == 0;
      EXPECT_EQ(cells[c].empty(), !filled) << "row " << i << " column " << column;
    }
  }

  // The report shows the acceleration chart of the stored result.
  const RunResult report = Napkin({"report", "--out", "r.html"});
  ASSERT_EQ(report.exit_code, 0) << report.err;
  EXPECT_NE(ReadText(dir_ / "r.html").find("id=\"chart-1-acc\""), std::string::npos);
}

TEST_F(AccelerationOnlyStorage, AResultsFileMergesBackWithItsFourChannels) {
  n_ = SampleCount();
  const RunResult shard = Napkin({"run", "--config", "float64.json", "--shard", "0/1", "--results", "r.db"});
  ASSERT_EQ(shard.exit_code, 0) << shard.err;
  EXPECT_EQ(Stored(dir_ / "r.db", "float64.json").first.size(), 4u);
  const RunResult merge = Napkin({"merge", "r.db"});
  ASSERT_EQ(merge.exit_code, 0) << merge.err;
  EXPECT_EQ(Stored(dir_ / "napkin.db", "float64.json").first.size(), 4u);
  const RunResult exported =
      Napkin({"export", "--test", "h1", "--config", "float64.json", "--format", "csv", "--out", "m.csv"});
  ASSERT_EQ(exported.exit_code, 0) << exported.err;
  EXPECT_EQ(Lines(ReadText(dir_ / "m.csv")).size(), static_cast<std::size_t>(n_) + 1);
}

}  // namespace
}  // namespace napkin::cli

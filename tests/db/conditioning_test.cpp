// The catalogue keeps what the files record about prefiltering (raw_channels.
// prefiltered_cfc) and what conditioning did to each channel of a result
// (result_conditioning; `query conditioning`), through a shard merge too.
#include <gtest/gtest.h>

#include <filesystem>

#include "db/catalogue.h"
#include "db/job_queue.h"
#include "tests/db/db_test_helpers.h"
#include "tests/support/test_support.h"

namespace napkin::db {
namespace {

engine::TestSignals TwoChannels() {
  engine::TestSignals signals;
  signals.dt_s = 1e-4;
  signals.t0_s = -0.001;
  signals.slots = {"cg_x", "ars_x"};
  signals.samples = Eigen::MatrixXd::Constant(8, 2, 1.5);
  return signals;
}

engine::TestSummary SummaryWithConditioning() {
  engine::TestSummary summary;
  summary.hic15.value = 123.0;
  engine::ChannelConditioning skipped;
  skipped.channel = "cg_x";
  skipped.prefiltered_cfc = 1000.0;
  skipped.filter_skipped_prefiltered = true;
  skipped.bias_removed = 0.125;
  skipped.bias_window_start_s = -0.001;
  skipped.bias_window_end_s = -0.0001;
  skipped.time_shift_s = 0.0005;
  engine::ChannelConditioning filtered;
  filtered.channel = "ars_x";
  filtered.filter_cfc = 60.0;
  filtered.time_shift_s = 0.0005;
  summary.conditioning = {skipped, filtered};
  return summary;
}

void ExpectSameRecords(const std::vector<engine::ChannelConditioning>& read,
                       const std::vector<engine::ChannelConditioning>& written) {
  ASSERT_EQ(read.size(), written.size());
  for (std::size_t i = 0; i < read.size(); ++i) {
    EXPECT_EQ(read[i].channel, written[i].channel);
    EXPECT_EQ(read[i].filter_cfc, written[i].filter_cfc);
    EXPECT_EQ(read[i].prefiltered_cfc, written[i].prefiltered_cfc);
    EXPECT_EQ(read[i].filter_skipped_prefiltered, written[i].filter_skipped_prefiltered);
    EXPECT_EQ(read[i].bias_removed, written[i].bias_removed);
    EXPECT_EQ(read[i].bias_window_start_s, written[i].bias_window_start_s);
    EXPECT_EQ(read[i].bias_window_end_s, written[i].bias_window_end_s);
    EXPECT_EQ(read[i].time_shift_s, written[i].time_shift_s);
  }
}

TEST(ConditioningCatalogue, PrefilterOfRawChannelsRoundTrips) {
  Catalogue catalogue = Catalogue::Open(":memory:");
  const ArrayId array = catalogue.WriteArray(test_support::IdealArray());
  const TestId marked = test_support::AddTest(catalogue, array, "marked");
  engine::TestSignals signals = TwoChannels();
  signals.prefiltered_cfc = {1000.0, std::nullopt};
  catalogue.WriteRawChannels(marked, signals, std::vector<std::string>{"g", "rad/s"});
  const engine::TestSignals read = catalogue.ReadTestSignals(marked);
  ASSERT_EQ(read.prefiltered_cfc.size(), 2u);
  EXPECT_EQ(read.PrefilteredCfc(0), 1000.0);
  EXPECT_EQ(read.PrefilteredCfc(1), std::nullopt);

  const TestId raw = test_support::AddTest(catalogue, array, "raw");
  catalogue.WriteRawChannels(raw, TwoChannels(), std::vector<std::string>{"g", "rad/s"});
  EXPECT_TRUE(catalogue.ReadTestSignals(raw).prefiltered_cfc.empty());
}

TEST(ConditioningCatalogue, ResultStoresConditioningAndQueryShowsIt) {
  Catalogue catalogue = Catalogue::Open(":memory:");
  const ArrayId array = catalogue.WriteArray(test_support::IdealArray());
  const ConfigId config = catalogue.WriteConfig(test_support::DefaultConfig());
  const TestId test = test_support::AddTest(catalogue, array, "t1", "S", "A");
  catalogue.WriteRawChannels(test, TwoChannels(), std::vector<std::string>{"g", "rad/s"});
  const engine::TestSummary summary = SummaryWithConditioning();
  catalogue.WriteResult(test, config, summary, "exact");
  ExpectSameRecords(catalogue.ReadSummary(test, config)->conditioning, summary.conditioning);

  for (const std::optional<ConfigId>& which : {std::optional<ConfigId>(), std::optional<ConfigId>(config)}) {
    QueryRequest request;
    request.config = which;
    const Table table = catalogue.Query(QueryKind::kConditioning, request);
    const std::vector<std::string> columns = {"test_id",      "series",    "variant",    "channel",
                                              "unit",         "filter",    "filter_cfc", "prefiltered_cfc",
                                              "bias_removed", "bias_t1_s", "bias_t2_s",  "time_shift_s"};
    EXPECT_EQ(table.columns, columns);
    ASSERT_EQ(table.rows.size(), 2u);  // in column order
    EXPECT_EQ(std::get<std::string>(table.rows[0][3]), "cg_x");
    EXPECT_EQ(std::get<std::string>(table.rows[0][4]), "g");
    EXPECT_EQ(std::get<std::string>(table.rows[0][5]), "none, prefiltered at CFC 1000");
    EXPECT_TRUE(std::holds_alternative<std::monostate>(table.rows[0][6]));
    EXPECT_EQ(std::get<double>(table.rows[0][7]), 1000.0);
    EXPECT_EQ(std::get<double>(table.rows[0][8]), 0.125);
    EXPECT_EQ(std::get<double>(table.rows[0][9]), -0.001);
    EXPECT_EQ(std::get<double>(table.rows[0][11]), 0.0005);
    EXPECT_EQ(std::get<std::string>(table.rows[1][3]), "ars_x");
    EXPECT_EQ(std::get<std::string>(table.rows[1][4]), "rad/s");
    EXPECT_EQ(std::get<std::string>(table.rows[1][5]), "CFC 60");
    EXPECT_EQ(std::get<double>(table.rows[1][6]), 60.0);
    EXPECT_TRUE(std::holds_alternative<std::monostate>(table.rows[1][9]));
  }
  QueryRequest skipped_only;
  skipped_only.where.push_back(
      WhereExpression{WhereComparison{"prefiltered_cfc", ComparisonOperator::kGreaterEqual, 1000.0}});
  EXPECT_EQ(catalogue.Query(QueryKind::kConditioning, skipped_only).rows.size(), 1u);

  // A new result replaces the record.
  engine::TestSummary again = summary;
  again.conditioning.pop_back();
  catalogue.WriteResult(test, config, again, "exact");
  EXPECT_EQ(catalogue.Query(QueryKind::kConditioning, QueryRequest{}).rows.size(), 1u);
}

TEST(ConditioningCatalogue, MergeBringsPrefilterAndConditioning) {
  test_support::TempDir dir;
  const std::string main_path = dir / "main.db";
  const std::string shard_path = dir / "shard.db";
  {
    Catalogue shard = Catalogue::Open(shard_path);
    const ArrayId array = shard.WriteArray(test_support::IdealArray());
    const ConfigId config = shard.WriteConfig(test_support::DefaultConfig());
    const TestId test = test_support::AddTest(shard, array, "t1");
    engine::TestSignals signals = TwoChannels();
    signals.prefiltered_cfc = {1000.0, std::nullopt};
    shard.WriteRawChannels(test, signals, std::vector<std::string>{"g", "rad/s"});
    shard.WriteResult(test, config, SummaryWithConditioning(), "exact");
  }
  Catalogue main = Catalogue::Open(main_path);
  main.MergeShard(shard_path);
  const TestId test = *main.FindTestByExternalId("t1");
  EXPECT_EQ(main.ReadTestSignals(test).PrefilteredCfc(0), 1000.0);
  const ConfigId config = *main.FindConfigByHash(test_support::DefaultConfig().config_hash);
  ExpectSameRecords(main.ReadSummary(test, config)->conditioning, SummaryWithConditioning().conditioning);
}

}  // namespace
}  // namespace napkin::db

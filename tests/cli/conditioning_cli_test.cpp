// Honest conditioning end to end (docs/algorithms.md "Signal conditioning"):
// an ISO-MME test whose channels are marked CFC 1000 (filter letter A) is not
// filtered again by `run`, a raw copy of it is; `query conditioning` and
// `query quality` say which.
#include <gtest/gtest.h>

#include "formats/channel_map.h"
#include "formats/isomme.h"
#include "tests/cli/cli_test_util.h"
#include "tests/support/test_support.h"

namespace napkin::test_support {
namespace {

TEST(CliConditioning, ChannelsMarkedCfc1000AreNotFilteredAgainAndQueriesSaySo) {
  TempDir dir;
  ASSERT_EQ(RunNapkin(dir.path(), {"init"}).exit_code, 0);
  const synth::SyntheticTest synth = SynthNapTest(5);
  engine::TestSignals marked = synth.signals;
  marked.prefiltered_cfc.assign(9, engine::kCfc1000);
  const formats::ChannelMap map = formats::LoadChannelMap("nap-example");
  fs::create_directories(dir / "tests");
  formats::WriteIsoMme(marked, synth.array, map, dir / "tests" / "marked", "MARKED");
  formats::WriteIsoMme(synth.signals, synth.array, map, dir / "tests" / "raw", "RAW");

  const RunResult import =
      RunNapkin(dir.path(), {"--db", "napkin.db", "import", "--array", "denton-3222", "--channel-map",
                             "nap-example", TripleFlag("--orientation", synth.initial.orientation_rad),
                             TripleFlag("--initial-velocity", synth.initial.velocity_fixed_mps), "tests"});
  ASSERT_EQ(import.exit_code, 0) << import.err;
  const RunResult run = RunNapkin(dir.path(), {"--db", "napkin.db", "--quiet", "run", "--threads", "1"});
  ASSERT_EQ(run.exit_code, 0) << run.err;

  db::Catalogue catalogue = OpenForReading(dir / "napkin.db");
  // The stored result of the marked test is the unfiltered computation of the same samples.
  const std::optional<db::TestId> found = catalogue.FindTestByExternalId("marked");
  ASSERT_TRUE(found.has_value());
  const db::TestId marked_id = *found;
  const db::TestRow record = catalogue.ReadTest(marked_id);
  EXPECT_EQ(catalogue.ReadTestSignals(marked_id).prefiltered_cfc,
            std::vector<std::optional<double>>(9, engine::kCfc1000));
  engine::ProcessingConfig unfiltered = records::ResolveConfig("").config;
  unfiltered.filter.linear_cfc.reset();
  engine::TestSignals plain = catalogue.ReadTestSignals(marked_id);
  plain.prefiltered_cfc.clear();
  const engine::ProcessedTest expected =
      engine::ProcessTest(synth.array, plain, record.initial_state, unfiltered);
  const db::ConfigId config = *catalogue.ReadLatestResultConfig(marked_id);
  const engine::TestSummary stored = *catalogue.ReadSummary(marked_id, config);
  EXPECT_EQ(stored.hic15.value, expected.summary.hic15.value);
  EXPECT_EQ(stored.peak_acc_g, expected.summary.peak_acc_g);
  EXPECT_EQ(stored.peak_omega_radps, expected.summary.peak_omega_radps);

  db::QueryRequest marked_rows;
  marked_rows.tests.external_ids = {"marked"};
  const db::Table conditioning = catalogue.Query(db::QueryKind::kConditioning, marked_rows);
  ASSERT_EQ(conditioning.rows.size(), 9u);
  for (const auto& row : conditioning.rows) {
    EXPECT_EQ(std::get<std::string>(row[5]), "none, prefiltered at CFC 1000");
    EXPECT_EQ(std::get<double>(row[7]), 1000.0);
  }
  db::QueryRequest raw_rows;
  raw_rows.tests.external_ids = {"raw"};
  const db::Table raw = catalogue.Query(db::QueryKind::kConditioning, raw_rows);
  ASSERT_EQ(raw.rows.size(), 9u);
  for (const auto& row : raw.rows) {
    EXPECT_EQ(std::get<std::string>(row[5]), "CFC 1000");
    EXPECT_TRUE(std::holds_alternative<std::monostate>(row[7]));
  }

  const RunResult quality = RunNapkin(dir.path(), {"--db", "napkin.db", "query", "quality", "--where",
                                                   "check=prefiltered", "--format", "csv"});
  ASSERT_EQ(quality.exit_code, 0) << quality.err;
  const std::vector<std::string> lines = Lines(quality.out);
  ASSERT_EQ(lines.size(), 10u) << quality.out;  // header + one per channel of marked
  for (std::size_t i = 1; i < lines.size(); ++i) {
    EXPECT_EQ(lines[i].rfind("marked,", 0), 0u) << lines[i];
    EXPECT_NE(lines[i].find("did not filter it again"), std::string::npos) << lines[i];
  }
  const RunResult query = RunNapkin(dir.path(), {"--db", "napkin.db", "query", "conditioning", "--where",
                                                 "test_id=marked and channel=cg_x", "--format", "csv"});
  ASSERT_EQ(query.exit_code, 0) << query.err;
  EXPECT_EQ(Lines(query.out).at(0),
            "test_id,series,variant,channel,unit,filter,filter_cfc,prefiltered_cfc,bias_removed,bias_t1_s,"
            "bias_t2_s,time_shift_s");
  EXPECT_NE(Lines(query.out).at(1).find(",cg_x,g,\"none, prefiltered at CFC 1000\",,1000,"),
            std::string::npos)
      << query.out;
}

}  // namespace
}  // namespace napkin::test_support

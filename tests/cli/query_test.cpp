// `napkin query`: the five tables with the contract's field names, series and
// variant filters, and the three output forms (table, CSV, JSON).
#include <gtest/gtest.h>

#include "common/error.h"
#include "engine/summary_fields.h"
#include "formats/csv.h"
#include "tests/cli/cli_test_util.h"
#include "tests/support/test_support.h"

namespace napkin::cli {

using namespace napkin::test_support;
namespace {

// docs/formats.md "Per-test summary fields": the test's labels, then the fields
// of the group (engine/summary_fields.h; tests/db/schema_test.cpp binds the
// schema's views to the same table).
std::vector<std::string> ViewFields(engine::SummaryGroup group) {
  std::vector<std::string> fields = {"test_id", "series", "variant"};
  for (const std::string& name : engine::SummaryFieldNames(group)) fields.push_back(name);
  return fields;
}
const std::vector<std::string> kHicFields = ViewFields(engine::SummaryGroup::kHic);
const std::vector<std::string> kRotationFields = ViewFields(engine::SummaryGroup::kRotation);

std::vector<std::string> Keys(const nlohmann::ordered_json& object) {
  std::vector<std::string> keys;
  for (const auto& item : object.items()) keys.push_back(item.key());
  return keys;
}

class CliQuery : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(RunNapkin(dir_.path(), {"init"}).exit_code, 0);
    // Series "sled": q1 (foam-a), q2 (foam-b); series "drop": q3 (foam-a).
    const std::vector<std::array<std::string, 3>> tests = {
        {"q1", "sled", "foam-a"}, {"q2", "sled", "foam-b"}, {"q3", "drop", "foam-a"}};
    std::uint64_t seed = 81;
    for (const auto& [id, series, variant] : tests) {
      formats::WriteSignalsCsv(SynthNapTest(seed++).signals, dir_ / (id + ".csv"));
      const RunResult run = RunNapkin(dir_.path(), {"import", "--array", "denton-3222", "--series", series,
                                                    "--variant", variant, id + ".csv"});
      ASSERT_EQ(run.exit_code, 0) << run.err;
    }
    processed_q1_ = ProcessAndStore(dir_ / "napkin.db", "q1");
    processed_q3_ = ProcessAndStore(dir_ / "napkin.db", "q3");
  }

  nlohmann::ordered_json QueryJson(std::vector<std::string> args) {
    args.insert(args.begin(), "query");
    args.insert(args.end(), {"--format", "json"});
    const RunResult run = RunNapkin(dir_.path(), args);
    EXPECT_EQ(run.exit_code, 0) << run.err;
    return nlohmann::ordered_json::parse(run.out);
  }

  napkin::test_support::TempDir dir_;
  engine::ProcessedTest processed_q1_;
  engine::ProcessedTest processed_q3_;
};

TEST_F(CliQuery, HicJsonHasTheContractFieldsAndTheStoredNumbers) {
  const nlohmann::ordered_json rows = QueryJson({"hic"});
  ASSERT_EQ(rows.size(), 2u);  // q2 has no result yet
  EXPECT_EQ(Keys(rows[0]), kHicFields);
  EXPECT_EQ(rows[0]["test_id"], "q1");
  EXPECT_EQ(rows[1]["test_id"], "q3");
  EXPECT_EQ(rows[0]["series"], "sled");
  EXPECT_EQ(rows[0]["variant"], "foam-a");
  const engine::TestSummary& s = processed_q1_.summary;
  ASSERT_TRUE(rows[0]["hic15"].is_number());
  EXPECT_EQ(rows[0]["hic15"].get<double>(), s.hic15.value);  // exact through JSON
  EXPECT_EQ(rows[0]["hic15_t2_s"].get<double>(), s.hic15.t2_s);
  EXPECT_EQ(rows[0]["hic"].get<double>(), s.hic.value);
  EXPECT_EQ(rows[0]["peak_acc_g"].get<double>(), s.peak_acc_g);
  EXPECT_EQ(rows[1]["a3ms_g"].get<double>(), processed_q3_.summary.a3ms_g);
  EXPECT_GT(s.peak_acc_g, 1.0);
}

TEST_F(CliQuery, RotationAndCriteriaJsonFields) {
  const nlohmann::ordered_json rotation = QueryJson({"rotation", "--series", "sled"});
  ASSERT_EQ(rotation.size(), 1u);
  EXPECT_EQ(Keys(rotation[0]), kRotationFields);
  const engine::TestSummary& s = processed_q1_.summary;
  EXPECT_EQ(rotation[0]["peak_omega_y_radps"].get<double>(), s.peak_omega_body_radps.y());
  EXPECT_EQ(rotation[0]["bric"].get<double>(), s.bric);
  EXPECT_EQ(rotation[0]["final_quat_z"].get<double>(), s.final_quat_wxyz[3]);
  EXPECT_EQ(rotation[0]["final_pos_x_m"].get<double>(), s.final_pos_fixed_m.x());

  std::vector<std::string> criteria_fields = kHicFields;
  criteria_fields.insert(criteria_fields.end(), kRotationFields.begin() + 3, kRotationFields.end());
  criteria_fields.push_back("salvaged");
  const nlohmann::ordered_json criteria = QueryJson({"criteria"});
  ASSERT_EQ(criteria.size(), 2u);
  EXPECT_EQ(Keys(criteria[1]), criteria_fields);
  EXPECT_EQ(criteria[1]["max_rotation_deg"].get<double>(), processed_q3_.summary.max_rotation_deg);
}

TEST_F(CliQuery, SeriesAndVariantFilterTheTests) {
  auto ids = [&](const std::vector<std::string>& args) {
    std::vector<std::string> found;
    for (const auto& row : QueryJson(args)) found.push_back(row["test_id"]);
    return found;
  };
  EXPECT_EQ(ids({"tests"}), (std::vector<std::string>{"q1", "q2", "q3"}));
  EXPECT_EQ(ids({"tests", "--series", "sled"}), (std::vector<std::string>{"q1", "q2"}));
  EXPECT_EQ(ids({"tests", "--variant", "foam-a"}), (std::vector<std::string>{"q1", "q3"}));
  EXPECT_EQ(ids({"tests", "--series", "sled", "--variant", "foam-b"}), std::vector<std::string>{"q2"});
  EXPECT_EQ(ids({"tests", "--series", "none"}), std::vector<std::string>{});
  const nlohmann::ordered_json tests = QueryJson({"tests", "--series", "drop"});
  EXPECT_EQ(Keys(tests[0]),
            (std::vector<std::string>{"test_id", "series", "variant", "array", "source_path", "content_hash",
                                      "imported_at", "position", "test_number", "title", "vehicle", "dummy",
                                      "test_date", "laboratory", "salvaged"}));
  EXPECT_EQ(tests[0]["array"], "denton-3222");
  EXPECT_EQ(tests[0]["source_path"], (dir_ / "q3.csv").string());
}

TEST_F(CliQuery, QualityListsFindingsWithTheirFields) {
  const nlohmann::ordered_json rows = QueryJson({"quality"});
  std::size_t expected = processed_q1_.summary.findings.size() + processed_q3_.summary.findings.size();
  ASSERT_EQ(rows.size(), expected);
  for (const auto& row : rows) {
    EXPECT_EQ(Keys(row), (std::vector<std::string>{"test_id", "series", "variant", "check", "channel",
                                                   "severity", "detail"}));
    EXPECT_TRUE(row["severity"] == "info" || row["severity"] == "warning" || row["severity"] == "error");
    EXPECT_TRUE(row["channel"].is_null() || row["channel"].is_string());
  }
}

TEST_F(CliQuery, CsvCarriesExactNumbersAndTableAlignsColumns) {
  const RunResult csv = RunNapkin(dir_.path(), {"query", "hic", "--format", "csv"});
  ASSERT_EQ(csv.exit_code, 0) << csv.err;
  const std::vector<std::string> lines = Lines(csv.out);
  ASSERT_EQ(lines.size(), 3u);
  std::string header;
  for (const std::string& field : kHicFields) header += (header.empty() ? "" : ",") + field;
  EXPECT_EQ(lines[0], header);
  const std::string hic15 = util::FormatNumber(processed_q1_.summary.hic15.value);
  EXPECT_EQ(lines[1].rfind("q1,sled,foam-a," + hic15 + ",", 0), 0u) << lines[1];

  const RunResult table = RunNapkin(dir_.path(), {"query", "hic", "--series", "sled"});
  ASSERT_EQ(table.exit_code, 0) << table.err;
  const std::vector<std::string> rows = Lines(table.out);
  ASSERT_EQ(rows.size(), 3u);  // header, rule, q1
  // Columns: the rule's dash runs; the header names and values line up with them.
  std::vector<std::pair<std::size_t, std::size_t>> spans;
  for (std::size_t i = 0; i < rows[1].size();) {
    const std::size_t end = rows[1].find(' ', i);
    spans.emplace_back(i, end == std::string::npos ? rows[1].size() : end);
    i = end == std::string::npos ? rows[1].size() : rows[1].find_first_not_of(' ', end);
  }
  ASSERT_EQ(spans.size(), kHicFields.size());
  auto cell = [&](const std::string& line, std::size_t c) {
    const auto [begin, end] = spans[c];
    EXPECT_TRUE(begin == 0 || line[begin - 1] == ' ') << line;
    const std::string text = line.substr(begin, std::min(end, line.size()) - begin);
    return std::string(util::Trim(text));
  };
  for (std::size_t c = 0; c < kHicFields.size(); ++c) EXPECT_EQ(cell(rows[0], c), kHicFields[c]);
  EXPECT_EQ(cell(rows[2], 0), "q1");
  const double shown = std::stod(cell(rows[2], 3));
  EXPECT_NEAR(shown, processed_q1_.summary.hic15.value, 1e-5 * processed_q1_.summary.hic15.value);
}

TEST_F(CliQuery, MissingCatalogueOrUnknownTableIsRefused) {
  const RunResult missing = RunNapkin(dir_.path(), {"--db", "other.db", "query", "tests"});
  EXPECT_EQ(missing.exit_code, 1);
  ExpectOneSentenceError(missing, {"other.db"});
  EXPECT_FALSE(fs::exists(dir_ / "other.db"));
  EXPECT_EQ(RunNapkin(dir_.path(), {"query", "everything"}).exit_code, 2);
  EXPECT_EQ(RunNapkin(dir_.path(), {"query", "hic", "--format", "xml"}).exit_code, 2);
}

}  // namespace
}  // namespace napkin::cli

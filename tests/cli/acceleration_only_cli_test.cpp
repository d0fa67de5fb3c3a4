// Acceleration-only tests (array 3a-cg; docs/algorithms.md "Acceleration-only
// arrays") through the whole command line: import, run, query (null rotation
// in json, csv and table), compare (rotation metrics have no values), report
// (the acceleration chart only, no NaN), export and transform (csv with the
// rotation cells empty; formats that need rotation refused naming the test).
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engine/injury_risk.h"
#include "engine/summary_fields.h"
#include "formats/csv.h"
#include "tests/cli/cli_test_util.h"
#include "tests/support/test_support.h"

namespace napkin::cli {
namespace {

using namespace napkin::test_support;

class CliAccelerationOnly : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(RunNapkin(dir_.path(), {"init"}).exit_code, 0);
    const engine::ArrayGeometry array = formats::LoadArray("3a-cg");
    for (const char* variant : {"a", "b"}) {
      fs::create_directories(dir_ / variant);
      for (int i = 1; i <= 2; ++i) {
        synth::RandomMotionOptions motion;
        const int seed = 100 + 10 * (variant[0] - 'a') + i;  // 101, 102 (variant a), 111, 112 (b)
        motion.seed = static_cast<std::uint64_t>(seed);
        motion.duration_s = 0.05;
        formats::WriteSignalsCsv(synth::SynthRandomMotion(array, motion).signals,
                                 dir_ / variant / (std::string(variant) + std::to_string(i) + ".csv"));
      }
      const RunResult import = RunNapkin(
          dir_.path(), {"import", "--array", "3a-cg", "--series", "heads", "--variant", variant, variant});
      ASSERT_EQ(import.exit_code, 0) << import.err;
    }
    const RunResult run = RunNapkin(dir_.path(), {"run"});
    ASSERT_EQ(run.exit_code, 0) << run.err;
  }

  RunResult Napkin(const std::vector<std::string>& args) { return RunNapkin(dir_.path(), args); }

  TempDir dir_;
};

TEST_F(CliAccelerationOnly, QueryShowsHicAndNullRotation) {
  const RunResult hic = Napkin({"query", "hic", "--format", "json"});
  ASSERT_EQ(hic.exit_code, 0) << hic.err;
  const nlohmann::json hic_rows = nlohmann::json::parse(hic.out);
  ASSERT_EQ(hic_rows.size(), 4u);
  for (const nlohmann::json& row : hic_rows) {
    EXPECT_GT(row.at("hic15").get<double>(), 0.0) << row.dump();
    EXPECT_GT(row.at("peak_acc_g").get<double>(), 0.0) << row.dump();
    EXPECT_TRUE(row.at("a3ms_g").is_number()) << row.dump();
  }

  const RunResult json = Napkin({"query", "rotation", "--format", "json"});
  ASSERT_EQ(json.exit_code, 0) << json.err;
  for (const nlohmann::json& row : nlohmann::json::parse(json.out))
    for (const auto& [key, value] : row.items())
      if (key != "test_id" && key != "series" && key != "variant") {
        EXPECT_TRUE(value.is_null()) << key;
      }

  // csv: every rotation field empty; table: blank cells, no "nan".
  const RunResult csv = Napkin({"query", "rotation", "--format", "csv"});
  ASSERT_EQ(csv.exit_code, 0) << csv.err;
  const std::vector<std::string> lines = Lines(csv.out);
  ASSERT_EQ(lines.size(), 5u) << csv.out;
  const std::size_t fields = engine::SummaryFieldNames(engine::SummaryGroup::kRotation).size();
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const std::size_t first_rotation = lines[i].find(",heads,") + std::string(",heads,").size() + 1;
    EXPECT_EQ(lines[i].substr(first_rotation), "," + std::string(fields - 1, ',')) << lines[i];
  }
  const RunResult table = Napkin({"query", "criteria"});
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_EQ(table.out.find("nan"), std::string::npos) << table.out;
  EXPECT_EQ(table.out.find("NaN"), std::string::npos) << table.out;

  const RunResult quality = Napkin({"query", "quality", "--format", "json"});
  ASSERT_EQ(quality.exit_code, 0) << quality.err;
  int rotation_findings = 0;
  for (const nlohmann::json& finding : nlohmann::json::parse(quality.out)) {
    EXPECT_NE(finding.at("check"), "residual") << finding.dump();
    EXPECT_NE(finding.at("check"), "consistency") << finding.dump();
    if (finding.at("check") == "rotation" && finding.at("severity") == "info") ++rotation_findings;
  }
  EXPECT_EQ(rotation_findings, 4);

  // Risks: the HIC risks are the curves at the HICs, the BrIC risks null.
  const RunResult risk = Napkin({"query", "risk", "--format", "json"});
  ASSERT_EQ(risk.exit_code, 0) << risk.err;
  const nlohmann::json risk_rows = nlohmann::json::parse(risk.out);
  ASSERT_EQ(risk_rows.size(), hic_rows.size());
  for (std::size_t i = 0; i < risk_rows.size(); ++i) {
    const nlohmann::json& row = risk_rows[i];
    EXPECT_EQ(row.at("hic15_p_ais3").get<double>(),
              engine::NcapHic15Ais3Risk(hic_rows[i].at("hic15").get<double>()))
        << row.dump();
    EXPECT_EQ(row.at("hic36_p_ais4").get<double>(),
              engine::PrasadMertzHic36Ais4Risk(hic_rows[i].at("hic36").get<double>()))
        << row.dump();
    EXPECT_TRUE(row.at("bric_p_ais3").is_null()) << row.dump();
    EXPECT_TRUE(row.at("bric_p_ais4").is_null()) << row.dump();
  }
}

TEST_F(CliAccelerationOnly, CompareCountsOnlyValues) {
  const RunResult compare = Napkin({"compare", "--series", "heads", "--baseline", "a", "--metrics",
                                    "hic15,peak_omega_radps,bric", "--format", "json"});
  ASSERT_EQ(compare.exit_code, 0) << compare.err;
  const nlohmann::json rows = nlohmann::json::parse(compare.out);
  ASSERT_EQ(rows.size(), 6u) << compare.out;
  for (const nlohmann::json& row : rows) {
    if (row.at("metric") == "hic15") {
      EXPECT_EQ(row.at("n"), 2) << row.dump();
      EXPECT_TRUE(row.at("mean").is_number()) << row.dump();
    } else {
      EXPECT_EQ(row.at("n"), 0) << row.dump();
      for (const char* key : {"mean", "sd", "median", "min", "max", "diff", "p_value"})
        EXPECT_TRUE(row.at(key).is_null()) << row.dump();
    }
  }
  const RunResult table = Napkin({"compare", "--series", "heads", "--metrics", "hic15,peak_omega_radps"});
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_EQ(table.out.find("nan"), std::string::npos) << table.out;
}

TEST_F(CliAccelerationOnly, ReportHasTheAccelerationChartOnly) {
  const RunResult report = Napkin({"report", "--out", "heads.html"});
  ASSERT_EQ(report.exit_code, 0) << report.err;
  std::ifstream in(dir_ / "heads.html");
  const std::string html((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (int test = 1; test <= 4; ++test) {
    const std::string prefix = "chart-" + std::to_string(test) + "-";
    EXPECT_NE(html.find(prefix + "acc"), std::string::npos) << prefix;
    for (const char* rotation_chart : {"omega", "angles", "velocity"})
      EXPECT_EQ(html.find(prefix + rotation_chart), std::string::npos) << prefix << rotation_chart;
  }
  // The plot data are valid JSON (a NaN would not parse) with finite traces only.
  const std::string marker = "<script type=\"application/json\" id=\"napkin-data\">";
  const std::size_t begin = html.find(marker);
  ASSERT_NE(begin, std::string::npos);
  const std::size_t end = html.find("</script>", begin);
  const std::string data_text = html.substr(begin + marker.size(), end - begin - marker.size());
  EXPECT_EQ(data_text.find("NaN"), std::string::npos);
  const nlohmann::json data = nlohmann::json::parse(data_text);
  ASSERT_EQ(data.at("charts").size(), 4u);
  for (const nlohmann::json& chart : data.at("charts"))
    for (const nlohmann::json& trace : chart.at("y"))
      for (const nlohmann::json& value : trace) EXPECT_TRUE(value.is_number()) << chart.at("id");
  // The tables show the rotation fields as "—".
  EXPECT_NE(html.find("<td class=\"num\">—</td>"), std::string::npos);

  // The series' comparison: the acceleration overlay only (a trace per test,
  // two bounds per variant), no rotation metric in its table or verdict.
  ASSERT_EQ(data.at("overlays").size(), 1u);
  const nlohmann::json& overlay = data.at("overlays")[0];
  EXPECT_EQ(overlay.at("id"), "overlay-1-acc");
  EXPECT_EQ(overlay.at("labels"), nlohmann::json({"a1", "a2", "b1", "b2", "a mean − 1 sd", "a mean + 1 sd",
                                                  "b mean − 1 sd", "b mean + 1 sd"}));
  EXPECT_EQ(html.find("overlay-1-omega"), std::string::npos);
  for (const engine::SummaryField* field : engine::SummaryFieldsOf({engine::SummaryGroup::kRotation}))
    EXPECT_EQ(html.find("<tr><td>" + std::string(field->name) + "</td>"), std::string::npos) << field->name;
  EXPECT_NE(html.find("<tr><td>hic15</td>"), std::string::npos);
  const std::size_t verdict = html.find("<div class=\"verdict\">");
  ASSERT_NE(verdict, std::string::npos);
  const std::string verdict_block = html.substr(verdict, html.find("</div>", verdict) - verdict);
  EXPECT_NE(verdict_block.find("<li>b: "), std::string::npos) << verdict_block;
  // The sentences and the table (the note under them states every rule, BrIC's examples too).
  const std::string sentences = verdict_block.substr(0, verdict_block.find("<p class=\"note\">"));
  EXPECT_NE(sentences.find("HIC15"), std::string::npos) << verdict_block;
  EXPECT_EQ(sentences.find("BrIC"), std::string::npos) << verdict_block;
}

TEST_F(CliAccelerationOnly, ExportGivesTheAccelerationAndRefusesRotationFormats) {
  ASSERT_EQ(Napkin({"export", "--test", "a1", "--format", "csv", "--out", "a1.csv"}).exit_code, 0);
  std::ifstream in(dir_ / "a1.csv");
  std::string header, row;
  std::getline(in, header);
  std::string expected_header;
  for (const std::string& column : formats::DerivedCsvColumns())
    expected_header += (expected_header.empty() ? "" : ",") + column;
  EXPECT_EQ(header, expected_header);
  int rows = 0;
  while (std::getline(in, row)) {
    ++rows;
    std::vector<std::string> cells;
    std::size_t start = 0;
    for (std::size_t comma = row.find(',');; comma = row.find(',', start)) {
      cells.push_back(row.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    ASSERT_EQ(cells.size(), formats::DerivedCsvColumns().size()) << row;
    for (std::size_t c = 0; c < cells.size(); ++c) {
      const std::string& column = formats::DerivedCsvColumns()[c];
      const bool known = column == "time_s" || column.rfind("acc_body_", 0) == 0;
      EXPECT_EQ(cells[c].empty(), !known) << column << " in " << row;
    }
  }
  EXPECT_EQ(rows, 501);

  for (const char* format : {"lsdyna", "lcfile", "uds"}) {
    const RunResult refused = Napkin({"export", "--test", "a1", "--format", format, "--out", "a1.out"});
    EXPECT_EQ(refused.exit_code, 1) << format;
    ExpectOneSentenceError(refused,
                           {"test 'a1' has no rotation", std::string("which format ") + format + " needs"});
    EXPECT_FALSE(fs::exists(dir_ / "a1.out")) << format;
  }
}

TEST_F(CliAccelerationOnly, TransformGivesNullRotationAndRefusesLsDyna) {
  const RunResult transform =
      Napkin({"transform", "--array", "3a-cg", "a/a1.csv", "--out", "t.csv", "--summary", "t.json"});
  ASSERT_EQ(transform.exit_code, 0) << transform.err;
  // Stored bit-exact: the default float32 storage rounds (docs/formats.md "Derived-channel storage").
  WriteText(dir_ / "float64.json", R"({"storage": {"derived_channels": "float64"}})");
  ASSERT_EQ(Napkin({"run", "--config", "float64.json"}).exit_code, 0);
  ASSERT_EQ(
      Napkin({"export", "--test", "a1", "--config", "float64.json", "--format", "csv", "--out", "e.csv"})
          .exit_code,
      0);
  std::ifstream t(dir_ / "t.csv"), e(dir_ / "e.csv");
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(t), {}),
            std::string(std::istreambuf_iterator<char>(e), {}));
  std::ifstream summary_in(dir_ / "t.json");
  const nlohmann::json summary = nlohmann::json::parse(summary_in);
  EXPECT_TRUE(summary.dump().find("\"bric\":null") != std::string::npos) << summary.dump();
  EXPECT_TRUE(summary.dump().find("\"peak_omega_radps\":null") != std::string::npos) << summary.dump();
  EXPECT_TRUE(summary.dump().find("\"hic15\":null") == std::string::npos) << summary.dump();

  const RunResult lsdyna =
      Napkin({"transform", "--array", "3a-cg", "a/a1.csv", "--out", "u.csv", "--lsdyna", "u.k"});
  EXPECT_EQ(lsdyna.exit_code, 1);
  ExpectOneSentenceError(lsdyna, {"cannot determine rotation", "--lsdyna"});
  EXPECT_FALSE(fs::exists(dir_ / "u.csv"));
  EXPECT_FALSE(fs::exists(dir_ / "u.k"));
}

}  // namespace
}  // namespace napkin::cli

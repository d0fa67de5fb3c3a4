// End-to-end test of `napkin demo --out DIR`: it builds and runs its
// catalogue, prints the report section 4.5 validation table with the known
// answers (engine/report_known_answers.h) and the padding series, and leaves
// a catalogue `napkin query` reads; run again, it rebuilds the same catalogue.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "engine/report_known_answers.h"
#include "formats/html_report.h"
#include "tests/cli/cli_test_util.h"
#include "tests/support/test_support.h"

namespace napkin {
namespace {

using namespace napkin::test_support;

// The numbers after `label` on the line of stdout that starts with it (words
// such as units skipped).
std::vector<double> RowNumbers(const std::string& out, const std::string& label) {
  for (const std::string& line : Lines(out)) {
    if (line.rfind(label, 0) != 0) continue;
    std::istringstream rest(line.substr(label.size()));
    std::vector<double> numbers;
    for (std::string word; rest >> word;) {
      char* end = nullptr;
      const double value = std::strtod(word.c_str(), &end);
      if (end == word.c_str() + word.size()) numbers.push_back(value);
    }
    return numbers;
  }
  ADD_FAILURE() << "no line starts with '" << label << "' in\n" << out;
  return {};
}

// The row's known column is the known answer as printed, and each of the
// three geometries' values is within `tolerance` of it.
void ExpectRow(const std::string& out, const std::string& label, double known, double printed_step,
               double tolerance) {
  const std::vector<double> numbers = RowNumbers(out, label);
  ASSERT_EQ(numbers.size(), 4u) << label;
  EXPECT_NEAR(numbers[0], known, 0.5 * printed_step) << label;
  for (int g = 1; g < 4; ++g) EXPECT_NEAR(numbers[g], known, tolerance) << label << ", geometry " << g;
}

nlohmann::json QueryJson(const fs::path& dir, const std::string& db, const std::string& what) {
  const RunResult query = RunNapkin(dir, {"--db", db, "query", what, "--format", "json"});
  EXPECT_EQ(query.exit_code, 0) << query.err;
  return nlohmann::json::parse(query.out);
}

TEST(DemoCli, BuildsAndRunsItsCatalogueAndPrintsTheValidationTable) {
  TempDir dir;
  const RunResult demo = RunNapkin(dir.path(), {"demo", "--out", "d"});
  ASSERT_EQ(demo.exit_code, 0) << demo.err << demo.out;
  const std::string& out = demo.out;

  // Report section 4.5 on the three geometries, exact solver.
  namespace known = engine::report;
  ExpectRow(out, "total rotation about fixed Y (deg)", known::kTotalRotationDeg, 1e-4, 0.005);
  ExpectRow(out, "peak fixed omega_Y (rad/s)", known::kPeakOmegaFixedYRadps, 1, 0.005);
  ExpectRow(out, "max |fixed omega_X|, |omega_Z| (rad/s)", known::kOmegaFixedXZRadps, 1, 0.005);
  ExpectRow(out, "peak angular acceleration (rad/s^2)", known::kPeakAlphaRadps2, 1, 0.5);
  ExpectRow(out, "peak resultant CG acceleration (g)", known::kPeakAccG, 0.01, 0.005);
  ExpectRow(out, "HIC, unlimited window", known::kHic, 0.01, 0.005);
  ExpectRow(out, "  t1 (ms)", known::kHicT1S * 1e3, 0.1, 0.05);
  ExpectRow(out, "  t2 (ms)", known::kHicT2S * 1e3, 0.1, 0.05);
  ExpectRow(out, "HIC36", known::kHic36, 0.01, 0.005);
  ExpectRow(out, "HIC15", known::kHic15, 0.01, 0.005);
  // The seed solver's legacy error: Table 4-2 data processed as ideal.
  const std::vector<double> seed_as_ideal = RowNumbers(out, "seed, ideal-3222");
  ASSERT_GE(seed_as_ideal.size(), 2u);
  EXPECT_NEAR(seed_as_ideal[0], 1.42, 0.005);
  EXPECT_NEAR(seed_as_ideal[1], 3.13, 0.005);

  // The padding series compared against production trim: both foams lower
  // in HIC15, the whole 95 % interval of the difference below zero.
  EXPECT_TRUE(std::regex_search(
      out,
      std::regex("\nhic15 \\(log scale[^\n]*\n[^\n]*vs production\n  production +5 [^\n]*\\(baseline\\)\n"
                 "  foam-a +5 [^\n]* -[0-9.]+ % \\[-[0-9.]+, -[0-9.]+\\][^\n]*\n"
                 "  foam-b +5 [^\n]* -[0-9.]+ % \\[-[0-9.]+, -[0-9.]+\\]")))
      << out;
  // The verdict first: production's FMVSS 201U sentence (the demo's
  // --limits), one sentence per foam, and the same sentences in the report
  // (compared with production there too).
  const std::size_t verdict = out.find("verdict on series padding-series against 'production'");
  ASSERT_NE(verdict, std::string::npos) << out;
  EXPECT_LT(verdict, out.find("series padding-series: variants compared with variant 'production'"));
  const std::string report_html = ReadText(dir.path() / "d" / "report.html");
  std::size_t sentences = 0;
  for (const std::string& line : Lines(out.substr(verdict))) {
    if (line.rfind("  foam-", 0) != 0 && line.rfind("  production", 0) != 0) {
      if (sentences > 0) break;
      continue;
    }
    ++sentences;
    EXPECT_EQ(line.rfind(sentences == 1 ? "  production (baseline): all 5 production tests meet FMVSS 201U ("
                         : sentences == 2 ? "  foam-a: lowers HIC15 by "
                                          : "  foam-b: lowers HIC15 by ",
                         0),
              0u)
        << line;
    if (sentences > 1) {
      EXPECT_NE(line.find("tests meet FMVSS 201U (highest HIC(d) "), std::string::npos) << line;
    }
    // The demo's second set (issue 44): Euro NCAP's points for the head and a further test's chance,
    // for every variant, the baseline too.
    EXPECT_NE(line.find("; a further test exceeds HIC(d) 1000 with probability "), std::string::npos) << line;
    EXPECT_TRUE(std::regex_search(
        line,
        std::regex(
            "; Euro NCAP v9.3 frontal head \\(HIII 50M\\): head [0-9]\\.[0-9]{2} of 4 points on average")))
        << line;
    EXPECT_TRUE(
        std::regex_search(line, std::regex("HIC15 [0-9]\\.[0-9]{2} points on average; a further test scores "
                                           "[0-9]\\.[0-9]{2} points expected \\[[0-9]\\.[0-9]{2}, "
                                           "[0-9]\\.[0-9]{2}\\] \\(80 % prediction interval\\) and exceeds "
                                           "HIC15 700 with probability [0-9.]+ %")))
        << line;
    EXPECT_EQ(line.find("unchanged"), std::string::npos) << line;
    EXPECT_NE(report_html.find("<li>" + formats::EscapeHtml(line.substr(2)) + "</li>"), std::string::npos)
        << line;
  }
  EXPECT_EQ(sentences, 3u) << out;
  EXPECT_NE(report_html.find("<h3>Verdict against production</h3>"), std::string::npos);

  // The report of the whole catalogue, and what to try next.
  EXPECT_NE(out.find("wrote d/report.html: 18 tests, "), std::string::npos) << out;
  EXPECT_TRUE(fs::exists(dir.path() / "d" / "report.html"));
  EXPECT_NE(out.find("napkin --db d/napkin.db query hic --where \"hic15>700\""), std::string::npos) << out;

  // The catalogue: 15 padding tests and 3 validation tests, all done.
  const std::string db = "d/napkin.db";
  const nlohmann::json hic = QueryJson(dir.path(), db, "hic");
  ASSERT_EQ(hic.size(), 18u);
  std::map<std::string, std::vector<double>> hic15;
  for (const nlohmann::json& row : hic) {
    ASSERT_TRUE(row.at("hic15").is_number()) << row.dump();
    const std::string series = row.at("series").get<std::string>();
    if (series == "validation") {
      EXPECT_NEAR(row.at("hic15").get<double>(), known::kHic15, 0.005) << row.dump();
      hic15["validation"].push_back(row.at("hic15").get<double>());
    } else {
      EXPECT_EQ(series, "padding-series");
      hic15[row.at("variant").get<std::string>()].push_back(row.at("hic15").get<double>());
    }
  }
  ASSERT_EQ(hic15.size(), 4u);
  for (const auto& [group, values] : hic15)
    EXPECT_EQ(values.size(), group == "validation" ? 3u : 5u) << group;
  for (double value : hic15.at("production")) {
    EXPECT_GE(value, 700.0);
    EXPECT_LE(value, 1100.0);
  }
  for (std::size_t r = 0; r < 5; ++r) {
    EXPECT_LT(hic15.at("foam-a")[r], hic15.at("production")[r]);
    EXPECT_LT(hic15.at("foam-b")[r], hic15.at("production")[r]);
  }
  const RunResult status = RunNapkin(dir.path(), {"--db", db, "status", "--format", "json"});
  ASSERT_EQ(status.exit_code, 0) << status.err;
  const nlohmann::json counts = nlohmann::json::parse(status.out);
  EXPECT_EQ(counts.at("tests"), 18);
  EXPECT_EQ(counts.at("done"), 18);
  EXPECT_EQ(counts.at("failed"), 0);

  // Run again: the catalogue is rebuilt from scratch, with the same results.
  const RunResult again = RunNapkin(dir.path(), {"demo", "--out", "d"});
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_NE(again.out.find("rebuilt from scratch"), std::string::npos) << again.out;
  EXPECT_EQ(QueryJson(dir.path(), db, "hic"), hic);
}

}  // namespace
}  // namespace napkin

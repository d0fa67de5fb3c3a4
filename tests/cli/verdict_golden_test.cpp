// The verdict's wording (app/verdict.h, docs/formats.md "Verdict") on the
// fixed synthetic padding series (`napkin synth --scenario padding-series`:
// fixed seeds, 5 repeats of production, foam-a and foam-b), run and
// reported against production: the report's verdict block is compared with
// tests/cli/golden/verdict/. Run with NAPKIN_UPDATE_GOLDEN=1 to rewrite the
// golden file after a deliberate change, and review its diff.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "app/verdict.h"
#include "tests/cli/cli_test_util.h"
#include "tests/support/run_command.h"
#include "tests/support/test_support.h"

namespace napkin::app {
namespace {

using namespace napkin::test_support;

const fs::path kGoldenDir = fs::path(NAPKIN_SOURCE_DIR) / "tests" / "cli" / "golden" / "verdict";

void ExpectGolden(const std::string& name, const std::string& text) {
  const fs::path golden = kGoldenDir / name;
  if (const char* update = std::getenv("NAPKIN_UPDATE_GOLDEN");
      update != nullptr && std::string(update) == "1") {
    std::ofstream(golden, std::ios::binary) << text;
    return;
  }
  ASSERT_TRUE(fs::exists(golden)) << golden << " is missing (NAPKIN_UPDATE_GOLDEN=1 writes it)";
  EXPECT_EQ(text, ReadText(golden)) << "golden file " << golden;
}

// The padding series in `dir`'s catalogue, run.
void PaddingSeries(const TempDir& dir) {
  for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
           {"synth", "--scenario", "padding-series"}, {"run", "--threads", "2"}}) {
    const RunResult result = RunNapkin(dir.path(), args);
    ASSERT_EQ(result.exit_code, 0) << result.err;
  }
}

TEST(VerdictGolden, PaddingSeriesAgainstProduction) {
  TempDir dir;
  PaddingSeries(dir);
  if (HasFatalFailure()) return;
  const RunResult report = RunNapkin(
      dir.path(), {"report", "--series", "padding-series", "--baseline", "production", "--out", "v.html"});
  ASSERT_EQ(report.exit_code, 0) << report.err;
  const std::string html = ReadText(dir / "v.html");
  const std::string open = "<div class=\"verdict\">";
  const std::size_t begin = html.find(open);
  ASSERT_NE(begin, std::string::npos);
  const std::size_t end = html.find("</div>", begin);
  ASSERT_NE(end, std::string::npos);
  const std::string block = html.substr(begin, end + 6 - begin) + "\n";
  ExpectGolden("padding_series_production.html", block);

  // The sentences are those of app::BuildVerdict on compare's rows: the
  // baseline's row first, then foam-a and foam-b, each sentence naming its variant.
  EXPECT_NE(block.find("<h3>Verdict against production</h3>"), std::string::npos);
  EXPECT_NE(block.find("<li>foam-a: "), std::string::npos) << block;
  EXPECT_NE(block.find("<li>foam-b: "), std::string::npos) << block;
  EXPECT_EQ(block.find("<li>production"), std::string::npos) << block;
  EXPECT_EQ(block.find("unchanged"), std::string::npos) << block;

  // Each clause agrees with `napkin compare`'s numbers: p < 0.05 lowers or
  // raises, else equivalence where the two one-sided tests show it, else
  // no significant difference.
  const RunResult compare =
      RunNapkin(dir.path(), {"compare", "--series", "padding-series", "--baseline", "production", "--metrics",
                             "hic15,bric", "--format", "json"});
  ASSERT_EQ(compare.exit_code, 0) << compare.err;
  for (const nlohmann::json& row : nlohmann::json::parse(compare.out)) {
    if (row.at("group") == "production") continue;
    const std::string label = row.at("metric") == "hic15" ? "HIC15" : "BrIC";
    const double p = row.at("p_value").get<double>();
    const double tost = row.at("tost_p_value").get<double>();
    const double change = row.at("diff_pct").get<double>();
    const std::string clause = p < kVerdictAlpha      ? (change < 0 ? "lowers " : "raises ") + label + " by "
                               : tost < kVerdictAlpha ? label + " equivalent within ±10 %"
                                                      : "no significant difference in " + label + " (";
    const std::size_t sentence = block.find("<li>" + row.at("group").get<std::string>() + ": ");
    ASSERT_NE(sentence, std::string::npos);
    EXPECT_LT(block.find(clause, sentence), block.find("</li>", sentence)) << row.dump() << "\n" << block;
  }
}

// With the demo's limit sets (docs/formats.md "Limits"): FMVSS 201U's maximum and Euro NCAP's
// sliding scales, each variant's points and a further test's chance, and the pictures' markup.
TEST(VerdictGolden, PaddingSeriesAgainstProductionWithLimits) {
  TempDir dir;
  PaddingSeries(dir);
  if (HasFatalFailure()) return;
  const RunResult report = RunNapkin(
      dir.path(), {"report", "--series", "padding-series", "--baseline", "production", "--limits",
                   "fmvss201u", "--limits", "euro-ncap-aop-v9.3-frontal-head-hiii50m", "--out", "v.html"});
  ASSERT_EQ(report.exit_code, 0) << report.err;
  const std::string html = ReadText(dir / "v.html");
  const std::size_t begin = html.find("<div class=\"verdict\">");
  ASSERT_NE(begin, std::string::npos);
  // The verdict, then its pictures (up to the first table under them).
  const std::size_t end = html.find("<h3>Every test against", begin);
  ASSERT_NE(end, std::string::npos);
  const std::string block = html.substr(begin, end - begin);
  ExpectGolden("padding_series_production_limits.html", block);
  // A strip per limited criterion (HIC(d); HIC15 and a3ms) and the forest.
  EXPECT_NE(block.find("id=\"forest-1\""), std::string::npos);
  for (const char* strip : {"strip-1-1", "strip-1-2", "strip-1-3"})
    EXPECT_NE(block.find(std::string("id=\"") + strip + "\""), std::string::npos) << strip;
  EXPECT_EQ(block.find("strip-1-4"), std::string::npos);
  for (const char* variant : {"production (baseline): ", "foam-a: ", "foam-b: "}) {
    const std::size_t sentence = block.find(std::string("<li>") + variant);
    ASSERT_NE(sentence, std::string::npos) << variant;
    const std::string text = block.substr(sentence, block.find("</li>", sentence) - sentence);
    EXPECT_NE(text.find("a further test exceeds HIC(d) 1000 with probability "), std::string::npos) << text;
    EXPECT_NE(text.find("Euro NCAP v9.3 frontal head (HIII 50M): head "), std::string::npos) << text;
    EXPECT_NE(text.find(" and exceeds HIC15 700 with probability "), std::string::npos) << text;
  }
  // Every test against each set, under the verdict.
  EXPECT_NE(html.find("<h3>Every test against FMVSS 201U</h3>"), std::string::npos);
  EXPECT_NE(html.find("<h3>Every test against Euro NCAP v9.3 frontal head (HIII 50M)</h3>"),
            std::string::npos);
}

}  // namespace
}  // namespace napkin::app

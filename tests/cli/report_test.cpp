// `napkin report` end to end: a synthetic padding series is synthesised,
// run and reported; the page is checked as text, then opened in headless
// Chromium (skipped where Chromium is not installed): every chart drawn (a
// canvas in each chart's element), no script error, and a screenshot that is
// not blank.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "app/comparison.h"
#include "formats/csv.h"
#include "tests/cli/cli_test_util.h"
#include "tests/support/run_command.h"
#include "tests/support/test_support.h"

namespace napkin {
namespace {

namespace fs = std::filesystem;
using test_support::RunResult;
using ::testing::HasSubstr;

std::size_t Count(const std::string& text, const std::string& what) {
  std::size_t count = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++count;
  return count;
}

// One catalogue for the suite: padding-series, 2 repeats of 3 variants (6
// tests of 4,001 samples: 100 ms at 40 kHz), run; and one test synthesised
// but not run.
class ReportCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test_support::TempDir;
    for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
             {"synth", "--scenario", "padding-series", "--count", "2", "--rate", "40000"},
             {"run", "--threads", "2"},
             {"synth", "--scenario", "random", "--series", "pending", "--test-id", "pending", "--seed", "777",
              "--samples", "1000"}}) {
      const RunResult result = Napkin(args);
      if (result.exit_code != 0 && setup_error_.empty())
        setup_error_ =
            "napkin " + args.front() + " exited " + std::to_string(result.exit_code) + ": " + result.err;
    }
  }
  static void TearDownTestSuite() { delete dir_; }

  // A failed suite set-up fails every test (an assertion in SetUpTestSuite
  // would only skip them).
  void SetUp() override { ASSERT_EQ(setup_error_, "") << "the suite's catalogue could not be built"; }

  static RunResult Napkin(const std::vector<std::string>& args) {
    return test_support::RunNapkin(dir_->path(), args);
  }

  static test_support::TempDir* dir_;
  static std::string setup_error_;
};
test_support::TempDir* ReportCli::dir_ = nullptr;
std::string ReportCli::setup_error_;

TEST_F(ReportCli, ReportsTheSelectedTestsWithFourChartsEach) {
  const RunResult report = Napkin({"report", "--series", "padding-series", "--out", "series.html"});
  ASSERT_EQ(report.exit_code, 0) << report.err;
  EXPECT_EQ(report.err, "");
  const std::string html = test_support::ReadText(dir_->path() / "series.html");
  EXPECT_EQ(report.out, "wrote series.html: 6 tests, " + std::to_string(html.size()) + " bytes.\n");
  EXPECT_EQ(Count(html, "<section class=\"test\""), 6u);
  EXPECT_EQ(Count(html, "<div class=\"chart\" id=\"chart-"), 24u);
  // The series has three variants: the compare table and one distribution plot per metric.
  EXPECT_EQ(Count(html, "<section class=\"comparison\">"), 1u);
  EXPECT_EQ(Count(html, "<div class=\"chart\" id=\"dist-"), app::DefaultComparisonMetrics().size());
  EXPECT_EQ(Count(html, "<tr><td>hic15</td><td>"), 3u);  // one compare row per variant
  for (const char* variant : {"production", "foam-a", "foam-b"})
    EXPECT_THAT(html, HasSubstr(std::string("variant ") + variant));
  EXPECT_THAT(html, HasSubstr("<strong>default</strong>"));  // the processing config
  EXPECT_THAT(html, HasSubstr("<meta name=\"generator\" content=\"napkin "));
}

TEST_F(ReportCli, SelectsByVariantAndTestAndLeavesOutTestsWithoutResults) {
  const RunResult by_variant =
      Napkin({"report", "--variant", "foam-a", "--variant", "foam-b", "--out", "foams.html"});
  ASSERT_EQ(by_variant.exit_code, 0) << by_variant.err;
  EXPECT_EQ(Count(test_support::ReadText(dir_->path() / "foams.html"), "<section class=\"test\""), 4u);

  const RunResult by_test = Napkin({"report", "--test", "padding-series-foam-b-02", "--test",
                                    "padding-series-production-01", "--out", "two.html"});
  ASSERT_EQ(by_test.exit_code, 0) << by_test.err;
  EXPECT_EQ(by_test.out.rfind("wrote two.html: 2 tests, ", 0), 0u) << by_test.out;
  const std::string two = test_support::ReadText(dir_->path() / "two.html");
  EXPECT_EQ(Count(two, "<section class=\"test\""), 2u);
  EXPECT_THAT(two, HasSubstr("<h2>Test padding-series-foam-b-02<"));
  EXPECT_THAT(two, HasSubstr("<h2>Test padding-series-production-01<"));

  const RunResult everything = Napkin({"report", "--out", "all.html"});
  ASSERT_EQ(everything.exit_code, 0) << everything.err;
  const std::vector<std::string> lines = test_support::Lines(everything.out);
  ASSERT_EQ(lines.size(), 2u) << everything.out;
  EXPECT_THAT(lines[0], HasSubstr(": 6 tests, "));
  EXPECT_THAT(lines[1], HasSubstr("left out 1 test without results (pending"));
  EXPECT_THAT(lines[1], HasSubstr("run `napkin run` first"));
}

TEST_F(ReportCli, WhereSelectsTheTestsQueryLists) {
  // The three largest HIC15 by `query`; the report of hic15 >= the third of them has exactly those.
  const RunResult top = Napkin({"query", "hic", "--sort", "hic15:desc", "--limit", "3", "--format", "json"});
  ASSERT_EQ(top.exit_code, 0) << top.err;
  const nlohmann::json rows = nlohmann::json::parse(top.out);
  ASSERT_EQ(rows.size(), 3u);
  const RunResult report =
      Napkin({"report", "--where", "hic15 >= " + rows[2]["hic15"].dump(), "--out", "top.html"});
  ASSERT_EQ(report.exit_code, 0) << report.err;
  EXPECT_EQ(report.out.rfind("wrote top.html: 3 tests, ", 0), 0u) << report.out;
  const std::string html = test_support::ReadText(dir_->path() / "top.html");
  EXPECT_EQ(Count(html, "<section class=\"test\""), 3u);
  for (const auto& row : rows)
    EXPECT_THAT(html, HasSubstr("<h2>Test " + row["test_id"].get<std::string>() + "<"));

  const RunResult bad = Napkin({"report", "--where", "hic15 >> 3", "--out", "bad.html"});
  EXPECT_EQ(bad.exit_code, 2);
  test_support::ExpectOneSentenceError(bad, {"--where \"hic15 >> 3\"", "hic_d"});
  EXPECT_FALSE(fs::exists(dir_->path() / "bad.html"));
}

// The overlays' plot data of a written report (docs/formats.md "Overlaid curves").
nlohmann::json OverlayData(const std::string& html) {
  const std::string marker = "<script type=\"application/json\" id=\"napkin-data\">";
  const std::size_t begin = html.find(marker);
  if (begin == std::string::npos) return {};
  const std::size_t end = html.find("</script>", begin);
  return nlohmann::json::parse(html.substr(begin + marker.size(), end - begin - marker.size()))
      .at("overlays");
}

// The time (ms) of the first plotted value of trace `k` above `threshold`; none if none.
std::optional<double> FirstAbove(const nlohmann::json& overlay, std::size_t k, double threshold) {
  const nlohmann::json& t = overlay.at("t");
  const nlohmann::json& y = overlay.at("y").at(k);
  for (std::size_t i = 0; i < t.size(); ++i)
    if (y[i].is_number() && y[i].get<double>() > threshold) return t[i].get<double>();
  return std::nullopt;
}

TEST_F(ReportCli, OverlaysLayEveryTestOverItsVariantsCorridor) {
  const RunResult recorded = Napkin({"report", "--series", "padding-series", "--out", "recorded.html"});
  ASSERT_EQ(recorded.exit_code, 0) << recorded.err;
  const std::string html = test_support::ReadText(dir_->path() / "recorded.html");
  const nlohmann::json overlays = OverlayData(html);
  ASSERT_EQ(overlays.size(), 2u);
  EXPECT_EQ(overlays[0].at("id"), "overlay-1-acc");
  EXPECT_EQ(overlays[1].at("id"), "overlay-1-omega");
  EXPECT_THAT(html, HasSubstr("Aligned at t = 0 as recorded"));
  for (const nlohmann::json& overlay : overlays) {
    const std::size_t points = overlay.at("t").size();
    EXPECT_LE(points, 2000u);
    ASSERT_EQ(overlay.at("labels").size(), 12u);  // 6 tests, 3 variants x 2 bounds
    ASSERT_EQ(overlay.at("y").size(), 12u);
    // Per variant (baseline foam-a first: first by name), its 2 tests and the
    // corridor: at every point where both tests have a value, mean ± sd of two
    // values are their min and max.
    EXPECT_EQ(overlay.at("groups"), nlohmann::json({"foam-a", "foam-b", "production"}));
    for (std::size_t g = 0; g < 3; ++g) {
      std::vector<std::size_t> members;
      std::size_t low = 0, high = 0;
      for (std::size_t k = 0; k < 12; ++k) {
        if (overlay.at("group")[k] != g) continue;
        const std::string kind = overlay.at("kind")[k];
        if (kind == "test") members.push_back(k);
        if (kind == "low") low = k;
        if (kind == "high") high = k;
      }
      ASSERT_EQ(members.size(), 2u);
      ASSERT_EQ(overlay.at("labels")[low], overlay.at("groups")[g].get<std::string>() + " mean − 1 sd");
      ASSERT_EQ(overlay.at("labels")[high], overlay.at("groups")[g].get<std::string>() + " mean + 1 sd");
      std::size_t checked = 0;
      for (std::size_t i = 0; i < points; ++i) {
        const nlohmann::json& a = overlay.at("y")[members[0]][i];
        const nlohmann::json& b = overlay.at("y")[members[1]][i];
        if (!a.is_number() || !b.is_number()) continue;
        const double x = a.get<double>(), z = b.get<double>();
        // sd of two values is |x - z| / sqrt(2). Every plotted value keeps 6
        // significant digits (error <= 5e-6 of its magnitude): x and z move
        // mean - sd by <= 5e-6 (|x| + |z|) (1/2 + 1/sqrt(2)), the bound's own
        // rounding by 5e-6 |bound| <= 5e-6 (|x| + |z|).
        const double mean = (x + z) / 2, sd = std::abs(x - z) / std::sqrt(2.0);
        const double tolerance = 1.5e-5 * (std::abs(x) + std::abs(z)) + 1e-12;
        EXPECT_NEAR(overlay.at("y")[low][i].get<double>(), mean - sd, tolerance);
        EXPECT_NEAR(overlay.at("y")[high][i].get<double>(), mean + sd, tolerance);
        ++checked;
      }
      EXPECT_GT(checked, points / 2);
    }
  }
  // Each test's peak is on the plot: the acceleration overlay reaches each
  // test's peak_acc_g (query), to the 6 digits plotted.
  const RunResult peaks = Napkin({"query", "hic", "--where", "series = padding-series", "--format", "json"});
  ASSERT_EQ(peaks.exit_code, 0) << peaks.err;
  for (const nlohmann::json& row : nlohmann::json::parse(peaks.out)) {
    const auto label =
        std::find(overlays[0].at("labels").begin(), overlays[0].at("labels").end(), row.at("test_id"));
    ASSERT_NE(label, overlays[0].at("labels").end()) << row.dump();
    double largest = 0;
    for (const nlohmann::json& value : overlays[0].at("y")[label - overlays[0].at("labels").begin()])
      if (value.is_number()) largest = std::max(largest, value.get<double>());
    EXPECT_NEAR(largest, row.at("peak_acc_g").get<double>(), 1e-5 * largest) << row.dump();
  }

  // --align onset: no test is above 5 g before t = 0, and each crosses it
  // right after (within one display bucket).
  const RunResult onset =
      Napkin({"report", "--series", "padding-series", "--align", "onset", "--out", "onset.html"});
  ASSERT_EQ(onset.exit_code, 0) << onset.err;
  const std::string onset_html = test_support::ReadText(dir_->path() / "onset.html");
  EXPECT_THAT(onset_html, HasSubstr("first sample whose resultant CG acceleration exceeds 5 g"));
  const nlohmann::json aligned = OverlayData(onset_html).at(0);
  for (std::size_t k = 0; k < 6; ++k) {
    const std::optional<double> first = FirstAbove(aligned, k, 5.0);
    ASSERT_TRUE(first) << k;
    EXPECT_GE(*first, -1e-9) << aligned.at("labels")[k];
    EXPECT_LE(*first, 5.0) << aligned.at("labels")[k];
  }
  // A threshold no test reaches leaves every test as recorded, and says so.
  const RunResult never = Napkin({"report", "--series", "padding-series", "--align", "onset",
                                  "--onset-threshold", "10000", "--out", "never.html"});
  ASSERT_EQ(never.exit_code, 0) << never.err;
  const std::string never_html = test_support::ReadText(dir_->path() / "never.html");
  EXPECT_EQ(OverlayData(never_html), overlays);
  EXPECT_THAT(never_html, HasSubstr("Never above 10000 g, so shown as recorded: padding-series-foam-a-01, "));

  const RunResult bad = Napkin({"report", "--align", "peak", "--out", "bad.html"});
  EXPECT_EQ(bad.exit_code, 2);
  const RunResult bad_baseline = Napkin({"report", "--baseline", "foam-c", "--out", "bad.html"});
  EXPECT_EQ(bad_baseline.exit_code, 2);
  test_support::ExpectOneSentenceError(bad_baseline,
                                       {"unknown baseline 'foam-c'", "foam-a, foam-b, production"});
  EXPECT_FALSE(fs::exists(dir_->path() / "bad.html"));
}

TEST_F(ReportCli, BaselineOptionComparesWithTheNamedVariant) {
  const RunResult report = Napkin(
      {"report", "--series", "padding-series", "--baseline", "production", "--out", "production.html"});
  ASSERT_EQ(report.exit_code, 0) << report.err;
  const std::string html = test_support::ReadText(dir_->path() / "production.html");
  EXPECT_THAT(html, HasSubstr("<h3>Verdict against production</h3>"));
  EXPECT_THAT(html, HasSubstr("<li>foam-a: "));
  EXPECT_THAT(html, HasSubstr("<li>foam-b: "));
  // The compare table's note and the overlays' variant order follow it.
  EXPECT_THAT(html, HasSubstr("napkin compare --series padding-series --baseline production shows them; "
                              "baseline production;"));
  EXPECT_EQ(OverlayData(html).at(0).at("groups"), nlohmann::json({"production", "foam-a", "foam-b"}));
  // Default: as compare, the first variant by name.
  const RunResult by_name = Napkin({"report", "--series", "padding-series", "--out", "by-name.html"});
  ASSERT_EQ(by_name.exit_code, 0) << by_name.err;
  const std::string by_name_html = test_support::ReadText(dir_->path() / "by-name.html");
  EXPECT_THAT(by_name_html, HasSubstr("<h3>Verdict against foam-a</h3>"));
  EXPECT_THAT(by_name_html, HasSubstr("<li>production: "));

  // --limits: the baseline's sentence, each variant's limits clause and the table's column.
  const RunResult limits = Napkin({"report", "--series", "padding-series", "--baseline", "production",
                                   "--limits", "fmvss208", "--out", "limits.html"});
  ASSERT_EQ(limits.exit_code, 0) << limits.err;
  const std::string limits_html = test_support::ReadText(dir_->path() / "limits.html");
  EXPECT_THAT(limits_html, HasSubstr("<li>production (baseline): "));
  EXPECT_THAT(limits_html, HasSubstr(" FMVSS 208 (highest HIC15 "));
  EXPECT_THAT(limits_html, HasSubstr("<th>meet FMVSS 208</th>"));
  const RunResult bad = Napkin({"report", "--limits", "nope", "--out", "nope.html"});
  EXPECT_EQ(bad.exit_code, 2);
  test_support::ExpectOneSentenceError(bad, {"\"nope\" is neither a file nor a preset"});
}

TEST_F(ReportCli, ExplainsWhatIsMissing) {
  const RunResult unknown = Napkin({"report", "--test", "nope", "--out", "x.html"});
  EXPECT_EQ(unknown.exit_code, 1);
  test_support::ExpectOneSentenceError(unknown, {"test 'nope' is not in catalogue"});

  const RunResult no_match = Napkin({"report", "--series", "nope", "--out", "x.html"});
  EXPECT_EQ(no_match.exit_code, 1);
  test_support::ExpectOneSentenceError(no_match, {"matches series nope"});

  const RunResult not_run = Napkin({"report", "--series", "pending", "--out", "x.html"});
  EXPECT_EQ(not_run.exit_code, 1);
  test_support::ExpectOneSentenceError(not_run, {"run `napkin run` first"});
  EXPECT_FALSE(fs::exists(dir_->path() / "x.html"));

  const RunResult no_out = Napkin({"report"});
  EXPECT_EQ(no_out.exit_code, 2);
}

std::string VisibleText(const std::string& fragment);  // below

// ---- headless Chromium

std::string ChromiumBinary() {
  for (const char* path : {"/usr/bin/chromium", "/usr/bin/chromium-headless-shell"})
    if (fs::exists(path)) return path;
  return {};
}

// Runs headless Chromium on `url` with a fresh profile in `dir`, at most 120 s.
RunResult RunChromium(const fs::path& dir, std::vector<std::string> args, const std::string& url) {
  std::vector<std::string> command = {"120",
                                      ChromiumBinary(),
                                      "--headless",
                                      "--no-sandbox",
                                      "--disable-gpu",
                                      "--no-first-run",
                                      "--disable-extensions",
                                      "--user-data-dir=" + (dir / "profile").string(),
                                      "--virtual-time-budget=10000"};
  command.insert(command.end(), args.begin(), args.end());
  command.push_back(url);
  return test_support::RunProgram("/usr/bin/timeout", command, dir);
}

// For each chart element of a dumped DOM: whether a canvas was drawn inside it.
std::vector<bool> ChartsWithCanvas(const std::string& dom) {
  std::vector<bool> drawn;
  const std::string marker = "<div class=\"chart\"";
  for (std::size_t at = dom.find(marker); at != std::string::npos;) {
    const std::size_t next = dom.find(marker, at + 1);
    const std::string element = dom.substr(at, next == std::string::npos ? std::string::npos : next - at);
    drawn.push_back(element.find("<canvas") != std::string::npos &&
                    element.substr(0, element.find('>')).find("data-drawn=\"true\"") != std::string::npos);
    at = next;
  }
  return drawn;
}

class ReportInChromium : public ReportCli {
 protected:
  void SetUp() override {
    ReportCli::SetUp();
    if (HasFatalFailure()) return;
    if (ChromiumBinary().empty()) GTEST_SKIP() << "headless Chromium (Debian: chromium) is not installed";
    const RunResult report = Napkin({"report", "--series", "padding-series", "--out", "browser.html"});
    ASSERT_EQ(report.exit_code, 0) << report.err;
    html_ = test_support::ReadText(dir_->path() / "browser.html");
  }
  std::string html_;
  test_support::TempDir browser_dir_;
};

TEST_F(ReportInChromium, DrawsEveryChartWithoutScriptErrors) {
  const fs::path page = browser_dir_ / "report.html";
  test_support::WriteText(page, html_);
  const RunResult dump = RunChromium(browser_dir_.path(), {"--dump-dom"}, "file://" + page.string());
  ASSERT_EQ(dump.exit_code, 0) << dump.err;
  const std::vector<bool> drawn = ChartsWithCanvas(dump.out);
  // 4 per test, a distribution per metric, the acceleration and angular velocity overlays, and the
  // verdict's forest plot.
  ASSERT_EQ(drawn.size(), 24u + app::DefaultComparisonMetrics().size() + 2u + 1u) << dump.out.substr(0, 2000);
  for (std::size_t i = 0; i < drawn.size(); ++i) EXPECT_TRUE(drawn[i]) << "chart " << i << " not drawn";
  EXPECT_THAT(dump.out, HasSubstr("dygraph-legend"));  // dygraphs wrote its legends
  EXPECT_EQ(dump.out.find("class=\"napkin-script-error\""), std::string::npos)
      << dump.out.substr(dump.out.find("napkin-script-error"), 400);

  // The check can fail: the same page with a throwing script shows the error marker.
  std::string broken = html_;
  broken.insert(broken.rfind("</body>"), "<script>undefinedFunctionOfTheTest();</script>");
  test_support::WriteText(browser_dir_ / "broken.html", broken);
  const RunResult broken_dump =
      RunChromium(browser_dir_.path(), {"--dump-dom"}, "file://" + (browser_dir_ / "broken.html").string());
  ASSERT_EQ(broken_dump.exit_code, 0) << broken_dump.err;
  EXPECT_THAT(broken_dump.out, HasSubstr("class=\"napkin-script-error\""));
  EXPECT_THAT(broken_dump.out, HasSubstr("undefinedFunctionOfTheTest"));
}

// The labels of the series a dygraphs legend lists at rest (legend
// 'always', no point highlighted): one bold span per series.
std::vector<std::string> LegendLabels(const std::string& legend_html) {
  std::vector<std::string> labels;
  const std::string marker = "<span style=\"font-weight: bold;";
  for (std::size_t at = legend_html.find(marker); at != std::string::npos;
       at = legend_html.find(marker, at + 1)) {
    // The span holds the line's dash (divs) and the label.
    const std::string label = VisibleText(legend_html.substr(at, legend_html.find("</span>", at) - at));
    labels.push_back(label.substr(std::min(label.size(), label.find_first_not_of(' '))));
  }
  return labels;
}

// The series' overlays: each drawn, a legend entry per variant (not per
// trace), no script error.
TEST_F(ReportInChromium, OverlaysHaveATracePerTestAndTwoCorridorBoundsPerVariant) {
  const fs::path page = browser_dir_ / "report.html";
  test_support::WriteText(page, html_);
  const RunResult dump = RunChromium(browser_dir_.path(), {"--dump-dom"}, "file://" + page.string());
  ASSERT_EQ(dump.exit_code, 0) << dump.err;
  EXPECT_EQ(dump.out.find("class=\"napkin-script-error\""), std::string::npos);
  const RunResult tests =
      Napkin({"query", "tests", "--where", "series = padding-series", "--format", "json"});
  ASSERT_EQ(tests.exit_code, 0) << tests.err;
  std::set<std::string> expected;
  for (const nlohmann::json& test : nlohmann::json::parse(tests.out))
    expected.insert(test.at("test_id").get<std::string>());
  ASSERT_EQ(expected.size(), 6u);
  for (const char* variant : {"production", "foam-a", "foam-b"})
    for (const char* bound : {" mean − 1 sd", " mean + 1 sd"}) expected.insert(std::string(variant) + bound);
  for (const char* id : {"overlay-1-acc", "overlay-1-omega"}) {
    const std::size_t at = dump.out.find(std::string("id=\"") + id + "\"");
    ASSERT_NE(at, std::string::npos) << id;
    const std::size_t open = dump.out.rfind("<div class=\"chart\"", at);
    const std::size_t figure_end = dump.out.find("</figure>", at);
    const std::string element = dump.out.substr(open, figure_end - open);
    EXPECT_NE(element.find("data-drawn=\"true\""), std::string::npos) << id;
    EXPECT_NE(element.find("<canvas"), std::string::npos) << id;
    const std::size_t legend = element.find("<div class=\"legend\"");
    ASSERT_NE(legend, std::string::npos) << id;
    // The legend (issue 30 point 7): one entry per variant with its corridor,
    // no test ids (those show on hover).
    const std::string legend_html = element.substr(legend);
    std::vector<std::string> entries;
    const std::string marker = "<span class=\"variant-legend\"";
    for (std::size_t at = legend_html.find(marker); at != std::string::npos;
         at = legend_html.find(marker, at + 1)) {
      const std::size_t end = legend_html.find("mean ± 1 sd</span>", at);
      ASSERT_NE(end, std::string::npos) << legend_html;
      entries.push_back(VisibleText(legend_html.substr(at, end + std::string("mean ± 1 sd").size() - at)));
    }
    EXPECT_EQ(entries,
              (std::vector<std::string>{"foam-a (2 tests) mean ± 1 sd", "foam-b (2 tests) mean ± 1 sd",
                                        "production (2 tests) mean ± 1 sd"}))
        << id;
    for (const std::string& label : expected) {
      if (label.find(" mean ") != std::string::npos) continue;  // the corridors' labels
      EXPECT_EQ(VisibleText(legend_html).find(label), std::string::npos) << id << " lists test " << label;
    }
    EXPECT_TRUE(LegendLabels(legend_html).empty()) << id;  // not dygraphs' one entry per trace
  }
}

// Counts, in Chromium itself, the pixels of a PNG that are not white and
// those that are strongly coloured (the traces), and writes them into the page.
constexpr const char* kPixelCountPage = R"html(<!DOCTYPE html>
<html><body><img id="shot" src="shot.png"><script>
window.addEventListener('load', function () {
  var image = document.getElementById('shot');
  var canvas = document.createElement('canvas');
  canvas.width = image.naturalWidth; canvas.height = image.naturalHeight;
  var context = canvas.getContext('2d');
  context.drawImage(image, 0, 0);
  var d = context.getImageData(0, 0, canvas.width, canvas.height).data, ink = 0, colour = 0;
  for (var i = 0; i < d.length; i += 4) {
    if (d[i] < 235 || d[i + 1] < 235 || d[i + 2] < 235) ++ink;
    if (Math.max(d[i], d[i + 1], d[i + 2]) - Math.min(d[i], d[i + 1], d[i + 2]) > 80) ++colour;
  }
  var result = document.createElement('pre');
  result.id = 'pixels';
  result.textContent = 'size ' + canvas.width + 'x' + canvas.height + ' ink ' + ink + ' colour ' + colour;
  document.body.appendChild(result);
});
</script></body></html>
)html";

// The screenshot of `page` in `dir` at `window` ("W,H"; kept at $NAPKIN_KEEP_SCREENSHOT when set),
// its pixels counted by kPixelCountPage: the dumped page, "size WxH ink I colour C" in it.
std::string ScreenshotPixels(const fs::path& dir, const fs::path& page, const std::string& window) {
  const fs::path shot = dir / "shot.png";
  const RunResult screenshot =
      RunChromium(dir, {"--screenshot=" + shot.string(), "--window-size=" + window, "--hide-scrollbars"},
                  "file://" + page.string());
  if (screenshot.exit_code != 0 || !fs::exists(shot)) return "no screenshot: " + screenshot.err;
  if (const char* keep = std::getenv("NAPKIN_KEEP_SCREENSHOT"))
    fs::copy_file(shot, keep, fs::copy_options::overwrite_existing);
  test_support::WriteText(dir / "pixels.html", kPixelCountPage);
  return RunChromium(dir, {"--allow-file-access-from-files", "--dump-dom"},
                     "file://" + (dir / "pixels.html").string())
      .out;
}

TEST_F(ReportInChromium, ScreenshotIsNotBlank) {
  const fs::path page = browser_dir_ / "report.html";
  test_support::WriteText(page, html_);
  const fs::path shot = browser_dir_ / "shot.png";
  const RunResult screenshot = RunChromium(
      browser_dir_.path(), {"--screenshot=" + shot.string(), "--window-size=1280,1800", "--hide-scrollbars"},
      "file://" + page.string());
  ASSERT_EQ(screenshot.exit_code, 0) << screenshot.err;
  ASSERT_TRUE(fs::exists(shot)) << screenshot.err;

  test_support::WriteText(browser_dir_ / "pixels.html", kPixelCountPage);
  const RunResult count = RunChromium(browser_dir_.path(), {"--allow-file-access-from-files", "--dump-dom"},
                                      "file://" + (browser_dir_ / "pixels.html").string());
  ASSERT_EQ(count.exit_code, 0) << count.err;
  std::smatch match;
  ASSERT_TRUE(std::regex_search(count.out, match, std::regex(R"(size (\d+)x(\d+) ink (\d+) colour (\d+))")))
      << count.out;
  const double pixels = std::stod(match[1]) * std::stod(match[2]);
  EXPECT_EQ(match[1], "1280");
  EXPECT_EQ(match[2], "1800");
  // Text, tables, axes and traces: a blank (white) page has neither ink nor colour.
  EXPECT_GT(std::stod(match[3]) / pixels, 0.02) << match[0];
  EXPECT_GT(std::stod(match[4]), 2000.0) << match[0];
}

// ---- names as a person sees them in the browser

// The visible text of an HTML fragment: tags dropped, the character
// references dygraphs and napkin write decoded.
std::string VisibleText(const std::string& fragment) {
  std::string text;
  bool in_tag = false;
  for (const char c : fragment) {
    if (c == '<') in_tag = true;
    if (!in_tag) text += c;
    if (c == '>') in_tag = false;
  }
  std::string decoded;
  for (std::size_t at = 0; at < text.size();) {
    bool replaced = false;
    for (const auto& [entity, character] :
         std::vector<std::pair<std::string, std::string>>{{"&amp;", "&"},
                                                          {"&lt;", "<"},
                                                          {"&gt;", ">"},
                                                          {"&quot;", "\""},
                                                          {"&#39;", "'"},
                                                          {"&#160;", " "},
                                                          {"&nbsp;", " "}}) {
      if (text.compare(at, entity.size(), entity) == 0) {
        decoded += character;
        at += entity.size();
        replaced = true;
        break;
      }
    }
    if (!replaced) decoded += text[at++];
  }
  return decoded;
}

// The verdict as a picture (issue 44): with limit sets, the forest plot and a
// strip per limited criterion are drawn without script errors, their legends
// name the outcomes, the screenshot of the pictures is coloured, and the page
// prints to a PDF of several pages.
TEST_F(ReportInChromium, TheVerdictsPicturesAreDrawnAndThePagePrints) {
  const RunResult report = Napkin({"report", "--series", "padding-series", "--limits", "fmvss201u",
                                   "--limits", "euro-ncap-aop-v9.3-frontal-head-hiii50m", "--limits",
                                   "iihs-small-overlap-head", "--out", "limits.html"});
  ASSERT_EQ(report.exit_code, 0) << report.err;
  const std::string html = test_support::ReadText(dir_->path() / "limits.html");
  const fs::path page = browser_dir_ / "limits.html";
  test_support::WriteText(page, html);
  const RunResult dump = RunChromium(browser_dir_.path(), {"--dump-dom"}, "file://" + page.string());
  ASSERT_EQ(dump.exit_code, 0) << dump.err;
  EXPECT_EQ(dump.out.find("class=\"napkin-script-error\""), std::string::npos)
      << dump.out.substr(dump.out.find("napkin-script-error"), 400);
  // The forest, then HIC(d) against FMVSS 201U, HIC15 and a3ms against Euro NCAP, HIC15 against IIHS.
  const std::vector<std::pair<std::string, std::vector<std::string>>> plots = {
      {"forest-1", {"significant change (p < 0.05)", "equivalent within the margin", "neither shown"}},
      {"strip-1-1", {"within the limit", "over the limit"}},
      {"strip-1-2", {"4 points", "between 0 and 4 points", "0 points"}},
      {"strip-1-3", {"4 points", "0 points"}},
      {"strip-1-4", {"Good", "Acceptable", "Marginal", "Poor"}}};
  for (const auto& [id, legend_labels] : plots) {
    const std::size_t at = dump.out.find("id=\"" + id + "\"");
    ASSERT_NE(at, std::string::npos) << id;
    const std::size_t open = dump.out.rfind("<div class=\"chart\"", at);
    const std::string element = dump.out.substr(open, dump.out.find("</figure>", at) - open);
    EXPECT_NE(element.find("data-drawn=\"true\""), std::string::npos) << id;
    EXPECT_NE(element.find("<canvas"), std::string::npos) << id;
    const std::string legend = VisibleText(element.substr(element.find("<div class=\"legend\"")));
    for (const std::string& label : legend_labels)
      EXPECT_NE(legend.find(label), std::string::npos) << id << ": " << legend;
  }
  EXPECT_EQ(dump.out.find("id=\"strip-1-5\""), std::string::npos);
  const std::vector<bool> drawn = ChartsWithCanvas(dump.out);
  for (std::size_t i = 0; i < drawn.size(); ++i) EXPECT_TRUE(drawn[i]) << "chart " << i << " not drawn";

  // The screenshot of the pictures alone: the shaded zones and coloured points are there.
  std::string pictures = html;
  pictures.insert(pictures.find("</style>"),
                  "header.report, section.test, section.comparison > *:not(.verdict-plots) {display: none}");
  test_support::WriteText(browser_dir_ / "pictures.html", pictures);
  const std::string pixels =
      ScreenshotPixels(browser_dir_.path(), browser_dir_ / "pictures.html", "1280,1400");
  std::smatch match;
  ASSERT_TRUE(std::regex_search(pixels, match, std::regex(R"(size (\d+)x(\d+) ink (\d+) colour (\d+))")))
      << pixels;
  EXPECT_GT(std::stod(match[4]), 5000.0) << match[0];

  // The browser's print to PDF (the print style sheet): a PDF of a page per section at least.
  const fs::path pdf = browser_dir_ / "limits.pdf";
  const RunResult print =
      RunChromium(browser_dir_.path(),
                  {"--print-to-pdf=" + pdf.string(), "--no-pdf-header-footer", "--window-size=1280,1000"},
                  "file://" + page.string());
  ASSERT_EQ(print.exit_code, 0) << print.err;
  const std::string bytes = test_support::ReadText(pdf);
  EXPECT_EQ(bytes.rfind("%PDF-", 0), 0u);
  std::size_t pages = 0;
  for (std::size_t at = bytes.find("/Type /Page"); at != std::string::npos;
       at = bytes.find("/Type /Page", at + 1))
    if (bytes.compare(at, 12, "/Type /Pages") != 0) ++pages;
  EXPECT_GE(pages, 7u);  // the comparison, and each of the 6 tests on its own page
}

// A series whose variants' names hold HTML's special characters, compared
// in the report: each name reads in the distribution plots' legends (drawn
// by dygraphs) and on their axes exactly as the user typed it.
TEST(ReportNamesInChromium, LegendsAndAxesShowVariantNamesAsTyped) {
  if (ChromiumBinary().empty()) GTEST_SKIP() << "headless Chromium (Debian: chromium) is not installed";
  test_support::TempDir dir;
  const std::vector<std::string> variants = {"a&b", "c<d>"};
  for (std::size_t v = 0; v < variants.size(); ++v) {
    const fs::path folder = dir / ("v" + std::to_string(v));
    fs::create_directories(folder);
    for (int i = 0; i < 2; ++i)
      formats::WriteSignalsCsv(
          test_support::SynthNapTest(40 + 10 * v + static_cast<std::uint64_t>(i)).signals,
          folder / ("t" + std::to_string(v) + std::to_string(i) + ".csv"));
    const RunResult import =
        test_support::RunNapkin(dir.path(), {"import", "--array", "denton-3222", "--series", "names",
                                             "--variant", variants[v], folder.filename().string()});
    ASSERT_EQ(import.exit_code, 0) << import.err;
  }
  ASSERT_EQ(test_support::RunNapkin(dir.path(), {"run"}).exit_code, 0);
  const RunResult report = test_support::RunNapkin(dir.path(), {"report", "--out", "names.html"});
  ASSERT_EQ(report.exit_code, 0) << report.err;

  test_support::TempDir browser;
  const RunResult dump =
      RunChromium(browser.path(), {"--dump-dom"}, "file://" + (dir / "names.html").string());
  ASSERT_EQ(dump.exit_code, 0) << dump.err;
  EXPECT_EQ(dump.out.find("class=\"napkin-script-error\""), std::string::npos);
  // Each distribution plot (one per metric): its legend, drawn by dygraphs,
  // and the whole figure (axis ticks included).
  std::size_t plots = 0;
  for (std::size_t at = dump.out.find("id=\"dist-1-"); at != std::string::npos;
       at = dump.out.find("id=\"dist-1-", at + 1)) {
    ++plots;
    const std::size_t figure_end = dump.out.find("</figure>", at);
    const std::size_t legend = dump.out.find("<div class=\"legend\"", at);
    ASSERT_LT(legend, figure_end) << "plot " << plots;
    const std::string legend_text = VisibleText(dump.out.substr(legend, figure_end - legend));
    const std::string figure_text = VisibleText(dump.out.substr(at, figure_end - at));
    for (const std::string& name : variants) {
      EXPECT_NE(legend_text.find(name), std::string::npos) << "plot " << plots << " legend: " << legend_text;
      EXPECT_NE(figure_text.find(name), std::string::npos) << "plot " << plots << ": " << figure_text;
    }
    EXPECT_EQ(legend_text.find("&amp;"), std::string::npos) << "plot " << plots << " legend: " << legend_text;
    EXPECT_EQ(legend_text.find("&lt;"), std::string::npos) << "plot " << plots << " legend: " << legend_text;
  }
  EXPECT_EQ(plots, app::DefaultComparisonMetrics().size());
}

// A rating against a model (issue 32 point 4): `report --model FILE`
// draws the test, the model and the ISO/TS 18571 inner and outer corridors
// (two shaded bands); the chart is drawn without script errors, and a
// screenshot of it has the bands' colours (green and orange shades).
TEST(ReportCorrelationInChromium, RatingChartDrawsItsCorridorsWithoutScriptErrors) {
  if (ChromiumBinary().empty()) GTEST_SKIP() << "headless Chromium (Debian: chromium) is not installed";
  test_support::TempDir dir;
  const auto napkin = [&](const std::vector<std::string>& args) {
    const RunResult run = test_support::RunNapkin(dir.path(), args);
    EXPECT_EQ(run.exit_code, 0) << args.front() << ": " << run.err;
    return run;
  };
  napkin({"synth", "--scenario", "padding-series", "--count", "2", "--rate", "10000"});
  napkin({"run"});
  const std::string test = "padding-series-foam-a-01";
  napkin({"export", "--test", test, "--format", "csv", "--out", "model.csv"});
  // The model: the test's body-x acceleration late by 2 ms and 20 % larger.
  {
    std::ifstream in((dir / "model.csv").string());
    std::string line;
    std::getline(in, line);
    std::ostringstream model;
    model << "time_s,head_x_g\n";
    while (std::getline(in, line)) {
      std::vector<std::string> cells;
      std::stringstream fields(line);
      for (std::string cell; std::getline(fields, cell, ',');) cells.push_back(cell);
      model << util::FormatNumber(std::stod(cells[0]) + 0.002) << ","
            << util::FormatNumber(1.2 * std::stod(cells[13])) << "\n";  // acc_body_x_g
    }
    test_support::WriteText(dir / "late.csv", model.str());
  }
  napkin({"correlate", "--test", test, "--channel", "acc_body_x_g", "--model", "late.csv"});
  napkin({"report", "--test", test, "--model", "late.csv", "--out", "rated.html"});

  test_support::TempDir browser;
  const RunResult dump =
      RunChromium(browser.path(), {"--dump-dom"}, "file://" + (dir / "rated.html").string());
  ASSERT_EQ(dump.exit_code, 0) << dump.err;
  EXPECT_EQ(dump.out.find("class=\"napkin-script-error\""), std::string::npos)
      << dump.out.substr(dump.out.find("napkin-script-error"), 400);
  const std::size_t at = dump.out.find("id=\"chart-1-rating-1\"");
  ASSERT_NE(at, std::string::npos);
  const std::size_t open = dump.out.rfind("<div class=\"chart\"", at);
  const std::string element = dump.out.substr(open, dump.out.find("</figure>", at) - open);
  EXPECT_NE(element.find("data-drawn=\"true\""), std::string::npos);
  EXPECT_NE(element.find("<canvas"), std::string::npos);
  const std::string legend = VisibleText(element.substr(element.find("<div class=\"legend\"")));
  for (const std::string& label : {test, std::string("late.csv:head_x_g"), std::string("inner corridor +"),
                                   std::string("outer corridor −")})
    EXPECT_NE(legend.find(label), std::string::npos) << legend;

  // The screenshot: the chart's bands are there (the bands' shades of green
  // and orange over white). It stays in the test's folder while it runs.
  std::string page = test_support::ReadText(dir / "rated.html");
  // Only the rating chart, at the top of the page.
  page.insert(page.find("</style>"),
              "header.report, section.test > *:not(.charts), "
              "section.test figure:not(:has(#chart-1-rating-1)) {display: none}");
  test_support::WriteText(browser / "rating.html", page);
  const std::string pixels = ScreenshotPixels(browser.path(), browser / "rating.html", "1000,700");
  std::smatch match;
  ASSERT_TRUE(std::regex_search(pixels, match, std::regex(R"(size (\d+)x(\d+) ink (\d+) colour (\d+))")))
      << pixels;
  EXPECT_GT(std::stod(match[4]), 2000.0) << match[0];
}

}  // namespace
}  // namespace napkin

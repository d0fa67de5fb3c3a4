// The HTML report's structure (docs/formats.md "HTML report"): one chart
// element per chart, the plot data embedded and complete, peaks kept by the
// display reduction, nothing loaded from outside the file, and user-supplied
// text unable to break out of its element.
#include "formats/html_report.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>

#include "common/error.h"
#include "engine/units.h"
#include "formats/report_assets.h"
#include "tests/support/run_command.h"
#include "tests/support/test_support.h"
#include "util/text.h"

namespace napkin::formats {
namespace {

std::string Lowercase(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

using nlohmann::json;

// 20,001 samples at 100 kHz: a 12 ms half-sine head pulse of 80 g along x
// with a one-sample 120 g spike at 30 ms, a rotation about z, the
// velocity and angles its integrals.
engine::Kinematics PulseKinematics() {
  const Eigen::Index n = 20001;
  engine::Kinematics k;
  k.Resize(n);
  const double dt = 1e-5;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) * dt;
    k.time_s(i) = t;
    const double pulse = t >= 0.02 && t <= 0.032 ? std::sin(std::numbers::pi * (t - 0.02) / 0.012) : 0.0;
    k.acc_fixed.row(i) << -80.0 * engine::kStandardGravity * pulse, 0.0, 0.0;
    k.acc_body.row(i) = k.acc_fixed.row(i);
    k.omega_body.row(i) << 0.0, 0.0, 30.0 * pulse;
    k.omega_fixed.row(i) = k.omega_body.row(i);
    k.roll_pitch_yaw_rad.row(i) << 0.0, 0.0, 0.2 * t / 0.2;
    k.vel_fixed.row(i) << -6.0 + 6.0 * std::min(1.0, std::max(0.0, (t - 0.02) / 0.012)), 0.0, 0.0;
  }
  k.acc_fixed(3000, 0) = -120.0 * engine::kStandardGravity;  // t = 30 ms, inside the pulse: 120 g
  return k;
}

engine::TestSummary PulseSummary() {
  engine::TestSummary summary;
  summary.hic15 = {812.3, 0.0205, 0.0315};
  summary.hic36 = {845.0, 0.0200, 0.0320};
  summary.hic = summary.hic36;
  summary.peak_acc_g = 120.0;
  summary.findings.push_back({"saturation", std::string("a1x"), engine::Severity::kWarning,
                              "channel a1x sits at <full scale> for 3 samples & more."});
  return summary;
}

// The text of the element opened by `open_tag` up to its closing </script>.
std::string ScriptText(const std::string& html, const std::string& open_tag) {
  const std::size_t begin = html.find(open_tag);
  if (begin == std::string::npos) return {};
  const std::size_t content = begin + open_tag.size();
  return html.substr(content, html.find("</script>", content) - content);
}

// The page without the text inside its <script> elements (the embedded
// library, the data, the page's own code): its markup.
std::string Markup(const std::string& html) {
  std::string markup;
  std::size_t at = 0;
  for (std::size_t open = html.find("<script", at); open != std::string::npos;
       open = html.find("<script", at)) {
    const std::size_t content = html.find('>', open) + 1;
    markup += html.substr(at, content - at);
    at = html.find("</script>", content);
  }
  return markup + html.substr(at);
}

std::size_t Count(const std::string& text, const std::string& what) {
  std::size_t count = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++count;
  return count;
}

ReportHeader Header() {
  ReportHeader header;
  header.catalogue = "napkin.db";
  header.napkin_version = "0.1.0";
  header.configs.push_back({"default", std::string(64, 'a'), R"({"hic":{"from_time_zero":false}})"});
  return header;
}

TEST(HtmlReport, OneChartElementPerChartAndTheirDataEmbedded) {
  const engine::Kinematics kinematics = PulseKinematics();
  std::vector<ReportTest> tests;
  tests.push_back(MakeReportTest("v0001", "sled", "foam-a", "default", PulseSummary(), kinematics));
  tests.push_back(MakeReportTest("v0002", "sled", "foam-b", "default", PulseSummary(), kinematics));
  const std::string html = RenderHtmlReport(Header(), {}, tests);

  const json data = json::parse(ScriptText(html, "<script type=\"application/json\" id=\"napkin-data\">"));
  ASSERT_EQ(data["charts"].size(), 8u);  // four per test
  EXPECT_EQ(Count(html, "<div class=\"chart\" id=\""), 8u);
  for (const json& chart : data["charts"]) {
    const std::string id = chart["id"];
    EXPECT_EQ(Count(html, "<div class=\"chart\" id=\"" + id + "\">"), 1u) << id;
    const std::size_t points = chart["t"].size();
    EXPECT_GT(points, 200u) << id;  // constant traces need fewer: their extremes coincide
    EXPECT_LE(points, static_cast<std::size_t>(kReportMaxPoints)) << id;
    ASSERT_EQ(chart["y"].size(), chart["labels"].size()) << id;
    for (const json& trace : chart["y"]) EXPECT_EQ(trace.size(), points) << id;
  }

  // The acceleration chart: the resultant's peak (the 120 g spike, one
  // sample of 20,001) survives the reduction, and both HIC windows are there.
  const json& acc = data["charts"][0];
  EXPECT_EQ(acc["id"], "chart-1-acc");
  const std::vector<double> resultant = acc["y"][0];
  const auto peak = std::max_element(resultant.begin(), resultant.end());
  EXPECT_EQ(*peak, 120.0);
  EXPECT_EQ(acc["t"][peak - resultant.begin()], 30.0);  // ms
  ASSERT_EQ(acc["windows"].size(), 2u);
  EXPECT_EQ(acc["windows"][0]["label"], "HIC15 = 812");
  EXPECT_DOUBLE_EQ(acc["windows"][0]["t1"], 20.5);
  EXPECT_DOUBLE_EQ(acc["windows"][0]["t2"], 31.5);
  EXPECT_EQ(acc["windows"][1]["label"], "HIC36 = 845");
  // The angular velocity chart: x, y, z and the resultant, peak 30 rad/s.
  const json& omega = data["charts"][1];
  EXPECT_EQ(omega["labels"], json({"x", "y", "z", "resultant"}));
  const std::vector<double> omega_resultant = omega["y"][3];
  EXPECT_EQ(*std::max_element(omega_resultant.begin(), omega_resultant.end()), 30.0);

  // The tables: the criteria and the escaped finding.
  EXPECT_NE(html.find("<section class=\"test\" id=\"test-2\">"), std::string::npos);
  EXPECT_NE(html.find("812.3"), std::string::npos);
  EXPECT_NE(html.find("sits at &lt;full scale&gt; for 3 samples &amp; more."), std::string::npos);
}

TEST(HtmlReport, NothingIsLoadedFromOutsideTheFile) {
  const std::vector<ReportTest> tests = {
      MakeReportTest("v0001", "sled", "foam-a", "default", PulseSummary(), PulseKinematics())};
  const std::string html = RenderHtmlReport(Header(), {}, tests);
  // No src or href that leaves the file: in the markup only #anchors (no
  // <link>, no <script src>, no image), nowhere a http(s):// or //host one.
  const std::string markup = Markup(html);
  // Every src= or href= value, case-insensitively (a scan, not std::regex:
  // GCC 12 with the sanitizers warns inside <regex> with icase).
  const std::string lower_markup = Lowercase(markup);
  for (const std::string attribute : {"src", "href"})
    for (std::size_t at = lower_markup.find(attribute); at != std::string::npos;
         at = lower_markup.find(attribute, at + 1)) {
      const bool word_start = at == 0 || !std::isalnum(static_cast<unsigned char>(lower_markup[at - 1]));
      std::size_t value = at + attribute.size();
      while (value < markup.size() && markup[value] == ' ') ++value;
      if (!word_start || value >= markup.size() || markup[value] != '=') continue;
      ++value;
      while (value < markup.size() && (markup[value] == ' ' || markup[value] == '"' || markup[value] == '\''))
        ++value;
      EXPECT_EQ(markup.compare(value, 1, "#"), 0)
          << "reference to outside the file: " << markup.substr(at, 80);
    }
  const std::string lower_html = Lowercase(html);
  for (const char* outside :
       {"src=\"http", "href=\"http", "src=\"//", "href=\"//", "src='http", "href='http"})
    EXPECT_EQ(lower_html.find(outside), std::string::npos) << outside;
  EXPECT_EQ(markup.find("<link"), std::string::npos);
  EXPECT_EQ(Count(markup, "<script>"), 3u);  // the library, the error catcher and the drawing code: inline
  EXPECT_EQ(Count(markup, "<script type=\"application/json\" id=\"napkin-data\">"), 1u);
  EXPECT_EQ(html.find("sourceMappingURL"), std::string::npos);
  // The charting library is inside, whole (but for its source-map comment).
  const std::string_view script = DygraphsScript();
  EXPECT_GT(script.size(), 100000u);
  const std::string library(script.substr(0, script.rfind("//# sourceMappingURL=")));
  EXPECT_NE(html.find(library), std::string::npos);
  std::string lower(script);
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  EXPECT_EQ(lower.find("</script"), std::string::npos);  // it cannot close its own element
}

TEST(HtmlReport, UserTextCannotBreakOutOfItsElement) {
  const std::string hostile_series = "</script><script>alert('series')</script>";
  const std::string hostile_id = "<img src=x onerror=alert(1)>";
  const std::string hostile_variant = "</script><b>\"foam\" & 'co'</b>";
  std::vector<ReportTest> tests = {MakeReportTest(hostile_id, hostile_series, hostile_variant, "</title>",
                                                  PulseSummary(), PulseKinematics())};
  ReportHeader header = Header();
  header.catalogue = "</title><script>alert(2)</script>.db";
  header.selection = "series " + hostile_series;
  header.configs[0].settings_json = R"({"note":"</pre></script><script>alert(3)</script>"})";
  ReportComparison comparison;
  comparison.series = hostile_series;
  comparison.columns = {"variant", "n"};
  comparison.rows = {{hostile_variant, "5"}};
  comparison.notes = {"</table>" + hostile_series};
  comparison.distributions.push_back(
      {"hic15",
       {{hostile_variant, {700.0, 720.0}, 710.0, 600.0, 820.0}, {"baseline", {650.0}, 650.0, {}, {}}}});
  const std::string html = RenderHtmlReport(header, std::span(&comparison, 1), tests);

  // Exactly the page's own four scripts open and close; no injected element.
  EXPECT_EQ(Count(html, "<script"), 4u);
  EXPECT_EQ(Count(html, "</script"), 4u);
  EXPECT_EQ(Count(html, "<title>"), 1u);
  EXPECT_EQ(Count(html, "</title>"), 1u);
  const std::string markup = Markup(html);
  EXPECT_EQ(markup.find("<img"), std::string::npos);
  EXPECT_EQ(markup.find("<b>"), std::string::npos);
  EXPECT_EQ(html.find("alert('series')</script>"), std::string::npos);
  EXPECT_NE(html.find(EscapeHtml(hostile_id)), std::string::npos);
  EXPECT_NE(html.find("&lt;/script&gt;&lt;script&gt;alert(&#39;series&#39;)&lt;/script&gt;"),
            std::string::npos);

  // The embedded JSON reads back to the same text.
  const json data = json::parse(ScriptText(html, "<script type=\"application/json\" id=\"napkin-data\">"));
  ASSERT_EQ(data["distributions"].size(), 1u);
  EXPECT_EQ(data["distributions"][0]["groups"][0]["name"], hostile_variant);
  EXPECT_EQ(data["distributions"][0]["groups"][1]["ci_low"], nullptr);
  EXPECT_EQ(EscapeHtml(R"(<a href="x">'&'</a>)"), "&lt;a href=&quot;x&quot;&gt;&#39;&amp;&#39;&lt;/a&gt;");
}

TEST(HtmlReport, WrittenAtomicallyAsRendered) {
  napkin::test_support::TempDir dir;
  const std::vector<ReportTest> tests = {
      MakeReportTest("v0001", "sled", "foam-a", "default", PulseSummary(), PulseKinematics())};
  WriteHtmlReport(Header(), {}, tests, dir / "report.html");
  EXPECT_EQ(napkin::test_support::ReadText(dir / "report.html"), RenderHtmlReport(Header(), {}, tests));
  EXPECT_THROW(WriteHtmlReport(Header(), {}, tests, dir / "missing" / "report.html"), InputError);
}

}  // namespace
}  // namespace napkin::formats

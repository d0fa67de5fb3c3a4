// A test's tables in the HTML report (docs/formats.md "HTML report") follow
// the summary-field table (engine/summary_fields.h): every numeric field of
// `napkin query criteria` and the solver residual is shown, the criteria in
// the contract's order.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "engine/summary_fields.h"
#include "formats/html_report.h"

namespace napkin::formats {
namespace {

// The section's summary tables (criteria, rotation, final pose) of a page of
// one test without charts.
std::string SummaryTables(const engine::TestSummary& summary) {
  ReportHeader header;
  header.catalogue = "napkin.db";
  header.napkin_version = "0.1.0";
  const std::vector<ReportTest> tests = {{"t1", "sled", "foam-a", "default", summary, {}, {}, {}}};
  const std::string html = RenderHtmlReport(header, {}, tests);
  const std::size_t begin = html.find("<div class=\"facts\">");
  const std::size_t end = html.find("<h3>Time histories</h3>");
  if (begin == std::string::npos || end == std::string::npos) return {};
  return html.substr(begin, end - begin);
}

// The <th> texts of the table of `table_class` in `html`, in order.
std::vector<std::string> RowLabels(const std::string& html, const std::string& table_class) {
  std::vector<std::string> labels;
  const std::size_t begin = html.find("<table class=\"" + table_class + "\">");
  const std::size_t end = html.find("</table>", begin);
  for (std::size_t at = html.find("<th>", begin); at < end; at = html.find("<th>", at)) {
    at += 4;
    labels.push_back(html.substr(at, html.find("</th>", at) - at));
  }
  return labels;
}

TEST(HtmlReportTables, CriteriaAreTheQueryCriteriaFieldsInContractOrder) {
  engine::TestSummary summary;
  summary.hic36 = {845.0, 0.0200, 0.0320};
  summary.hic_d = 0.75446 * 845.0 + 166.4;  // 803.9187
  const std::string tables = SummaryTables(summary);
  EXPECT_EQ(RowLabels(tables, "criteria"),
            (std::vector<std::string>{"HIC15", "HIC36", "HIC (no window limit)", "peak acceleration (g)",
                                      "a3ms (g)", "HIC(d)", "BrIC", "DAMAGE", "UBrIC",
                                      "P(AIS 3+) from HIC15 (NCAP)", "P(AIS 4+) from HIC36 (Prasad–Mertz)",
                                      "P(AIS 3+) from BrIC (Takhounts)", "P(AIS 4+) from BrIC (Takhounts)"}));
  EXPECT_NE(tables.find("<tr><th>HIC(d)</th><td class=\"num\">803.9</td></tr>"), std::string::npos) << tables;
  EXPECT_NE(tables.find("<tr><th>HIC36</th><td class=\"num\">845.0 <span class=\"note\">(20.00–32.00 "
                        "ms)</span></td></tr>"),
            std::string::npos)
      << tables;
}

// Each field of `query criteria`, `query risk` and the residual shows in the tables: set
// alone to a value of its own, it changes them.
TEST(HtmlReportTables, EverySummaryFieldIsShown) {
  const engine::TestSummary zero;
  const std::string zero_tables = SummaryTables(zero);
  ASSERT_FALSE(zero_tables.empty());
  std::vector<const engine::SummaryField*> fields = engine::SummaryFieldsOf(
      {engine::SummaryGroup::kHic, engine::SummaryGroup::kRotation, engine::SummaryGroup::kRisk});
  for (const engine::SummaryField* field : engine::SummaryFieldsOf({engine::SummaryGroup::kQuality}))
    fields.push_back(field);
  EXPECT_EQ(fields.size(), engine::SummaryFields().size());
  for (const engine::SummaryField* field : fields) {
    engine::TestSummary summary;
    field->Set(summary, 4.321);
    EXPECT_NE(SummaryTables(summary), zero_tables) << field->name << " is not in the report's tables";
  }
}

}  // namespace
}  // namespace napkin::formats

// The report page streams (formats/html_report.h HtmlReportWriter): it is
// the page of before, byte for byte (a golden file written by the renderer
// that held the whole page, tests/formats/report_sample.h), and the writer
// hands each test's section to its sink as the test is added, never the
// page at once, so its memory does not grow with the number of tests.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "formats/html_report.h"
#include "formats/report_assets.h"
#include "tests/formats/report_sample.h"
#include "tests/support/run_command.h"

namespace napkin::formats {
namespace {

namespace fs = std::filesystem;

const fs::path kGolden = fs::path(NAPKIN_SOURCE_DIR) / "tests" / "formats" / "golden" / "report_sample.html";

// `page` with each occurrence of `text` replaced by `placeholder`.
std::string Replaced(std::string page, std::string_view text, const std::string& placeholder) {
  for (std::size_t at = page.find(text); !text.empty() && at != std::string::npos;
       at = page.find(text, at + placeholder.size()))
    page.replace(at, text.size(), placeholder);
  return page;
}

// The page as the golden file keeps it: the embedded charting library
// (Debian's dygraphs, as installed) and the page's drawing script (which
// changes with its fixes) replaced by placeholders; napkin's markup and plot
// data stay.
std::string Comparable(std::string page) {
  const std::string_view script = DygraphsScript();
  const std::string_view stylesheet = DygraphsStylesheet();
  page = Replaced(std::move(page), script.substr(0, script.rfind("//# sourceMappingURL=")), "@DYGRAPHS_JS@");
  page = Replaced(std::move(page), stylesheet.substr(0, stylesheet.rfind("/*# sourceMappingURL=")),
                  "@DYGRAPHS_CSS@");
  const std::size_t last_script = page.rfind("<script>") + std::string("<script>").size();
  const std::size_t end = page.find("</script>", last_script);
  return page.replace(last_script, end - last_script, "@DRAW_SCRIPT@");
}

TEST(HtmlReportStream, PageIsByteIdenticalToTheOneRenderedWhole) {
  const std::vector<ReportTest> tests = report_sample::Tests();
  const std::vector<ReportComparison> comparisons = report_sample::Comparisons();
  std::string page;
  WriteHtmlReport(report_sample::Header(), comparisons, tests,
                  [&page](std::string_view text) { page += text; });
  const std::string comparable = Comparable(page);
  if (const char* update = std::getenv("NAPKIN_UPDATE_GOLDEN");
      update != nullptr && std::string(update) == "1")
    std::ofstream(kGolden, std::ios::binary) << comparable;
  ASSERT_TRUE(fs::exists(kGolden)) << kGolden << " is missing (NAPKIN_UPDATE_GOLDEN=1 writes it)";
  EXPECT_EQ(comparable, napkin::test_support::ReadText(kGolden));
  EXPECT_EQ(RenderHtmlReport(report_sample::Header(), comparisons, tests), page);
}

// A sink that records what it was given, and when.
struct RecordingSink {
  std::string page;
  std::size_t calls = 0;
  std::size_t largest = 0;
  void operator()(std::string_view text) {
    page += text;
    ++calls;
    largest = std::max(largest, text.size());
  }
};

TEST(HtmlReportStream, EachSectionReachesTheSinkWhenItsTestIsAdded) {
  const std::vector<ReportTest> sample = report_sample::Tests();
  constexpr std::size_t kTests = 60;
  std::vector<std::string> ids;
  for (std::size_t i = 0; i < kTests; ++i) ids.push_back("t" + std::to_string(i + 1));
  RecordingSink sink;
  const auto header = report_sample::Header();
  HtmlReportWriter writer([&sink](std::string_view text) { sink(text); }, header, ids, {});
  const std::size_t head = sink.page.size();
  EXPECT_NE(sink.page.find("<nav class=\"tests\">"), std::string::npos);  // the header is out
  std::size_t largest_section = 0;
  for (std::size_t i = 0; i < kTests; ++i) {
    ReportTest test = sample[i % sample.size()];
    test.test_id = ids[i];
    const std::size_t before = sink.page.size();
    writer.AddTest(test);
    // The section is in the sink before the next test exists.
    const std::string section = sink.page.substr(before);
    EXPECT_EQ(section.rfind("<section class=\"test\" id=\"test-" + std::to_string(i + 1) + "\">", 0), 0u)
        << i;
    EXPECT_EQ(section.size() - section.rfind("</section>\n"), std::string("</section>\n").size()) << i;
    largest_section = std::max(largest_section, section.size());
  }
  const std::size_t sections_end = sink.page.size();
  writer.Finish();
  EXPECT_GT(sink.page.size(), sections_end);
  EXPECT_EQ(sink.page.substr(sink.page.size() - 8), "</html>\n");

  // No piece is the page: each is at most a section, the embedded library or
  // a bounded block of the plot data, however many tests there are.
  const std::size_t bound = std::max({largest_section, DygraphsScript().size(), std::size_t{1} << 16});
  EXPECT_LE(sink.largest, bound);
  EXPECT_GT(sink.page.size(), 3 * bound);
  EXPECT_GT(head, 0u);

  // Every chart's data arrived, in page order.
  const std::string open = "<script type=\"application/json\" id=\"napkin-data\">";
  const std::size_t data_at = sink.page.find(open) + open.size();
  const auto data =
      nlohmann::json::parse(sink.page.substr(data_at, sink.page.find("</script>", data_at) - data_at));
  std::size_t charts = 0;
  for (std::size_t i = 0; i < kTests; ++i) charts += sample[i % sample.size()].charts.size();
  ASSERT_EQ(data["charts"].size(), charts);
  EXPECT_EQ(data["charts"][0]["id"], "chart-1-acc");
  EXPECT_EQ(data["charts"][charts - 1]["id"], "chart-" + std::to_string(kTests) + "-acc");
}

TEST(HtmlReportStream, TheTestsMustBeThoseTheHeaderNames) {
  const std::vector<ReportTest> sample = report_sample::Tests();
  const std::vector<std::string> ids = {"a"};
  std::string page;
  {
    HtmlReportWriter writer([&page](std::string_view text) { page += text; }, report_sample::Header(), ids,
                            {});
    EXPECT_THROW(writer.Finish(), std::logic_error);  // "a" missing
    writer.AddTest(sample[0]);
    EXPECT_THROW(writer.AddTest(sample[1]), std::logic_error);  // one too many
    writer.Finish();
  }
  EXPECT_EQ(page.substr(page.size() - 8), "</html>\n");
}

}  // namespace
}  // namespace napkin::formats

#pragma once
// The page of `napkin report`: one self-contained HTML file (docs/formats.md
// "HTML report") that opens offline in any browser. Its stylesheet and
// scripts (formats/report/), the charting library (dygraphs; all embedded at
// build time, formats/report_assets.h) and the plot data (JSON,
// nlohmann-json) are inside the file; nothing is loaded from a network or
// from beside it. Every user-supplied text (test ids, series and variant
// names, config names and settings, finding details) is escaped against HTML
// and script injection.
//
// The writer takes plain data and streams the page: the commands `report`
// and `demo` (cli/command_report.cpp, cli/demo_session.cpp) call
// app::WriteCatalogueReport (app/report_builder.cpp), which reads the
// catalogue one test at a time, turns it into a ReportTest with
// MakeReportTest (which keeps only the reduced traces) and hands it to an
// HtmlReportWriter, which writes its section through a sink at once, so the
// memory of a report does not grow with its tests.
#include <Eigen/Core>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "engine/kinematics.h"
#include "engine/summary.h"

namespace napkin::formats {

// At most this many points per plotted time history (engine/display_reduction.h).
inline constexpr Eigen::Index kReportMaxPoints = 2000;

// A processing config whose results the report shows.
struct ReportConfig {
  std::string name;           // e.g. "default"
  std::string hash;           // SHA-256 of the canonical JSON
  std::string settings_json;  // the canonical JSON
};

struct ReportHeader {
  std::string catalogue;       // the catalogue's path as given
  std::string napkin_version;  // napkin::Version() (common/version.h), e.g. "0.1.0+g1a2b3c4"
  std::string selection;       // what was asked for, e.g. "series sled" ("" = every test)
  std::vector<ReportConfig> configs;
};

// A shaded time window of a chart (HIC15, HIC36), its label written on the plot.
struct ReportWindow {
  std::string label;  // e.g. "HIC15 = 812"
  double t1_ms = 0.0;
  double t2_ms = 0.0;
};

// A band of a chart shaded between two of its traces (the ISO/TS 18571
// corridors about a test's curve), indexes into trace_labels.
struct ReportBand {
  std::size_t low = 0;
  std::size_t high = 0;
};

// A table of text under a heading, with notes (ratings, repeatability).
struct ReportTable {
  std::string heading;
  std::vector<std::string> columns;
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> notes;
};

// One time-history chart: traces over a shared time axis, reduced for display.
struct ReportChart {
  std::string key;      // "acc", "omega", "angles", "velocity": part of the chart's element id
  std::string title;    // e.g. "Resultant CG acceleration"
  std::string y_label;  // with its unit, e.g. "acceleration (g)"
  std::vector<std::string> trace_labels;
  std::vector<double> time_ms;
  std::vector<std::vector<double>> traces;  // one per label, each as long as time_ms
  std::vector<ReportWindow> windows;
  std::vector<ReportBand> bands;  // shaded, each between its two (dashed) traces
};

// One test's section of the report.
struct ReportTest {
  std::string test_id;
  std::optional<std::string> series;
  std::optional<std::string> variant;
  std::string config_name;  // the config of the result shown
  engine::TestSummary summary;
  std::vector<ReportChart> charts;
  std::vector<ReportTable> tables;         // after the charts: the test's ISO/TS 18571 ratings
  std::vector<ReportChart> rating_charts;  // under them: each rating against a model drawn
};

// The test's section: its summary, and its charts (resultant CG acceleration
// in g with the HIC15 and HIC36 windows; body angular velocity x, y, z and
// resultant; roll, pitch, yaw in degrees; CG velocity in the fixed frame),
// each reduced to at most `max_points` points by
// engine::PeakPreservingSamples, time in ms. A test without rotation
// (engine::HasRotation: an acceleration-only array) has the acceleration
// chart only.
ReportTest MakeReportTest(std::string test_id, std::optional<std::string> series,
                          std::optional<std::string> variant, std::string config_name,
                          engine::TestSummary summary, const engine::Kinematics& kinematics,
                          Eigen::Index max_points = kReportMaxPoints);

// One metric of a series compared across its variants: every test as a point,
// each group's mean with its 95 % confidence interval.
struct ReportDistribution {
  std::string metric;  // summary field name, e.g. "hic15"
  struct Group {
    std::string name;  // the variant
    std::vector<double> values;
    double mean = 0.0;
    std::optional<double> ci_low, ci_high;  // none when n < 2
  };
  std::vector<Group> groups;
};

// The verdict that opens a series' comparison (app/verdict.h): a short
// table and one sentence per variant against the baseline, as text.
struct ReportVerdict {
  std::string baseline;
  std::vector<std::string> columns;
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> sentences;
  std::vector<std::string> notes;
};

// One quantity of a series' tests laid over each other: every test's trace
// and each group's (variant's) mean - 1 sd and mean + 1 sd on a common time
// base (engine/overlay.h), reduced for display.
struct ReportOverlay {
  std::string key;                  // "acc", "omega": part of the chart's element id
  std::string title;                // e.g. "Resultant CG acceleration, every test"
  std::string y_label;              // with its unit
  std::vector<std::string> groups;  // the variants, in the comparison's order
  struct Trace {
    std::string label;  // a test id, or "<variant> mean − 1 sd" / "mean + 1 sd"
    std::size_t group = 0;
    enum class Kind { kTest, kLow, kHigh } kind = Kind::kTest;
  };
  std::vector<Trace> traces;
  std::vector<double> time_ms;
  std::vector<std::vector<double>> values;  // one per trace, each as long as time_ms; NaN: no sample
};

// `traces` (one column per trace, NaN where a trace has no sample) on the
// common time base `time_s`, reduced to at most `max_points` points by
// engine::PeakPreservingSamples (NaN counted as 0 for choosing the points:
// the quantities overlaid are resultants, never negative), time in ms.
ReportOverlay MakeReportOverlay(std::string key, std::string title, std::string y_label,
                                std::vector<std::string> groups, std::vector<ReportOverlay::Trace> traces,
                                const Eigen::VectorXd& time_s, const Eigen::MatrixXd& values,
                                Eigen::Index max_points = kReportMaxPoints);

// The verdict as a picture (docs/formats.md "HTML report"), drawn above its
// table: a forest plot of the changes against the baseline and, per limited
// criterion, a strip of every test's value against the limit's lines.
struct ReportForestRow {
  std::string label;                      // "HIC15 · foam-a"
  double ratio = 1.0;                     // to the baseline (geometric means)
  std::optional<double> ci_low, ci_high;  // its 95 % interval, none without one
  bool significant = false;               // p < 0.05
  bool equivalent = false;                // two one-sided tests show it within the margin
};
struct ReportForest {
  std::string baseline;
  double equivalence_pct = 10.0;  // the margin, shaded from 1 - m to 1 + m
  std::vector<ReportForestRow> rows;
};
// Every test's value of one criterion against one limit: its edges (a
// maximum, a scale's higher and lower performance limits, the bands' upper
// values, ascending) split the axis into classes, best first (`classes`
// names them: one more than the edges); each point is in the class of its
// outcome (for a scale's lower limit itself: no points).
struct ReportStrip {
  std::string title;                // "HIC15 against Euro NCAP v9.3 frontal head (HIII 50M)"
  std::string y_label;              // "HIC15"
  std::vector<std::string> groups;  // the variants, in the comparison's order
  struct Edge {
    std::string label;  // "higher performance limit 500"
    double value = 0.0;
  };
  std::vector<Edge> edges;
  std::vector<std::string>
      classes;  // "4 points", "0 to 4 points", "0 points"; "Good", ...; "meets", "exceeds"
  struct Point {
    std::size_t group = 0;
    std::string test_id;
    double value = 0.0;
    std::size_t category = 0;  // index into classes
  };
  std::vector<Point> points;
};
struct ReportVerdictPlots {
  std::optional<ReportForest> forest;  // none without a change to draw
  std::vector<ReportStrip> strips;
};

// The comparison of a series' variants (`napkin compare`): the verdict, the
// overlaid curves, its table, already formatted as text, footnotes, and the
// distribution plots.
struct ReportComparison {
  std::string series;
  ReportVerdict verdict;
  ReportVerdictPlots verdict_plots;
  std::vector<ReportTable> limit_tables;  // every test against each limit set, under the verdict
  std::vector<ReportOverlay> overlays;
  std::vector<std::string> overlay_notes;
  std::vector<std::string> columns;
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> notes;
  std::vector<ReportDistribution> distributions;
  std::vector<ReportTable> repeatability;  // per variant: each repeat against its mean (app/correlation.h)
};

// A chart as MakeReportTest makes them: `traces` (a column each) on
// `time_s`, reduced to at most `max_points` points, time in ms.
ReportChart MakeReportChart(std::string key, std::string title, std::string y_label,
                            std::vector<std::string> trace_labels, const Eigen::VectorXd& time_s,
                            const Eigen::MatrixXd& traces, Eigen::Index max_points = kReportMaxPoints);

// Where the page goes, piece by piece, in order: an AtomicFile
// (util/atomic_file.h), standard output, a string.
using HtmlSink = std::function<void(std::string_view)>;

// Writes the page through a sink while it is made: the head, the header (the
// test ids form its navigation) and the comparisons on construction, each
// test's section on AddTest, the charting library and the plot data on
// Finish. The plot data of every chart belong in one element after all
// sections (docs/formats.md "HTML report"); until Finish they wait in an
// unnamed temporary file (in TMPDIR, removed whatever happens), so the
// writer holds one test's section at a time, whatever the number of tests.
// The bytes are those of the page written at once. Throws InputError when
// the temporary file cannot be written (a full disk), and what the sink
// throws.
class HtmlReportWriter {
 public:
  HtmlReportWriter(HtmlSink sink, const ReportHeader& header, std::span<const std::string> test_ids,
                   std::span<const ReportComparison> comparisons);
  ~HtmlReportWriter();
  HtmlReportWriter(const HtmlReportWriter&) = delete;
  HtmlReportWriter& operator=(const HtmlReportWriter&) = delete;

  // The next test, in the order of `test_ids` (throws std::logic_error beyond them).
  void AddTest(const ReportTest& test);
  // Ends the page (throws std::logic_error unless every test was added).
  void Finish();

 private:
  void SpoolChartData(std::string_view text);

  HtmlSink sink_;
  std::size_t test_count_ = 0;
  std::size_t tests_added_ = 0;
  std::size_t charts_spooled_ = 0;
  std::string distributions_json_;
  std::string overlays_json_;
  std::string verdict_plots_json_;
  std::FILE* chart_data_ = nullptr;  // the spooled plot data, once there are any
  bool finished_ = false;
};

// The whole page of `tests` through `sink` (HtmlReportWriter).
void WriteHtmlReport(const ReportHeader& header, std::span<const ReportComparison> comparisons,
                     std::span<const ReportTest> tests, const HtmlSink& sink);

// The whole page as a string (small reports and tests).
std::string RenderHtmlReport(const ReportHeader& header, std::span<const ReportComparison> comparisons,
                             std::span<const ReportTest> tests);

// Writes the page atomically (util/atomic_file.h). Throws
// InputError naming `path` when it cannot be written.
void WriteHtmlReport(const ReportHeader& header, std::span<const ReportComparison> comparisons,
                     std::span<const ReportTest> tests, const std::filesystem::path& path);

// `text` with & < > " ' replaced by character references (safe in element
// content and in quoted attribute values).
std::string EscapeHtml(std::string_view text);

}  // namespace napkin::formats

#pragma once
// `napkin report`: one self-contained HTML file (docs/formats.md "HTML
// report") that opens offline in any browser. The charting library
// (dygraphs, formats/report_assets.h) and the plot data (JSON, nlohmann-json)
// are inside the file; nothing is loaded from a network or from beside it.
// Every user-supplied text (test ids, series and variant names, config names
// and settings, finding details) is escaped against HTML and script injection.
//
// The writer takes plain data: the command (cli/command_report.cpp) reads the
// catalogue and turns each test into a ReportTest with MakeReportTest, which
// keeps only the reduced traces, so a report of hundreds of tests never holds
// their full-resolution kinematics at once.
#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
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

// One time-history chart: traces over a shared time axis, reduced for display.
struct ReportChart {
  std::string key;      // "acc", "omega", "angles", "velocity": part of the chart's element id
  std::string title;    // e.g. "Resultant CG acceleration"
  std::string y_label;  // with its unit, e.g. "acceleration (g)"
  std::vector<std::string> trace_labels;
  std::vector<double> time_ms;
  std::vector<std::vector<double>> traces;  // one per label, each as long as time_ms
  std::vector<ReportWindow> windows;
};

// One test's section of the report.
struct ReportTest {
  std::string test_id;
  std::optional<std::string> series;
  std::optional<std::string> variant;
  std::string config_name;  // the config of the result shown
  engine::TestSummary summary;
  std::vector<ReportChart> charts;
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

// The comparison of a series' variants (`napkin compare`): its table, already
// formatted as text, footnotes, and the distribution plots.
struct ReportComparison {
  std::string series;
  std::vector<std::string> columns;
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> notes;
  std::vector<ReportDistribution> distributions;
};

// The whole page.
std::string RenderHtmlReport(const ReportHeader& header, std::span<const ReportComparison> comparisons,
                             std::span<const ReportTest> tests);

// Writes RenderHtmlReport atomically (formats/atomic_file.h). Throws
// InputError naming `path` when it cannot be written.
void WriteHtmlReport(const ReportHeader& header, std::span<const ReportComparison> comparisons,
                     std::span<const ReportTest> tests, const std::filesystem::path& path);

// `text` with & < > " ' replaced by character references (safe in element
// content and in quoted attribute values).
std::string EscapeHtml(std::string_view text);

}  // namespace napkin::formats

#include "formats/html_report.h"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <utility>

#include "common/error.h"
#include "engine/display_reduction.h"
#include "engine/summary_fields.h"
#include "engine/units.h"
#include "engine/vocabulary.h"
#include "formats/report_assets.h"
#include "formats/report_verdict_plots.h"
#include "util/atomic_file.h"
#include "util/temporary_directory.h"
#include "util/text.h"

namespace napkin::formats {
namespace {

using nlohmann::json;

// Plotted values keep 6 significant digits: far below a pixel, and the
// embedded data stays small. Tables show the stored values.
double ForDisplay(double value) {
  if (!std::isfinite(value)) return value;  // null in the JSON: a gap in the trace
  return util::ParseDouble(util::FormatNumber(value, 6)).value_or(value);
}

// A number for a table: about four significant digits, no exponent for the
// magnitudes of head kinematics.
std::string Display(double value) {
  if (!std::isfinite(value)) return "—";
  if (value == 0.0) return "0";
  const double magnitude = std::abs(value);
  if (magnitude < 1e-3) return util::FormatNumber(value, 3);
  const int decimals = std::clamp(3 - static_cast<int>(std::floor(std::log10(magnitude))), 0, 6);
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", decimals, value);
  return text;
}

std::string Fixed(double value, int decimals) {
  if (!std::isfinite(value)) return "—";
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", decimals, value);
  return text;
}

ReportChart MakeChart(std::string key, std::string title, std::string y_label,
                      std::vector<std::string> trace_labels, const Eigen::VectorXd& time_s,
                      const Eigen::MatrixXd& traces, Eigen::Index max_points) {
  ReportChart chart{
      std::move(key), std::move(title), std::move(y_label), std::move(trace_labels), {}, {}, {}, {}};
  const std::vector<Eigen::Index> kept = engine::PeakPreservingSamples(traces, max_points);
  chart.time_ms.reserve(kept.size());
  for (const Eigen::Index row : kept) chart.time_ms.push_back(ForDisplay(time_s(row) * 1000.0));
  chart.traces.resize(static_cast<std::size_t>(traces.cols()));
  for (Eigen::Index trace = 0; trace < traces.cols(); ++trace) {
    std::vector<double>& values = chart.traces[static_cast<std::size_t>(trace)];
    values.reserve(kept.size());
    for (const Eigen::Index row : kept) values.push_back(ForDisplay(traces(row, trace)));
  }
  return chart;
}

// Components and their resultant (last column).
Eigen::MatrixXd WithResultant(const engine::Series3& components, double scale = 1.0) {
  Eigen::MatrixXd traces(components.rows(), 4);
  traces.leftCols(3) = components * scale;
  traces.col(3) = traces.leftCols(3).rowwise().norm();
  return traces;
}

// ---- script elements

// Text between <script> and </script> must not close the element: in JSON
// '<', '>' and '&' occur only inside strings, where \u escapes mean the same.
std::string JsonForScript(const json& value) {
  const std::string text = value.dump(-1, ' ', false, json::error_handler_t::replace);
  std::string out;
  out.reserve(text.size() + text.size() / 64);
  for (const char c : text) {
    if (c == '<')
      out += "\\u003c";
    else if (c == '>')
      out += "\\u003e";
    else if (c == '&')
      out += "\\u0026";
    else
      out += c;
  }
  return out;
}

// The embedded file without its source-map comment, which names a file that
// is not beside the report.
std::string_view WithoutSourceMap(std::string_view text, std::string_view marker) {
  const std::size_t at = text.rfind(marker);
  return at == std::string_view::npos ? text : text.substr(0, at);
}

// ---- markup

// Text of the page. User-supplied text (test ids, names, settings, finding
// details) becomes Html only through Text(), the one place it is escaped;
// Markup() is for napkin's own tags, words and numbers.
struct Html {
  std::string text;
};

Html Text(std::string_view text) { return {EscapeHtml(text)}; }
Html Markup(std::string markup) { return {std::move(markup)}; }

Html& operator+=(Html& html, const Html& more) {
  html.text += more.text;
  return html;
}
Html operator+(Html html, const Html& more) { return html += more; }

// <tag attributes>content</tag>; `open` is the tag with its attributes.
Html Element(std::string_view open, const Html& content) {
  const std::string_view tag = open.substr(0, open.find(' '));
  std::string element = "<";
  element.append(open).append(">").append(content.text).append("</").append(tag).append(">");
  return Markup(element);
}

Html TextOrDash(const std::optional<std::string>& text) { return text ? Text(*text) : Markup("—"); }

// A row of cells (each an Element "td ..." or "th ...") and its line end.
Html Row(std::initializer_list<Html> cells) {
  Html row = Markup("<tr>");
  for (const Html& cell : cells) row += cell;
  return row + Markup("</tr>\n");
}

// A row of texts, each in a `cell` element ("th" or "td").
template <typename Texts>
Html TextRow(std::string_view cell, const Texts& texts) {
  Html row = Markup("<tr>");
  for (const std::string_view text : texts) row += Element(cell, Text(text));
  return row + Markup("</tr>\n");
}

// A labelled value: the row of the header's and a section's small tables.
Html LabelledRow(std::string_view label, const Html& value, bool numeric = true) {
  return Row({Element("th", Text(label)), Element(numeric ? "td class=\"num\"" : "td", value)});
}

// A chart's place: dygraphs draws into the element `id`, its legend below.
Html Figure(const std::string& id, std::string_view caption) {
  return Markup("<figure>") + Element("figcaption", Text(caption)) +
         Markup("<div class=\"chart\" id=\"" + id + "\"></div><div class=\"legend\"></div></figure>\n");
}

// A ReportTable: its heading, the table (scrolling sideways when wide) and its notes.
Html TableBlock(const ReportTable& table) {
  Html rows = Markup("\n") + TextRow("th", table.columns);
  for (const std::vector<std::string>& row : table.rows) rows += TextRow("td", row);
  Html html = Element("h3", Text(table.heading)) + Markup("\n") +
              Element("div class=\"wide\"", Element("table class=\"rating\"", rows)) + Markup("\n");
  for (const std::string& note : table.notes) html += Element("p class=\"note\"", Text(note)) + Markup("\n");
  return html;
}

// ---- the header

std::string PrettySettings(const std::string& settings_json) {
  const json settings = json::parse(settings_json, nullptr, /*allow_exceptions=*/false);
  if (settings.is_discarded()) return settings_json;
  return settings.dump(2, ' ', false, json::error_handler_t::replace);
}

Html ConfigCell(const ReportConfig& config) {
  return Element("strong", Text(config.name)) + Markup(" ") +
         Element("span class=\"note\"", Markup("SHA-256 ") + Element("code", Text(config.hash))) +
         Markup("\n") +
         Element("details", Element("summary", Markup("settings")) +
                                Element("pre", Text(PrettySettings(config.settings_json))));
}

Html Navigation(std::span<const std::string> test_ids) {
  if (test_ids.empty()) return {};
  Html nav = Element("strong", Markup("Tests:"));
  for (std::size_t i = 0; i < test_ids.size(); ++i)
    nav += Markup(" ") + Element("a href=\"#test-" + std::to_string(i + 1) + "\"", Text(test_ids[i]));
  return Element("nav class=\"tests\"", nav) + Markup("\n");
}

Html PageHeader(const ReportHeader& header, std::span<const std::string> test_ids) {
  Html meta = Markup("\n");
  meta += LabelledRow("catalogue", Element("code", Text(header.catalogue)), false);
  meta += LabelledRow("napkin version", Text(header.napkin_version), false);
  meta += LabelledRow("selection", header.selection.empty() ? Markup("every test") : Text(header.selection),
                      false);
  meta += LabelledRow("tests", Markup(std::to_string(test_ids.size())), false);
  for (const ReportConfig& config : header.configs)
    meta += LabelledRow("processing config", ConfigCell(config), false);
  const Html hint = Markup(
      "Time histories: drag across a plot to zoom in, double-click to zoom out. Traces are reduced for "
      "display to at most " +
      std::to_string(kReportMaxPoints) +
      " points per plot keeping every bucket's minimum and maximum, so no peak is lost; the full-resolution "
      "data stays in the catalogue (<code>napkin export</code>).");
  return Element("header class=\"report\"",
                 Markup("\n") +
                     Element("h1", Element("span class=\"product\"", Markup("napkin")) +
                                       Markup(" head-kinematics report")) +
                     Markup("\n") + Element("table class=\"meta\"", meta) + Markup("\n") +
                     Element("p class=\"hint\"", hint) + Markup("\n") + Navigation(test_ids)) +
         Markup("\n");
}

// ---- a series' comparison

using TraceKind = ReportOverlay::Trace::Kind;  // its names as report.js reads them:
constexpr std::array<engine::NamedValue<TraceKind>, 3> kTraceKindNames{
    {{TraceKind::kTest, "test"}, {TraceKind::kLow, "low"}, {TraceKind::kHigh, "high"}}};

// The verdict: its table and one sentence per variant (app/verdict.h).
Html VerdictBlock(const ReportVerdict& verdict) {
  if (verdict.sentences.empty()) return {};
  Html table = Markup("\n") + TextRow("th", verdict.columns);
  for (const std::vector<std::string>& row : verdict.rows) table += TextRow("td", row);
  Html sentences = Markup("\n");
  for (const std::string& sentence : verdict.sentences)
    sentences += Element("li", Text(sentence)) + Markup("\n");
  Html block = Markup("\n") + Element("h3", Markup("Verdict against ") + Text(verdict.baseline)) +
               Markup("\n") + Element("table class=\"verdict\"", table) + Markup("\n") +
               Element("ul class=\"verdict\"", sentences) + Markup("\n");
  for (const std::string& note : verdict.notes)
    block += Element("p class=\"note\"", Text(note)) + Markup("\n");
  return Element("div class=\"verdict\"", block) + Markup("\n");
}

// The overlaid curves; their data are appended to `overlays`.
Html OverlayFigures(json& overlays, const ReportComparison& comparison, std::size_t index) {
  if (comparison.overlays.empty()) return {};
  Html figures = Markup("\n");
  for (const ReportOverlay& overlay : comparison.overlays) {
    const std::string id = "overlay-" + std::to_string(index + 1) + "-" + overlay.key;
    figures += Figure(id, overlay.title);
    json labels = json::array();
    json groups_of = json::array();
    json kinds = json::array();
    for (const ReportOverlay::Trace& trace : overlay.traces) {
      labels.push_back(trace.label);
      groups_of.push_back(trace.group);
      kinds.push_back(engine::NameIn(kTraceKindNames, trace.kind));
    }
    overlays.push_back({{"id", id},
                        {"ylabel", overlay.y_label},
                        {"groups", overlay.groups},
                        {"labels", std::move(labels)},
                        {"group", std::move(groups_of)},
                        {"kind", std::move(kinds)},
                        {"t", overlay.time_ms},
                        {"y", overlay.values}});
  }
  Html html = Element("h3", Markup("Time histories, every test")) + Markup("\n") +
              Element("div class=\"charts overlays\"", figures) + Markup("\n");
  for (const std::string& note : comparison.overlay_notes)
    html += Element("p class=\"note\"", Text(note)) + Markup("\n");
  return html;
}

// Its section; the data of its overlaid curves and distribution plots are
// appended to `overlays` and `distributions`.
Html ComparisonSection(json& overlays, json& distributions, json& verdict_plots,
                       const ReportComparison& comparison, std::size_t index) {
  Html table = Markup("\n") + TextRow("th", comparison.columns);
  for (const std::vector<std::string>& row : comparison.rows) table += TextRow("td", row);
  Html repeatability;
  for (const ReportTable& variant : comparison.repeatability) repeatability += TableBlock(variant);
  Html limit_tables;  // every test against each limit set
  for (const ReportTable& limits : comparison.limit_tables) limit_tables += TableBlock(limits);
  Html section = Markup("\n") +
                 Element("h2", Markup("Series ") + Text(comparison.series) + Markup(": variants compared")) +
                 Markup("\n") + VerdictBlock(comparison.verdict) +
                 // The verdict as a picture, under its sentences and above every table of the section.
                 Markup(VerdictPlotsMarkup(comparison.verdict_plots, index, verdict_plots)) + limit_tables +
                 OverlayFigures(overlays, comparison, index) + repeatability +
                 Element("h3", Markup("Every metric")) + Markup("\n") +
                 // Scrolls sideways where its columns (compare's contract) are wider than the page.
                 Element("div class=\"wide\"", Element("table class=\"compare\"", table)) + Markup("\n");
  for (const std::string& note : comparison.notes)
    section += Element("p class=\"note\"", Text(note)) + Markup("\n");
  if (!comparison.distributions.empty()) {
    Html figures = Markup("\n");
    for (std::size_t m = 0; m < comparison.distributions.size(); ++m) {
      const ReportDistribution& distribution = comparison.distributions[m];
      const std::string id = "dist-" + std::to_string(index + 1) + "-" + std::to_string(m + 1);
      figures += Figure(id, distribution.metric + ": every test, mean and 95 % CI per variant");
      json groups = json::array();
      for (const ReportDistribution::Group& group : distribution.groups) {
        json values = json::array();
        for (const double value : group.values) values.push_back(ForDisplay(value));
        groups.push_back({{"name", group.name},
                          {"values", std::move(values)},
                          {"mean", group.mean},
                          {"ci_low", group.ci_low ? json(*group.ci_low) : json(nullptr)},
                          {"ci_high", group.ci_high ? json(*group.ci_high) : json(nullptr)}});
      }
      distributions.push_back({{"id", id}, {"ylabel", distribution.metric}, {"groups", std::move(groups)}});
    }
    section += Element("div class=\"charts\"", figures) + Markup("\n");
  }
  return Element("section class=\"comparison\"", section) + Markup("\n");
}

// ---- a test's summary tables

const engine::SummaryField& Field(std::string_view name) {
  const engine::SummaryField* field = engine::FindSummaryField(name);
  if (field == nullptr) throw std::logic_error("html report: no summary field '" + std::string(name) + "'");
  return *field;
}

// A row of the rotation or final-pose table: summary fields shown together,
// comma-separated, with about four significant digits (decimals < 0) or a
// fixed number of decimals, times `scale` (the unit of the label).
struct FieldRow {
  std::string_view label;
  std::array<std::string_view, 4> fields;  // engine/summary_fields.h names; unused ones empty
  int decimals = -1;
  double scale = 1.0;
};

constexpr FieldRow kRotationRows[] = {
    {"peak |ω| x, y, z (rad/s)", {"peak_omega_x_radps", "peak_omega_y_radps", "peak_omega_z_radps"}},
    {"peak ω resultant (rad/s)", {"peak_omega_radps"}},
    {"peak α resultant (rad/s²)", {"peak_alpha_radps2"}},
    {"max rotation (deg)", {"max_rotation_deg"}},
    {"max residual (m/s²)", {"max_residual_mps2"}},
};

constexpr FieldRow kPoseRows[] = {
    {"quaternion w, x, y, z", {"final_quat_w", "final_quat_x", "final_quat_y", "final_quat_z"}, 5},
    {"roll, pitch, yaw (deg)", {"final_roll_deg", "final_pitch_deg", "final_yaw_deg"}, 2},
    {"position x, y, z (mm)", {"final_pos_x_m", "final_pos_y_m", "final_pos_z_m"}, 1, 1000.0},
};

Html FieldRowHtml(const FieldRow& row, const engine::TestSummary& summary) {
  std::string values;
  for (const std::string_view name : row.fields) {
    if (name.empty()) break;
    const double value = Field(name).Get(summary) * row.scale;
    values += (values.empty() ? "" : ", ") + (row.decimals < 0 ? Display(value) : Fixed(value, row.decimals));
  }
  return LabelledRow(row.label, Markup(values));
}

Html FieldTable(std::string_view table_class, std::span<const FieldRow> rows,
                const engine::TestSummary& summary) {
  Html html = Markup("\n");
  for (const FieldRow& row : rows) html += FieldRowHtml(row, summary);
  return Element("table class=\"" + std::string(table_class) + "\"", html);
}

bool InFieldRows(std::string_view name, std::span<const FieldRow> rows) {
  for (const FieldRow& row : rows)
    if (std::find(row.fields.begin(), row.fields.end(), name) != row.fields.end()) return true;
  return false;
}

// A HIC window's start or end (its HIC's cell shows it).
bool IsWindowBound(std::string_view name) {
  return (name.ends_with("_t1_s") || name.ends_with("_t2_s")) &&
         engine::FindSummaryField(name.substr(0, name.size() - 5)) != nullptr;
}

// The criteria table: every field of `napkin query criteria` and `napkin
// query risk` (engine::SummaryFieldsOf, in its order) that the rotation and
// final-pose tables do not show, a HIC with its window: "812.3 (20.50–31.50 ms)".
Html CriteriaTable(const engine::TestSummary& summary) {
  Html rows = Markup("\n");
  for (const engine::SummaryField* field : engine::SummaryFieldsOf(
           {engine::SummaryGroup::kHic, engine::SummaryGroup::kRotation, engine::SummaryGroup::kRisk})) {
    const std::string_view name = field->name;
    if (IsWindowBound(name) || InFieldRows(name, kRotationRows) || InFieldRows(name, kPoseRows)) continue;
    const std::string label = engine::FieldTableLabel(*field);  // "peak acceleration (g)"
    Html value = Markup(Display(field->Get(summary)));
    const engine::SummaryField* t1 = engine::FindSummaryField(std::string(name) + "_t1_s");
    const engine::SummaryField* t2 = engine::FindSummaryField(std::string(name) + "_t2_s");
    if (t1 != nullptr && t2 != nullptr)
      value += Markup(" ") + Element("span class=\"note\"",
                                     Markup(std::string("(").append(Fixed(t1->Get(summary) * 1000.0, 2)) +
                                            "–" + Fixed(t2->Get(summary) * 1000.0, 2) + " ms)"));
    rows += LabelledRow(label, value);
  }
  return Element("table class=\"criteria\"", rows);
}

// ---- a test's section

constexpr std::string_view kFindingColumns[] = {"severity", "check", "channel", "detail"};
constexpr std::string_view kConditioningColumns[] = {"channel", "filter", "bias removed", "bias window (ms)",
                                                     "time shift (ms)"};

Html FindingsTable(const std::vector<engine::Finding>& findings) {
  if (findings.empty())
    return Element("p class=\"note\"", Markup("No findings: every check passed.")) + Markup("\n");
  Html rows = Markup("\n") + TextRow("th", kFindingColumns);
  for (const engine::Finding& finding : findings) {
    const std::string severity = engine::NameOf(finding.severity);
    rows += Row({Element("td class=\"severity-" + severity + "\"", Markup(severity)),
                 Element("td", Text(finding.check)), Element("td", TextOrDash(finding.channel)),
                 Element("td", Text(finding.detail))});
  }
  return Element("table class=\"findings\"", rows) + Markup("\n");
}

// What conditioning did to each channel (docs/formats.md "Conditioning record").
Html ConditioningTable(const std::vector<engine::ChannelConditioning>& conditioning) {
  if (conditioning.empty()) return {};
  Html rows = Markup("\n") + TextRow("th", kConditioningColumns);
  for (const engine::ChannelConditioning& record : conditioning) {
    const std::string window = record.bias_window_start_s && record.bias_window_end_s
                                   ? Display(*record.bias_window_start_s * 1000.0) + " to " +
                                         Display(*record.bias_window_end_s * 1000.0)
                                   : std::string("none");
    rows += Row({Element("td", Text(record.channel)), Element("td", Text(engine::FilterDescription(record))),
                 Element("td", Markup(Display(record.bias_removed))), Element("td", Markup(window)),
                 Element("td", Markup(Display(record.time_shift_s * 1000.0)))});
  }
  return Element("h3", Markup("Conditioning")) + Markup("\n") +
         Element("table class=\"conditioning\"", rows) + Markup("\n");
}

// The mark of a salvaged result (docs/algorithms.md "Faulty channels"):
// a badge in the test's heading naming the mode and the channels.
Html SalvageBadge(const engine::TestSummary& summary) {
  if (!summary.salvage) return {};
  std::string channels;
  for (const engine::SalvagedChannel& channel : summary.salvage->channels)
    channels += (channels.empty() ? "" : ", ") + channel.channel + " " + engine::NameOf(channel.action);
  return Element(
      "span class=\"badge salvaged\" title=\"the result comes from salvaged channels\"",
      Markup("salvaged (") + Text(summary.salvage->mode) + Markup(": ") + Text(channels) + Markup(")"));
}

// A facts column: its heading and table.
Html Facts(std::string_view heading, const Html& table) {
  return Element("div", Element("h3", Markup(std::string(heading))) + table) + Markup("\n");
}

// The test's section; its charts' data are appended to `charts`.
Html TestSection(json& charts, const ReportTest& test, std::size_t index) {
  const engine::TestSummary& s = test.summary;
  const Html heading =
      Element("h2", Markup("Test ") + Text(test.test_id) +
                        Element("span class=\"tag\"", Markup("series ") + TextOrDash(test.series) +
                                                          Markup(" · variant ") + TextOrDash(test.variant) +
                                                          Markup(" · config ") + Text(test.config_name)) +
                        SalvageBadge(s));
  const Html facts = Markup("\n") + Facts("Injury criteria", CriteriaTable(s)) +
                     Facts("Rotation", FieldTable("rotation", kRotationRows, s)) +
                     Facts("Final pose", FieldTable("pose", kPoseRows, s));
  // Each chart's figure; its data appended to `charts`.
  const auto chart_figures = [&](const std::vector<ReportChart>& shown) {
    Html figures = Markup("\n");
    for (const ReportChart& chart : shown) {
      const std::string id = "chart-" + std::to_string(index + 1) + "-" + chart.key;
      figures += Figure(id, chart.title);
      json windows = json::array();
      for (const ReportWindow& window : chart.windows)
        windows.push_back({{"label", window.label}, {"t1", window.t1_ms}, {"t2", window.t2_ms}});
      json data = {{"id", id},           {"ylabel", chart.y_label}, {"labels", chart.trace_labels},
                   {"t", chart.time_ms}, {"y", chart.traces},       {"windows", std::move(windows)}};
      // Only a rating's chart has bands: other charts' data stay as they were.
      if (!chart.bands.empty()) {
        json bands = json::array();
        for (const ReportBand& band : chart.bands) bands.push_back({band.low, band.high});
        data["bands"] = std::move(bands);
      }
      charts.push_back(std::move(data));
    }
    return figures;
  };
  const Html figures = chart_figures(test.charts);
  Html ratings;
  for (const ReportTable& table : test.tables) ratings += TableBlock(table);
  if (!test.rating_charts.empty())
    ratings += Element("div class=\"charts\"", chart_figures(test.rating_charts)) + Markup("\n");
  const Html section = Markup("\n") + heading + Markup("\n") + Element("div class=\"facts\"", facts) +
                       Markup("\n") + Element("h3", Markup("Time histories")) + Markup("\n") +
                       Element("div class=\"charts\"", figures) + Markup("\n") + ratings +
                       Element("h3", Markup("Screening findings")) + Markup("\n") +
                       FindingsTable(s.findings) + ConditioningTable(s.conditioning);
  return Element("section class=\"test\" id=\"test-" + std::to_string(index + 1) + "\"", section) +
         Markup("\n");
}

}  // namespace

ReportTest MakeReportTest(std::string test_id, std::optional<std::string> series,
                          std::optional<std::string> variant, std::string config_name,
                          engine::TestSummary summary, const engine::Kinematics& kinematics,
                          Eigen::Index max_points) {
  ReportTest test{std::move(test_id),
                  std::move(series),
                  std::move(variant),
                  std::move(config_name),
                  std::move(summary),
                  {},
                  {},
                  {}};
  const Eigen::VectorXd& t = kinematics.time_s;

  // An acceleration-only test (engine::HasRotation) has its CG acceleration
  // in body axes (the same resultant) and no rotation charts.
  const bool rotation = engine::HasRotation(kinematics);
  ReportChart acc =
      MakeChart("acc", "Resultant CG acceleration", "acceleration (g)", {"resultant"}, t,
                rotation ? Eigen::VectorXd(kinematics.acc_fixed.rowwise().norm() / engine::kStandardGravity)
                         : Eigen::VectorXd(kinematics.acc_body.rowwise().norm() / engine::kStandardGravity),
                max_points);
  const std::pair<const char*, const engine::HicWindow*> hic_windows[] = {{"HIC15", &test.summary.hic15},
                                                                          {"HIC36", &test.summary.hic36}};
  for (const auto& [name, window] : hic_windows) {
    if (!(window->t2_s > window->t1_s)) continue;  // no window with a positive integral
    acc.windows.push_back(
        {std::string(name) + " = " + Fixed(window->value, 0), window->t1_s * 1000.0, window->t2_s * 1000.0});
  }
  test.charts.push_back(std::move(acc));
  if (!rotation) return test;
  test.charts.push_back(MakeChart("omega", "Angular velocity, head axes", "angular velocity (rad/s)",
                                  {"x", "y", "z", "resultant"}, t, WithResultant(kinematics.omega_body),
                                  max_points));
  test.charts.push_back(MakeChart("angles", "Roll, pitch and yaw", "angle (deg)", {"roll", "pitch", "yaw"}, t,
                                  kinematics.roll_pitch_yaw_rad * engine::kDegPerRad, max_points));
  test.charts.push_back(MakeChart("velocity", "CG velocity, fixed frame", "velocity (m/s)",
                                  {"x", "y", "z", "resultant"}, t, WithResultant(kinematics.vel_fixed),
                                  max_points));
  return test;
}

ReportChart MakeReportChart(std::string key, std::string title, std::string y_label,
                            std::vector<std::string> trace_labels, const Eigen::VectorXd& time_s,
                            const Eigen::MatrixXd& traces, Eigen::Index max_points) {
  return MakeChart(std::move(key), std::move(title), std::move(y_label), std::move(trace_labels), time_s,
                   traces, max_points);
}

ReportOverlay MakeReportOverlay(std::string key, std::string title, std::string y_label,
                                std::vector<std::string> groups, std::vector<ReportOverlay::Trace> traces,
                                const Eigen::VectorXd& time_s, const Eigen::MatrixXd& values,
                                Eigen::Index max_points) {
  ReportOverlay overlay{
      std::move(key), std::move(title), std::move(y_label), std::move(groups), std::move(traces), {}, {}};
  const Eigen::MatrixXd for_choosing = values.unaryExpr([](double v) { return std::isfinite(v) ? v : 0.0; });
  // At least one bucket, however many traces (a series of hundreds of tests).
  const std::vector<Eigen::Index> kept =
      engine::PeakPreservingSamples(for_choosing, std::max(max_points, 2 * values.cols() + 2));
  overlay.time_ms.reserve(kept.size());
  for (const Eigen::Index row : kept) overlay.time_ms.push_back(ForDisplay(time_s(row) * 1000.0));
  overlay.values.resize(static_cast<std::size_t>(values.cols()));
  for (Eigen::Index trace = 0; trace < values.cols(); ++trace) {
    std::vector<double>& out = overlay.values[static_cast<std::size_t>(trace)];
    out.reserve(kept.size());
    for (const Eigen::Index row : kept) out.push_back(ForDisplay(values(row, trace)));
  }
  return overlay;
}

// ---- the page, piece by piece

HtmlReportWriter::HtmlReportWriter(HtmlSink sink, const ReportHeader& header,
                                   std::span<const std::string> test_ids,
                                   std::span<const ReportComparison> comparisons)
    : sink_(std::move(sink)), test_count_(test_ids.size()) {
  // The error catcher runs first, so any later script error is written into
  // the page (the headless-browser test looks for it).
  sink_(
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<meta name=\"generator\" "
      "content=\"napkin " +
      Text(header.napkin_version).text + "\">\n" +
      Element("title", Markup("napkin report: ") + Text(header.catalogue)).text + "\n<script>\n");
  sink_(ReportErrorScript());
  sink_("</script>\n<style>\n");
  sink_(WithoutSourceMap(DygraphsStylesheet(), "/*# sourceMappingURL="));
  sink_("\n</style>\n<style>\n");
  sink_(ReportStylesheet());
  sink_("</style>\n</head>\n<body>\n<main>\n");
  sink_(PageHeader(header, test_ids).text);
  json overlays = json::array();
  json distributions = json::array();
  json verdict_plots = json::array();
  for (std::size_t i = 0; i < comparisons.size(); ++i)
    sink_(ComparisonSection(overlays, distributions, verdict_plots, comparisons[i], i).text);
  distributions_json_ = JsonForScript(distributions);
  overlays_json_ = JsonForScript(overlays);
  verdict_plots_json_ = JsonForScript(verdict_plots);
}

HtmlReportWriter::~HtmlReportWriter() {
  if (chart_data_ != nullptr) std::fclose(chart_data_);
}

void HtmlReportWriter::AddTest(const ReportTest& test) {
  if (finished_ || tests_added_ == test_count_)
    throw std::logic_error("HtmlReportWriter: more tests added than the header names");
  json charts = json::array();
  sink_(TestSection(charts, test, tests_added_).text);
  // The plot data go to the page's one data element after every section:
  // kept in a temporary file until then (one test's charts in memory).
  for (const json& chart : charts) {
    SpoolChartData(charts_spooled_ == 0 ? "" : ",");
    SpoolChartData(JsonForScript(chart));
    ++charts_spooled_;
  }
  ++tests_added_;
}

void HtmlReportWriter::Finish() {
  if (finished_ || tests_added_ != test_count_)
    throw std::logic_error("HtmlReportWriter: Finish without every test the header names");
  finished_ = true;
  std::string html;
  if (test_count_ == 0) html += "<p>No test with results matches the selection.</p>\n";
  html += "</main>\n<script>";
  sink_(html);
  sink_(WithoutSourceMap(DygraphsScript(), "//# sourceMappingURL="));
  // JsonForScript of {"charts": [...], "distributions": [...], "overlays": [...], "verdict_plots": [...]}
  // (keys in nlohmann's order), one chart at a time.
  sink_("</script>\n<script type=\"application/json\" id=\"napkin-data\">{\"charts\":[");
  if (chart_data_ != nullptr) {
    if (std::fflush(chart_data_) != 0 || std::fseek(chart_data_, 0, SEEK_SET) != 0)
      throw InputError(
          "cannot read back the report's temporary chart data: " + std::string(std::strerror(errno)) + ".");
    std::vector<char> buffer(1 << 16);
    for (;;) {
      const std::size_t read = std::fread(buffer.data(), 1, buffer.size(), chart_data_);
      if (read > 0) sink_(std::string_view(buffer.data(), read));
      if (read < buffer.size()) break;
    }
    if (std::ferror(chart_data_))
      throw InputError(
          "cannot read back the report's temporary chart data: " + std::string(std::strerror(errno)) + ".");
    std::fclose(chart_data_);
    chart_data_ = nullptr;
  }
  sink_("],\"distributions\":" + distributions_json_ + ",\"overlays\":" + overlays_json_ +
        ",\"verdict_plots\":" + verdict_plots_json_ + "}</script>\n<script>\n");
  // Draws every chart of the embedded data with dygraphs. The axis labels,
  // tick labels and legend values dygraphs inserts as HTML are escaped
  // first; the series labels are handed over as text, since dygraphs escapes
  // them itself for its legend (dygraph.js "labelHTML"): escaped twice, `a&b`
  // would read `a&amp;b` there.
  sink_(ReportDrawScript());
  sink_("</script>\n</body>\n</html>\n");
}

void HtmlReportWriter::SpoolChartData(std::string_view text) {
  if (chart_data_ == nullptr) {
    // An unnamed file (unlinked at once): nothing is left behind, whatever happens.
    const std::filesystem::path directory = util::TemporaryDirectory();
    std::string name = (directory / "napkin-report-XXXXXX").string();
    const int descriptor = mkstemp(name.data());
    if (descriptor < 0)
      throw InputError("cannot create a temporary file for the report's chart data in '" +
                       directory.string() + "': " + std::strerror(errno) + ".");
    unlink(name.c_str());
    chart_data_ = fdopen(descriptor, "w+b");
    if (chart_data_ == nullptr) {
      close(descriptor);
      throw InputError("cannot open a temporary file for the report's chart data: " +
                       std::string(std::strerror(errno)) + ".");
    }
  }
  if (!text.empty() && std::fwrite(text.data(), 1, text.size(), chart_data_) != text.size())
    throw InputError("cannot write the report's chart data to a temporary file in '" +
                     util::TemporaryDirectory().string() + "': " + std::strerror(errno) + ".");
}

std::string RenderHtmlReport(const ReportHeader& header, std::span<const ReportComparison> comparisons,
                             std::span<const ReportTest> tests) {
  std::string html;
  WriteHtmlReport(header, comparisons, tests, [&html](std::string_view text) { html += text; });
  return html;
}

void WriteHtmlReport(const ReportHeader& header, std::span<const ReportComparison> comparisons,
                     std::span<const ReportTest> tests, const HtmlSink& sink) {
  std::vector<std::string> test_ids;
  for (const ReportTest& test : tests) test_ids.push_back(test.test_id);
  HtmlReportWriter writer(sink, header, test_ids, comparisons);
  for (const ReportTest& test : tests) writer.AddTest(test);
  writer.Finish();
}

void WriteHtmlReport(const ReportHeader& header, std::span<const ReportComparison> comparisons,
                     std::span<const ReportTest> tests, const std::filesystem::path& path) {
  util::WriteFileAtomically(path, [&](util::AtomicFile& file) {
    WriteHtmlReport(header, comparisons, tests, [&file](std::string_view text) { file.Write(text); });
  });
}

}  // namespace napkin::formats

#include "formats/html_report.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <utility>

#include "common/error.h"
#include "engine/display_reduction.h"
#include "engine/units.h"
#include "formats/report_assets.h"
#include "util/atomic_file.h"
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
      std::move(key), std::move(title), std::move(y_label), std::move(trace_labels), {}, {}, {}};
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

// ---- page text

constexpr const char* kPageStyle = R"css(
:root { --ink: #1b1f24; --muted: #5b6470; --line: #d8dde3; --band: #f5f7f9; --accent: #1f4e9c; }
* { box-sizing: border-box; }
body { margin: 0; font: 14px/1.45 system-ui, -apple-system, "Segoe UI", Roboto, "Helvetica Neue", Arial, sans-serif;
       color: var(--ink); background: #fff; }
main { max-width: 1280px; margin: 0 auto; padding: 24px 32px 64px; }
header.report { border-bottom: 3px solid var(--accent); padding-bottom: 12px; margin-bottom: 20px; }
h1 { font-size: 26px; margin: 0 0 10px; }
h1 .product { color: var(--accent); }
h2 { font-size: 20px; margin: 36px 0 8px; padding-top: 8px; border-top: 1px solid var(--line); }
h2 .tag { font-size: 13px; font-weight: normal; color: var(--muted); margin-left: 10px; }
h3 { font-size: 15px; margin: 18px 0 6px; color: var(--accent); }
table { border-collapse: collapse; margin: 4px 0 8px; }
th, td { border: 1px solid var(--line); padding: 3px 9px; text-align: left; vertical-align: top; }
th { background: var(--band); font-weight: 600; }
td.num, table.compare td:nth-child(n+3) { text-align: right; font-variant-numeric: tabular-nums; }
table.compare { font-size: 13px; }
table.compare td { padding: 2px 7px; }
table.meta th { width: 170px; }
table.meta code { word-break: break-all; }
details { margin: 4px 0; }
details pre { background: var(--band); border: 1px solid var(--line); padding: 8px; max-height: 320px;
              overflow: auto; font-size: 12px; }
nav.tests { display: flex; flex-wrap: wrap; gap: 4px 14px; margin: 6px 0 0; }
nav.tests a { color: var(--accent); text-decoration: none; }
.facts { display: flex; flex-wrap: wrap; gap: 8px 28px; }
.charts { display: grid; grid-template-columns: repeat(auto-fill, minmax(560px, 1fr)); gap: 14px 22px; }
figure { margin: 0; border: 1px solid var(--line); border-radius: 4px; padding: 8px 10px 6px; }
figcaption { font-weight: 600; margin-bottom: 4px; }
.chart { width: 100%; height: 280px; }
.legend { min-height: 20px; font-size: 12px; color: var(--muted); margin-top: 4px; }
.legend span { margin-right: 6px; }
.hint, .note { color: var(--muted); font-size: 12px; }
.severity-error { color: #b00020; font-weight: 600; }
.severity-warning { color: #a05a00; font-weight: 600; }
.severity-info { color: var(--muted); }
.napkin-script-error { background: #b00020; color: #fff; padding: 6px 10px; margin: 4px 0; }
)css";

// Runs first: any later script error is written into the page (the
// headless-browser test looks for it).
constexpr const char* kErrorScript = R"js(
window.napkinReportError = function (message) {
  var box = document.createElement('div');
  box.className = 'napkin-' + 'script-error';
  box.textContent = 'report script error: ' + message;
  (document.body || document.documentElement).appendChild(box);
};
window.addEventListener('error', function (e) {
  window.napkinReportError(e.message + ' (' + e.filename + ':' + e.lineno + ')');
});
window.addEventListener('unhandledrejection', function (e) { window.napkinReportError(String(e.reason)); });
)js";

// Draws every chart of the embedded data with dygraphs. The axis labels,
// tick labels and legend values dygraphs inserts as HTML are escaped first;
// the series labels are handed over as text, since dygraphs escapes them
// itself for its legend (dygraph.js "labelHTML"): escaped twice, `a&b`
// would read `a&amp;b` there.
constexpr const char* kDrawScript = R"js(
(function () {
  'use strict';
  var data = JSON.parse(document.getElementById('napkin-data').textContent);
  function esc(text) {
    return String(text).replace(/[&<>"']/g, function (c) {
      return { '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;', "'": '&#39;' }[c];
    });
  }
  var componentColors = ['#1f77b4', '#d62728', '#2ca02c', '#222222'];
  var groupColors = ['#1f4e9c', '#d9730d', '#2a9d55', '#8e44ad', '#c0392b', '#16a085', '#7f8c8d'];
  var windowFill = ['rgba(230, 126, 34, 0.20)', 'rgba(52, 120, 200, 0.13)'];
  var windowInk = ['#b85c00', '#1f4e9c'];

  function drawn(element) {
    return function (graph, initial) { if (initial) element.setAttribute('data-drawn', 'true'); };
  }

  function timeHistory(chart) {
    var element = document.getElementById(chart.id);
    var rows = new Array(chart.t.length);
    for (var i = 0; i < chart.t.length; ++i) {
      var row = [chart.t[i]];
      for (var k = 0; k < chart.y.length; ++k) row.push(chart.y[k][i]);
      rows[i] = row;
    }
    new Dygraph(element, rows, {
      labels: ['time (ms)'].concat(chart.labels),
      xlabel: 'time (ms)',
      ylabel: esc(chart.ylabel),
      colors: chart.labels.length === 1 ? ['#1f4e9c'] : componentColors.slice(0, chart.labels.length),
      strokeWidth: 1.4,
      legend: 'always',
      labelsDiv: element.parentNode.querySelector('.legend'),
      labelsSeparateLines: false,
      gridLineColor: '#e4e7eb',
      axisLabelFontSize: 12,
      xLabelHeight: 16,
      yLabelWidth: 16,
      axes: { y: { axisLabelWidth: 56 } },
      underlayCallback: function (canvas, area, graph) {
        chart.windows.forEach(function (w, i) {
          var x1 = graph.toDomXCoord(w.t1), x2 = graph.toDomXCoord(w.t2);
          canvas.fillStyle = windowFill[i % 2];
          canvas.fillRect(x1, area.y, x2 - x1, area.h);
          canvas.strokeStyle = windowInk[i % 2];
          canvas.lineWidth = 1;
          canvas.setLineDash([4, 3]);
          canvas.beginPath();
          canvas.moveTo(x1, area.y); canvas.lineTo(x1, area.y + area.h);
          canvas.moveTo(x2, area.y); canvas.lineTo(x2, area.y + area.h);
          canvas.stroke();
          canvas.setLineDash([]);
          canvas.font = 'bold 12px system-ui, sans-serif';
          canvas.fillStyle = windowInk[i % 2];
          var text = w.label + '  (' + w.t1.toFixed(1) + '–' + w.t2.toFixed(1) + ' ms)';
          var x = Math.max(area.x + 4, Math.min(x2 + 6, area.x + area.w - canvas.measureText(text).width - 4));
          canvas.fillText(text, x, area.y + 16 + 16 * i);
        });
      },
      drawCallback: drawn(element)
    });
  }

  // Every test as a point (left of its group's tick), the group's mean with
  // its 95 % confidence interval as a bar (right of the tick).
  function distribution(chart) {
    var element = document.getElementById(chart.id);
    var groups = chart.groups;
    var rows = [];
    groups.forEach(function (group, g) {
      group.values.forEach(function (value, j) {
        var row = [g - 0.12 + ((j % 5) - 2) * 0.035];
        for (var k = 0; k < groups.length; ++k) row.push(k === g ? value : null);
        rows.push(row);
      });
    });
    rows.sort(function (a, b) { return a[0] - b[0]; });
    new Dygraph(element, rows, {
      labels: ['variant'].concat(groups.map(function (g) { return g.name; })),
      ylabel: esc(chart.ylabel),
      colors: groups.map(function (g, k) { return groupColors[k % groupColors.length]; }),
      strokeWidth: 0,
      drawPoints: true,
      pointSize: 3.5,
      highlightCircleSize: 5,
      legend: 'always',
      labelsDiv: element.parentNode.querySelector('.legend'),
      labelsSeparateLines: false,
      gridLineColor: '#e4e7eb',
      axisLabelFontSize: 12,
      yLabelWidth: 16,
      includeZero: true,
      dateWindow: [-0.5, groups.length - 0.5],
      interactionModel: {},
      axes: {
        x: {
          drawGrid: false,
          axisLabelWidth: 120,
          ticker: function () { return groups.map(function (g, k) { return { v: k, label: esc(g.name) }; }); },
          valueFormatter: function (x) { var k = Math.round(x); return k >= 0 && k < groups.length ? esc(groups[k].name) : ''; }
        },
        y: { axisLabelWidth: 56 }
      },
      underlayCallback: function (canvas, area, graph) {
        groups.forEach(function (group, k) {
          var x = graph.toDomXCoord(k + 0.18);
          var ink = groupColors[k % groupColors.length];
          canvas.strokeStyle = ink;
          canvas.fillStyle = ink;
          canvas.lineWidth = 2;
          if (group.ci_low !== null && group.ci_high !== null) {
            var top = graph.toDomYCoord(group.ci_high), bottom = graph.toDomYCoord(group.ci_low);
            canvas.beginPath();
            canvas.moveTo(x, top); canvas.lineTo(x, bottom);
            canvas.moveTo(x - 6, top); canvas.lineTo(x + 6, top);
            canvas.moveTo(x - 6, bottom); canvas.lineTo(x + 6, bottom);
            canvas.stroke();
          }
          var y = graph.toDomYCoord(group.mean);
          canvas.fillRect(x - 10, y - 1.5, 20, 3);
        });
      },
      drawCallback: drawn(element)
    });
  }

  function guarded(draw) {
    return function (chart) {
      try { draw(chart); } catch (e) { window.napkinReportError(chart.id + ': ' + (e && e.message ? e.message : e)); }
    };
  }
  data.charts.forEach(guarded(timeHistory));
  data.distributions.forEach(guarded(distribution));
})();
)js";

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

std::string PrettySettings(const std::string& settings_json) {
  const json settings = json::parse(settings_json, nullptr, /*allow_exceptions=*/false);
  if (settings.is_discarded()) return settings_json;
  return settings.dump(2, ' ', false, json::error_handler_t::replace);
}

void AppendRow(std::string& html, std::string_view label, const std::string& value, bool numeric = true) {
  html += "<tr><th>";
  html += label;
  html += numeric ? "</th><td class=\"num\">" : "</th><td>";
  html += value;
  html += "</td></tr>\n";
}

std::string HicCell(const engine::HicWindow& hic) {
  return Display(hic.value) + " <span class=\"note\">(" + Fixed(hic.t1_s * 1000.0, 2) + "–" +
         Fixed(hic.t2_s * 1000.0, 2) + " ms)</span>";
}

void AppendHeader(std::string& html, const ReportHeader& header, std::span<const std::string> test_ids) {
  html +=
      "<header class=\"report\">\n<h1><span class=\"product\">napkin</span> head-kinematics report</h1>\n";
  html += "<table class=\"meta\">\n";
  AppendRow(html, "catalogue", "<code>" + EscapeHtml(header.catalogue) + "</code>", false);
  AppendRow(html, "napkin version", EscapeHtml(header.napkin_version), false);
  AppendRow(html, "selection", header.selection.empty() ? "every test" : EscapeHtml(header.selection), false);
  AppendRow(html, "tests", std::to_string(test_ids.size()), false);
  for (const ReportConfig& config : header.configs) {
    std::string cell = "<strong>" + EscapeHtml(config.name) +
                       "</strong> <span class=\"note\">SHA-256 <code>" + EscapeHtml(config.hash) +
                       "</code></span>\n<details><summary>settings</summary><pre>" +
                       EscapeHtml(PrettySettings(config.settings_json)) + "</pre></details>";
    AppendRow(html, "processing config", cell, false);
  }
  html += "</table>\n";
  html +=
      "<p class=\"hint\">Time histories: drag across a plot to zoom in, double-click to zoom out. Traces are "
      "reduced for display to at most " +
      std::to_string(kReportMaxPoints) +
      " points per plot keeping every bucket's minimum and maximum, so no peak is lost; the full-resolution "
      "data stays in the catalogue (<code>napkin export</code>).</p>\n";
  if (!test_ids.empty()) {
    html += "<nav class=\"tests\"><strong>Tests:</strong>";
    for (std::size_t i = 0; i < test_ids.size(); ++i) {
      html += " <a href=\"#test-" + std::to_string(i + 1) + "\">" + EscapeHtml(test_ids[i]) + "</a>";
    }
    html += "</nav>\n";
  }
  html += "</header>\n";
}

void AppendFigure(std::string& html, const std::string& id, const std::string& caption) {
  html += "<figure><figcaption>" + EscapeHtml(caption) + "</figcaption><div class=\"chart\" id=\"" + id +
          "\"></div><div class=\"legend\"></div></figure>\n";
}

void AppendComparison(std::string& html, json& distributions, const ReportComparison& comparison,
                      std::size_t index) {
  html += "<section class=\"comparison\">\n<h2>Series " + EscapeHtml(comparison.series) +
          ": variants compared</h2>\n<table class=\"compare\">\n<tr>";
  for (const std::string& column : comparison.columns) html += "<th>" + EscapeHtml(column) + "</th>";
  html += "</tr>\n";
  for (const std::vector<std::string>& row : comparison.rows) {
    html += "<tr>";
    for (const std::string& cell : row) html += "<td>" + EscapeHtml(cell) + "</td>";
    html += "</tr>\n";
  }
  html += "</table>\n";
  for (const std::string& note : comparison.notes) html += "<p class=\"note\">" + EscapeHtml(note) + "</p>\n";
  if (!comparison.distributions.empty()) {
    html += "<div class=\"charts\">\n";
    for (std::size_t m = 0; m < comparison.distributions.size(); ++m) {
      const ReportDistribution& distribution = comparison.distributions[m];
      const std::string id = "dist-" + std::to_string(index + 1) + "-" + std::to_string(m + 1);
      AppendFigure(html, id, distribution.metric + ": every test, mean and 95 % CI per variant");
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
    html += "</div>\n";
  }
  html += "</section>\n";
}

void AppendTest(std::string& html, json& charts, const ReportTest& test, std::size_t index) {
  const std::string section_id = "test-" + std::to_string(index + 1);
  const engine::TestSummary& s = test.summary;
  html += "<section class=\"test\" id=\"" + section_id + "\">\n<h2>Test " + EscapeHtml(test.test_id);
  html += "<span class=\"tag\">series " + (test.series ? EscapeHtml(*test.series) : std::string("—")) +
          " · variant " + (test.variant ? EscapeHtml(*test.variant) : std::string("—")) + " · config " +
          EscapeHtml(test.config_name) + "</span></h2>\n";

  html += "<div class=\"facts\">\n<div><h3>Injury criteria</h3><table class=\"criteria\">\n";
  AppendRow(html, "HIC15", HicCell(s.hic15));
  AppendRow(html, "HIC36", HicCell(s.hic36));
  AppendRow(html, "HIC (no window limit)", HicCell(s.hic));
  AppendRow(html, "peak acceleration (g)", Display(s.peak_acc_g));
  AppendRow(html, "a3ms (g)", Display(s.a3ms_g));
  AppendRow(html, "BrIC", Display(s.bric));
  AppendRow(html, "DAMAGE", Display(s.damage));
  html += "</table></div>\n<div><h3>Rotation</h3><table class=\"rotation\">\n";
  AppendRow(html, "peak |ω| x, y, z (rad/s)",
            Display(s.peak_omega_body_radps.x()) + ", " + Display(s.peak_omega_body_radps.y()) + ", " +
                Display(s.peak_omega_body_radps.z()));
  AppendRow(html, "peak ω resultant (rad/s)", Display(s.peak_omega_radps));
  AppendRow(html, "peak α resultant (rad/s²)", Display(s.peak_alpha_radps2));
  AppendRow(html, "max rotation (deg)", Display(s.max_rotation_deg));
  AppendRow(html, "max residual (m/s²)", Display(s.max_residual_mps2));
  html += "</table></div>\n<div><h3>Final pose</h3><table class=\"pose\">\n";
  AppendRow(html, "quaternion w, x, y, z",
            Fixed(s.final_quat_wxyz(0), 5) + ", " + Fixed(s.final_quat_wxyz(1), 5) + ", " +
                Fixed(s.final_quat_wxyz(2), 5) + ", " + Fixed(s.final_quat_wxyz(3), 5));
  AppendRow(html, "roll, pitch, yaw (deg)",
            Fixed(s.final_roll_pitch_yaw_deg.x(), 2) + ", " + Fixed(s.final_roll_pitch_yaw_deg.y(), 2) +
                ", " + Fixed(s.final_roll_pitch_yaw_deg.z(), 2));
  AppendRow(html, "position x, y, z (mm)",
            Fixed(s.final_pos_fixed_m.x() * 1000.0, 1) + ", " + Fixed(s.final_pos_fixed_m.y() * 1000.0, 1) +
                ", " + Fixed(s.final_pos_fixed_m.z() * 1000.0, 1));
  html += "</table></div>\n</div>\n";

  html += "<h3>Time histories</h3>\n<div class=\"charts\">\n";
  for (const ReportChart& chart : test.charts) {
    const std::string id = "chart-" + std::to_string(index + 1) + "-" + chart.key;
    AppendFigure(html, id, chart.title);
    json windows = json::array();
    for (const ReportWindow& window : chart.windows)
      windows.push_back({{"label", window.label}, {"t1", window.t1_ms}, {"t2", window.t2_ms}});
    charts.push_back({{"id", id},
                      {"ylabel", chart.y_label},
                      {"labels", chart.trace_labels},
                      {"t", chart.time_ms},
                      {"y", chart.traces},
                      {"windows", std::move(windows)}});
  }
  html += "</div>\n";

  html += "<h3>Screening findings</h3>\n";
  if (s.findings.empty()) {
    html += "<p class=\"note\">No findings: every check passed.</p>\n";
  } else {
    html +=
        "<table "
        "class=\"findings\">\n<tr><th>severity</th><th>check</th><th>channel</th><th>detail</th></tr>\n";
    for (const engine::Finding& finding : s.findings) {
      const std::string severity = engine::SeverityName(finding.severity);
      html += "<tr><td class=\"severity-" + severity + "\">" + severity + "</td><td>" +
              EscapeHtml(finding.check) + "</td><td>" +
              (finding.channel ? EscapeHtml(*finding.channel) : std::string("—")) + "</td><td>" +
              EscapeHtml(finding.detail) + "</td></tr>\n";
    }
    html += "</table>\n";
  }
  if (!s.conditioning.empty()) {
    // What conditioning did to each channel (docs/formats.md "Conditioning record").
    html +=
        "<h3>Conditioning</h3>\n<table class=\"conditioning\">\n<tr><th>channel</th><th>filter</th>"
        "<th>bias removed</th><th>bias window (ms)</th><th>time shift (ms)</th></tr>\n";
    for (const engine::ChannelConditioning& record : s.conditioning) {
      const std::string window = record.bias_window_start_s && record.bias_window_end_s
                                     ? Display(*record.bias_window_start_s * 1000.0) + " to " +
                                           Display(*record.bias_window_end_s * 1000.0)
                                     : std::string("none");
      html += "<tr><td>" + EscapeHtml(record.channel) + "</td><td>" +
              EscapeHtml(engine::FilterDescription(record)) + "</td><td>" + Display(record.bias_removed) +
              "</td><td>" + window + "</td><td>" + Display(record.time_shift_s * 1000.0) + "</td></tr>\n";
    }
    html += "</table>\n";
  }
  html += "</section>\n";
}

}  // namespace

std::string EscapeHtml(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

ReportTest MakeReportTest(std::string test_id, std::optional<std::string> series,
                          std::optional<std::string> variant, std::string config_name,
                          engine::TestSummary summary, const engine::Kinematics& kinematics,
                          Eigen::Index max_points) {
  ReportTest test{std::move(test_id),     std::move(series),  std::move(variant),
                  std::move(config_name), std::move(summary), {}};
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

// ---- the page, piece by piece

HtmlReportWriter::HtmlReportWriter(HtmlSink sink, const ReportHeader& header,
                                   std::span<const std::string> test_ids,
                                   std::span<const ReportComparison> comparisons)
    : sink_(std::move(sink)), test_count_(test_ids.size()) {
  std::string html;
  html +=
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
      "<meta name=\"generator\" content=\"napkin " +
      EscapeHtml(header.napkin_version) + "\">\n<title>napkin report: " + EscapeHtml(header.catalogue) +
      "</title>\n<script>" + kErrorScript + "</script>\n<style>\n";
  sink_(html);
  sink_(WithoutSourceMap(DygraphsStylesheet(), "/*# sourceMappingURL="));
  html = "\n</style>\n<style>";
  html += kPageStyle;
  html += "</style>\n</head>\n<body>\n<main>\n";
  AppendHeader(html, header, test_ids);
  sink_(html);
  json distributions = json::array();
  for (std::size_t i = 0; i < comparisons.size(); ++i) {
    html.clear();
    AppendComparison(html, distributions, comparisons[i], i);
    sink_(html);
  }
  distributions_json_ = JsonForScript(distributions);
}

HtmlReportWriter::~HtmlReportWriter() {
  if (chart_data_ != nullptr) std::fclose(chart_data_);
}

void HtmlReportWriter::AddTest(const ReportTest& test) {
  if (finished_ || tests_added_ == test_count_)
    throw std::logic_error("HtmlReportWriter: more tests added than the header names");
  std::string html;
  json charts = json::array();
  AppendTest(html, charts, test, tests_added_);
  sink_(html);
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
  // JsonForScript of {"charts": [...], "distributions": [...]} (keys in
  // nlohmann's order), one chart at a time.
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
  html = "],\"distributions\":" + distributions_json_ + "}</script>\n<script>";
  html += kDrawScript;
  html += "</script>\n</body>\n</html>\n";
  sink_(html);
}

void HtmlReportWriter::SpoolChartData(std::string_view text) {
  if (chart_data_ == nullptr) {
    // An unnamed file (unlinked at once): nothing is left behind, whatever happens.
    const std::filesystem::path directory = std::filesystem::temp_directory_path();
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
                     std::filesystem::temp_directory_path().string() + "': " + std::strerror(errno) + ".");
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

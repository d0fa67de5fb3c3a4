#include "formats/report_verdict_plots.h"

#include <algorithm>
#include <cmath>

#include "util/text.h"

namespace napkin::formats {
namespace {

using nlohmann::json;

// A number for the plot data; a missing one is null.
json PlotNumber(const std::optional<double>& value) {
  return value && std::isfinite(*value) ? json(*value) : json(nullptr);
}

// A figure dygraphs draws into `id`, its legend below; `height_px` where the plot's rows set it.
std::string PlotFigure(const std::string& id, const std::string& caption, const std::string& css_class,
                       std::size_t height_px) {
  const std::string style = height_px > 0 ? " style=\"height: " + std::to_string(height_px) + "px\"" : "";
  return "<figure class=\"" + css_class + "\"><figcaption>" + EscapeHtml(caption) +
         "</figcaption><div class=\"chart\" id=\"" + id + "\"" + style +
         "></div><div class=\"legend\"></div></figure>\n";
}

json ForestData(const std::string& id, const ReportForest& forest) {
  json rows = json::array();
  for (const ReportForestRow& row : forest.rows)
    rows.push_back({{"label", row.label},
                    {"ratio", row.ratio},
                    {"low", PlotNumber(row.ci_low)},
                    {"high", PlotNumber(row.ci_high)},
                    {"significant", row.significant},
                    {"equivalent", row.equivalent}});
  return {{"id", id},
          {"kind", "forest"},
          {"baseline", forest.baseline},
          {"margin", forest.equivalence_pct / 100.0},
          {"rows", std::move(rows)}};
}

json StripData(const std::string& id, const ReportStrip& strip) {
  json edges = json::array();
  for (const ReportStrip::Edge& edge : strip.edges)
    edges.push_back({{"label", edge.label}, {"value", edge.value}});
  json points = json::array();
  for (const ReportStrip::Point& point : strip.points)
    points.push_back(json::array({point.group, point.value, point.category, point.test_id}));
  return {
      {"id", id},       {"kind", "strip"},          {"ylabel", strip.y_label},    {"groups", strip.groups},
      {"edges", edges}, {"classes", strip.classes}, {"points", std::move(points)}};
}

}  // namespace

std::string VerdictPlotsMarkup(const ReportVerdictPlots& plots, std::size_t index, json& data) {
  if (!plots.forest && plots.strips.empty()) return "";
  const std::string prefix = std::to_string(index + 1);
  std::string figures;
  if (plots.forest) {
    const std::string id = "forest-" + prefix;
    // A row every 26 px, with room for the axis and the legend.
    const std::size_t height = 26 * plots.forest->rows.size() + 64;
    figures += PlotFigure(id,
                          "Change against " + plots.forest->baseline +
                              ": ratio of geometric means with its 95 % interval (log axis); shaded: the ±" +
                              util::FormatNumber(plots.forest->equivalence_pct, 6) + " % equivalence margin",
                          "forest", height);
    data.push_back(ForestData(id, *plots.forest));
  }
  for (std::size_t s = 0; s < plots.strips.size(); ++s) {
    const std::string id = "strip-" + prefix + "-" + std::to_string(s + 1);
    figures += PlotFigure(id, plots.strips[s].title, "strip", 0);
    data.push_back(StripData(id, plots.strips[s]));
  }
  return "<div class=\"charts verdict-plots\">\n" + figures + "</div>\n";
}

}  // namespace napkin::formats

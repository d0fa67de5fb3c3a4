#pragma once
// The verdict as a picture in the HTML report (docs/formats.md "HTML report",
// formats/html_report.h ReportVerdictPlots): the figures report.js draws with
// dygraphs, a forest plot of the changes against the baseline and a strip of
// every test's value per limited criterion, and their data. Kept apart from
// formats/html_report.cpp, which lays out the rest of the page.
#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>

#include "formats/html_report.h"

namespace napkin::formats {

// The figures of comparison `index` (0-based) as markup, user text escaped
// (EscapeHtml); each figure's data, {"id", "kind": "forest" | "strip", ...},
// appended to `data` (the page data's "verdict_plots"). Empty without plots.
std::string VerdictPlotsMarkup(const ReportVerdictPlots& plots, std::size_t index, nlohmann::json& data);

}  // namespace napkin::formats

#pragma once
// The report's verdict as a picture and its every-test tables of limits
// (docs/formats.md "HTML report"): made from a by-variant comparison
// (app/comparison.h) for formats/html_report.h to draw. Kept apart from
// app/report_builder.cpp, which assembles the rest of the page.
#include <vector>

#include "app/comparison.h"
#include "formats/html_report.h"

namespace napkin::app {

// The forest plot (each non-baseline variant's change in the verdict's
// criteria and the limited ones, on the log scale: ratio with its 95 %
// interval, significant and equivalent as the verdict words them) and a
// strip per limit of each set (every test's value, classed by its outcome).
formats::ReportVerdictPlots VerdictPlotsOf(const Comparison& comparison);

// Per limit set, every test of the comparison against it: each criterion's
// value and its points, band or whether it meets the limit, the combined
// region's points and the hard-contact rule's finding; the notes cite each
// limit's clause, the set's source and what it leaves out.
std::vector<formats::ReportTable> LimitTablesOf(const Comparison& comparison);

}  // namespace napkin::app

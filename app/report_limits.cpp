#include "app/report_limits.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include "app/verdict.h"
#include "engine/summary_fields.h"
#include "util/text.h"

namespace napkin::app {
namespace {

constexpr double kAbsent = std::numeric_limits<double>::quiet_NaN();

const MetricComparison* MetricNamed(const Comparison& comparison, const std::string& name) {
  for (const MetricComparison& metric : comparison.metrics)
    if (metric.metric == name) return &metric;
  return nullptr;
}

// The forest's criteria: the verdict's, then each set's limited ones, each once.
std::vector<std::string> ForestCriteria(const Comparison& comparison) {
  std::vector<std::string> criteria = VerdictCriteria();
  for (const ComparedLimitSet& compared : comparison.limit_sets)
    for (const Limit& limit : compared.set.limits)
      if (std::find(criteria.begin(), criteria.end(), limit.metric) == criteria.end())
        criteria.push_back(limit.metric);
  return criteria;
}

std::optional<formats::ReportForest> ForestOf(const Comparison& comparison) {
  formats::ReportForest forest;
  forest.baseline = comparison.baseline;
  forest.equivalence_pct = comparison.equivalence_pct;
  for (const std::string& criterion : ForestCriteria(comparison)) {
    const MetricComparison* metric = MetricNamed(comparison, criterion);
    if (metric == nullptr) continue;
    for (const ComparisonRow& row : metric->rows) {
      if (row.is_baseline || row.scale != CompareScale::kLog || !std::isfinite(row.difference.diff)) continue;
      formats::ReportForestRow& drawn = forest.rows.emplace_back();
      drawn.label = MetricLabel(criterion) + " · " + row.group;
      drawn.ratio = std::exp(row.difference.diff);
      if (std::isfinite(row.difference.ci_low) && std::isfinite(row.difference.ci_high)) {
        drawn.ci_low = std::exp(row.difference.ci_low);
        drawn.ci_high = std::exp(row.difference.ci_high);
      }
      drawn.significant = std::isfinite(row.difference.p_value) && row.difference.p_value < kVerdictAlpha;
      drawn.equivalent = std::isfinite(row.equivalence.p_value) && row.equivalence.p_value < kVerdictAlpha;
    }
  }
  if (forest.rows.empty()) return std::nullopt;
  return forest;
}

// "HIC15", "a3ms (g)": a criterion's label with its unit.
std::string LabelWithUnit(const std::string& metric) {
  const engine::SummaryField* field = engine::FindSummaryField(metric);
  const std::string label = MetricLabel(metric);
  return field != nullptr && *field->unit ? label + " (" + field->unit + ")" : label;
}

// The class of a test's value under a limit, as ReportStrip orders them.
std::size_t CategoryOf(const Limit& limit, double value) {
  switch (limit.kind) {
    case LimitKind::kMaximum:
      return value <= limit.max ? 0 : 1;
    case LimitKind::kScale: {
      const double points = ScalePoints(limit, value);
      return points >= limit.points ? 0 : (points > 0.0 ? 1 : 2);
    }
    case LimitKind::kBands:
      return static_cast<std::size_t>(&BandOf(limit, value) - limit.bands.data());
  }
  return 0;
}

formats::ReportStrip StripOf(const Comparison& comparison, const MetricComparison& metric,
                             const MetricLimit& checked) {
  const Limit& limit = checked.limit;
  formats::ReportStrip strip;
  strip.title =
      MetricLabel(limit.metric) + " of every test against " + comparison.limit_sets[checked.set].set.name;
  strip.y_label = LabelWithUnit(limit.metric);
  strip.groups = comparison.groups;
  const auto number = [](double value) { return util::FormatNumber(value, 6); };
  switch (limit.kind) {
    case LimitKind::kMaximum:
      strip.edges = {{"limit " + number(limit.max), limit.max}};
      strip.classes = {"within the limit", "over the limit"};
      break;
    case LimitKind::kScale:
      strip.edges = {{"higher performance limit " + number(limit.higher_limit), limit.higher_limit},
                     {"lower performance limit " + number(limit.max), limit.max}};
      strip.classes = {number(limit.points) + " points", "between 0 and " + number(limit.points) + " points",
                       "0 points"};
      break;
    case LimitKind::kBands:
      for (const LimitBand& band : limit.bands) {
        strip.classes.push_back(band.name);
        if (band.max) strip.edges.push_back({band.name + " ≤ " + number(*band.max), *band.max});
      }
      break;
  }
  for (std::size_t g = 0; g < metric.groups.size(); ++g) {
    const GroupValues& values = metric.groups[g];
    for (std::size_t i = 0; i < values.values.size(); ++i)
      strip.points.push_back({g, values.test_ids[i], values.values[i], CategoryOf(limit, values.values[i])});
  }
  return strip;
}

// Each test's value of every compared metric.
std::map<std::string, std::map<std::string, double>> ValuesByTest(const Comparison& comparison) {
  std::map<std::string, std::map<std::string, double>> values;
  for (const MetricComparison& metric : comparison.metrics)
    for (const GroupValues& group : metric.groups)
      for (std::size_t i = 0; i < group.values.size(); ++i)
        values[group.test_ids[i]][metric.metric] = group.values[i];
  return values;
}

std::string CellNumber(double value) { return std::isfinite(value) ? util::FormatNumber(value, 4) : "—"; }

// Points with two decimals, as the verdict prints them (app/verdict_limits.cpp).
std::string CellPoints(double points) { return std::isfinite(points) ? fmt::format("{:.2f}", points) : "—"; }

}  // namespace

formats::ReportVerdictPlots VerdictPlotsOf(const Comparison& comparison) {
  formats::ReportVerdictPlots plots;
  plots.forest = ForestOf(comparison);
  for (std::size_t s = 0; s < comparison.limit_sets.size(); ++s)
    for (const Limit& limit : comparison.limit_sets[s].set.limits) {
      const MetricComparison* metric = MetricNamed(comparison, limit.metric);
      if (metric == nullptr) continue;
      for (const MetricLimit& checked : metric->limits)
        if (checked.set == s) plots.strips.push_back(StripOf(comparison, *metric, checked));
    }
  return plots;
}

std::vector<formats::ReportTable> LimitTablesOf(const Comparison& comparison) {
  std::vector<formats::ReportTable> tables;
  const std::map<std::string, std::map<std::string, double>> values = ValuesByTest(comparison);
  for (const ComparedLimitSet& compared : comparison.limit_sets) {
    const LimitSet& set = compared.set;
    formats::ReportTable& table = tables.emplace_back();
    table.heading = "Every test against " + set.name;
    table.columns = {"test", "variant"};
    for (const Limit& limit : set.limits) {
      const std::string label = MetricLabel(limit.metric);
      table.columns.push_back(label);
      table.columns.push_back(limit.kind == LimitKind::kScale ? label + " points"
                              : limit.kind == LimitKind::kBands
                                  ? label + " band"
                                  : label + " ≤ " + util::FormatNumber(limit.max, 6));
    }
    if (set.combined) table.columns.push_back(set.combined->name + " points");
    if (set.hard_contact) table.columns.push_back("hard contact");
    // The tests with a value of one of the set's metrics, by variant and test id.
    const std::vector<std::string> metrics = LimitMetrics(set);
    for (std::size_t g = 0; g < comparison.groups.size(); ++g) {
      std::set<std::string> tests;
      for (const std::string& name : metrics)
        if (const MetricComparison* metric = MetricNamed(comparison, name))
          tests.insert(metric->groups[g].test_ids.begin(), metric->groups[g].test_ids.end());
      for (const std::string& test : tests) {
        const std::map<std::string, double>& of_test = values.at(test);
        const TestRating rating = RateTest(set, [&](const std::string& metric) {
          const auto found = of_test.find(metric);
          return found == of_test.end() ? kAbsent : found->second;
        });
        std::vector<std::string>& row = table.rows.emplace_back();
        row = {test, comparison.groups[g]};
        for (std::size_t i = 0; i < set.limits.size(); ++i) {
          const CriterionRating& criterion = rating.criteria[i];
          row.push_back(CellNumber(criterion.value));
          if (!criterion.has_value)
            row.emplace_back("—");
          else if (set.limits[i].kind == LimitKind::kScale)
            row.push_back(CellPoints(criterion.points));
          else if (set.limits[i].kind == LimitKind::kBands)
            row.push_back(criterion.band->name);
          else
            row.emplace_back(*criterion.meets ? "yes" : "no");
        }
        if (set.combined) row.push_back(CellPoints(rating.combined_points));
        if (set.hard_contact) row.push_back(HardContactText(set, rating));
      }
    }
    for (const Limit& limit : set.limits)
      table.notes.push_back(MetricLabel(limit.metric) + ": " + limit.requirement + ".");
    if (set.combined)
      table.notes.push_back(set.combined->name + " points: " + set.combined->requirement + ".");
    if (set.hard_contact) table.notes.push_back("Hard contact: " + set.hard_contact->requirement + ".");
    table.notes.push_back("Source: " + set.source + (set.url.empty() ? "" : " (" + set.url + ")") + ".");
    if (!set.note.empty()) table.notes.push_back(set.note);
  }
  return tables;
}

}  // namespace napkin::app

#include "app/verdict_limits.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "app/verdict.h"
#include "common/joined.h"
#include "engine/summary_fields.h"
#include "util/text.h"

namespace napkin::app {
namespace {

// "80 g", "700": a limit or value with its metric's unit.
std::string ValueText(const std::string& metric, double value, int digits = 4) {
  const engine::SummaryField* field = engine::FindSummaryField(metric);
  const std::string unit = field != nullptr && *field->unit ? std::string(" ") + field->unit : std::string();
  return util::FormatNumber(value, digits) + unit;
}

// Points with two decimals, as Euro NCAP prints them: "4.00", "2.13", "0.00".
std::string PointsText(double points) { return std::isfinite(points) ? fmt::format("{:.2f}", points) : "—"; }

// A full score as the protocol states it: "4".
std::string FullPointsText(double points) { return util::FormatNumber(points, 6); }

// The limits of set `s` on the comparison's metrics, in the set's order.
std::vector<const MetricLimit*> LimitsOfSet(const Comparison& comparison, std::size_t s) {
  std::vector<const MetricLimit*> found;
  for (const Limit& limit : comparison.limit_sets[s].set.limits)
    for (const MetricComparison& metric : comparison.metrics)
      for (const MetricLimit& checked : metric.limits)
        if (checked.set == s && checked.limit.metric == limit.metric) found.push_back(&checked);
  return found;
}

const MetricComparison& MetricOf(const Comparison& comparison, const MetricLimit& checked) {
  for (const MetricComparison& metric : comparison.metrics)
    for (const MetricLimit& candidate : metric.limits)
      if (&candidate == &checked) return metric;
  return comparison.metrics.front();  // every MetricLimit is some metric's
}

// The tests of group g with a value of some maximum limit of the set, and those exceeding one.
struct MaximumCount {
  std::set<std::string> tested, failing;
};
MaximumCount CountMaximum(const Comparison& comparison, const std::vector<const MetricLimit*>& limits,
                          std::size_t g) {
  MaximumCount count;
  for (const MetricLimit* checked : limits) {
    if (checked->limit.kind != LimitKind::kMaximum) continue;
    const GroupValues& values = MetricOf(comparison, *checked).groups[g];
    for (std::size_t i = 0; i < values.values.size(); ++i) {
      count.tested.insert(values.test_ids[i]);
      if (!(values.values[i] <= checked->limit.max)) count.failing.insert(values.test_ids[i]);
    }
  }
  return count;
}

// "a further test exceeds HIC(d) 1000 with probability 0.3 %", or why not estimated.
std::string ExceedText(const MetricLimit& checked, const GroupLimitCheck& check) {
  const std::string limit =
      MetricLabel(checked.limit.metric) + " " + ValueText(checked.limit.metric, checked.limit.max, 6);
  if (check.prediction_gap != engine::PredictionGap::kNone)
    return "the chance that a further test exceeds " + limit + " is not estimated (" +
           std::string(engine::PredictionGapText(check.prediction_gap)) + ")";
  return "a further test exceeds " + limit + " with probability " +
         FurtherProbabilityText(check.exceed_probability);
}

// The maximum limits' part: "all 5 foam-b tests meet FMVSS 201U (highest HIC(d) 562.7, margin 44 %);
// a further test exceeds HIC(d) 1000 with probability 0.3 %".
std::string MaximumPart(const Comparison& comparison, const std::vector<const MetricLimit*>& limits,
                        std::size_t g) {
  const std::string& name = comparison.limit_sets[limits.front()->set].set.name;
  const std::string& group = comparison.groups[g];
  const MaximumCount count = CountMaximum(comparison, limits, g);
  std::vector<std::string> parts, labels, further;
  for (const MetricLimit* checked : limits) {
    if (checked->limit.kind != LimitKind::kMaximum) continue;
    labels.push_back(MetricLabel(checked->limit.metric));
    const GroupLimitCheck& check = checked->checks[g];
    if (check.tests == 0) continue;
    const std::string margin = check.margin_pct < 0 ? PercentText(-check.margin_pct) + " % over"
                                                    : "margin " + PercentText(check.margin_pct) + " %";
    parts.push_back("highest " + MetricLabel(checked->limit.metric) + " " +
                    util::FormatNumber(check.worst_value, 4) + ", " + margin);
    further.push_back(ExceedText(*checked, check));
  }
  if (count.tested.empty())
    return "no test of " + group + " has " + Joined(labels) + ": " + name + " not checked";
  const std::size_t meet = count.tested.size() - count.failing.size();
  std::string head;
  if (meet == count.tested.size())
    head = count.tested.size() == 1 ? "the 1 " + group + " test meets "
                                    : fmt::format("all {} {} tests meet ", count.tested.size(), group);
  else
    head =
        fmt::format("{} of {} {} tests {} ", meet, count.tested.size(), group, meet == 1 ? "meets" : "meet");
  std::string joined;
  for (const std::string& part : parts) joined += (joined.empty() ? "" : "; ") + part;
  std::string text = head + name + " (" + joined + ")";
  for (const std::string& part : further) text += "; " + part;
  return text;
}

// The combined region's part: "head 2.13 of 4 points on average, lowest 0.9 (t-03) (per test the
// lowest of HIC15 and a3ms; hard contact assumed in all 5: peak acceleration above 80 g)".
std::string CombinedPart(const Comparison& comparison, std::size_t s, std::size_t g) {
  const ComparedLimitSet& compared = comparison.limit_sets[s];
  const LimitSet& set = compared.set;
  const GroupCombinedPoints& combined = compared.combined[g];
  std::vector<std::string> scales;
  for (const Limit& limit : set.limits)
    if (limit.kind == LimitKind::kScale) scales.push_back(MetricLabel(limit.metric));
  const std::string criteria =
      scales.size() == 1
          ? scales.front()
          : Joined(std::vector<std::string>(scales.begin(), scales.end() - 1)) + " and " + scales.back();
  if (combined.tests == 0) return set.combined->name + " points not given (a test lacks " + criteria + ")";
  std::string text = set.combined->name + " " + PointsText(combined.mean_points) + " of " +
                     FullPointsText(CombinedMaxPoints(set)) + " points on average";
  if (combined.tests > 1 && combined.lowest_points < combined.mean_points)
    text += ", lowest " + PointsText(combined.lowest_points) + " (" + combined.lowest_test + ")";
  text += " (per test the lowest of " + criteria;
  if (set.hard_contact) {
    const HardContactRule& rule = *set.hard_contact;
    const std::string label = MetricLabel(rule.metric);
    const std::size_t rated =
        combined.contact_assumed + combined.contact_not_assumed + combined.contact_not_applied;
    const std::string above = label + " above " + ValueText(rule.metric, rule.above, 6);
    if (combined.contact_assumed == rated)
      text += fmt::format("; hard contact assumed in {}: {}",
                          rated == 1 ? "the 1 test" : fmt::format("all {}", rated), above);
    else if (combined.contact_not_applied == rated)
      text += "; the hard-contact rule not applied: no " + label;
    else
      text += fmt::format("; hard contact assumed in {} of {} ({}), {} without: {} points",
                          combined.contact_assumed, rated, above, combined.contact_not_assumed,
                          FullPointsText(rule.points_without)) +
              (combined.contact_not_applied > 0
                   ? fmt::format(", the rule not applied to {} (no {})", combined.contact_not_applied, label)
                   : std::string());
  }
  return text + ")";
}

// A scale's part: "HIC15 2.3 points on average; a further test scores HIC15 2.2 points expected
// [0.5, 3.6] (80 % prediction interval) and exceeds HIC15 700 with probability 9.3 %".
std::string ScalePart(const MetricLimit& checked, std::size_t g, bool first_interval) {
  const GroupLimitCheck& check = checked.checks[g];
  const std::string label = MetricLabel(checked.limit.metric);
  if (check.tests == 0) return label + " not measured";
  std::string text = label + " " + PointsText(check.mean_points) + " points on average; ";
  if (check.prediction_gap != engine::PredictionGap::kNone) return text + ExceedText(checked, check);
  return text + "a further test scores " + PointsText(check.expected_points) + " points expected [" +
         PointsText(check.points_low) + ", " + PointsText(check.points_high) + "]" +
         (first_interval ? " (80 % prediction interval)" : "") + " and exceeds " + label + " " +
         ValueText(checked.limit.metric, checked.limit.max, 6) + " with probability " +
         FurtherProbabilityText(check.exceed_probability);
}

// A bands limit's part: "HIC15 Good in 3, Acceptable in 2 of 5 (highest 640); a further test is
// beyond Good (HIC15 > 560) with probability 31 %".
std::string BandsPart(const MetricLimit& checked, std::size_t g) {
  const GroupLimitCheck& check = checked.checks[g];
  const Limit& limit = checked.limit;
  const std::string label = MetricLabel(limit.metric);
  if (check.tests == 0) return label + " not measured";
  std::string counts;
  for (std::size_t b = 0; b < limit.bands.size(); ++b)
    if (check.band_counts[b] > 0)
      counts +=
          (counts.empty() ? "" : ", ") + limit.bands[b].name + fmt::format(" in {}", check.band_counts[b]);
  std::string text =
      label + " " + counts +
      fmt::format(" of {} (highest {})", check.tests, util::FormatNumber(check.worst_value, 4));
  const std::string beyond = "beyond " + limit.bands.front().name + " (" + label + " > " +
                             ValueText(limit.metric, limit.max, 6) + ")";
  if (check.prediction_gap != engine::PredictionGap::kNone)
    return text + "; the chance that a further test is " + beyond + " is not estimated (" +
           std::string(engine::PredictionGapText(check.prediction_gap)) + ")";
  return text + "; a further test is " + beyond + " with probability " +
         FurtherProbabilityText(check.exceed_probability);
}

}  // namespace

std::string FurtherProbabilityText(double p) {
  if (!std::isfinite(p)) return "—";
  if (p < 1e-6) return "< 0.0001 %";
  if (p > 1.0 - 1e-6) return "> 99.9999 %";
  const double percent = 100.0 * p;
  if (percent < 1.0) return util::FormatNumber(percent, 2) + " %";  // 0.3 %, 0.0012 %: never "0"
  // One decimal from 1 %, more where one would round a probability below 1 to 100 %.
  std::string text = fmt::format("{:.1f}", percent);
  for (int decimals = 2; text.starts_with("100") && decimals <= 4; ++decimals)
    text = fmt::format("{:.{}f}", percent, decimals);
  return text + " %";
}

std::vector<std::string> LimitSetColumns(const Comparison& comparison, std::size_t s) {
  const LimitSet& set = comparison.limit_sets[s].set;
  std::vector<std::string> columns;
  const std::vector<const MetricLimit*> limits = LimitsOfSet(comparison, s);
  if (std::any_of(limits.begin(), limits.end(),
                  [](const MetricLimit* checked) { return checked->limit.kind == LimitKind::kMaximum; }))
    columns.push_back("meet " + set.name);
  if (set.combined) columns.push_back(set.name + " " + set.combined->name + " points");
  for (const MetricLimit* checked : limits) {
    if (checked->limit.kind == LimitKind::kScale && !set.combined)
      columns.push_back(set.name + " " + MetricLabel(checked->limit.metric) + " points");
    if (checked->limit.kind == LimitKind::kBands)
      columns.push_back(set.name + " " + MetricLabel(checked->limit.metric));
  }
  return columns;
}

std::vector<std::string> LimitSetCells(const Comparison& comparison, std::size_t s, std::size_t g) {
  const ComparedLimitSet& compared = comparison.limit_sets[s];
  const LimitSet& set = compared.set;
  std::vector<std::string> cells;
  const std::vector<const MetricLimit*> limits = LimitsOfSet(comparison, s);
  if (std::any_of(limits.begin(), limits.end(),
                  [](const MetricLimit* checked) { return checked->limit.kind == LimitKind::kMaximum; })) {
    const MaximumCount count = CountMaximum(comparison, limits, g);
    cells.push_back(fmt::format("{} of {}", count.tested.size() - count.failing.size(), count.tested.size()));
  }
  if (set.combined) {
    const GroupCombinedPoints& combined = compared.combined[g];
    cells.push_back(combined.tests == 0
                        ? "—"
                        : PointsText(combined.mean_points) + " of " + FullPointsText(CombinedMaxPoints(set)));
  }
  for (const MetricLimit* checked : limits) {
    const GroupLimitCheck& check = checked->checks[g];
    if (checked->limit.kind == LimitKind::kScale && !set.combined)
      cells.push_back(check.tests == 0
                          ? "—"
                          : PointsText(check.mean_points) + " of " + FullPointsText(checked->limit.points));
    if (checked->limit.kind == LimitKind::kBands) {
      std::string counts;
      for (std::size_t b = 0; b < checked->limit.bands.size(); ++b)
        if (check.band_counts[b] > 0)
          counts += (counts.empty() ? "" : ", ") +
                    fmt::format("{} {}", check.band_counts[b], checked->limit.bands[b].name);
      cells.push_back(counts.empty() ? "—" : counts);
    }
  }
  return cells;
}

std::string LimitSetClause(const Comparison& comparison, std::size_t s, std::size_t g) {
  const ComparedLimitSet& compared = comparison.limit_sets[s];
  const std::vector<const MetricLimit*> limits = LimitsOfSet(comparison, s);
  if (limits.empty()) return compared.set.name + " not checked: the series has none of its criteria";
  std::vector<std::string> parts;
  const bool maximum = std::any_of(limits.begin(), limits.end(), [](const MetricLimit* checked) {
    return checked->limit.kind == LimitKind::kMaximum;
  });
  if (maximum) parts.push_back(MaximumPart(comparison, limits, g));
  if (compared.set.combined) parts.push_back(CombinedPart(comparison, s, g));
  bool first_interval = true;
  for (const MetricLimit* checked : limits) {
    if (checked->limit.kind == LimitKind::kScale) {
      parts.push_back(ScalePart(*checked, g, first_interval));
      if (checked->checks[g].prediction_gap == engine::PredictionGap::kNone) first_interval = false;
    }
    if (checked->limit.kind == LimitKind::kBands) parts.push_back(BandsPart(*checked, g));
  }
  std::string text;
  for (const std::string& part : parts) text += (text.empty() ? "" : "; ") + part;
  return maximum ? text : compared.set.name + ": " + text;
}

std::string LimitSetNote(const Comparison& comparison, std::size_t s) {
  const LimitSet& set = comparison.limit_sets[s].set;
  const std::vector<const MetricLimit*> limits = LimitsOfSet(comparison, s);
  const auto has = [&](LimitKind kind) {
    return std::any_of(limits.begin(), limits.end(),
                       [&](const MetricLimit* checked) { return checked->limit.kind == kind; });
  };
  std::string note = set.name + (set.version.empty() ? "" : " (version " + set.version + ")") + ": ";
  std::vector<std::string> parts;
  if (has(LimitKind::kMaximum))
    parts.push_back(
        "the tests whose every limited criterion is within its limit, and per criterion the highest value "
        "and its "
        "margin, 100 (limit − highest) / limit");
  if (has(LimitKind::kScale))
    parts.push_back(
        "points on the protocol's sliding scales, full at or below the higher performance limit, none at or "
        "above "
        "the lower, linear between");
  if (set.combined) parts.push_back("the " + set.combined->name + "'s points: " + set.combined->requirement);
  if (set.hard_contact) parts.push_back(set.hard_contact->requirement);
  if (has(LimitKind::kBands))
    parts.push_back("each test's rating band, each band up to and including its upper value");
  parts.push_back(
      "a further test: from the variant's tests on the log scale (mean m and sd s of the n logs), the chance "
      "it "
      "exceeds the limit L, 1 − T_{n−1}((ln L − m) / (s √(1 + 1/n))) (Student's t with n − 1 degrees of "
      "freedom), "
      "and on a scale its expected points with their 80 % prediction interval; not estimated with fewer than "
      "3 "
      "tests or without spread");
  for (std::size_t i = 0; i < parts.size(); ++i) note += (i == 0 ? "" : "; ") + parts[i];
  note += ". Source: " + set.source + ".";
  if (!set.note.empty()) note += " " + set.note;
  return note;
}

}  // namespace napkin::app

#include "app/verdict.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <optional>
#include <set>
#include <utility>

#include "app/verdict_limits.h"
#include "common/joined.h"
#include "engine/summary_fields.h"
#include "util/text.h"

namespace napkin::app {
namespace {

// U+2212, the minus sign of the wording ("−9 % [−27, +8]").
constexpr std::string_view kMinus = "\xE2\x88\x92";

// "+8", "−9", "0": a signed percentage (PercentText's digits).
std::string Signed(double pct) {
  const std::string magnitude = PercentText(std::abs(pct));
  if (magnitude == "0") return magnitude;
  return (pct < 0 ? std::string(kMinus) : std::string("+")) + magnitude;
}

// A difference in the metric's unit (where the baseline mean is 0): 3 significant digits.
std::string Units(double value) { return util::FormatNumber(value, 3); }

// A probability (0..1) in %: one decimal from 1 %, two significant digits below.
std::string Probability(double p) {
  if (!std::isfinite(p)) return "—";
  const double percent = 100.0 * p;
  if (percent == 0.0) return "0 %";
  if (std::abs(percent) >= 1.0) return fmt::format("{:.1f} %", percent);
  return util::FormatNumber(percent, 2) + " %";
}

// Two risks shown as a change: with as many digits as tell them apart (up to four significant), so
// that a change is never printed as "7.7 % → 7.7 %"; the same at four digits: nullopt.
std::optional<std::pair<std::string, std::string>> DistinctProbabilities(double from, double to) {
  std::pair<std::string, std::string> shown{Probability(from), Probability(to)};
  for (int digits = 2; shown.first == shown.second && digits <= 4; ++digits)
    shown = {util::FormatNumber(100.0 * from, digits) + " %", util::FormatNumber(100.0 * to, digits) + " %"};
  if (shown.first == shown.second) return std::nullopt;
  return shown;
}

std::string Counts(const ComparisonRow& row, const ComparisonRow& baseline) {
  return fmt::format("n = {} vs {}", row.description.n, baseline.description.n);
}

bool Below(double p) { return std::isfinite(p) && p < kVerdictAlpha; }

const MetricComparison* FindMetric(const Comparison& comparison, std::string_view name) {
  for (const MetricComparison& metric : comparison.metrics)
    if (metric.metric == name) return &metric;
  return nullptr;
}

bool HasValues(const MetricComparison& metric) {
  return std::any_of(metric.groups.begin(), metric.groups.end(),
                     [](const GroupValues& values) { return !values.values.empty(); });
}

bool IsRotationCriterion(std::string_view name) {
  const engine::SummaryField* field = engine::FindSummaryField(name);
  return field != nullptr && field->group == engine::SummaryGroup::kRotation;
}

// The parenthetical's last words for a ratio metric compared linearly.
std::string FallbackNote(const ComparisonRow& row) {
  return row.log_fallback ? ", difference of means: a value ≤ 0" : "";
}

// A criterion of the verdict and the risks computed from it.
struct VerdictMetric {
  const MetricComparison* metric;
  std::string label;
  bool rotation;
  std::vector<std::pair<const MetricComparison*, std::string>> risks;  // with their labels
};

std::vector<VerdictMetric> VerdictMetrics(const Comparison& comparison) {
  std::vector<VerdictMetric> metrics;
  for (const std::string& criterion : VerdictCriteria()) {
    const MetricComparison* metric = FindMetric(comparison, criterion);
    if (metric == nullptr || !HasValues(*metric)) continue;
    VerdictMetric& entry = metrics.emplace_back(
        VerdictMetric{metric, MetricLabel(criterion), IsRotationCriterion(criterion), {}});
    for (const engine::SummaryField* field : engine::RiskFields()) {  // the risks read from it
      const MetricComparison* risk = FindMetric(comparison, field->name);
      if (field->curve->criterion == criterion && risk != nullptr && HasValues(*risk))
        entry.risks.emplace_back(risk, MetricLabel(field->name));
    }
  }
  return metrics;
}

}  // namespace

const VerdictRule& RuleOf(ClauseKind kind) {
  for (const VerdictRule& rule : kVerdictRules)
    if (rule.kind == kind) return rule;
  return kVerdictRules[0];  // every kind has a rule (tests/app/verdict_test.cpp)
}

std::vector<std::string> VerdictCriteria() {
  std::vector<std::string> criteria;
  for (const engine::SummaryField& field : engine::SummaryFields())
    if (field.in_verdict) criteria.emplace_back(field.name);
  return criteria;
}

std::string MetricLabel(std::string_view name) {
  const engine::SummaryField* field = engine::FindSummaryField(name);
  return field != nullptr ? engine::FieldLabel(*field) : std::string(name);
}

std::string PValueText(double p) {
  if (!std::isfinite(p)) return "p = —";
  if (p < 1e-4) return "p < 0.0001";
  for (int digits = 2; digits < 17; ++digits) {
    const std::string text = util::FormatNumber(p, digits);
    const std::optional<double> read = util::ParseDouble(text);
    if (read && (*read < kVerdictAlpha) == (p < kVerdictAlpha)) return "p = " + text;
  }
  return "p = " + util::FormatNumber(p);
}

std::string PercentText(double pct) {
  if (!std::isfinite(pct)) return "—";
  if (pct == 0.0) return "0";
  const std::string sign = pct < 0 ? std::string(kMinus) : std::string();
  const double magnitude = std::abs(pct);
  if (magnitude >= 0.95) return sign + fmt::format("{:.0f}", magnitude);
  return sign + util::FormatNumber(magnitude, 2);  // 0.3, 0.042: never "0"
}

ClauseKind ClassifyClause(const ComparisonRow& row, const ComparisonRow& baseline, bool rotation_criterion) {
  const engine::Description& a = row.description;
  const engine::Description& b = baseline.description;
  if (rotation_criterion && (a.n == 0 || b.n == 0)) return ClauseKind::kNotMeasured;
  if (a.n < 2 || b.n < 2 || !std::isfinite(row.difference.diff)) return ClauseKind::kTooFew;
  if (a.min == a.max && b.min == b.max && a.min == b.min) return ClauseKind::kIdentical;
  if (!std::isfinite(row.difference.ci_low) || !std::isfinite(row.difference.p_value))
    return ClauseKind::kNoScatter;
  if (Below(row.difference.p_value)) return ClauseKind::kSignificant;
  if (Below(row.equivalence.p_value)) return ClauseKind::kEquivalent;
  return ClauseKind::kInconclusive;
}

std::string CriterionClause(std::string_view label, const ComparisonRow& row, const ComparisonRow& baseline,
                            bool rotation_criterion, bool with_counts) {
  const std::string name(label);
  const std::string counts = Counts(row, baseline);
  const std::string tail = (with_counts ? ", " + counts : "") + FallbackNote(row);
  const engine::MeanDifference& d = row.difference;
  const bool percent = std::isfinite(row.pct);
  const double main = percent ? row.pct : d.diff;
  const std::string unit = percent ? " %" : "";
  const auto magnitude = [&](double value) {
    return percent ? PercentText(std::abs(value)) : Units(std::abs(value));
  };
  const auto signed_value = [&](double value) {
    if (percent) return Signed(value);
    // Appended, not `"+" + temporary` (GCC 12's false -Wrestrict, util/text.h InQuotes).
    std::string text = value > 0 ? "+" : "";
    text += Units(value);
    return text;
  };
  const std::string verb = main < 0 ? "lowers " : "raises ";
  switch (ClassifyClause(row, baseline, rotation_criterion)) {
    case ClauseKind::kNotMeasured:
      return row.description.n == 0
                 ? name + " not measured (acceleration-only heads)"
                 : name + " not measured in " + baseline.group + " (acceleration-only heads)";
    case ClauseKind::kTooFew:
      return "no " + name + " comparison (" + counts + ": fewer than 2 tests)";
    case ClauseKind::kIdentical:
      return fmt::format("{} identical in all {} tests", name, row.description.n + baseline.description.n);
    case ClauseKind::kNoScatter:
      return verb + name + " by " + magnitude(main) + unit + " (no scatter: no interval, " + counts +
             FallbackNote(row) + ")";
    case ClauseKind::kSignificant: {
      // A lowering's interval as reductions: [−high, −low], both positive.
      const double low = percent ? row.pct_ci_low : d.ci_low;
      const double high = percent ? row.pct_ci_high : d.ci_high;
      const double from = main < 0 ? -high : low;
      const double to = main < 0 ? -low : high;
      std::string text = verb + name + " by " + magnitude(main) + unit + " [" +
                         (percent ? PercentText(from) : Units(from)) + ", " +
                         (percent ? PercentText(to) : Units(to)) + "] (" + PValueText(d.p_value) + tail + ")";
      if (Below(row.equivalence.p_value))
        text += ", a change within ±" + util::FormatNumber(row.equivalence_pct, 6) + " %";
      return text;
    }
    case ClauseKind::kEquivalent: {
      const double low = percent ? row.equivalence_ci_low_pct : row.equivalence.ci_low;
      const double high = percent ? row.equivalence_ci_high_pct : row.equivalence.ci_high;
      return name + " equivalent within ±" + util::FormatNumber(row.equivalence_pct, 6) +
             " % (90 % interval " + signed_value(low) + unit + " to " + signed_value(high) + unit + tail +
             ")";
    }
    case ClauseKind::kInconclusive: {
      const double low = percent ? row.pct_ci_low : d.ci_low;
      const double high = percent ? row.pct_ci_high : d.ci_high;
      std::string text = "no significant difference in " + name + " (" + signed_value(main) + unit + " [" +
                         signed_value(low) + ", " + signed_value(high) + "], " + PValueText(d.p_value);
      if (std::isfinite(row.mdd_low_pct) && std::isfinite(row.mdd_high_pct)) {
        const bool symmetric = PercentText(-row.mdd_low_pct) == PercentText(row.mdd_high_pct);
        text += fmt::format("; {} vs {} tests detect ", row.description.n, baseline.description.n) +
                (symmetric ? "±" + PercentText(row.mdd_high_pct) + " %"
                           : Signed(row.mdd_low_pct) + " % or " + Signed(row.mdd_high_pct) + " %") +
                " with 80 % power";
      }
      return text + FallbackNote(row) + ")";
    }
  }
  return name;
}

std::string RiskConsequence(std::string_view label, ClauseKind criterion_clause, const ComparisonRow& row,
                            const ComparisonRow& baseline) {
  const std::string from = Probability(baseline.description.mean);
  const std::string to = Probability(row.description.mean);
  switch (criterion_clause) {
    case ClauseKind::kNotMeasured:
    case ClauseKind::kTooFew:
      return "";
    case ClauseKind::kIdentical:
      return std::string(label) + " " + to + " in both";
    case ClauseKind::kSignificant:
    case ClauseKind::kNoScatter: {
      const auto distinct = DistinctProbabilities(baseline.description.mean, row.description.mean);
      if (!distinct)
        return std::string(label) + " " + util::FormatNumber(100.0 * row.description.mean, 4) +
               " % in both at the precision shown";
      return std::string(label) + " " + distinct->first + " → " + distinct->second;
    }
    case ClauseKind::kEquivalent:
    case ClauseKind::kInconclusive:
      return std::string(label) + " " + from + " vs " + to;
  }
  return "";
}

SeriesVerdict BuildVerdict(const Comparison& comparison) {
  SeriesVerdict verdict;
  verdict.series = comparison.series;
  verdict.baseline = comparison.baseline;
  const std::vector<VerdictMetric> metrics = VerdictMetrics(comparison);
  const std::size_t sets = comparison.limit_sets.size();
  verdict.columns = {"variant", "tests"};
  for (const VerdictMetric& metric : metrics) {
    verdict.columns.push_back(metric.label + " mean ± sd");
    for (const auto& [risk, label] : metric.risks) verdict.columns.push_back(label);
  }
  for (std::size_t set = 0; set < sets; ++set)
    for (std::string& column : LimitSetColumns(comparison, set)) verdict.columns.push_back(std::move(column));

  for (std::size_t g = 0; g < comparison.groups.size(); ++g) {
    std::vector<std::string>& cells = verdict.rows.emplace_back();
    cells.push_back(comparison.groups[g]);
    std::size_t tests = 0;
    for (const VerdictMetric& metric : metrics) {
      const engine::Description& d = metric.metric->rows[g].description;
      tests = std::max(tests, d.n);
      cells.push_back(d.n == 0
                          ? "—"
                          : util::FormatNumber(d.mean, 4) +
                                (std::isfinite(d.sd) ? " ± " + util::FormatNumber(d.sd, 3) : std::string()));
      for (const auto& [risk, label] : metric.risks)
        cells.push_back(Probability(risk->rows[g].description.mean));
    }
    for (std::size_t set = 0; set < sets; ++set)
      for (std::string& cell : LimitSetCells(comparison, set, g)) cells.push_back(std::move(cell));
    cells.insert(cells.begin() + 1, std::to_string(tests));
    if (g == 0) {  // the baseline: its limits, when asked for
      std::string clauses;
      for (std::size_t set = 0; set < sets; ++set)
        clauses += (set == 0 ? "" : "; ") + LimitSetClause(comparison, set, 0);
      if (sets > 0) verdict.sentences.push_back(comparison.groups[0] + " (baseline): " + clauses);
      continue;
    }

    std::vector<std::string> clauses;
    std::optional<std::pair<std::size_t, std::size_t>> first_counts;
    for (const VerdictMetric& metric : metrics) {
      const ComparisonRow& row = metric.metric->rows[g];
      const ComparisonRow& baseline = metric.metric->rows.front();
      const std::pair<std::size_t, std::size_t> counts{row.description.n, baseline.description.n};
      const bool with_counts = !first_counts || counts != *first_counts;
      if (!first_counts) first_counts = counts;
      std::string clause = CriterionClause(metric.label, row, baseline, metric.rotation, with_counts);
      const ClauseKind kind = ClassifyClause(row, baseline, metric.rotation);
      std::string risks;  // " → P(AIS 3+ | BrIC) 21.9 % vs 20.6 %, P(AIS 4+ | BrIC) ..."
      for (const auto& [risk, label] : metric.risks) {
        const std::string consequence = RiskConsequence(label, kind, risk->rows[g], risk->rows.front());
        if (!consequence.empty()) risks += (risks.empty() ? " → " : ", ") + consequence;
      }
      clause += risks;
      clauses.push_back(std::move(clause));
    }
    for (std::size_t set = 0; set < sets; ++set) clauses.push_back(LimitSetClause(comparison, set, g));
    if (clauses.empty()) clauses.push_back("none of the verdict's criteria has a value");
    // Results of salvaged channels are said (docs/algorithms.md "Faulty channels").
    if (g < comparison.salvaged_per_group.size() && comparison.salvaged_per_group[g] > 0)
      clauses.push_back(fmt::format("{} of {} tests salvaged from a faulty channel",
                                    comparison.salvaged_per_group[g], comparison.tests_per_group[g]));
    std::string sentence = comparison.groups[g] + ": ";
    for (std::size_t c = 0; c < clauses.size(); ++c) sentence += (c == 0 ? "" : "; ") + clauses[c];
    verdict.sentences.push_back(sentence);
  }
  return verdict;
}

std::string VerdictNote(const Comparison& comparison) {
  std::string note = "Each variant against " + comparison.baseline +
                     ", criterion by criterion, by the first rule that applies: ";
  bool first = true;
  for (const VerdictRule& rule : kVerdictRules) {
    note += (first ? "" : "; ") + std::string(rule.when) + " (\"" + std::string(rule.example) + "\")";
    first = false;
  }
  note += fmt::format(
      ". Changes are in % of the baseline with their 95 % confidence interval (Welch's t) and two-sided p; "
      "{}; "
      "the equivalence margin is ±{} % (90 % interval). Risks P(AIS n+ | criterion) are functions of their "
      "criterion and follow its clause (mean risk of the baseline, then of the variant: → where the "
      "criterion "
      "changed significantly, vs where not); they are not tested separately.",
      comparison.scale == CompareScale::kLog
          ? "positive criteria (HIC, BrIC, DAMAGE, accelerations, angular rates) as the ratio of geometric "
            "means "
            "(Welch's t on the logs), 100 (ratio − 1); others, and any with a value ≤ 0, as the difference "
            "of "
            "means in % of the baseline mean"
          : "every criterion as the difference of means in % of the baseline mean (--scale linear)",
      util::FormatNumber(comparison.equivalence_pct, 6));
  for (std::size_t set = 0; set < comparison.limit_sets.size(); ++set) {
    note += ' ';  // not `" " + temporary` (GCC 12's false -Wrestrict, util/text.h InQuotes)
    note += LimitSetNote(comparison, set);
  }
  return note;
}

std::string FormatVerdict(const SeriesVerdict& verdict) {
  std::string text = fmt::format(
      "verdict on series {} against '{}' (positive criteria as ratios of geometric means, 95 % confidence "
      "intervals, Welch's t; significant where p < {}; equivalent only where two one-sided tests show it):\n",
      util::EscapeControl(verdict.series), util::EscapeControl(verdict.baseline), kVerdictAlpha);
  for (const std::string& sentence : verdict.sentences) text += "  " + util::EscapeControl(sentence) + "\n";
  return text;
}

}  // namespace napkin::app

#include "cli/verdict.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "util/text.h"

namespace napkin::cli {
namespace {

// U+2212, the minus sign of the wording ("−9 % [−27, +8]").
constexpr std::string_view kMinus = "\xE2\x88\x92";

struct CriterionLabel {
  std::string_view name, label;
};
constexpr CriterionLabel kLabels[] = {
    {"hic15", "HIC15"},
    {"hic36", "HIC36"},
    {"hic", "HIC"},
    {"hic_d", "HIC(d)"},
    {"bric", "BrIC"},
    {"damage", "DAMAGE"},
    {"a3ms_g", "a3ms"},
    {"peak_acc_g", "peak acceleration"},
    {"peak_omega_radps", "peak angular velocity"},
    {"peak_alpha_radps2", "peak angular acceleration"},
    {"max_rotation_deg", "max rotation"},
};

std::vector<std::string> Parts(std::string_view name) {
  std::vector<std::string> parts;
  std::size_t begin = 0;
  for (std::size_t at = 0; at <= name.size(); ++at) {
    if (at == name.size() || name[at] == '_') {
      parts.emplace_back(name.substr(begin, at - begin));
      begin = at + 1;
    }
  }
  return parts;
}

// The criterion a risk of no verdict criterion belongs to: "HIC36" for
// "hic36_p_ais4" (a part with a label), else the field's name.
std::string OwnerLabel(std::string_view risk) {
  for (const std::string& part : Parts(risk))
    for (const CriterionLabel& known : kLabels)
      if (known.name == part) return std::string(known.label);
  return std::string(risk);
}

// A percentage, rounded to whole percent (one decimal below 1 %, so a small
// change does not read 0 %): `decimals` from the clause's main number.
int PercentDecimals(double main) { return std::abs(main) < 0.95 ? 1 : 0; }

std::string Fixed(double value, int decimals) { return fmt::format("{:.{}f}", value, decimals); }

// "44", "0.12" (3 significant digits where the difference is in the metric's unit).
std::string Magnitude(double value, bool percent, int decimals) {
  return percent ? Fixed(std::abs(value), decimals) : util::FormatNumber(std::abs(value), 3);
}

// "−9", "+8", "0".
std::string Signed(double value, bool percent, int decimals) {
  std::string magnitude = Magnitude(value, percent, decimals);
  if (magnitude.find_first_not_of("0.") == std::string::npos) return magnitude;
  return (value < 0 ? std::string(kMinus) : std::string("+")) + magnitude;
}

// A probability (0..1) in %: one decimal from 1 %, two significant digits below.
std::string Probability(double p) {
  if (!std::isfinite(p)) return "—";
  const double percent = 100.0 * p;
  if (percent == 0.0) return "0 %";
  if (std::abs(percent) >= 1.0) return Fixed(percent, 1) + " %";
  return util::FormatNumber(percent, 2) + " %";
}

std::string Counts(const ComparisonRow& row, const engine::Description& baseline) {
  return fmt::format("n = {} vs {}", row.description.n, baseline.n);
}

bool Significant(double p) { return std::isfinite(p) && p < kVerdictAlpha; }

const MetricComparison* FindMetric(const Comparison& comparison, std::string_view name) {
  for (const MetricComparison& metric : comparison.metrics)
    if (metric.metric == name) return &metric;
  return nullptr;
}

bool HasValues(const MetricComparison& metric) {
  return std::any_of(metric.groups.begin(), metric.groups.end(),
                     [](const GroupValues& values) { return !values.values.empty(); });
}

// A metric of the verdict, in sentence order.
struct VerdictMetric {
  const MetricComparison* metric;
  bool risk;
  std::string label;         // in a sentence
  std::string column_label;  // in the table
};

std::vector<VerdictMetric> VerdictMetrics(const Comparison& comparison) {
  const std::vector<std::string> criteria = VerdictCriteria();
  std::vector<VerdictMetric> metrics;
  std::vector<const MetricComparison*> placed;
  auto risks_of = [&](const std::optional<std::string>& criterion) {
    for (const MetricComparison& metric : comparison.metrics) {
      const std::optional<RiskMetric> risk = IsRiskMetric(metric.metric, criteria);
      if (!risk || risk->criterion != criterion || !HasValues(metric)) continue;
      if (std::find(placed.begin(), placed.end(), &metric) != placed.end()) continue;
      placed.push_back(&metric);
      const std::string label = MetricLabel(metric.metric);
      const std::string owner = criterion ? MetricLabel(*criterion) : OwnerLabel(metric.metric);
      // Next to its criterion the risk's label is enough; elsewhere it names it.
      metrics.push_back({&metric, true,
                         criterion ? label : label.substr(0, label.size() - 1) + ", " + owner + ")",
                         fmt::format("{} {}", label, owner)});
    }
  };
  for (const std::string& criterion : criteria) {
    const MetricComparison* metric = FindMetric(comparison, criterion);
    if (metric == nullptr || !HasValues(*metric)) continue;
    metrics.push_back({metric, false, MetricLabel(criterion), MetricLabel(criterion)});
    risks_of(criterion);
  }
  risks_of(std::nullopt);
  return metrics;
}

}  // namespace

std::vector<std::string> VerdictCriteria() { return {"hic15", "bric"}; }

std::optional<RiskMetric> IsRiskMetric(std::string_view name, const std::vector<std::string>& criteria) {
  std::optional<RiskMetric> risk;
  const std::vector<std::string> parts = Parts(name);
  for (const std::string& part : parts)
    if (part.size() > 3 && part.compare(0, 3, "ais") == 0 && part[3] >= '0' && part[3] <= '9')
      risk = RiskMetric{part[3] - '0', std::nullopt};
  if (!risk) return risk;
  for (const std::string& part : parts)
    if (std::find(criteria.begin(), criteria.end(), part) != criteria.end()) risk->criterion = part;
  return risk;
}

std::string MetricLabel(std::string_view name) {
  for (const CriterionLabel& known : kLabels)
    if (known.name == name) return std::string(known.label);
  const std::vector<std::string> criteria = VerdictCriteria();
  if (const std::optional<RiskMetric> risk = IsRiskMetric(name, criteria))
    return fmt::format("P(AIS {}+)", risk->ais_level);
  return std::string(name);
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

std::string CriterionClause(std::string_view label, const ComparisonRow& row,
                            const engine::Description& baseline, bool first, bool with_counts) {
  const engine::MeanDifference& d = row.difference;
  const std::string name(label);
  const std::string counts = Counts(row, baseline);
  if (!std::isfinite(d.diff))
    return (first ? "has no " : "no ") + name + " comparison (" + counts + ": fewer than 2 tests)";
  const bool percent = std::isfinite(d.diff_pct) && std::isfinite(row.baseline_mean);
  const double main = percent ? d.diff_pct : d.diff;
  const int decimals = PercentDecimals(main);
  const std::string unit = percent ? " %" : "";
  const std::string verb = d.diff < 0 ? "lowers " : "raises ";
  const std::string tail = with_counts ? ", " + counts : "";
  if (!std::isfinite(d.ci_low) || !std::isfinite(d.p_value)) {
    if (d.diff == 0.0)
      return (first ? "has the same " : "the same ") + name + " in every test (" + counts + ")";
    return verb + name + " by " + Magnitude(main, percent, decimals) + unit + " (no interval: no scatter, " +
           counts + ")";
  }
  const double scale = percent ? 100.0 / row.baseline_mean : 1.0;
  const double low = d.ci_low * scale;
  const double high = d.ci_high * scale;
  if (Significant(d.p_value)) {
    // A lowering's interval as reductions: [−high, −low], both positive.
    const double from = d.diff < 0 ? -high : low;
    const double to = d.diff < 0 ? -low : high;
    return verb + name + " by " + Magnitude(main, percent, decimals) + unit + " [" +
           (percent ? Fixed(from, decimals) : util::FormatNumber(from, 3)) + ", " +
           (percent ? Fixed(to, decimals) : util::FormatNumber(to, 3)) + "] (" + PValueText(d.p_value) +
           tail + ")";
  }
  return (first ? "leaves " + name + " unchanged (" : name + " unchanged (") +
         Signed(main, percent, decimals) + unit + " [" + Signed(low, percent, decimals) + ", " +
         Signed(high, percent, decimals) + "], " + PValueText(row.difference.p_value) + tail + ")";
}

std::string RiskClause(std::string_view label, const ComparisonRow& row, const engine::Description& baseline,
                       bool with_counts) {
  const std::string name(label);
  const std::string from = Probability(baseline.mean);
  const std::string to = Probability(row.description.mean);
  const std::string counts = Counts(row, baseline);
  const double p = row.difference.p_value;
  if (Significant(p)) return name + " from " + from + " to " + to + (with_counts ? " (" + counts + ")" : "");
  if (std::isfinite(p))
    return name + " unchanged (" + from + " vs " + to + ", " + PValueText(p) +
           (with_counts ? ", " + counts : "") + ")";
  if (from == to) return name + " " + from + " in both (" + counts + ")";
  return name + " " + from + " vs " + to +
         " (no p-value: " + (std::isfinite(row.difference.diff) ? "no scatter" : "fewer than 2 tests") +
         ", " + counts + ")";
}

SeriesVerdict BuildVerdict(const Comparison& comparison) {
  SeriesVerdict verdict;
  verdict.series = comparison.series;
  verdict.baseline = comparison.baseline;
  const std::vector<VerdictMetric> metrics = VerdictMetrics(comparison);
  verdict.columns = {"variant", "tests"};
  for (const VerdictMetric& metric : metrics)
    verdict.columns.push_back(metric.risk ? metric.column_label : metric.column_label + " mean ± sd");

  for (std::size_t g = 0; g < comparison.groups.size(); ++g) {
    std::vector<std::string>& cells = verdict.rows.emplace_back();
    cells.push_back(comparison.groups[g]);
    std::size_t tests = 0;
    for (const VerdictMetric& metric : metrics) {
      const engine::Description& d = metric.metric->rows[g].description;
      tests = std::max(tests, d.n);
      if (metric.risk)
        cells.push_back(Probability(d.mean));
      else if (d.n == 0)
        cells.push_back("—");
      else
        cells.push_back(util::FormatNumber(d.mean, 4) +
                        (std::isfinite(d.sd) ? " ± " + util::FormatNumber(d.sd, 3) : std::string()));
    }
    cells.insert(cells.begin() + 1, std::to_string(tests));
    if (g == 0) continue;  // the baseline

    std::string sentence = comparison.groups[g];
    std::optional<std::pair<std::size_t, std::size_t>> first_counts;
    for (const VerdictMetric& metric : metrics) {
      const ComparisonRow& row = metric.metric->rows[g];
      const engine::Description& baseline = metric.metric->rows.front().description;
      const std::pair<std::size_t, std::size_t> counts{row.description.n, baseline.n};
      const bool first = !first_counts;
      const bool with_counts = first || counts != *first_counts;
      if (first) first_counts = counts;
      const std::string clause = metric.risk
                                     ? RiskClause(metric.label, row, baseline, with_counts)
                                     : CriterionClause(metric.label, row, baseline, first, with_counts);
      sentence += (first ? (metric.risk ? ": " : " ") : "; ") + clause;
    }
    if (!first_counts) sentence += ": none of the verdict's criteria has a value";
    verdict.sentences.push_back(sentence);
  }
  return verdict;
}

std::string FormatVerdict(const SeriesVerdict& verdict) {
  std::string text = fmt::format(
      "verdict on series {} against '{}' (mean differences, 95 % confidence intervals, Welch's t; "
      "significant where p < {}):\n",
      util::EscapeControl(verdict.series), util::EscapeControl(verdict.baseline), kVerdictAlpha);
  for (const std::string& sentence : verdict.sentences) text += "  " + util::EscapeControl(sentence) + "\n";
  return text;
}

}  // namespace napkin::cli

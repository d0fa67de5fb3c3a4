// The comparison as people and programs read it (app/comparison.h): the
// table of `napkin compare --format csv|json` (ComparisonTable), its text
// for people (kTable), and the cells' wording. The statistics behind them
// are app/comparison.cpp.
#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string_view>

#include "app/comparison.h"
#include "app/limits.h"
#include "common/joined.h"
#include "engine/summary_fields.h"
#include "util/text.h"

namespace napkin::app {
namespace {

// A cell without a value (NULL in JSON, empty in CSV).
constexpr double kEmptyCell = std::numeric_limits<double>::quiet_NaN();

// n_for_80pct_power as an integer cell, or NULL.
db::Cell PowerCell(double n) {
  if (!std::isfinite(n)) return std::monostate{};
  return static_cast<std::int64_t>(n);
}

std::string PowerText(double n) {
  return std::isfinite(n) ? fmt::format("{}", static_cast<long long>(n)) : "-";
}

std::string Number(double value) { return std::isfinite(value) ? fmt::format("{:.6g}", value) : "-"; }

// "-23.1 % [-31.0, -15.2] p=0.0004": the change and its interval in % of
// the baseline (on the log scale: of its geometric mean), or the difference
// in the metric's unit when the baseline mean is 0.
std::string DifferenceText(const ComparisonRow& row, CompareBy by) {
  if (row.is_baseline) return "(baseline)";
  const engine::MeanDifference& d = row.difference;
  const std::string paired = by == CompareBy::kConfig ? fmt::format(" ({} pairs)", row.pairs) : "";
  if (!std::isfinite(d.diff)) return "n < 2: no difference (1)" + paired;
  const bool percent = std::isfinite(row.pct);
  std::string text = percent ? fmt::format("{:+.1f} %", row.pct) : fmt::format("{:+.4g}", d.diff);
  if (!std::isfinite(d.ci_low)) return text + " (no scatter: no interval)" + paired;
  if (percent)
    text += fmt::format(" [{:+.1f}, {:+.1f}]", row.pct_ci_low, row.pct_ci_high);
  else
    text += fmt::format(" [{:+.4g}, {:+.4g}]", d.ci_low, d.ci_high);
  return text + "  " + ComparisonPValueText(d.p_value) + paired;
}

// "-33/+49 %": the smallest fall and rise these tests detect with 80 % power.
std::string DetectableText(const ComparisonRow& row) {
  if (!std::isfinite(row.mdd_low_pct) || !std::isfinite(row.mdd_high_pct)) return "-";
  // Whole percent from 0.95 %, two significant digits below: a small change never reads 0.
  const auto magnitude = [](double pct) {
    return std::abs(pct) >= 0.95 ? fmt::format("{:.0f}", std::abs(pct))
                                 : util::FormatNumber(std::abs(pct), 2);
  };
  // Appended, not concatenated: GCC 12's false -Wrestrict on `"-" + std::string` inlined here.
  std::string text = "-";
  text.append(magnitude(row.mdd_low_pct)).append("/+").append(magnitude(row.mdd_high_pct)).append(" %");
  return text;
}

// "yes p=0.003" where equivalence within the margin is shown (TOST p < 0.05), "no p=0.41" where not.
std::string EquivalenceText(const ComparisonRow& row) {
  const double p = row.equivalence.p_value;
  if (row.is_baseline || !std::isfinite(p)) return "-";
  return (p < engine::kEquivalenceAlpha ? "yes " : "no ") + ComparisonPValueText(p);
}

// What the block of a metric compares: its scale.
std::string ScaleNote(const MetricComparison& metric) {
  for (const ComparisonRow& row : metric.rows) {
    if (row.log_fallback) return " (difference of means: a value <= 0 rules out the log scale)";
    if (!row.is_baseline && row.scale == CompareScale::kLog) return " (log scale: ratio of geometric means)";
  }
  return "";
}

// "0.3 %": a probability in % with two significant digits ("<0.0001 %" below).
std::string ProbabilityPercent(double p) {
  if (!std::isfinite(p)) return "-";
  if (p < 1e-6) return "<0.0001 %";
  if (p > 1.0 - 1e-6) return ">99.9999 %";
  // Two significant digits of the smaller of p and 1 - p: 0.35 %, 14 %, 99.8 %.
  const double percent = 100.0 * p;
  const int digits = percent < 90.0 ? 2 : 3 + static_cast<int>(std::ceil(-std::log10(100.0 - percent)));
  return util::FormatNumber(percent, digits) + " %";
}

// A further test's figures for the table: "P(> 700) 0.3 %" and on a scale
// "points 2.1 [0.4, 3.5]", or why they are not estimated.
std::string FurtherTestText(const Limit& limit, const GroupLimitCheck& check) {
  if (check.prediction_gap != engine::PredictionGap::kNone)
    return "further test not estimated (" + std::string(engine::PredictionGapText(check.prediction_gap)) +
           ")";
  std::string text =
      "P(further > " + util::FormatNumber(limit.max, 6) + ") " + ProbabilityPercent(check.exceed_probability);
  if (limit.kind == LimitKind::kScale)
    text += fmt::format(", further points {} [{}, {}]", util::FormatNumber(check.expected_points, 3),
                        util::FormatNumber(check.points_low, 3), util::FormatNumber(check.points_high, 3));
  return text;
}

// The line under a metric's block for one of its limits: per group how many
// tests are within it (and on a scale their mean points, with bands the
// tests per band), the worst, and a further test.
std::string LimitLine(const Comparison& comparison, const MetricLimit& checked) {
  const Limit& limit = checked.limit;
  const std::string& name = comparison.limit_sets[checked.set].set.name;
  std::string out;
  switch (limit.kind) {
    case LimitKind::kMaximum:
      out = fmt::format("  {} limit {}: ", name, util::FormatNumber(limit.max, 6));
      break;
    case LimitKind::kScale:
      out = fmt::format("  {} scale {} to {} ({} to 0 points): ", name,
                        util::FormatNumber(limit.higher_limit, 6), util::FormatNumber(limit.max, 6),
                        util::FormatNumber(limit.points, 6));
      break;
    case LimitKind::kBands: {
      std::string bands;
      for (const LimitBand& band : limit.bands)
        bands += (bands.empty() ? "" : ", ") + band.name +
                 (band.max ? " ≤ " + util::FormatNumber(*band.max, 6) : std::string(" above"));
      out = fmt::format("  {} bands {}: ", name, bands);
      break;
    }
  }
  for (std::size_t g = 0; g < checked.checks.size(); ++g) {
    const GroupLimitCheck& check = checked.checks[g];
    out += (g == 0 ? "" : "; ") + util::EscapeControl(comparison.groups[g]) +
           fmt::format(" {} of {} within", check.within, check.tests);
    if (check.tests == 0) continue;
    if (limit.kind == LimitKind::kScale)
      out += fmt::format(", {} points on average", util::FormatNumber(check.mean_points, 3));
    if (limit.kind == LimitKind::kBands) {
      std::string counts;
      for (std::size_t b = 0; b < limit.bands.size(); ++b)
        if (check.band_counts[b] > 0)
          counts +=
              (counts.empty() ? "" : ", ") + fmt::format("{} {}", check.band_counts[b], limit.bands[b].name);
      out += " (" + counts + ")";
    }
    out += fmt::format(" (worst {} {}, margin {:+.1f} %), ", util::EscapeControl(check.worst_test),
                       util::FormatNumber(check.worst_value, 4), check.margin_pct) +
           FurtherTestText(limit, check);
  }
  return out + "\n";
}

std::string HumanComparison(const Comparison& comparison) {
  const bool by_variant = comparison.by == CompareBy::kVariant;
  // Stored names are shown escaped (control characters, bytes that are not UTF-8).
  std::string out =
      fmt::format("series {}: {} compared with {} '{}'\n", util::EscapeControl(comparison.series),
                  by_variant ? "variants" : "processing configs", by_variant ? "variant" : "config",
                  util::EscapeControl(comparison.baseline));
  out += by_variant ? "change in % of the baseline, [95 % confidence interval] (Welch's t), two-sided p: "
                      "of the geometric mean on the log scale, of the mean on the linear\n"
                    : "mean per-test change in % of the baseline over the same tests, [95 % confidence "
                      "interval] (paired t), two-sided p: of the ratio on the log scale, of the "
                      "difference on the linear\n";
  out += by_variant ? "n80: tests per variant that would detect the observed difference with 80 % power "
                      "(two-sided t, alpha 0.05)\n"
                    : "n80: tests that would detect the observed mean difference with 80 % power "
                      "(two-sided paired t, alpha 0.05)\n";
  out += fmt::format(
      "detects: the smallest fall/rise these tests detect with 80 % power; equiv: equivalence within "
      "±{} % shown by two one-sided tests (p < 0.05)\n",
      util::FormatNumber(comparison.equivalence_pct, 6));
  bool small_group = false;
  for (const MetricComparison& metric : comparison.metrics) {
    std::vector<std::vector<std::string>> cells;
    cells.push_back({by_variant ? "variant" : "config", "n", "mean", "sd", "median", "min", "max", "n80",
                     "detects", "equiv", "vs " + util::EscapeControl(comparison.baseline)});
    for (const ComparisonRow& row : metric.rows) {
      const engine::Description& d = row.description;
      cells.push_back({util::EscapeControl(row.group), std::to_string(d.n), Number(d.mean), Number(d.sd),
                       Number(d.median), Number(d.min), Number(d.max), PowerText(row.n_for_80pct_power),
                       DetectableText(row), EquivalenceText(row), DifferenceText(row, comparison.by)});
      if (!row.is_baseline && !std::isfinite(row.difference.diff)) small_group = true;
    }
    std::vector<std::size_t> width(cells.front().size(), 0);
    const auto length = [](const std::string& text) { return text.size(); };
    for (const auto& line : cells)
      for (std::size_t c = 0; c < line.size(); ++c) width[c] = std::max(width[c], length(line[c]));
    out += "\n" + metric.metric + ScaleNote(metric) + "\n";
    for (const auto& line : cells) {
      std::string text = "  ";
      for (std::size_t c = 0; c < line.size(); ++c) {
        const std::string pad(width[c] - length(line[c]), ' ');
        if (c == 0)
          text += line[c] + pad;
        else if (c + 1 == line.size())
          text += "  " + line[c];
        else
          text += "  " + pad + line[c];
      }
      out += text + "\n";
    }
    for (const MetricLimit& checked : metric.limits) out += LimitLine(comparison, checked);
  }
  if (small_group)
    out += by_variant ? "\n(1) n < 2: with fewer than 2 tests in the group or the baseline there is no "
                        "difference, interval or p-value (null in --format json and csv).\n"
                      : "\n(1) n < 2: fewer than 2 tests have results under both configs: no difference, "
                        "interval or p-value (null in --format json and csv).\n";
  return out;
}

}  // namespace

std::string ComparisonPValueText(double p) {
  if (!std::isfinite(p)) return "-";
  if (p < 1e-4) return "p<0.0001";
  const std::string text = fmt::format("p={:.2g}", p);
  // Two digits round 0.99993 to 1, which a p below 1 is not.
  if (p < 1.0 && text == "p=1") return "p>0.99";
  return text;
}

db::Table ComparisonTable(const Comparison& comparison) {
  db::Table table;
  table.columns = {"metric",
                   "group",
                   "n",
                   "mean",
                   "sd",
                   "median",
                   "min",
                   "max",
                   "baseline",
                   "scale",
                   "diff",
                   "diff_pct",
                   "ci_low",
                   "ci_high",
                   "ratio",
                   "ratio_ci_low",
                   "ratio_ci_high",
                   "p_value",
                   "n_for_80pct_power",
                   "mdd_low_pct",
                   "mdd_high_pct",
                   "equivalence_pct",
                   "tost_p_value"};
  const bool limits = !comparison.limit_sets.empty();
  if (limits)
    table.columns.insert(table.columns.end(),
                         {"limit", "tests_within_limit", "worst_test", "limit_margin_pct",
                          // Additions (issue 44): the set, and a further test.
                          "limits", "exceed_probability", "expected_points", "points_low", "points_high"});
  for (const MetricComparison& metric : comparison.metrics) {
    for (std::size_t g = 0; g < metric.rows.size(); ++g) {
      const ComparisonRow& row = metric.rows[g];
      const engine::Description& d = row.description;
      const engine::MeanDifference& m = row.difference;
      const bool log = row.scale == CompareScale::kLog;
      // On the log scale the interval is the ratio's; diff stays the plain difference of means.
      const double diff = log ? row.mean_diff : m.diff;
      const auto exp_or_nan = [&](double x) { return log && std::isfinite(x) ? std::exp(x) : kEmptyCell; };
      std::vector<db::Cell> cells = {row.metric,
                                     row.group,
                                     static_cast<std::int64_t>(d.n),
                                     d.mean,
                                     d.sd,
                                     d.median,
                                     d.min,
                                     d.max,
                                     row.baseline,
                                     std::string(ScaleName(row.scale)),
                                     diff,
                                     m.diff_pct,
                                     log ? kEmptyCell : m.ci_low,
                                     log ? kEmptyCell : m.ci_high,
                                     exp_or_nan(m.diff),
                                     exp_or_nan(m.ci_low),
                                     exp_or_nan(m.ci_high),
                                     m.p_value,
                                     PowerCell(row.n_for_80pct_power),
                                     row.mdd_low_pct,
                                     row.mdd_high_pct,
                                     row.is_baseline ? kEmptyCell : row.equivalence_pct,
                                     row.equivalence.p_value};
      if (limits) {
        if (!metric.limits.empty() && g < metric.limits.front().checks.size()) {
          const MetricLimit& first = metric.limits.front();
          const GroupLimitCheck& check = first.checks[g];
          cells.insert(cells.end(),
                       {first.limit.max, static_cast<std::int64_t>(check.within),
                        check.tests > 0 ? db::Cell(check.worst_test) : db::Cell(), check.margin_pct,
                        comparison.limit_sets[first.set].set.name, check.exceed_probability,
                        check.expected_points, check.points_low, check.points_high});
        } else {
          cells.insert(cells.end(), 9, db::Cell());
        }
      }
      table.rows.push_back(std::move(cells));
    }
  }
  return table;
}

bool IsComparisonTextColumn(std::string_view column) {
  for (const std::string_view text : {"metric", "group", "baseline", "scale", "worst_test", "limits"})
    if (column == text) return true;
  return false;
}

std::string FormatComparison(const Comparison& comparison, TableFormat format) {
  if (format == TableFormat::kTable) return HumanComparison(comparison);
  return FormatTable(ComparisonTable(comparison), format);
}

}  // namespace napkin::app

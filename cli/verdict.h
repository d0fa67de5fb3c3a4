#pragma once
// The engineer's verdict on a series' variants (docs/formats.md "Verdict"):
// a short table of the headline criteria and one sentence per variant
// against the baseline, worded from `napkin compare`'s numbers
// (cli/comparison.h: Welch's t, 95 % interval, two-sided p). The one place
// the sentences are made: the HTML report (cli/report_builder.cpp) shows
// them and `napkin demo` prints them.
//
// Wording rules (a difference is significant when p < kVerdictAlpha):
//  * significant: "lowers HIC15 by 44 % [40, 49] (p < 0.0001, n = 5 vs 5)",
//    "raises ..." when the mean difference is positive; a lowering's
//    interval is written as reductions (both bounds positive);
//  * not significant: "leaves HIC15 unchanged (−9 % [−27, +8], p = 0.24, ...)"
//    (the first clause), "BrIC unchanged (...)" (the others): signed numbers;
//  * a risk metric (IsRiskMetric): "P(AIS 3+) from 11.3 % to 2.1 %" when its
//    own difference is significant, else "P(AIS 3+) unchanged (11.3 % vs
//    10.9 %, p = 0.41)"; placed right after its criterion, or, of a criterion
//    the verdict does not speak of, at the end: "P(AIS 4+, HIC36) from ...";
//  * no interval, no difference (n < 2, no scatter): said so, never "unchanged".
// "n = a vs b" (variant vs baseline) is on the first clause and on any later
// clause whose counts differ from the first's.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cli/comparison.h"

namespace napkin::cli {

// The significance level of the verdict's wording (two-sided).
inline constexpr double kVerdictAlpha = 0.05;

// The criteria a verdict speaks of, in its order: HIC15 and BrIC (and the
// risks that belong to them, IsRiskMetric), where the comparison has them
// and some test of the series has a value.
std::vector<std::string> VerdictCriteria();

// A risk metric: a summary field whose name has a '_'-separated part
// "ais<N>..." (N a digit: P(AIS N+)), e.g. "hic15_p_ais3" or
// "p_ais3_hic15"; it belongs to the criterion named by another of its parts
// (one of `criteria`, e.g. "hic15"), or to none. Values are probabilities
// (0..1), printed in %.
struct RiskMetric {
  int ais_level = 0;
  std::optional<std::string> criterion;
};
std::optional<RiskMetric> IsRiskMetric(std::string_view name, const std::vector<std::string>& criteria);

// "HIC15", "BrIC", "P(AIS 3+)"; other names as they are.
std::string MetricLabel(std::string_view name);

// "p < 0.0001"; else "p = " and two significant digits, more where two
// would round across kVerdictAlpha (p = 0.0496 reads "p = 0.0496", not 0.050).
std::string PValueText(double p);

// One clause of a sentence (no leading separator), from `row` (a variant's
// row of the comparison; its baseline's mean and n in `baseline`).
// `first`: the clause that opens the sentence; `with_counts`: append
// "n = a vs b".
std::string CriterionClause(std::string_view label, const ComparisonRow& row,
                            const engine::Description& baseline, bool first, bool with_counts);
std::string RiskClause(std::string_view label, const ComparisonRow& row, const engine::Description& baseline,
                       bool with_counts);

struct SeriesVerdict {
  std::string series;
  std::string baseline;
  // The short table: variant, tests, then "mean ± sd" of each criterion and
  // the mean of each risk (in %), baseline first.
  std::vector<std::string> columns;
  std::vector<std::vector<std::string>> rows;
  // One per variant other than the baseline, in the comparison's order,
  // starting with the variant's name.
  std::vector<std::string> sentences;
};

// The verdict of a by-variant comparison (its metrics should include
// VerdictCriteria(); those it lacks, or no test has, are left out).
SeriesVerdict BuildVerdict(const Comparison& comparison);

// The sentences as text for a terminal: a heading line naming the series
// and the baseline, then each sentence on a line of its own, indented by
// two spaces (names escaped as `napkin compare` prints them).
std::string FormatVerdict(const SeriesVerdict& verdict);

}  // namespace napkin::cli

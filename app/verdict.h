#pragma once
// The engineer's verdict on a series' variants (docs/formats.md "Verdict"):
// a short table of the headline criteria and one sentence per variant
// against the baseline, worded from `napkin compare`'s numbers
// (app/comparison.h: ratios on the log scale for the positive criteria,
// Welch's t, 95 % interval, two-sided p, equivalence by two one-sided tests,
// the smallest detectable change). The one place the sentences are made:
// the HTML report (app/report_builder.cpp) shows them and `napkin demo`
// prints them. Plain functions over data (no command line), with the rules
// as a table beside them (kVerdictRules), which the report's note and
// docs/formats.md "Verdict" state.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "app/comparison.h"

namespace napkin::app {

// The significance level of the verdict's wording (two-sided), and of the
// two one-sided tests of equivalence.
inline constexpr double kVerdictAlpha = 0.05;

// What a clause about a criterion says, tried in this order (the first
// that applies).
enum class ClauseKind {
  kNotMeasured,   // a side has no test with a value of a rotation criterion
  kTooFew,        // fewer than 2 tests with a value on a side
  kIdentical,     // every test of both sides has the same value
  kNoScatter,     // no scatter on either side, different values
  kSignificant,   // p < alpha
  kEquivalent,    // not significant, equivalence shown (TOST p < alpha)
  kInconclusive,  // neither significant nor equivalent
};

// A rule of the wording: when it applies and an example of what it says.
// docs/formats.md "Verdict" states each `when` word for word
// (tests/app/verdict_test.cpp checks it).
struct VerdictRule {
  ClauseKind kind;
  std::string_view when;
  std::string_view example;
};
inline constexpr VerdictRule kVerdictRules[] = {
    {ClauseKind::kNotMeasured,
     "no test of one side has a value of a rotation criterion (acceleration-only heads)",
     "BrIC not measured (acceleration-only heads)"},
    {ClauseKind::kTooFew, "fewer than 2 tests with a value on a side",
     "no HIC15 comparison (n = 1 vs 5: fewer than 2 tests)"},
    {ClauseKind::kIdentical, "every test of both sides has the same value",
     "HIC15 identical in all 10 tests"},
    {ClauseKind::kNoScatter, "no scatter on either side but different values: no interval",
     "lowers HIC15 by 10 % (no scatter: no interval, n = 3 vs 3)"},
    {ClauseKind::kSignificant, "the two-sided p is below 0.05: lowers or raises, the interval as magnitudes",
     "lowers HIC15 by 44 % [40, 49] (p < 0.0001, n = 5 vs 5)"},
    {ClauseKind::kEquivalent,
     "not significant, and two one-sided tests show the change within the equivalence margin: the only "
     "wording that says the criterion did not change",
     "HIC15 equivalent within ±10 % (90 % interval −4 % to +3 %, n = 5 vs 5)"},
    {ClauseKind::kInconclusive,
     "neither significant nor equivalent: what the series cannot tell, with the smallest change its tests "
     "detect with 80 % power",
     "no significant difference in BrIC (−4 % [−29, +22], p = 0.76; 5 vs 5 tests detect −33 % or +49 % "
     "with 80 % power)"},
};

// The rule of `kind`.
const VerdictRule& RuleOf(ClauseKind kind);

// The criteria a verdict speaks of, in table order: the summary fields
// marked in_verdict in engine/summary_fields.cpp, HIC15 and BrIC (each
// followed by the risks computed from it, engine::RiskFields()),
// where the comparison has them and some test of the series has a value.
std::vector<std::string> VerdictCriteria();

// A summary field's label (engine::FieldLabel): "HIC15", "BrIC", "HIC(d)",
// "P(AIS 3+ | HIC15)" (a risk names its criterion); other names as they are.
std::string MetricLabel(std::string_view name);

// "p < 0.0001"; else "p = " and two significant digits, more where two
// would round across kVerdictAlpha (p = 0.0496 reads "p = 0.0496", not 0.050).
std::string PValueText(double p);

// A percentage as the verdict prints it: whole percent from 0.95 %, two
// significant digits below, so a bound that is not 0 never reads 0.
std::string PercentText(double pct);

// Which rule words `row` (a variant's row of the comparison; its
// baseline's row in `baseline`), on a criterion that is a rotation
// criterion or not.
ClauseKind ClassifyClause(const ComparisonRow& row, const ComparisonRow& baseline, bool rotation_criterion);

// One clause about a criterion (no leading separator), by its rule, with
// "n = a vs b" when `with_counts`.
std::string CriterionClause(std::string_view label, const ComparisonRow& row, const ComparisonRow& baseline,
                            bool rotation_criterion, bool with_counts);

// A risk as the consequence of its criterion's clause: "P(AIS 3+ | HIC15)
// 17.6 % → 4.3 %" after a significant clause (or one without scatter),
// "… 21.9 % vs 20.6 %" after an equivalent or inconclusive one, "… 7.7 % in
// both" for identical criteria (baseline's mean risk, then the variant's).
// Empty where the clause has no numbers (not measured, too few). The
// sentence joins a criterion's risks with ", " after " → ".
std::string RiskConsequence(std::string_view label, ClauseKind criterion_clause, const ComparisonRow& row,
                            const ComparisonRow& baseline);

struct SeriesVerdict {
  std::string series;
  std::string baseline;
  // The short table: variant, tests, then "mean ± sd" of each criterion and
  // the mean of each risk (in %), with limits the tests within them;
  // baseline first.
  std::vector<std::string> columns;
  std::vector<std::vector<std::string>> rows;
  // With limits, one for the baseline first; then one per other variant,
  // in the comparison's order, each starting with the variant's name.
  std::vector<std::string> sentences;
};

// The verdict of a by-variant comparison (its metrics should include
// VerdictCriteria(); those it lacks, or no test has, are left out).
SeriesVerdict BuildVerdict(const Comparison& comparison);

// What the wording means, for the report's note under the sentences: built
// from kVerdictRules and the comparison's scale, margin and limits.
std::string VerdictNote(const Comparison& comparison);

// The sentences as text for a terminal: a heading line naming the series
// and the baseline, then each sentence on a line of its own, indented by
// two spaces (names escaped as `napkin compare` prints them).
std::string FormatVerdict(const SeriesVerdict& verdict);

}  // namespace napkin::app

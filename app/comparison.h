#pragma once
// Comparisons of summary metrics across the groups of tests of one series
// (docs/formats.md "napkin compare"; the statistics are engine/statistics.h,
// docs/algorithms.md "Comparing groups of tests"). `napkin compare` prints
// them; `napkin report` prints the same rows and plots the per-test values.
// The statistics are app/comparison.cpp; the tables and words the front ends
// print (ComparisonTable, FormatComparison, ComparisonPValueText) are
// app/comparison_format.cpp.
//
// Groups are the series' variants (Welch's t against the baseline variant) or
// the processing configs its tests were run under (paired t over the tests
// that have results under both the config and the baseline config).
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "app/limits.h"
#include "app/request_options.h"
#include "app/table_output.h"
#include "db/catalogue.h"
#include "engine/prediction.h"
#include "engine/statistics.h"

namespace napkin::app {

enum class CompareBy { kVariant, kConfig };

// The scale a metric's groups are compared on (docs/formats.md "napkin
// compare", docs/algorithms.md "Ratios of positive criteria"): kLog, the
// ratio of geometric means (Welch's t, by config the paired t, on the
// natural logs), for the positive, right-skewed criteria (IsRatioMetric);
// kLinear, the difference of means.
enum class CompareScale { kLog, kLinear };

std::string_view ScaleName(CompareScale scale);

// The summary fields marked log_scale in engine/summary_fields.cpp (HIC of
// every window, HIC(d), BrIC, DAMAGE, peak and 3 ms accelerations, peak
// angular velocities and acceleration): compared as ratios under --scale log.
// Every other metric is compared on the linear scale.
bool IsRatioMetric(std::string_view metric);

// The default equivalence margin, ±10 % (--equivalence PCT).
inline constexpr double kDefaultEquivalencePct = 10.0;

// What to compare (ParseCompareRequest reads it from any front end's options).
struct CompareRequest {
  std::string series;
  CompareBy by = CompareBy::kVariant;
  // A group name (by config: also a config's name or hash prefix); default:
  // the first group in name order.
  std::optional<std::string> baseline;
  // Summary field names (engine::SummaryFields()); empty: DefaultComparisonMetrics().
  std::vector<std::string> metrics;
  // Processing configs as NAME or HASH-PREFIX (ResolveConfigSelector, app/result_selection.h). By
  // variant: at most one, whose results are compared (default: each test's
  // latest result, as `napkin query`). By config: the configs compared
  // (default: every config with results in the series).
  std::vector<std::string> configs;
  // kLog: ratio metrics on the log scale; kLinear: every metric linear.
  CompareScale scale = CompareScale::kLog;
  // The equivalence margin in % (two one-sided tests).
  double equivalence_pct = kDefaultEquivalencePct;
  // Limit sets to check (app/limits.h), each a preset name of config/limits
  // or a file; their metrics (and a hard-contact rule's) are compared too.
  std::vector<std::string> limits;
  // The front end the request came through: BuildComparison's sentences name
  // its options as it spells them (app/request_options.h).
  FrontEnd front_end = FrontEnd::kCommandLine;
};

// The options of `napkin compare`, of GET /api/v1/compare and of
// napkin.Catalogue.compare, one parser for the three (docs/formats.md
// "napkin compare"): series (required), by (variant or config; default
// variant), baseline, metrics (comma-separated, repeatable), config
// (repeatable), scale (log or linear; default log), equivalence (a margin in
// % in (0, 100); default 10), limits (repeatable; no two sets may limit one
// metric: a row of compare holds one limit). Throws UsageError, one sentence
// naming the option as `options`' front end spells it, for an unknown,
// repeated or malformed option, and for --by variant with more than one
// --config; reads the limit sets (their errors name the file).
CompareRequest ParseCompareRequest(const RequestOptions& options);

// The group of a test of `variant` when comparing by variant: the name, or
// "(none)" for tests without one (docs/formats.md "napkin compare").
std::string VariantGroup(const std::optional<std::string>& variant);

// The metrics `napkin compare` shows by default: hic15, hic36, hic_d (when
// this build has it), peak_acc_g, a3ms_g, peak_omega_radps, peak_alpha_radps2,
// bric, damage, max_rotation_deg, then the risks read from hic15 and bric
// (engine::RiskFields(): P(AIS 3+ | HIC15), P(AIS 3+ | BrIC), P(AIS 4+ | BrIC)).
std::vector<std::string> DefaultComparisonMetrics();

// A group's values of one metric, one per test with a result (tests whose
// value is absent, NULL in the catalogue, are left out), in test id order.
struct GroupValues {
  std::string group;
  std::vector<std::string> test_ids;
  std::vector<double> values;
};

// One row of the compare contract: the group's statistics and, except on the
// baseline's own row, its difference from the baseline.
struct ComparisonRow {
  std::string metric;
  std::string group;
  engine::Description description;
  std::string baseline;
  bool is_baseline = false;
  // diff ... p_value; every field NaN on the baseline's row and where the
  // statistics are undefined (engine/statistics.h).
  engine::MeanDifference difference;
  // The baseline mean diff_pct refers to: the baseline group's mean (by
  // variant) or its mean over the paired tests (by config); NaN on the
  // baseline's row and where the difference is undefined.
  double baseline_mean = 0.0;
  // By config: the number of tests paired with the baseline; by variant 0.
  std::size_t pairs = 0;
  // Repeats per group that would detect the observed difference with 80 %
  // power at two-sided alpha 0.05 (engine::WholeRepeatsForPower: Welch by
  // variant, paired by config; docs/algorithms.md "Planning a series"); NaN
  // on the baseline's row, where the difference is undefined or 0, and where
  // both spreads are 0. On the row's scale.
  double n_for_80pct_power = std::numeric_limits<double>::quiet_NaN();

  // The scale of `difference`, `equivalence` and the power figures: kLog
  // (difference of the natural logs, ratio = exp(diff)) for a ratio metric
  // under --scale log whose values are all > 0 in both groups (by config:
  // in every pair), else kLinear.
  CompareScale scale = CompareScale::kLinear;
  // A ratio metric under --scale log compared on the linear scale because a
  // value is <= 0 (docs/formats.md: "and says so").
  bool log_fallback = false;
  // The plain difference of means (by config: the mean per-test difference),
  // whatever the scale; NaN where `difference` is undefined.
  double mean_diff = std::numeric_limits<double>::quiet_NaN();
  // The change in % of the baseline on the row's scale and its 95 %
  // interval: 100 (ratio - 1) on the log scale, 100 diff / baseline_mean on
  // the linear; NaN where undefined.
  double pct = std::numeric_limits<double>::quiet_NaN();
  double pct_ci_low = std::numeric_limits<double>::quiet_NaN();
  double pct_ci_high = std::numeric_limits<double>::quiet_NaN();
  // Equivalence within ±margin (engine::TwoOneSidedTests) on the row's
  // scale: log bounds ln(1 - m), ln(1 + m); linear ±m baseline_mean. Its
  // 90 % interval in % as pct above.
  engine::Equivalence equivalence;
  double equivalence_pct = kDefaultEquivalencePct;
  double equivalence_ci_low_pct = std::numeric_limits<double>::quiet_NaN();
  double equivalence_ci_high_pct = std::numeric_limits<double>::quiet_NaN();
  // The smallest change (in % of the baseline, a fall and a rise) that these
  // tests detect with 80 % power at two-sided alpha 0.05
  // (engine::DetectableEffectSize times the pooled sd on the row's scale;
  // by config the paired form); NaN where a side has n < 2 or no scatter.
  double mdd_low_pct = std::numeric_limits<double>::quiet_NaN();
  double mdd_high_pct = std::numeric_limits<double>::quiet_NaN();
};

// A limit's check for one group (app/limits.h): how many of its tests with a
// value are within it (value <= Limit::max: the maximum, a scale's lower
// performance limit, the best band's upper edge), the worst (highest) test,
// and what a further test would give (engine/prediction.h).
struct GroupLimitCheck {
  std::size_t tests = 0;   // with a value of the limit's metric
  std::size_t within = 0;  // value <= the limit
  std::string worst_test;
  double worst_value = std::numeric_limits<double>::quiet_NaN();
  double margin_pct = std::numeric_limits<double>::quiet_NaN();  // 100 (limit - worst) / limit
  // A scale: the mean points of the tests; bands: the tests in each band (Limit::bands order).
  double mean_points = std::numeric_limits<double>::quiet_NaN();
  std::vector<std::size_t> band_counts;
  // A further test, from the group's values on the log scale: why there is
  // no prediction (n < 3, a value <= 0, no spread: every figure below NaN),
  // P(value > limit), and on a scale its expected points with the 80 %
  // prediction interval of its points (the points at the 90 % and the 10 %
  // predictive quantiles of the value).
  engine::PredictionGap prediction_gap = engine::PredictionGap::kNone;
  double exceed_probability = std::numeric_limits<double>::quiet_NaN();
  double expected_points = std::numeric_limits<double>::quiet_NaN();
  double points_low = std::numeric_limits<double>::quiet_NaN();
  double points_high = std::numeric_limits<double>::quiet_NaN();
};

// The two-sided coverage of the points' prediction interval.
inline constexpr double kPointsPredictionCoverage = 0.80;

// A limit of one of the comparison's sets on a metric, checked per group.
struct MetricLimit {
  std::size_t set = 0;  // index into Comparison::limit_sets
  Limit limit;
  std::vector<GroupLimitCheck> checks;  // per group, in Comparison::groups order
};

struct MetricComparison {
  std::string metric;
  std::vector<GroupValues> groups;  // in Comparison::groups order
  std::vector<ComparisonRow> rows;  // one per group, same order
  // The limits of the request's sets on this metric, in their order.
  std::vector<MetricLimit> limits;
};

// A set's combined region (the head's points, app/limits.h) for one group:
// its tests' points, as the protocol combines its criteria.
struct GroupCombinedPoints {
  std::size_t tests = 0;  // tests with combined points
  double mean_points = std::numeric_limits<double>::quiet_NaN();
  double lowest_points = std::numeric_limits<double>::quiet_NaN();
  std::string lowest_test;
  // The hard-contact rule's finding, per test of the group.
  std::size_t contact_assumed = 0;
  std::size_t contact_not_assumed = 0;
  std::size_t contact_not_applied = 0;
};

struct ComparedLimitSet {
  LimitSet set;
  std::vector<GroupCombinedPoints> combined;  // per group, when set.combined
};

struct Comparison {
  std::string series;
  CompareBy by = CompareBy::kVariant;
  CompareScale scale = CompareScale::kLog;
  double equivalence_pct = kDefaultEquivalencePct;
  std::string baseline;
  std::vector<std::string> groups;  // the baseline, then the others in name order
  std::vector<MetricComparison> metrics;
  // Per group (in `groups` order): its tests, and those whose result comes
  // from salvaged channels (docs/algorithms.md "Faulty channels").
  std::vector<std::size_t> tests_per_group;
  std::vector<std::size_t> salvaged_per_group;
  // The limit sets checked, in the request's order.
  std::vector<ComparedLimitSet> limit_sets;
};

// The check of `limit` on one group's values (test ids alongside), as
// BuildComparison makes it.
GroupLimitCheck CheckGroupLimit(const Limit& limit, const GroupValues& values);

// Reads the series' results and compares them. Throws UsageError (one line
// listing the valid choices) for an unknown series, metric, config or
// baseline, or more than one config by variant; InputError "... run `napkin
// run` first." when the series has no results (under the chosen configs).
// With the default metrics (request.metrics empty) a metric no test of the
// series has a value of is left out (the rotation of acceleration-only
// tests); metrics named in request.metrics are always kept.
Comparison BuildComparison(db::Catalogue& catalogue, const CompareRequest& request);

// A p-value as compare's table shows it: "p=0.041", "p<0.0001", and "p>0.99" for a p that two
// digits would round to 1.
std::string ComparisonPValueText(double p);

// The comparison of one metric from each group's values (baseline first),
// as BuildComparison makes it; by config the groups' test ids pair the values.
MetricComparison CompareMetric(const std::string& metric, std::vector<GroupValues> groups, CompareBy by,
                               CompareScale scale, double equivalence_pct);

// The rows as the compare contract's table: columns metric, group, n, mean,
// sd, median, min, max, baseline, scale, diff, diff_pct, ci_low, ci_high,
// ratio, ratio_ci_low, ratio_ci_high, p_value, n_for_80pct_power,
// mdd_low_pct, mdd_high_pct, equivalence_pct, tost_p_value, and with limits
// limit, tests_within_limit, worst_test, limit_margin_pct, then limits (the
// set's name), exceed_probability, expected_points, points_low, points_high
// (the first of the sets' limits on the row's metric; NaN cells become null
// in JSON and empty fields in CSV via FormatTable).
db::Table ComparisonTable(const Comparison& comparison);

// Whether a column of ComparisonTable holds text (metric, group, baseline,
// scale, worst_test, limits); every other holds numbers, NULL where undefined
// (napkin.Catalogue.compare_frame's float64 columns).
bool IsComparisonTextColumn(std::string_view column);

// kJson and kCsv: FormatTable(ComparisonTable(comparison)). kTable: one
// aligned block per metric, for people (docs/formats.md "napkin compare").
std::string FormatComparison(const Comparison& comparison, TableFormat format);

}  // namespace napkin::app

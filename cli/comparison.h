#pragma once
// Comparisons of summary metrics across the groups of tests of one series
// (docs/formats.md "napkin compare"; the statistics are engine/statistics.h,
// docs/algorithms.md "Comparing groups of tests"). `napkin compare` prints
// them; `napkin report` prints the same rows and plots the per-test values.
//
// Groups are the series' variants (Welch's t against the baseline variant) or
// the processing configs its tests were run under (paired t over the tests
// that have results under both the config and the baseline config).
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "cli/table_output.h"
#include "db/catalogue.h"
#include "engine/statistics.h"

namespace napkin::cli {

enum class CompareBy { kVariant, kConfig };

// "variant" or "config"; throws UsageError otherwise.
CompareBy ParseCompareBy(const std::string& text);

struct ComparisonRequest {
  std::string series;
  CompareBy by = CompareBy::kVariant;
  // A group name (by config: also a config's name or hash prefix); default:
  // the first group in name order.
  std::optional<std::string> baseline;
  // Summary field names (engine::SummaryFields()); empty: DefaultComparisonMetrics().
  std::vector<std::string> metrics;
  // Processing configs as NAME or HASH-PREFIX (ResolveConfigSelector, cli/db_option.h). By
  // variant: at most one, whose results are compared (default: each test's
  // latest result, as `napkin query`). By config: the configs compared
  // (default: every config with results in the series).
  std::vector<std::string> configs;
};

// The group of a test of `variant` when comparing by variant: the name, or
// "(none)" for tests without one (docs/formats.md "napkin compare").
std::string VariantGroup(const std::optional<std::string>& variant);

// The metrics `napkin compare` shows by default: hic15, hic36, hic_d (when
// this build has it), peak_acc_g, a3ms_g, peak_omega_radps, peak_alpha_radps2,
// bric, damage, max_rotation_deg, hic15_p_ais3, bric_p_ais3, bric_p_ais4.
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
  // both spreads are 0.
  double n_for_80pct_power = std::numeric_limits<double>::quiet_NaN();
};

struct MetricComparison {
  std::string metric;
  std::vector<GroupValues> groups;  // in Comparison::groups order
  std::vector<ComparisonRow> rows;  // one per group, same order
};

struct Comparison {
  std::string series;
  CompareBy by = CompareBy::kVariant;
  std::string baseline;
  std::vector<std::string> groups;  // the baseline, then the others in name order
  std::vector<MetricComparison> metrics;
};

// Reads the series' results and compares them. Throws UsageError (one line
// listing the valid choices) for an unknown series, metric, config or
// baseline, or more than one config by variant; InputError "... run `napkin
// run` first." when the series has no results (under the chosen configs).
Comparison BuildComparison(db::Catalogue& catalogue, const ComparisonRequest& request);

// The rows as the compare contract's table: columns metric, group, n, mean,
// sd, median, min, max, baseline, diff, diff_pct, ci_low, ci_high, p_value
// (NaN cells become null in JSON and empty fields in CSV via FormatTable).
db::Table ComparisonTable(const Comparison& comparison);

// kJson and kCsv: FormatTable(ComparisonTable(comparison)). kTable: one
// aligned block per metric, for people (docs/formats.md "napkin compare").
std::string FormatComparison(const Comparison& comparison, TableFormat format);

}  // namespace napkin::cli

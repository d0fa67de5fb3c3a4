#pragma once
// Regulatory and consumer-test limits of head criteria (docs/formats.md
// "Limits"): data files config/limits/NAME.json, one per protocol and
// version, each number with its clause and the set with its public source,
// read by `compare`, `report` and `demo --limits NAME` and `query limits`.
// A limit is a maximum (pass/fail), a sliding scale (points from a higher to
// a lower performance limit, linear between: Euro NCAP) or bands (Good,
// Acceptable, Marginal, Poor: IIHS). Plain data and functions: no command
// line here.
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "db/catalogue.h"
#include "formats/presets.h"

namespace napkin::app {

// The range of every number of a limit: wider than any head criterion's limit, narrow enough that
// every margin (LimitMarginPct) of a finite value is a finite percentage.
inline constexpr double kMinLimit = 1e-6;
inline constexpr double kMaxLimit = 1e6;

enum class LimitKind {
  kMaximum,  // "max": the value must not exceed it
  kScale,    // "scale": points, full at or below the higher performance limit, 0 at or above the lower
  kBands,    // "bands": the first band whose "max" the value does not exceed, else the last band
};

// "maximum", "scale", "bands" (the `kind` column of `query limits`).
std::string_view LimitKindName(LimitKind kind);

// A rating band: its name and the highest value it takes (none: the last band, everything above).
struct LimitBand {
  std::string name;
  std::optional<double> max;
};

// One limit on a summary field (a numeric field of `query criteria`).
struct Limit {
  std::string metric;
  LimitKind kind = LimitKind::kMaximum;
  // The value a test must not exceed, which compare counts tests within and
  // a further test's chance of exceeding is given for: the maximum; a
  // scale's lower performance limit (beyond it no points); the first
  // band's upper edge (beyond it not the best band).
  double max = 0.0;
  double higher_limit = 0.0;     // kScale: full points at or below it
  double points = 0.0;           // kScale: the full points
  std::vector<LimitBand> bands;  // kBands, best first; the last without max
  std::string requirement;       // the clause, in the source's words
};

// The points of a body region (the head) from its criteria's points on a
// scale: the lowest of them, as the protocol combines them.
struct CombinedPoints {
  std::string name;  // "head"
  std::string requirement;
};

// Euro NCAP's hard-contact rule: a hard contact is assumed when the test's
// `metric` (the peak resultant head acceleration) exceeds `above`; without
// one the region scores `points_without`, with one its combined points.
struct HardContactRule {
  std::string metric;
  double above = 0.0;
  double points_without = 0.0;
  std::string requirement;
};

struct LimitSet {
  std::string name;        // short, for sentences: "FMVSS 201U"
  std::string title;       // what the limits are
  std::string applies_to;  // the test and dummy or headform they are for
  std::string source;      // the citation
  std::string url;
  std::string version;  // the protocol's version and date, where the file gives it
  std::string note;     // what the file leaves out and why, where it says
  std::vector<Limit> limits;
  std::optional<CombinedPoints> combined;
  std::optional<HardContactRule> hard_contact;
  std::filesystem::path path;  // the file read
};

// The limit set `name_or_path`: a JSON file, or a preset of `config_dir`/limits.
// Throws formats::UnknownPresetError (a UsageError, formats/presets.h: one
// sentence listing the presets) when it is neither, InputError naming the file when the file is malformed (a
// missing or unknown key, a metric that is not a field of `query criteria`,
// a number that is not a plausible limit, bands out of order, a combination
// without a scale).
LimitSet LoadLimits(std::string_view name_or_path,
                    const std::filesystem::path& config_dir = formats::DefaultConfigDir());

// The preset names of `config_dir`/limits, in name order.
std::vector<std::string> LimitPresets(const std::filesystem::path& config_dir = formats::DefaultConfigDir());

// 100 (limit - value) / limit: positive within the limit, negative over it.
double LimitMarginPct(double value, double limit);

// A scale's points for `value`: limit.points at or below the higher
// performance limit, 0 at or above the lower (limit.max), linear between.
double ScalePoints(const Limit& limit, double value);

// The band `value` falls in: the first whose max it does not exceed, else the last.
const LimitBand& BandOf(const Limit& limit, double value);

// What the hard-contact rule found for a test.
enum class HardContact {
  kNotApplied,  // no rule, or the test has no value of its metric
  kAssumed,     // the metric exceeds the rule's threshold
  kNotAssumed,  // at or below it: no hard contact, the rule's points
};

// One test against a set: each limit's outcome (same order as set.limits)
// and the combined points.
struct CriterionRating {
  double value = 0.0;  // NaN without a value
  bool has_value = false;
  double points = 0.0;              // kScale (NaN otherwise or without a value)
  const LimitBand* band = nullptr;  // kBands with a value
  std::optional<bool> meets;        // kMaximum with a value
};
struct TestRating {
  std::vector<CriterionRating> criteria;
  // With set.combined: the lowest points of the scale criteria (NaN when one
  // lacks a value), or the rule's points without a hard contact.
  double combined_points = 0.0;
  HardContact hard_contact = HardContact::kNotApplied;
  double contact_value = 0.0;  // the rule's metric, NaN without one
};

// The test whose criteria `value_of` gives (NaN: no value) against `set`.
TestRating RateTest(const LimitSet& set, const std::function<double(const std::string& metric)>& value_of);

// "assumed (peak_acc_g 93.1 > 80)", "not assumed (peak_acc_g 62.4 ≤ 80): 4 points",
// "not applied (no peak_acc_g)"; "" without a rule.
std::string HardContactText(const LimitSet& set, const TestRating& rating);

// The full points of the set's combined region (the scales' points), NaN without one.
double CombinedMaxPoints(const LimitSet& set);

// The metrics a set needs: its limits' and its hard-contact rule's, each once, in file order.
std::vector<std::string> LimitMetrics(const LimitSet& set);

// `query limits`: each row of `criteria` (a `query criteria` table: test_id,
// series, variant, then the criteria) against each limit of `limits`:
// columns test_id, series, variant, limits, metric, value, limit,
// margin_pct, meets ("yes", "no", or null without a value or for a scale or
// bands), then kind, higher_limit, points, max_points, band, hard_contact;
// with a combined region one more row per test, metric its name (`head`),
// kind "combined", its points and the hard-contact rule's finding.
db::Table LimitsTable(const db::Table& criteria, const LimitSet& limits);

}  // namespace napkin::app

#include "app/comparison.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <string_view>

#include "app/limits.h"
#include "app/result_selection.h"
#include "common/error.h"
#include "common/joined.h"
#include "db/job_queue.h"
#include "engine/summary_fields.h"
#include "ingest/import.h"
#include "util/text.h"

namespace napkin::app {
namespace {

// The group of the tests without a variant; import refuses it as a variant name.
constexpr std::string_view kNoVariant = ingest::kNoVariantGroup;

std::vector<const engine::SummaryField*> ResolveMetrics(const std::vector<std::string>& requested) {
  const std::vector<std::string> names = requested.empty() ? DefaultComparisonMetrics() : requested;
  std::vector<const engine::SummaryField*> fields;
  for (const std::string& name : names) {
    const engine::SummaryField* field = engine::FindSummaryField(name);
    if (field == nullptr) {
      std::vector<std::string> valid;
      for (const engine::SummaryField& known : engine::SummaryFields()) valid.emplace_back(known.name);
      throw UsageError("unknown metric '" + name + "' (metrics: " + Joined(valid) + ").");
    }
    if (std::find(fields.begin(), fields.end(), field) == fields.end()) fields.push_back(field);
  }
  return fields;
}

// The group of a result: its variant, or its config's name (with a hash
// prefix when two of the compared configs share the name).
std::string GroupOf(const db::LabelledResult& result, CompareBy by,
                    const std::set<std::string>& shared_names) {
  if (by == CompareBy::kVariant) return VariantGroup(result.variant);
  if (shared_names.count(result.config_name) == 0) return result.config_name;
  return result.config_name + "@" + result.config_hash.substr(0, 8);
}

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

engine::MeanDifference NoDifference() { return {kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN}; }

std::vector<double> Logs(const std::vector<double>& values) {
  std::vector<double> logs;
  logs.reserve(values.size());
  for (const double value : values) logs.push_back(std::log(value));
  return logs;
}

// A change on the row's scale in % of the baseline: 100 (e^x - 1) on the
// log scale (expm1 keeps small changes exact), 100 x / baseline mean on the
// linear one (NaN for a baseline mean of 0).
double PercentOf(double x, CompareScale scale, double baseline_mean) {
  if (!std::isfinite(x)) return kNaN;
  if (scale == CompareScale::kLog) return 100.0 * std::expm1(x);
  return baseline_mean != 0.0 ? 100.0 * x / baseline_mean : kNaN;
}

// The percentages, the equivalence and the smallest detectable change of a
// row from its difference on the row's scale (`pooled_sd`: the pooled sd,
// by config the sd of the differences; `effect_size` the detectable d).
void FillScaleFigures(ComparisonRow& row, double pooled_sd, double effect_size, double equivalence_pct) {
  const engine::MeanDifference& d = row.difference;
  const double base = row.baseline_mean;
  const bool log = row.scale == CompareScale::kLog;
  row.pct = PercentOf(d.diff, row.scale, base);
  row.pct_ci_low = PercentOf(d.ci_low, row.scale, base);
  row.pct_ci_high = PercentOf(d.ci_high, row.scale, base);
  if (log) row.difference.diff_pct = row.pct;
  const double m = equivalence_pct / 100.0;
  const double low = log ? std::log1p(-m) : (base != 0.0 ? -m * std::abs(base) : kNaN);
  const double high = log ? std::log1p(m) : (base != 0.0 ? m * std::abs(base) : kNaN);
  row.equivalence_pct = equivalence_pct;
  row.equivalence = engine::TwoOneSidedTests(d, low, high);
  row.equivalence_ci_low_pct = PercentOf(row.equivalence.ci_low, row.scale, base);
  row.equivalence_ci_high_pct = PercentOf(row.equivalence.ci_high, row.scale, base);
  const double detectable = effect_size * pooled_sd;
  if (std::isfinite(detectable) && detectable > 0.0) {
    row.mdd_low_pct =
        log ? 100.0 * std::expm1(-detectable) : PercentOf(-detectable, row.scale, std::abs(base));
    row.mdd_high_pct =
        log ? 100.0 * std::expm1(detectable) : PercentOf(detectable, row.scale, std::abs(base));
  }
}

// Welch's t of `group` against `baseline` on the row's scale.
void IndependentDifference(const GroupValues& group, const GroupValues& baseline, ComparisonRow& row,
                           double equivalence_pct) {
  const bool log = row.scale == CompareScale::kLog;
  const std::vector<double> a = log ? Logs(group.values) : group.values;
  const std::vector<double> b = log ? Logs(baseline.values) : baseline.values;
  row.difference = engine::WelchComparison(a, b);
  if (!std::isfinite(row.difference.diff)) return;
  const engine::Description da = engine::Describe(a), db = engine::Describe(b);
  row.baseline_mean = engine::Describe(baseline.values).mean;
  row.mean_diff = row.description.mean - row.baseline_mean;
  row.n_for_80pct_power =
      engine::WholeRepeatsForPower(engine::WelchPowerModel(row.difference.diff, da.sd, db.sd));
  FillScaleFigures(row, engine::PooledStandardDeviation(da, db),
                   engine::DetectableEffectSize(static_cast<double>(da.n), static_cast<double>(db.n)),
                   equivalence_pct);
}

// Paired t of `group` against `baseline` over the tests both have, on the row's scale.
void PairedDifference(const GroupValues& group, const GroupValues& baseline, ComparisonRow& row,
                      double equivalence_pct) {
  std::map<std::string, double> baseline_by_test;
  for (std::size_t i = 0; i < baseline.test_ids.size(); ++i)
    baseline_by_test.emplace(baseline.test_ids[i], baseline.values[i]);
  const bool log = row.scale == CompareScale::kLog;
  std::vector<double> differences, linear_differences, baseline_values;
  for (std::size_t i = 0; i < group.test_ids.size(); ++i) {
    const auto found = baseline_by_test.find(group.test_ids[i]);
    if (found == baseline_by_test.end()) continue;
    differences.push_back(log ? std::log(group.values[i]) - std::log(found->second)
                              : group.values[i] - found->second);
    linear_differences.push_back(group.values[i] - found->second);
    baseline_values.push_back(found->second);
  }
  row.pairs = differences.size();
  row.baseline_mean = engine::Describe(baseline_values).mean;
  row.difference = engine::PairedComparison(differences, row.baseline_mean);
  if (!std::isfinite(row.difference.diff)) return;
  row.mean_diff = engine::Describe(linear_differences).mean;
  const double sd = engine::Describe(differences).sd;
  row.n_for_80pct_power = engine::WholeRepeatsForPower(engine::PairedPowerModel(row.difference.diff, sd));
  FillScaleFigures(row, sd, engine::PairedDetectableEffectSize(static_cast<double>(row.pairs)),
                   equivalence_pct);
}

// The limits of the sets on the metric, each checked per group.
void CheckLimits(const std::vector<ComparedLimitSet>& sets, MetricComparison& metric) {
  for (std::size_t s = 0; s < sets.size(); ++s)
    for (const Limit& limit : sets[s].set.limits) {
      if (limit.metric != metric.metric) continue;
      MetricLimit& checked = metric.limits.emplace_back();
      checked.set = s;
      checked.limit = limit;
      for (const GroupValues& group : metric.groups) checked.checks.push_back(CheckGroupLimit(limit, group));
    }
}

// The combined points of a set per group (its tests' ratings, app/limits.h).
GroupCombinedPoints CombineGroup(const LimitSet& set, const std::vector<const db::LabelledResult*>& members) {
  GroupCombinedPoints combined;
  double sum = 0.0;
  for (const db::LabelledResult* result : members) {
    const TestRating rating = RateTest(set, [&](const std::string& name) {
      const engine::SummaryField* field = engine::FindSummaryField(name);
      return field != nullptr ? field->Get(result->summary) : kNaN;
    });
    if (set.hard_contact) {
      combined.contact_assumed += rating.hard_contact == HardContact::kAssumed;
      combined.contact_not_assumed += rating.hard_contact == HardContact::kNotAssumed;
      combined.contact_not_applied += rating.hard_contact == HardContact::kNotApplied;
    }
    if (!std::isfinite(rating.combined_points)) continue;
    ++combined.tests;
    sum += rating.combined_points;
    if (!(rating.combined_points >= combined.lowest_points)) {  // the first of the lowest (NaN at first)
      combined.lowest_points = rating.combined_points;
      combined.lowest_test = result->test_id;
    }
  }
  if (combined.tests > 0) combined.mean_points = sum / static_cast<double>(combined.tests);
  return combined;
}

}  // namespace

// The group of a variant: its name, except that names of the form (none),
// "(none)", ""(none)"" ... get one more pair of double quotes, so no variant
// is taken for (or pooled with) the tests without one, also in a catalogue
// written before import refused the name (docs/formats.md "napkin compare").
std::string VariantGroup(const std::optional<std::string>& variant) {
  if (!variant) return std::string(kNoVariant);
  std::string_view core = *variant;
  while (core.size() >= 2 && core.front() == '"' && core.back() == '"')
    core = core.substr(1, core.size() - 2);
  return core == kNoVariant ? "\"" + *variant + "\"" : *variant;
}

std::string_view ScaleName(CompareScale scale) { return scale == CompareScale::kLog ? "log" : "linear"; }

bool IsRatioMetric(std::string_view metric) {
  const engine::SummaryField* field = engine::FindSummaryField(metric);
  return field != nullptr && field->log_scale;
}

CompareRequest ParseCompareRequest(const RequestOptions& options) {
  options.CheckKnown({"series", "by", "baseline", "metrics", "config", "scale", "equivalence", "limits"});
  CompareRequest request;
  request.front_end = options.front_end();
  request.series = options.Required("series", "the series whose tests are compared");
  request.by = options.OneOf("by", {"variant", "config"}, "variant") == "variant" ? CompareBy::kVariant
                                                                                  : CompareBy::kConfig;
  request.baseline = options.One("baseline");
  request.metrics = options.CommaList("metrics");
  request.configs = options.All("config");
  request.scale =
      options.OneOf("scale", {"log", "linear"}, "log") == "log" ? CompareScale::kLog : CompareScale::kLinear;
  if (const std::optional<std::string> equivalence = options.One("equivalence")) {
    const std::optional<double> value = util::ParseDouble(*equivalence);
    if (!value || !(*value > 0.0) || !(*value < 100.0))
      throw UsageError(options.Name("equivalence") + " must be a margin in percent between 0 and 100 " +
                       "(exclusive), e.g. 10 for ±10 %; it is '" + util::Abbreviated(*equivalence) + "'.");
    request.equivalence_pct = *value;
  }
  request.limits = options.All("limits");
  if (request.by == CompareBy::kVariant && request.configs.size() > 1)
    throw UsageError(options.Setting("by", "variant") + " compares the results of one config; give " +
                     options.Name("config") + " once (or use " + options.Setting("by", "config") + ").");
  // A row of compare's JSON holds one limit: two sets that limit one metric are refused.
  std::map<std::string, std::string> set_of_metric;
  for (const std::string& name : request.limits) {
    const LimitSet set = LoadLimits(name);
    for (const Limit& limit : set.limits) {
      const auto [at, added] = set_of_metric.emplace(limit.metric, set.name);
      if (!added)
        throw UsageError(options.Name("limits") + ": " + at->second + " and " + set.name + " both limit " +
                         limit.metric +
                         ", and a row of compare holds one limit; compare them one at a time (napkin report "
                         "and napkin demo take both).");
    }
  }
  return request;
}

std::vector<std::string> DefaultComparisonMetrics() {
  std::vector<std::string> metrics;
  for (const char* name : {"hic15", "hic36", "hic_d", "peak_acc_g", "a3ms_g", "peak_omega_radps",
                           "peak_alpha_radps2", "bric", "damage", "max_rotation_deg"})
    if (engine::FindSummaryField(name) != nullptr) metrics.emplace_back(name);
  // The risks read from the verdict's criteria (in_verdict: HIC15 and BrIC), in table order.
  for (const engine::SummaryField* risk : engine::RiskFields())
    if (engine::FindSummaryField(risk->curve->criterion)->in_verdict) metrics.emplace_back(risk->name);
  return metrics;
}

Comparison BuildComparison(db::Catalogue& catalogue, const CompareRequest& request) {
  if (!catalogue.ReadSeries(request.series)) {
    std::vector<std::string> names;
    for (const db::SeriesRow& series : catalogue.ReadAllSeries()) names.push_back(series.name);
    throw UsageError(
        "unknown series '" + request.series + "' (" +
        (names.empty() ? std::string("the catalogue has no series") : "series: " + Joined(names)) + ").");
  }
  std::vector<const engine::SummaryField*> fields = ResolveMetrics(request.metrics);
  std::vector<ComparedLimitSet> limit_sets;
  for (const std::string& name : request.limits) {
    ComparedLimitSet& loaded = limit_sets.emplace_back();
    loaded.set = LoadLimits(name);
    for (const std::string& metric : LimitMetrics(loaded.set)) {  // a limit's metric is compared too
      const engine::SummaryField* field = engine::FindSummaryField(metric);
      if (field != nullptr && std::find(fields.begin(), fields.end(), field) == fields.end())
        fields.push_back(field);
    }
  }
  std::set<std::int64_t> config_ids;
  for (const std::string& spec : request.configs)
    config_ids.insert(static_cast<std::int64_t>(
        ResolveConfigSelector(catalogue, spec, OptionName(request.front_end, "config")).id));

  db::TestFilter filter;
  filter.series = {request.series};
  const bool latest = request.by == CompareBy::kVariant && request.configs.empty();
  std::vector<db::LabelledResult> results = catalogue.ReadResults(
      filter, latest ? db::ResultSelection::kLatest : db::ResultSelection::kEveryConfig);
  if (!config_ids.empty())
    std::erase_if(results, [&](const db::LabelledResult& result) {
      return config_ids.count(static_cast<std::int64_t>(result.config_id)) == 0;
    });
  if (results.empty()) {
    // After a run whose tests all failed, "run `napkin run` first" would send the reader in a circle.
    db::JobScope scope;
    scope.tests = filter;
    std::int64_t failed = 0;
    for (const db::VersionCount& count : db::JobQueue(catalogue).ReadVersionCounts(scope))
      failed += count.failed;
    if (failed > 0)
      throw InputError("series '" + request.series + "' has no results" +
                       (request.configs.empty() ? "" : " under the chosen config") + ": " +
                       (failed == 1 ? "its test failed" : "its " + std::to_string(failed) + " tests failed") +
                       " processing; `napkin status` lists the failures with their reasons.");
    throw InputError("series '" + request.series + "' has no results" +
                     (request.configs.empty() ? "" : " under the chosen config") +
                     ": run `napkin run` first.");
  }

  // Config names shared by two compared configs get a hash suffix.
  std::set<std::string> shared_names;
  if (request.by == CompareBy::kConfig) {
    std::map<std::string, std::set<std::string>> hashes_by_name;
    for (const db::LabelledResult& result : results)
      hashes_by_name[result.config_name].insert(result.config_hash);
    for (const auto& [name, hashes] : hashes_by_name)
      if (hashes.size() > 1) shared_names.insert(name);
  }
  std::map<std::string, std::vector<const db::LabelledResult*>> results_by_group;  // name order
  for (const db::LabelledResult& result : results)
    results_by_group[GroupOf(result, request.by, shared_names)].push_back(&result);

  Comparison comparison;
  comparison.series = request.series;
  comparison.by = request.by;
  comparison.baseline = results_by_group.begin()->first;
  if (request.baseline) {
    std::optional<std::string> found;
    if (results_by_group.count(*request.baseline) != 0) {
      found = *request.baseline;
    } else if (request.by == CompareBy::kConfig) {
      // The config of one of the groups, by the rule of --config
      // (MatchConfigSelector: a name, else a hash prefix in any case; a name
      // two configs share is ambiguous). Each group holds one config.
      std::vector<std::string> groups;
      std::vector<db::ConfigRow> configs;
      for (const auto& [group, members] : results_by_group) {
        groups.push_back(group);
        db::ConfigRow& config = configs.emplace_back();
        config.id = members.front()->config_id;
        config.name = members.front()->config_name;
        config.config_hash = members.front()->config_hash;
      }
      found =
          groups[MatchConfigSelector(configs, OptionName(request.front_end, "baseline"), *request.baseline,
                                     "the configs of series '" + request.series + "' with results are")];
    }
    if (!found) {
      std::vector<std::string> names;
      names.reserve(results_by_group.size());
      for (const auto& [group, members] : results_by_group) names.push_back(group);
      throw UsageError("unknown baseline '" + *request.baseline + "' (" +
                       (request.by == CompareBy::kVariant ? "variants" : "configs") + " of series '" +
                       request.series + "' with results: " + Joined(names) + ").");
    }
    comparison.baseline = *found;
  }
  comparison.groups.push_back(comparison.baseline);
  for (const auto& [group, members] : results_by_group)
    if (group != comparison.baseline) comparison.groups.push_back(group);

  for (const std::string& group : comparison.groups) {
    const std::vector<const db::LabelledResult*>& members = results_by_group.at(group);
    comparison.tests_per_group.push_back(members.size());
    comparison.salvaged_per_group.push_back(static_cast<std::size_t>(std::count_if(
        members.begin(), members.end(), [](const db::LabelledResult* result) { return result->salvaged; })));
  }
  comparison.scale = request.scale;
  comparison.equivalence_pct = request.equivalence_pct;
  for (ComparedLimitSet& loaded : limit_sets)
    if (loaded.set.combined)
      for (const std::string& group : comparison.groups)
        loaded.combined.push_back(CombineGroup(loaded.set, results_by_group.at(group)));
  comparison.limit_sets = std::move(limit_sets);
  for (const engine::SummaryField* field : fields) {
    MetricComparison& metric = comparison.metrics.emplace_back();
    metric.metric = field->name;
    for (const std::string& group : comparison.groups) {
      GroupValues& values = metric.groups.emplace_back();
      values.group = group;
      for (const db::LabelledResult* result : results_by_group.at(group)) {
        const double value = field->Get(result->summary);
        if (!std::isfinite(value)) continue;  // absent (NULL) in the catalogue
        values.test_ids.push_back(result->test_id);
        values.values.push_back(value);
      }
    }
  }
  // The default metrics leave out those no test of the series has (the
  // rotation of acceleration-only tests); named ones stay.
  if (request.metrics.empty())
    std::erase_if(comparison.metrics, [](const MetricComparison& metric) {
      return std::all_of(metric.groups.begin(), metric.groups.end(),
                         [](const GroupValues& values) { return values.values.empty(); });
    });
  for (MetricComparison& metric : comparison.metrics) {
    metric = CompareMetric(metric.metric, std::move(metric.groups), request.by, request.scale,
                           request.equivalence_pct);
    CheckLimits(comparison.limit_sets, metric);
  }
  return comparison;
}

MetricComparison CompareMetric(const std::string& name, std::vector<GroupValues> groups, CompareBy by,
                               CompareScale scale, double equivalence_pct) {
  MetricComparison metric;
  metric.metric = name;
  metric.groups = std::move(groups);
  // The log scale for a ratio metric whose values are all > 0; else the
  // linear scale, and a ratio metric says why.
  const bool ratio = scale == CompareScale::kLog && IsRatioMetric(name);
  const bool positive = std::all_of(metric.groups.begin(), metric.groups.end(), [](const GroupValues& g) {
    return std::all_of(g.values.begin(), g.values.end(), [](double v) { return v > 0.0; });
  });
  if (metric.groups.empty()) return metric;
  const GroupValues& baseline = metric.groups.front();
  for (const GroupValues& values : metric.groups) {
    ComparisonRow& row = metric.rows.emplace_back();
    row.metric = metric.metric;
    row.group = values.group;
    row.description = engine::Describe(values.values);
    row.baseline = baseline.group;
    row.is_baseline = &values == &baseline;
    row.scale = ratio && positive ? CompareScale::kLog : CompareScale::kLinear;
    row.log_fallback = ratio && !positive;
    row.equivalence_pct = equivalence_pct;
    row.equivalence = engine::TwoOneSidedTests(NoDifference(), kNaN, kNaN);
    if (row.is_baseline)
      row.difference = NoDifference();
    else if (by == CompareBy::kVariant)
      IndependentDifference(values, baseline, row, equivalence_pct);
    else
      PairedDifference(values, baseline, row, equivalence_pct);
    if (!std::isfinite(row.difference.diff)) row.baseline_mean = kNaN;
  }
  return metric;
}

GroupLimitCheck CheckGroupLimit(const Limit& limit, const GroupValues& values) {
  GroupLimitCheck check;
  check.tests = values.values.size();
  check.band_counts.assign(limit.bands.size(), 0);
  double points = 0.0;
  for (std::size_t i = 0; i < values.values.size(); ++i) {
    const double value = values.values[i];
    if (value <= limit.max) ++check.within;
    if (!(value <= check.worst_value)) {  // the first of the highest (NaN at first)
      check.worst_value = value;
      check.worst_test = values.test_ids[i];
    }
    if (limit.kind == LimitKind::kScale) points += ScalePoints(limit, value);
    if (limit.kind == LimitKind::kBands)
      ++check.band_counts[static_cast<std::size_t>(&BandOf(limit, value) - limit.bands.data())];
  }
  if (check.tests == 0) {
    check.prediction_gap = engine::PredictionGap::kTooFew;
    return check;
  }
  check.margin_pct = LimitMarginPct(check.worst_value, limit.max);
  if (limit.kind == LimitKind::kScale) check.mean_points = points / static_cast<double>(check.tests);
  // A further test (engine/prediction.h, docs/algorithms.md "A further test").
  const engine::PredictiveFit fit = engine::FitLogPredictive(values.values);
  check.prediction_gap = fit.gap;
  if (!fit.predictive) return check;
  check.exceed_probability = engine::ExceedProbability(*fit.predictive, limit.max);
  if (limit.kind == LimitKind::kScale) {
    check.expected_points =
        engine::ExpectedScalePoints(*fit.predictive, limit.higher_limit, limit.max, limit.points);
    const double tail = (1.0 - kPointsPredictionCoverage) / 2.0;
    // Points fall as the value rises: the low end of the points is the high end of the value.
    check.points_low = ScalePoints(limit, engine::PredictiveQuantile(*fit.predictive, 1.0 - tail));
    check.points_high = ScalePoints(limit, engine::PredictiveQuantile(*fit.predictive, tail));
  }
  return check;
}

}  // namespace napkin::app

#include "cli/comparison.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <string_view>

#include "cli/db_option.h"
#include "common/error.h"
#include "common/joined.h"
#include "engine/summary_fields.h"
#include "ingest/import.h"
#include "util/text.h"

namespace napkin::cli {
namespace {

// The group of the tests without a variant; import refuses it as a variant name.
constexpr std::string_view kNoVariant = ingest::kNoVariantGroup;

const engine::SummaryField* FindField(const std::string& name) {
  for (const engine::SummaryField& field : engine::SummaryFields())
    if (name == field.name) return &field;
  return nullptr;
}

std::vector<const engine::SummaryField*> ResolveMetrics(const std::vector<std::string>& requested) {
  const std::vector<std::string> names = requested.empty() ? DefaultComparisonMetrics() : requested;
  std::vector<const engine::SummaryField*> fields;
  for (const std::string& name : names) {
    const engine::SummaryField* field = FindField(name);
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

// Paired t of `group` against `baseline` over the tests both have.
engine::MeanDifference PairedDifference(const GroupValues& group, const GroupValues& baseline,
                                        ComparisonRow& row) {
  std::map<std::string, double> baseline_by_test;
  for (std::size_t i = 0; i < baseline.test_ids.size(); ++i)
    baseline_by_test.emplace(baseline.test_ids[i], baseline.values[i]);
  std::vector<double> differences;
  std::vector<double> baseline_values;
  for (std::size_t i = 0; i < group.test_ids.size(); ++i) {
    const auto found = baseline_by_test.find(group.test_ids[i]);
    if (found == baseline_by_test.end()) continue;
    differences.push_back(group.values[i] - found->second);
    baseline_values.push_back(found->second);
  }
  row.pairs = differences.size();
  row.baseline_mean = engine::Describe(baseline_values).mean;
  const engine::MeanDifference difference = engine::PairedComparison(differences, row.baseline_mean);
  if (std::isfinite(difference.diff))
    row.n_for_80pct_power = engine::WholeRepeatsForPower(
        engine::PairedPowerModel(difference.diff, engine::Describe(differences).sd));
  return difference;
}

engine::MeanDifference NoDifference() {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  return {kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN};
}

// ---------------------------------------------------------------- the table

// n_for_80pct_power as an integer cell, or NULL.
db::Cell PowerCell(double n) {
  if (!std::isfinite(n)) return std::monostate{};
  return static_cast<std::int64_t>(n);
}

std::string PowerText(double n) {
  return std::isfinite(n) ? fmt::format("{}", static_cast<long long>(n)) : "-";
}

std::string Number(double value) { return std::isfinite(value) ? fmt::format("{:.6g}", value) : "-"; }

std::string PValue(double p) {
  if (!std::isfinite(p)) return "-";
  if (p < 1e-4) return "p<0.0001";
  return fmt::format("p={:.2g}", p);
}

// "-23.1 % [-31.0, -15.2] p=0.0004": the difference and its interval in % of
// the baseline mean, or in the metric's unit when that mean is 0.
std::string DifferenceText(const ComparisonRow& row, CompareBy by) {
  if (row.is_baseline) return "(baseline)";
  const engine::MeanDifference& d = row.difference;
  const std::string paired = by == CompareBy::kConfig ? fmt::format(" ({} pairs)", row.pairs) : "";
  if (!std::isfinite(d.diff)) return "n < 2: no difference (1)" + paired;
  const bool percent = std::isfinite(d.diff_pct);
  std::string text = percent ? fmt::format("{:+.1f} %", d.diff_pct) : fmt::format("{:+.4g}", d.diff);
  if (!std::isfinite(d.ci_low)) return text + " (no scatter: no interval)" + paired;
  if (percent) {
    const double scale = 100.0 / row.baseline_mean;
    text += fmt::format(" [{:+.1f}, {:+.1f}]", d.ci_low * scale, d.ci_high * scale);
  } else {
    text += fmt::format(" [{:+.4g}, {:+.4g}]", d.ci_low, d.ci_high);
  }
  return text + "  " + PValue(d.p_value) + paired;
}

std::string HumanComparison(const Comparison& comparison) {
  const bool by_variant = comparison.by == CompareBy::kVariant;
  // Stored names are shown escaped (control characters, bytes that are not UTF-8).
  std::string out =
      fmt::format("series {}: {} compared with {} '{}'\n", util::EscapeControl(comparison.series),
                  by_variant ? "variants" : "processing configs", by_variant ? "variant" : "config",
                  util::EscapeControl(comparison.baseline));
  out += by_variant ? "difference of means in % of the baseline mean, [95 % confidence interval] "
                      "(Welch's t), two-sided p\n"
                    : "mean of the per-test differences in % of the baseline's mean over the same tests, "
                      "[95 % confidence interval] (paired t), two-sided p\n";
  out += by_variant ? "n80: tests per variant that would detect the observed difference with 80 % power "
                      "(two-sided t, alpha 0.05)\n"
                    : "n80: tests that would detect the observed mean difference with 80 % power "
                      "(two-sided paired t, alpha 0.05)\n";
  bool small_group = false;
  for (const MetricComparison& metric : comparison.metrics) {
    std::vector<std::vector<std::string>> cells;
    cells.push_back({by_variant ? "variant" : "config", "n", "mean", "sd", "median", "min", "max", "n80",
                     "vs " + util::EscapeControl(comparison.baseline)});
    for (const ComparisonRow& row : metric.rows) {
      const engine::Description& d = row.description;
      cells.push_back({util::EscapeControl(row.group), std::to_string(d.n), Number(d.mean), Number(d.sd),
                       Number(d.median), Number(d.min), Number(d.max), PowerText(row.n_for_80pct_power),
                       DifferenceText(row, comparison.by)});
      if (!row.is_baseline && !std::isfinite(row.difference.diff)) small_group = true;
    }
    std::vector<std::size_t> width(cells.front().size(), 0);
    for (const auto& line : cells)
      for (std::size_t c = 0; c < line.size(); ++c) width[c] = std::max(width[c], line[c].size());
    out += "\n" + metric.metric + "\n";
    for (const auto& line : cells) {
      std::string text = "  ";
      for (std::size_t c = 0; c < line.size(); ++c) {
        const std::string pad(width[c] - line[c].size(), ' ');
        if (c == 0)
          text += line[c] + pad;
        else if (c + 1 == line.size())
          text += "  " + line[c];
        else
          text += "  " + pad + line[c];
      }
      out += text + "\n";
    }
  }
  if (small_group)
    out += by_variant ? "\n(1) n < 2: with fewer than 2 tests in the group or the baseline there is no "
                        "difference, interval or p-value (null in --format json and csv).\n"
                      : "\n(1) n < 2: fewer than 2 tests have results under both configs: no difference, "
                        "interval or p-value (null in --format json and csv).\n";
  return out;
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

CompareBy ParseCompareBy(const std::string& text) {
  if (text == "variant") return CompareBy::kVariant;
  if (text == "config") return CompareBy::kConfig;
  throw UsageError("unknown --by '" + text + "' (use variant or config).");
}

std::vector<std::string> DefaultComparisonMetrics() {
  std::vector<std::string> metrics;
  for (const char* name :
       {"hic15", "hic36", "hic_d", "peak_acc_g", "a3ms_g", "peak_omega_radps", "peak_alpha_radps2", "bric",
        "damage", "max_rotation_deg", "hic15_p_ais3", "bric_p_ais3", "bric_p_ais4"})
    if (FindField(name) != nullptr) metrics.emplace_back(name);
  return metrics;
}

Comparison BuildComparison(db::Catalogue& catalogue, const ComparisonRequest& request) {
  if (!catalogue.ReadSeries(request.series)) {
    std::vector<std::string> names;
    for (const db::SeriesRow& series : catalogue.ReadAllSeries()) names.push_back(series.name);
    throw UsageError(
        "unknown series '" + request.series + "' (" +
        (names.empty() ? std::string("the catalogue has no series") : "series: " + Joined(names)) + ").");
  }
  const std::vector<const engine::SummaryField*> fields = ResolveMetrics(request.metrics);
  if (request.by == CompareBy::kVariant && request.configs.size() > 1)
    throw UsageError(
        "--by variant compares the results of one config; give --config once (or use --by config).");
  std::set<std::int64_t> config_ids;
  for (const std::string& spec : request.configs)
    config_ids.insert(static_cast<std::int64_t>(ResolveConfigSelector(catalogue, spec).id));

  db::TestFilter filter;
  filter.series = request.series;
  const bool latest = request.by == CompareBy::kVariant && request.configs.empty();
  std::vector<db::LabelledResult> results = catalogue.ReadResults(
      filter, latest ? db::ResultSelection::kLatest : db::ResultSelection::kEveryConfig);
  if (!config_ids.empty())
    std::erase_if(results, [&](const db::LabelledResult& result) {
      return config_ids.count(static_cast<std::int64_t>(result.config_id)) == 0;
    });
  if (results.empty())
    throw InputError("series '" + request.series + "' has no results" +
                     (request.configs.empty() ? "" : " under the chosen config") +
                     ": run `napkin run` first.");

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
      found = groups[MatchConfigSelector(configs, "--baseline", *request.baseline,
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
    const GroupValues& baseline = metric.groups.front();
    for (const GroupValues& values : metric.groups) {
      ComparisonRow& row = metric.rows.emplace_back();
      row.metric = metric.metric;
      row.group = values.group;
      row.description = engine::Describe(values.values);
      row.baseline = comparison.baseline;
      row.is_baseline = &values == &baseline;
      if (row.is_baseline) {
        row.difference = NoDifference();
      } else if (request.by == CompareBy::kVariant) {
        row.difference = engine::WelchComparison(values.values, baseline.values);
        row.baseline_mean = metric.rows.front().description.mean;
        if (std::isfinite(row.difference.diff))
          row.n_for_80pct_power = engine::WholeRepeatsForPower(engine::WelchPowerModel(
              row.difference.diff, row.description.sd, metric.rows.front().description.sd));
      } else {
        row.difference = PairedDifference(values, baseline, row);
      }
      if (!std::isfinite(row.difference.diff)) row.baseline_mean = std::numeric_limits<double>::quiet_NaN();
    }
  }
  return comparison;
}

db::Table ComparisonTable(const Comparison& comparison) {
  db::Table table;
  table.columns = {"metric",   "group",  "n",       "mean",     "sd",
                   "median",   "min",    "max",     "baseline", "diff",
                   "diff_pct", "ci_low", "ci_high", "p_value",  "n_for_80pct_power"};
  for (const MetricComparison& metric : comparison.metrics) {
    for (const ComparisonRow& row : metric.rows) {
      const engine::Description& d = row.description;
      const engine::MeanDifference& m = row.difference;
      table.rows.push_back({row.metric, row.group, static_cast<std::int64_t>(d.n), d.mean, d.sd, d.median,
                            d.min, d.max, row.baseline, m.diff, m.diff_pct, m.ci_low, m.ci_high, m.p_value,
                            PowerCell(row.n_for_80pct_power)});
    }
  }
  return table;
}

std::string FormatComparison(const Comparison& comparison, TableFormat format) {
  if (format == TableFormat::kTable) return HumanComparison(comparison);
  return FormatTable(ComparisonTable(comparison), format);
}

}  // namespace napkin::cli

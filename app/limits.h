#pragma once
// Regulatory and consumer-test limits of head criteria (docs/formats.md
// "Limits"): data files config/limits/NAME.json, each with its source, read
// by `compare`, `report` and `demo --limits NAME` and `query limits`. Plain
// data and functions: no command line here.
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "db/catalogue.h"
#include "formats/array_json.h"

namespace napkin::app {

// The range of a limit's `max`: wider than any head criterion's limit, narrow enough that every
// margin (LimitMarginPct) of a finite value is a finite percentage.
inline constexpr double kMinLimit = 1e-6;
inline constexpr double kMaxLimit = 1e6;

// One limit: the summary field (of `query criteria`) must not exceed `max`.
struct Limit {
  std::string metric;
  double max = 0.0;
  std::string requirement;  // the source's words, e.g. "S6.1: HIC(d) shall not exceed 1000"
};

struct LimitSet {
  std::string name;        // short, for sentences: "FMVSS 201U"
  std::string title;       // what the limits are
  std::string applies_to;  // the test and dummy or headform they are for
  std::string source;      // the citation
  std::string url;
  std::vector<Limit> limits;
  std::filesystem::path path;  // the file read
};

// The limit set `name_or_path`: a JSON file, or a preset of `config_dir`/limits.
// Throws UsageError naming --limits (one sentence listing the presets) when
// it is neither, InputError naming the file when the file is malformed (a
// missing key, a metric that is not a field of `query criteria`, a limit
// that is not a positive number).
LimitSet LoadLimits(std::string_view name_or_path,
                    const std::filesystem::path& config_dir = formats::DefaultConfigDir());

// The preset names of `config_dir`/limits, in name order.
std::vector<std::string> LimitPresets(const std::filesystem::path& config_dir = formats::DefaultConfigDir());

// 100 (limit - value) / limit: positive within the limit, negative over it.
double LimitMarginPct(double value, double limit);

// `query limits`: each row of `criteria` (a `query criteria` table: test_id,
// series, variant, then the criteria) against each limit of `limits`:
// columns test_id, series, variant, limits, metric, value, limit,
// margin_pct, meets ("yes", "no", or null without a value).
db::Table LimitsTable(const db::Table& criteria, const LimitSet& limits);

}  // namespace napkin::app

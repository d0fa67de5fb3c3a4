#include "app/limits.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/joined.h"
#include "formats/json_file.h"
#include "util/text.h"

namespace napkin::app {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

std::string Text(const json& root, const char* key, const fs::path& path) {
  if (!root.contains(key) || !root.at(key).is_string() || root.at(key).get<std::string>().empty())
    throw InputError("limits file " + path.string() + ": \"" + key + "\" must be a non-empty string.");
  return root.at(key).get<std::string>();
}

// Every key of `object` is one of `known`: a misspelt key ("colour", "maximum") is refused naming
// it, never silently ignored.
void CheckKeys(const json& object, std::initializer_list<std::string> known, const std::string& where,
               const fs::path& path) {
  for (const auto& [key, value] : object.items())
    if (std::find(known.begin(), known.end(), key) == known.end())
      throw InputError("limits file " + path.string() + ": " + where + " has the unknown key \"" +
                       util::Abbreviated(key) + "\" (it may give " + Joined(std::vector<std::string>(known)) +
                       ").");
}

// The fields a limit may name: those of `query criteria`.
std::vector<std::string> CriteriaFields() {
  std::vector<std::string> fields;
  for (const db::QueryField& field : db::QueryFields(db::QueryKind::kCriteria))
    if (field.numeric) fields.push_back(field.name);
  return fields;
}

}  // namespace

std::vector<std::string> LimitPresets(const fs::path& config_dir) {
  std::vector<std::string> names;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(config_dir / "limits", error))
    if (entry.path().extension() == ".json") names.push_back(entry.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

LimitSet LoadLimits(std::string_view name_or_path, const fs::path& config_dir) {
  std::error_code error;
  fs::path path(name_or_path);
  if (name_or_path.empty() || !fs::is_regular_file(path, error)) {
    path = config_dir / "limits" / (std::string(name_or_path) + ".json");
    if (name_or_path.empty() || name_or_path.find('/') != std::string_view::npos ||
        !fs::is_regular_file(path, error))
      throw UsageError("--limits '" + std::string(name_or_path) + "' is neither a file nor a preset in " +
                       (config_dir / "limits").string() + " (presets: " + Joined(LimitPresets(config_dir)) +
                       ").");
  }
  // Read through one descriptor, a regular file of bounded size (formats/json_file.h).
  const std::string text = formats::ReadWholeFile(path, formats::kMaxJsonFileBytes);
  json root;
  try {
    root = json::parse(text);
  } catch (const json::exception& e) {
    throw InputError("limits file " + path.string() + " is not valid JSON (" + e.what() + ").");
  }
  if (!root.is_object()) throw InputError("limits file " + path.string() + " must hold a JSON object.");
  CheckKeys(root, {"name", "title", "applies_to", "source", "url", "limits"}, "the file", path);
  LimitSet set;
  set.path = path;
  set.name = Text(root, "name", path);
  set.title = Text(root, "title", path);
  set.applies_to = Text(root, "applies_to", path);
  set.source = Text(root, "source", path);
  set.url = Text(root, "url", path);
  if (!root.contains("limits") || !root.at("limits").is_array() || root.at("limits").empty())
    throw InputError("limits file " + path.string() + ": \"limits\" must be a non-empty array.");
  const std::vector<std::string> fields = CriteriaFields();
  for (const json& entry : root.at("limits")) {
    if (!entry.is_object())
      throw InputError("limits file " + path.string() + ": each limit must be an object.");
    CheckKeys(entry, {"metric", "max", "requirement"}, "a limit", path);
    Limit limit;
    limit.metric = Text(entry, "metric", path);
    limit.requirement = Text(entry, "requirement", path);
    if (std::find(fields.begin(), fields.end(), limit.metric) == fields.end())
      throw InputError("limits file " + path.string() + ": metric '" + limit.metric +
                       "' is not a field of `napkin query criteria` (" + Joined(fields) + ").");
    // Plausible as a limit of a head criterion, so that every margin is a finite percentage (1e308
    // gave margins of +inf %).
    if (!entry.contains("max") || !entry.at("max").is_number() || !(entry.at("max").get<double>() > 0.0) ||
        !std::isfinite(entry.at("max").get<double>()))
      throw InputError("limits file " + path.string() + ": the \"max\" of metric '" + limit.metric +
                       "' must be a positive number.");
    if (entry.at("max").get<double>() < kMinLimit || entry.at("max").get<double>() > kMaxLimit)
      throw InputError("limits file " + path.string() + ": the \"max\" of metric '" + limit.metric + "', " +
                       util::FormatNumber(entry.at("max").get<double>()) +
                       ", is not a plausible limit (it must be from 1e-06 to 1e+06).");
    limit.max = entry.at("max").get<double>();
    set.limits.push_back(std::move(limit));
  }
  return set;
}

double LimitMarginPct(double value, double limit) { return 100.0 * (limit - value) / limit; }

db::Table LimitsTable(const db::Table& criteria, const LimitSet& limits) {
  db::Table table;
  table.columns = {"test_id", "series", "variant",    "limits", "metric",
                   "value",   "limit",  "margin_pct", "meets"};
  const auto column = [&](const std::string& name) {
    return static_cast<std::size_t>(std::find(criteria.columns.begin(), criteria.columns.end(), name) -
                                    criteria.columns.begin());
  };
  for (const std::vector<db::Cell>& row : criteria.rows) {
    for (const Limit& limit : limits.limits) {
      const std::size_t at = column(limit.metric);
      const db::Cell value = at < row.size() ? row[at] : db::Cell{};
      const double* number = std::get_if<double>(&value);
      std::vector<db::Cell> out = {row[column("test_id")],
                                   row[column("series")],
                                   row[column("variant")],
                                   limits.name,
                                   limit.metric,
                                   value,
                                   limit.max};
      if (number != nullptr && std::isfinite(*number)) {
        out.emplace_back(LimitMarginPct(*number, limit.max));
        out.emplace_back(std::string(*number <= limit.max ? "yes" : "no"));
      } else {
        out.emplace_back(std::monostate{});
        out.emplace_back(std::monostate{});
      }
      table.rows.push_back(std::move(out));
    }
  }
  return table;
}

}  // namespace napkin::app

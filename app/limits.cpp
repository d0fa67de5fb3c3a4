#include "app/limits.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/joined.h"
#include "formats/json_file.h"
#include "util/text.h"

namespace napkin::app {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

constexpr double kNoValue = std::numeric_limits<double>::quiet_NaN();

[[noreturn]] void Malformed(const fs::path& path, const std::string& what) {
  throw InputError("limits file " + path.string() + ": " + what);
}

std::string Text(const json& root, const char* key, const fs::path& path) {
  if (!root.contains(key) || !root.at(key).is_string() || root.at(key).get<std::string>().empty())
    Malformed(path, "\"" + std::string(key) + "\" must be a non-empty string.");
  return root.at(key).get<std::string>();
}

std::string OptionalText(const json& root, const char* key, const fs::path& path) {
  return root.contains(key) ? Text(root, key, path) : std::string();
}

// Every key of `object` is one of `known`: a misspelt key ("colour", "maximum") is refused naming
// it, never silently ignored.
void CheckKeys(const json& object, std::initializer_list<std::string> known, const std::string& where,
               const fs::path& path) {
  for (const auto& [key, value] : object.items())
    if (std::find(known.begin(), known.end(), key) == known.end())
      Malformed(path, where + " has the unknown key \"" + util::Abbreviated(key) + "\" (it may give " +
                          Joined(std::vector<std::string>(known)) + ").");
}

// The fields a limit may name: those of `query criteria`.
std::vector<std::string> CriteriaFields() {
  std::vector<std::string> fields;
  for (const db::QueryField& field : db::QueryFields(db::QueryKind::kCriteria))
    if (field.numeric) fields.push_back(field.name);
  return fields;
}

std::string Metric(const json& entry, const fs::path& path) {
  const std::string metric = Text(entry, "metric", path);
  const std::vector<std::string> fields = CriteriaFields();
  if (std::find(fields.begin(), fields.end(), metric) == fields.end())
    Malformed(path,
              "metric '" + metric + "' is not a field of `napkin query criteria` (" + Joined(fields) + ").");
  return metric;
}

// A number of a limit: positive, and plausible as a limit of a head criterion, so that every
// margin is a finite percentage (1e308 gave margins of +inf %). `what`: "the \"max\" of metric
// 'hic15'".
double LimitNumber(const json& object, const char* key, const std::string& what, const fs::path& path) {
  if (!object.contains(key) || !object.at(key).is_number() || !(object.at(key).get<double>() > 0.0) ||
      !std::isfinite(object.at(key).get<double>()))
    Malformed(path, what + " must be a positive number.");
  const double value = object.at(key).get<double>();
  if (value < kMinLimit || value > kMaxLimit)
    Malformed(path, what + ", " + util::FormatNumber(value) +
                        ", is not a plausible limit (it must be from 1e-06 to 1e+06).");
  return value;
}

void ReadScale(const json& scale, Limit& limit, const fs::path& path) {
  const std::string of = " of metric '" + limit.metric + "'";
  if (!scale.is_object()) Malformed(path, "the \"scale\"" + of + " must be an object.");
  CheckKeys(scale, {"higher_performance_limit", "lower_performance_limit", "points"}, "the \"scale\"" + of,
            path);
  limit.kind = LimitKind::kScale;
  limit.higher_limit =
      LimitNumber(scale, "higher_performance_limit", "the higher performance limit" + of, path);
  limit.max = LimitNumber(scale, "lower_performance_limit", "the lower performance limit" + of, path);
  limit.points = LimitNumber(scale, "points", "the points" + of, path);
  if (!(limit.higher_limit < limit.max))
    Malformed(path, "the higher performance limit" + of + ", " + util::FormatNumber(limit.higher_limit) +
                        ", must be below its lower performance limit, " + util::FormatNumber(limit.max) +
                        " (full points at or below the higher, none at or above the lower).");
}

void ReadBands(const json& bands, Limit& limit, const fs::path& path) {
  const std::string of = " of metric '" + limit.metric + "'";
  if (!bands.is_array() || bands.size() < 2)
    Malformed(path, "the \"bands\"" + of + " must be an array of at least 2 bands, best first.");
  limit.kind = LimitKind::kBands;
  for (std::size_t i = 0; i < bands.size(); ++i) {
    const json& band = bands[i];
    if (!band.is_object()) Malformed(path, "each band" + of + " must be an object.");
    CheckKeys(band, {"band", "max"}, "a band" + of, path);
    LimitBand read{Text(band, "band", path), std::nullopt};
    const bool last = i + 1 == bands.size();
    if (last && band.contains("max"))
      Malformed(path, "the last band" + of + ", " + read.name +
                          ", takes every value above the others: it has no \"max\".");
    if (!last) {
      read.max = LimitNumber(band, "max", "the \"max\" of band " + read.name + of, path);
      if (!limit.bands.empty() && !(*read.max > *limit.bands.back().max))
        Malformed(path, "the bands" + of + " must rise: band " + read.name + "'s max " +
                            util::FormatNumber(*read.max) + " is not above " + limit.bands.back().name +
                            "'s " + util::FormatNumber(*limit.bands.back().max) + ".");
    }
    limit.bands.push_back(std::move(read));
  }
  limit.max = *limit.bands.front().max;
}

Limit ReadLimit(const json& entry, const fs::path& path) {
  if (!entry.is_object()) Malformed(path, "each limit must be an object.");
  CheckKeys(entry, {"metric", "max", "scale", "bands", "requirement"}, "a limit", path);
  Limit limit;
  limit.metric = Metric(entry, path);
  limit.requirement = Text(entry, "requirement", path);
  const int kinds = static_cast<int>(entry.contains("max")) + static_cast<int>(entry.contains("scale")) +
                    static_cast<int>(entry.contains("bands"));
  if (kinds > 1)
    Malformed(path, "the limit of metric '" + limit.metric +
                        "' gives more than one of \"max\", \"scale\" and "
                        "\"bands\".");
  if (entry.contains("scale")) {
    ReadScale(entry.at("scale"), limit, path);
  } else if (entry.contains("bands")) {
    ReadBands(entry.at("bands"), limit, path);
  } else {
    limit.max = LimitNumber(entry, "max", "the \"max\" of metric '" + limit.metric + "'", path);
  }
  return limit;
}

void ReadCombined(const json& root, LimitSet& set, const fs::path& path) {
  const json& combined = root.at("combined");
  if (!combined.is_object()) Malformed(path, "\"combined\" must be an object.");
  CheckKeys(combined, {"name", "rule", "requirement"}, "\"combined\"", path);
  if (Text(combined, "rule", path) != "lowest")
    Malformed(path, "the \"rule\" of \"combined\" must be \"lowest\" (the lowest points of the criteria).");
  const auto scale = std::find_if(set.limits.begin(), set.limits.end(),
                                  [](const Limit& limit) { return limit.kind == LimitKind::kScale; });
  if (scale == set.limits.end()) Malformed(path, "\"combined\" needs a limit with a \"scale\".");
  for (const Limit& limit : set.limits)
    if (limit.kind == LimitKind::kScale && limit.points != scale->points)
      Malformed(path, "the scales of a combined region must give the same points (" + scale->metric + ": " +
                          util::FormatNumber(scale->points) + ", " + limit.metric + ": " +
                          util::FormatNumber(limit.points) + ").");
  set.combined = CombinedPoints{Text(combined, "name", path), Text(combined, "requirement", path)};
}

void ReadHardContact(const json& root, LimitSet& set, const fs::path& path) {
  const json& rule = root.at("hard_contact");
  if (!rule.is_object()) Malformed(path, "\"hard_contact\" must be an object.");
  CheckKeys(rule, {"metric", "above", "points_without", "requirement"}, "\"hard_contact\"", path);
  if (!set.combined)
    Malformed(path, "\"hard_contact\" gives the points of a \"combined\" region: it needs one.");
  HardContactRule read;
  read.metric = Metric(rule, path);
  read.above = LimitNumber(rule, "above", "the \"above\" of \"hard_contact\"", path);
  read.points_without =
      LimitNumber(rule, "points_without", "the \"points_without\" of \"hard_contact\"", path);
  read.requirement = Text(rule, "requirement", path);
  if (read.points_without > CombinedMaxPoints(set))
    Malformed(path, "the \"points_without\" of \"hard_contact\", " + util::FormatNumber(read.points_without) +
                        ", exceeds the region's full points, " + util::FormatNumber(CombinedMaxPoints(set)) +
                        ".");
  set.hard_contact = std::move(read);
}

}  // namespace

std::string_view LimitKindName(LimitKind kind) {
  switch (kind) {
    case LimitKind::kMaximum:
      return "maximum";
    case LimitKind::kScale:
      return "scale";
    case LimitKind::kBands:
      return "bands";
  }
  return "maximum";
}

std::vector<std::string> LimitPresets(const fs::path& config_dir) {
  return formats::PresetNames(formats::PresetKind::kLimits, config_dir);
}

LimitSet LoadLimits(std::string_view name_or_path, const fs::path& config_dir) {
  const fs::path path = formats::ResolvePreset(formats::PresetKind::kLimits, name_or_path, config_dir);
  // Read through one descriptor, a regular file of bounded size (formats/json_file.h).
  const std::string text = formats::ReadWholeFile(path, formats::kMaxJsonFileBytes);
  json root;
  try {
    root = json::parse(text);
  } catch (const json::exception& e) {
    throw InputError("limits file " + path.string() + " is not valid JSON (" + e.what() + ").");
  }
  if (!root.is_object()) throw InputError("limits file " + path.string() + " must hold a JSON object.");
  CheckKeys(root,
            {"name", "title", "applies_to", "source", "url", "version", "note", "limits", "combined",
             "hard_contact"},
            "the file", path);
  LimitSet set;
  set.path = path;
  set.name = Text(root, "name", path);
  set.title = Text(root, "title", path);
  set.applies_to = Text(root, "applies_to", path);
  set.source = Text(root, "source", path);
  set.url = Text(root, "url", path);
  set.version = OptionalText(root, "version", path);
  set.note = OptionalText(root, "note", path);
  if (!root.contains("limits") || !root.at("limits").is_array() || root.at("limits").empty())
    Malformed(path, "\"limits\" must be a non-empty array.");
  for (const json& entry : root.at("limits")) {
    Limit limit = ReadLimit(entry, path);
    for (const Limit& earlier : set.limits)
      if (earlier.metric == limit.metric)
        Malformed(path, "metric '" + limit.metric + "' has two limits (a set gives each criterion one).");
    set.limits.push_back(std::move(limit));
  }
  if (root.contains("combined")) ReadCombined(root, set, path);
  if (root.contains("hard_contact")) ReadHardContact(root, set, path);
  return set;
}

double LimitMarginPct(double value, double limit) { return 100.0 * (limit - value) / limit; }

double ScalePoints(const Limit& limit, double value) {
  if (value <= limit.higher_limit) return limit.points;
  if (value >= limit.max) return 0.0;
  return limit.points * (limit.max - value) / (limit.max - limit.higher_limit);
}

const LimitBand& BandOf(const Limit& limit, double value) {
  for (const LimitBand& band : limit.bands)
    if (band.max && value <= *band.max) return band;
  return limit.bands.back();
}

double CombinedMaxPoints(const LimitSet& set) {
  if (!set.combined) return kNoValue;
  for (const Limit& limit : set.limits)
    if (limit.kind == LimitKind::kScale) return limit.points;
  return kNoValue;
}

std::vector<std::string> LimitMetrics(const LimitSet& set) {
  std::vector<std::string> metrics;
  for (const Limit& limit : set.limits) metrics.push_back(limit.metric);
  if (set.hard_contact &&
      std::find(metrics.begin(), metrics.end(), set.hard_contact->metric) == metrics.end())
    metrics.push_back(set.hard_contact->metric);
  return metrics;
}

TestRating RateTest(const LimitSet& set, const std::function<double(const std::string& metric)>& value_of) {
  TestRating rating;
  double lowest = std::numeric_limits<double>::infinity();
  bool every_scale_valued = true;
  for (const Limit& limit : set.limits) {
    CriterionRating& criterion = rating.criteria.emplace_back();
    criterion.value = value_of(limit.metric);
    criterion.has_value = std::isfinite(criterion.value);
    criterion.points = kNoValue;
    if (!criterion.has_value) {
      criterion.value = kNoValue;
      if (limit.kind == LimitKind::kScale) every_scale_valued = false;
      continue;
    }
    switch (limit.kind) {
      case LimitKind::kMaximum:
        criterion.meets = criterion.value <= limit.max;
        break;
      case LimitKind::kScale:
        criterion.points = ScalePoints(limit, criterion.value);
        lowest = std::min(lowest, criterion.points);
        break;
      case LimitKind::kBands:
        criterion.band = &BandOf(limit, criterion.value);
        break;
    }
  }
  rating.combined_points = kNoValue;
  rating.contact_value = kNoValue;
  if (!set.combined) return rating;
  const double assessed = every_scale_valued ? lowest : kNoValue;
  rating.combined_points = assessed;
  if (!set.hard_contact) return rating;
  const double contact = value_of(set.hard_contact->metric);
  if (!std::isfinite(contact)) return rating;  // not applied: the criteria's points
  rating.contact_value = contact;
  if (contact > set.hard_contact->above) {
    rating.hard_contact = HardContact::kAssumed;
  } else {
    rating.hard_contact = HardContact::kNotAssumed;
    rating.combined_points = set.hard_contact->points_without;
  }
  return rating;
}

std::string HardContactText(const LimitSet& set, const TestRating& rating) {
  if (!set.hard_contact) return "";
  const HardContactRule& rule = *set.hard_contact;
  const std::string threshold = util::FormatNumber(rule.above, 6);
  switch (rating.hard_contact) {
    case HardContact::kNotApplied:
      return "not applied (no " + rule.metric + ")";
    case HardContact::kAssumed:
      return "assumed (" + rule.metric + " " + util::FormatNumber(rating.contact_value, 4) + " > " +
             threshold + ")";
    case HardContact::kNotAssumed:
      return "not assumed (" + rule.metric + " " + util::FormatNumber(rating.contact_value, 4) + " ≤ " +
             threshold + "): " + util::FormatNumber(rule.points_without, 6) + " points";
  }
  return "";
}

db::Table LimitsTable(const db::Table& criteria, const LimitSet& limits) {
  db::Table table;
  table.columns = {"test_id", "series", "variant", "limits", "metric", "value", "limit", "margin_pct",
                   "meets",
                   // Additions (issue 44): the kind of limit and its outcome.
                   "kind", "higher_limit", "points", "max_points", "band", "hard_contact"};
  const auto column = [&](const std::string& name) {
    return static_cast<std::size_t>(std::find(criteria.columns.begin(), criteria.columns.end(), name) -
                                    criteria.columns.begin());
  };
  const auto number_or_null = [](double value) {
    return std::isfinite(value) ? db::Cell(value) : db::Cell(std::monostate{});
  };
  for (const std::vector<db::Cell>& row : criteria.rows) {
    const TestRating rating = RateTest(limits, [&](const std::string& metric) {
      const std::size_t at = column(metric);
      const double* number = at < row.size() ? std::get_if<double>(&row[at]) : nullptr;
      return number != nullptr ? *number : kNoValue;
    });
    const std::vector<db::Cell> head = {row[column("test_id")], row[column("series")], row[column("variant")],
                                        limits.name};
    for (std::size_t i = 0; i < limits.limits.size(); ++i) {
      const Limit& limit = limits.limits[i];
      const CriterionRating& criterion = rating.criteria[i];
      std::vector<db::Cell> out = head;
      out.insert(out.end(), {limit.metric, number_or_null(criterion.value), limit.max});
      out.push_back(criterion.has_value ? db::Cell(LimitMarginPct(criterion.value, limit.max)) : db::Cell());
      out.push_back(criterion.meets ? db::Cell(std::string(*criterion.meets ? "yes" : "no")) : db::Cell());
      out.push_back(std::string(LimitKindName(limit.kind)));
      const bool scale = limit.kind == LimitKind::kScale;
      out.push_back(scale ? db::Cell(limit.higher_limit) : db::Cell());
      out.push_back(number_or_null(criterion.points));
      out.push_back(scale ? db::Cell(limit.points) : db::Cell());
      out.push_back(criterion.band ? db::Cell(criterion.band->name) : db::Cell());
      out.emplace_back(std::monostate{});
      table.rows.push_back(std::move(out));
    }
    if (limits.combined) {
      std::vector<db::Cell> out = head;
      out.insert(out.end(), {limits.combined->name, db::Cell(), db::Cell(), db::Cell(), db::Cell(),
                             std::string("combined"), db::Cell(), number_or_null(rating.combined_points),
                             CombinedMaxPoints(limits), db::Cell()});
      const std::string contact = HardContactText(limits, rating);
      out.push_back(contact.empty() ? db::Cell() : db::Cell(contact));
      table.rows.push_back(std::move(out));
    }
  }
  return table;
}

}  // namespace napkin::app

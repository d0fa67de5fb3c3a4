#include "formats/summary_json.h"

#include <cmath>

#include "engine/summary_fields.h"

namespace napkin::formats {
namespace {

nlohmann::ordered_json Number(double value) {
  if (!std::isfinite(value)) return nullptr;
  return value;
}

}  // namespace

nlohmann::ordered_json FindingToJson(const engine::Finding& finding) {
  nlohmann::ordered_json json = nlohmann::ordered_json::object();
  json["check"] = finding.check;
  json["channel"] =
      finding.channel ? nlohmann::ordered_json(*finding.channel) : nlohmann::ordered_json(nullptr);
  json["severity"] = engine::SeverityName(finding.severity);
  json["detail"] = finding.detail;
  return json;
}

nlohmann::ordered_json SummaryToJson(const engine::TestSummary& summary, const std::string& test_id,
                                     const std::string& series, const std::string& variant) {
  nlohmann::ordered_json json = nlohmann::ordered_json::object();
  json["test_id"] = test_id;
  json["series"] = series;
  json["variant"] = variant;
  for (const engine::SummaryField* field :
       engine::SummaryFieldsOf({engine::SummaryGroup::kHic, engine::SummaryGroup::kRotation}))
    json[field->name] = Number(field->Get(summary));
  nlohmann::ordered_json quality = nlohmann::ordered_json::array();
  for (const engine::Finding& finding : summary.findings) quality.push_back(FindingToJson(finding));
  json["quality"] = std::move(quality);
  return json;
}

}  // namespace napkin::formats

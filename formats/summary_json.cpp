#include "formats/summary_json.h"

#include <cmath>

#include "engine/summary_fields.h"
#include "engine/units.h"

namespace napkin::formats {
namespace {

nlohmann::ordered_json Number(double value) {
  if (!std::isfinite(value)) return nullptr;
  return value;
}

nlohmann::ordered_json OptionalNumber(const std::optional<double>& value) {
  return value ? Number(*value) : nlohmann::ordered_json(nullptr);
}

}  // namespace

nlohmann::ordered_json ConditioningToJson(const engine::ChannelConditioning& record) {
  nlohmann::ordered_json json = nlohmann::ordered_json::object();
  json["channel"] = record.channel;
  json["filter"] = engine::FilterDescription(record);
  json["filter_cfc"] = OptionalNumber(record.filter_cfc);
  json["prefiltered_cfc"] = OptionalNumber(record.prefiltered_cfc);
  json["bias_removed"] = Number(record.bias_removed);
  json["bias_window_s"] = record.bias_window_start_s && record.bias_window_end_s
                              ? nlohmann::ordered_json::array(
                                    {Number(*record.bias_window_start_s), Number(*record.bias_window_end_s)})
                              : nlohmann::ordered_json(nullptr);
  json["time_shift_s"] = Number(record.time_shift_s);
  return json;
}

nlohmann::ordered_json FindingToJson(const engine::Finding& finding) {
  nlohmann::ordered_json json = nlohmann::ordered_json::object();
  json["check"] = finding.check;
  json["channel"] =
      finding.channel ? nlohmann::ordered_json(*finding.channel) : nlohmann::ordered_json(nullptr);
  json["severity"] = engine::NameOf(finding.severity);
  json["detail"] = finding.detail;
  return json;
}

nlohmann::ordered_json SalvageToJson(const engine::SalvageAudit& record) {
  nlohmann::ordered_json json = nlohmann::ordered_json::object();
  json["mode"] = record.mode;
  nlohmann::ordered_json channels = nlohmann::ordered_json::array();
  for (const engine::SalvagedChannel& channel : record.channels) {
    nlohmann::ordered_json entry = nlohmann::ordered_json::object();
    entry["channel"] = channel.channel;
    entry["fault"] = engine::NameOf(channel.fault);
    entry["action"] = engine::NameOf(channel.action);
    entry["partner"] =
        channel.partner ? nlohmann::ordered_json(*channel.partner) : nlohmann::ordered_json(nullptr);
    entry["interval_s"] = nlohmann::ordered_json::array({Number(channel.t1_s), Number(channel.t2_s)});
    entry["samples_replaced"] = channel.samples_replaced;
    channels.push_back(std::move(entry));
  }
  json["channels"] = std::move(channels);
  json["rms_residual_before_g"] = Number(record.rms_residual_before_mps2 / engine::kStandardGravity);
  json["rms_residual_after_g"] = Number(record.rms_residual_after_mps2 / engine::kStandardGravity);
  json["channels_used"] = record.channels_used;
  json["channels_total"] = record.channels_total;
  return json;
}

nlohmann::ordered_json SummaryToJson(const engine::TestSummary& summary, const std::string& test_id,
                                     const std::string& series, const std::string& variant) {
  nlohmann::ordered_json json = nlohmann::ordered_json::object();
  json["test_id"] = test_id;
  json["series"] = series;
  json["variant"] = variant;
  for (const engine::SummaryField* field : engine::SummaryFieldsOf(
           {engine::SummaryGroup::kHic, engine::SummaryGroup::kRotation, engine::SummaryGroup::kRisk}))
    json[field->name] = Number(field->Get(summary));
  nlohmann::ordered_json quality = nlohmann::ordered_json::array();
  for (const engine::Finding& finding : summary.findings) quality.push_back(FindingToJson(finding));
  json["quality"] = std::move(quality);
  // Present only for a salvaged result (docs/formats.md "Salvage record").
  if (summary.salvage) json["salvage"] = SalvageToJson(*summary.salvage);
  if (!summary.conditioning.empty()) {
    nlohmann::ordered_json conditioning = nlohmann::ordered_json::array();
    for (const engine::ChannelConditioning& record : summary.conditioning)
      conditioning.push_back(ConditioningToJson(record));
    json["conditioning"] = std::move(conditioning);
  }
  return json;
}

}  // namespace napkin::formats

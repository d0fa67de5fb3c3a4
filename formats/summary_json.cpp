#include "formats/summary_json.h"

#include <cmath>

namespace napkin::formats {
namespace {

nlohmann::ordered_json Number(double value) {
  if (!std::isfinite(value)) return nullptr;
  return value;
}

}  // namespace

nlohmann::json FindingToJson(const engine::Finding& finding) {
  nlohmann::json json = nlohmann::json::object();
  json["check"] = finding.check;
  json["channel"] = finding.channel ? nlohmann::json(*finding.channel) : nlohmann::json(nullptr);
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
  // query hic
  json["hic15"] = Number(summary.hic15.value);
  json["hic15_t1_s"] = Number(summary.hic15.t1_s);
  json["hic15_t2_s"] = Number(summary.hic15.t2_s);
  json["hic36"] = Number(summary.hic36.value);
  json["hic36_t1_s"] = Number(summary.hic36.t1_s);
  json["hic36_t2_s"] = Number(summary.hic36.t2_s);
  json["hic"] = Number(summary.hic.value);
  json["hic_t1_s"] = Number(summary.hic.t1_s);
  json["hic_t2_s"] = Number(summary.hic.t2_s);
  json["peak_acc_g"] = Number(summary.peak_acc_g);
  json["a3ms_g"] = Number(summary.a3ms_g);
  // query rotation
  json["peak_omega_x_radps"] = Number(summary.peak_omega_body_radps.x());
  json["peak_omega_y_radps"] = Number(summary.peak_omega_body_radps.y());
  json["peak_omega_z_radps"] = Number(summary.peak_omega_body_radps.z());
  json["peak_omega_radps"] = Number(summary.peak_omega_radps);
  json["peak_alpha_radps2"] = Number(summary.peak_alpha_radps2);
  json["bric"] = Number(summary.bric);
  json["damage"] = Number(summary.damage);
  json["final_quat_w"] = Number(summary.final_quat_wxyz[0]);
  json["final_quat_x"] = Number(summary.final_quat_wxyz[1]);
  json["final_quat_y"] = Number(summary.final_quat_wxyz[2]);
  json["final_quat_z"] = Number(summary.final_quat_wxyz[3]);
  json["final_roll_deg"] = Number(summary.final_roll_pitch_yaw_deg.x());
  json["final_pitch_deg"] = Number(summary.final_roll_pitch_yaw_deg.y());
  json["final_yaw_deg"] = Number(summary.final_roll_pitch_yaw_deg.z());
  json["final_pos_x_m"] = Number(summary.final_pos_fixed_m.x());
  json["final_pos_y_m"] = Number(summary.final_pos_fixed_m.y());
  json["final_pos_z_m"] = Number(summary.final_pos_fixed_m.z());
  json["max_rotation_deg"] = Number(summary.max_rotation_deg);
  nlohmann::ordered_json quality = nlohmann::ordered_json::array();
  for (const engine::Finding& finding : summary.findings) {
    nlohmann::ordered_json item = nlohmann::ordered_json::object();
    item["check"] = finding.check;
    item["channel"] = finding.channel ? nlohmann::ordered_json(*finding.channel) : nlohmann::ordered_json(nullptr);
    item["severity"] = engine::SeverityName(finding.severity);
    item["detail"] = finding.detail;
    quality.push_back(std::move(item));
  }
  json["quality"] = std::move(quality);
  return json;
}

}  // namespace napkin::formats

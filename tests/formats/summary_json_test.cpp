#include "formats/summary_json.h"

#include <gtest/gtest.h>

#include <limits>

#include "engine/summary_fields.h"

namespace napkin::formats {
namespace {

TEST(SummaryJsonTest, ExactlyTheContractFieldsInOrder) {
  engine::TestSummary summary;
  summary.hic15 = {512.5, 0.010, 0.025};
  summary.hic36 = {700.0, 0.005, 0.041};
  summary.hic = {701.0, 0.004, 0.050};
  summary.peak_acc_g = 88.0;
  summary.a3ms_g = 80.0;
  summary.hic_d = 694.5;
  summary.peak_omega_body_radps = Eigen::Vector3d(1, 2, 3);
  summary.peak_omega_radps = 3.5;
  summary.peak_alpha_radps2 = 1500;
  summary.bric = 0.7;
  summary.damage = std::numeric_limits<double>::quiet_NaN();
  summary.final_quat_wxyz = Eigen::Vector4d(0.5, 0.5, -0.5, 0.5);
  summary.final_roll_pitch_yaw_deg = Eigen::Vector3d(10, 20, 30);
  summary.final_pos_fixed_m = Eigen::Vector3d(0.1, 0.2, 0.3);
  summary.max_rotation_deg = 45;
  engine::FindSummaryField("ubric")->Set(summary, 0.375);  // a criterion its row computes
  summary.hic15_p_ais3 = 0.25;
  summary.hic36_p_ais4 = 0.125;
  summary.bric_p_ais3 = 0.5;
  summary.bric_p_ais4 = std::numeric_limits<double>::quiet_NaN();
  summary.findings.push_back(
      {"saturation", std::string("yarm_z"), engine::Severity::kWarning, "Clipped at 500 g."});
  summary.findings.push_back({"residual", std::nullopt, engine::Severity::kError, "Residual is large."});
  const nlohmann::ordered_json json = SummaryToJson(summary, "T1", "S", "foam-a");

  const std::vector<std::string> expected_keys = {"test_id",
                                                  "series",
                                                  "variant",
                                                  "hic15",
                                                  "hic15_t1_s",
                                                  "hic15_t2_s",
                                                  "hic36",
                                                  "hic36_t1_s",
                                                  "hic36_t2_s",
                                                  "hic",
                                                  "hic_t1_s",
                                                  "hic_t2_s",
                                                  "peak_acc_g",
                                                  "a3ms_g",
                                                  "hic_d",
                                                  "peak_omega_x_radps",
                                                  "peak_omega_y_radps",
                                                  "peak_omega_z_radps",
                                                  "peak_omega_radps",
                                                  "peak_alpha_radps2",
                                                  "bric",
                                                  "damage",
                                                  "final_quat_w",
                                                  "final_quat_x",
                                                  "final_quat_y",
                                                  "final_quat_z",
                                                  "final_roll_deg",
                                                  "final_pitch_deg",
                                                  "final_yaw_deg",
                                                  "final_pos_x_m",
                                                  "final_pos_y_m",
                                                  "final_pos_z_m",
                                                  "max_rotation_deg",
                                                  "ubric",
                                                  "hic15_p_ais3",
                                                  "hic36_p_ais4",
                                                  "bric_p_ais3",
                                                  "bric_p_ais4",
                                                  "quality"};
  std::vector<std::string> keys;
  for (const auto& item : json.items()) keys.push_back(item.key());
  EXPECT_EQ(keys, expected_keys);
  EXPECT_EQ(json["test_id"], "T1");
  EXPECT_EQ(json["variant"], "foam-a");
  EXPECT_EQ(json["hic15_t2_s"], 0.025);
  EXPECT_EQ(json["hic36"], 700.0);
  EXPECT_EQ(json["peak_omega_y_radps"], 2.0);
  EXPECT_TRUE(json["damage"].is_null());
  EXPECT_EQ(json["final_quat_y"], -0.5);
  EXPECT_EQ(json["final_yaw_deg"], 30.0);
  EXPECT_EQ(json["final_pos_z_m"], 0.3);
  ASSERT_EQ(json["quality"].size(), 2u);
  EXPECT_EQ(json["quality"][0].dump(),
            R"({"check":"saturation","channel":"yarm_z","severity":"warning","detail":"Clipped at 500 g."})");
  EXPECT_TRUE(json["quality"][1]["channel"].is_null());
  EXPECT_EQ(json["quality"][1]["severity"], "error");
  EXPECT_EQ(FindingToJson(summary.findings[0])["channel"], "yarm_z");
  EXPECT_EQ(FindingToJson(summary.findings[1]).dump(), json["quality"][1].dump());
  // The whole text, byte for byte, as the hand-written writer produced it
  // before the field table drove it (plus hic_d, added with schema 3, and the
  // injury risks, schema 8, and UBrIC, schema 14).
  EXPECT_EQ(
      json.dump(),
      R"({"test_id":"T1","series":"S","variant":"foam-a","hic15":512.5,"hic15_t1_s":0.01,)"
      R"("hic15_t2_s":0.025,"hic36":700.0,"hic36_t1_s":0.005,"hic36_t2_s":0.041,"hic":701.0,)"
      R"("hic_t1_s":0.004,"hic_t2_s":0.05,"peak_acc_g":88.0,"a3ms_g":80.0,"hic_d":694.5,)"
      R"("peak_omega_x_radps":1.0,)"
      R"("peak_omega_y_radps":2.0,"peak_omega_z_radps":3.0,"peak_omega_radps":3.5,)"
      R"("peak_alpha_radps2":1500.0,"bric":0.7,"damage":null,"final_quat_w":0.5,"final_quat_x":0.5,)"
      R"("final_quat_y":-0.5,"final_quat_z":0.5,"final_roll_deg":10.0,"final_pitch_deg":20.0,)"
      R"("final_yaw_deg":30.0,"final_pos_x_m":0.1,"final_pos_y_m":0.2,"final_pos_z_m":0.3,)"
      R"("max_rotation_deg":45.0,"ubric":0.375,"hic15_p_ais3":0.25,"hic36_p_ais4":0.125,"bric_p_ais3":0.5,)"
      R"("bric_p_ais4":null,"quality":[{"check":"saturation","channel":"yarm_z",)"
      R"("severity":"warning","detail":"Clipped at 500 g."},{"check":"residual","channel":null,)"
      R"("severity":"error","detail":"Residual is large."}]})");
}

}  // namespace
}  // namespace napkin::formats

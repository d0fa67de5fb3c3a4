#pragma once
// A small, fixed report (header, one series comparison, three tests: two
// with rotation, one acceleration-only) whose page is kept as a golden file
// (tests/formats/golden/report_sample.html), written by the page renderer of
// before the report streamed: the streamed page must stay byte-identical.
// Only what formats/html_report.h offered then is used here.
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "engine/kinematics.h"
#include "engine/summary.h"
#include "engine/units.h"
#include "formats/html_report.h"

namespace napkin::report_sample {

// n samples at 10 kHz from t = -2 ms: a half-sine pulse of `peak_g` with a
// rotation about z and the velocity of the pulse. Without rotation (an
// acceleration-only array), every series that needs it is NaN, as stored
// before such series were left out.
inline engine::Kinematics Kinematics(Eigen::Index n, double peak_g, bool rotation) {
  engine::Kinematics k;
  k.Resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = -0.002 + static_cast<double>(i) * 1e-4;
    const double pulse = t >= 0.0 && t <= 0.012 ? std::sin(std::numbers::pi * t / 0.012) : 0.0;
    k.time_s(i) = t;
    k.acc_body.row(i) << -peak_g * engine::kStandardGravity * pulse,
        0.1 * peak_g * engine::kStandardGravity * pulse * pulse, 0.5;
    k.acc_fixed.row(i) = k.acc_body.row(i);
    k.omega_body.row(i) << 0.5 * pulse, -0.25 * pulse, 20.0 * pulse;
    k.omega_fixed.row(i) = k.omega_body.row(i);
    k.alpha_body.row(i) << 0.0, 0.0, 1000.0 * pulse;
    k.alpha_fixed.row(i) = k.alpha_body.row(i);
    k.roll_pitch_yaw_rad.row(i) << 0.001 * static_cast<double>(i), 0.0, 0.3 * pulse;
    k.dcos_rad.row(i) << 0.3 * pulse, 0.3 * pulse, 0.0;
    k.vel_fixed.row(i) << -5.0 + 5.0 * std::min(1.0, std::max(0.0, t / 0.012)), 0.0, 0.0;
    k.pos_fixed.row(i) << -5.0 * t, 0.0, 0.0;
    k.quat_fixed_from_body.row(i) << 1.0, 0.0, 0.0, 0.0;
    k.residual(i) = 0.01;
  }
  if (!rotation) {
    constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
    for (engine::Series3* series :
         {&k.omega_body, &k.alpha_body, &k.omega_fixed, &k.alpha_fixed, &k.acc_fixed, &k.vel_fixed,
          &k.pos_fixed, &k.roll_pitch_yaw_rad, &k.dcos_rad})
      series->setConstant(kNaN);
    k.quat_fixed_from_body.setConstant(kNaN);
    k.residual.setConstant(kNaN);
  }
  return k;
}

inline engine::TestSummary Summary(double hic15, bool rotation) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  engine::TestSummary summary;
  summary.hic15 = {hic15, 0.0021, 0.0099};
  summary.hic36 = {hic15 * 1.05, 0.0010, 0.0110};
  summary.hic = summary.hic36;
  summary.hic_d = 0.75446 * summary.hic36.value + 166.4;
  summary.peak_acc_g = 80.0;
  summary.a3ms_g = 71.25;
  summary.bric = rotation ? 0.61 : kNaN;
  summary.damage = rotation ? 0.07 : kNaN;
  summary.peak_omega_body_radps =
      rotation ? Eigen::Vector3d(0.5, 0.25, 20.0) : Eigen::Vector3d::Constant(kNaN);
  summary.peak_omega_radps = rotation ? 20.01 : kNaN;
  summary.peak_alpha_radps2 = rotation ? 1000.0 : kNaN;
  summary.final_quat_wxyz = rotation ? Eigen::Vector4d(1.0, 0.0, 0.0, 0.0) : Eigen::Vector4d::Constant(kNaN);
  summary.final_roll_pitch_yaw_deg =
      rotation ? Eigen::Vector3d(1.5, 0.0, 0.0) : Eigen::Vector3d::Constant(kNaN);
  summary.final_pos_fixed_m = rotation ? Eigen::Vector3d(0.05, 0.0, 0.0) : Eigen::Vector3d::Constant(kNaN);
  summary.max_rotation_deg = rotation ? 17.2 : kNaN;
  summary.max_residual_mps2 = rotation ? 0.01 : kNaN;
  summary.findings.push_back({"saturation", std::string("cg_x"), engine::Severity::kWarning,
                              "channel cg_x sits at <full scale> for 3 samples & more."});
  if (!rotation)
    summary.findings.push_back({"rotation", std::nullopt, engine::Severity::kInfo,
                                "array 3a-cg cannot determine rotation from its sensors."});
  return summary;
}

inline formats::ReportHeader Header() {
  formats::ReportHeader header;
  header.catalogue = "lab & co.db";
  header.napkin_version = "0.1.0+gsample";
  header.selection = "series sled";
  header.configs.push_back({"default", std::string(64, 'c'), R"({"filter":{"linear_cfc":1000}})"});
  return header;
}

inline std::vector<formats::ReportComparison> Comparisons() {
  formats::ReportComparison comparison;
  comparison.series = "sled";
  comparison.columns = {"metric", "variant", "n", "mean"};
  comparison.rows = {{"hic15", "a&b", "2", "650.5"}, {"hic15", "plain", "1", "700"}};
  comparison.notes = {"Variant plain has fewer than 2 tests with results: no interval and no p-value (—)."};
  comparison.distributions.push_back(
      {"hic15", {{"a&b", {600.25, 700.75}, 650.5, 300.0, 1000.0}, {"plain", {700.0}, 700.0, {}, {}}}});
  return {comparison};
}

inline std::vector<formats::ReportTest> Tests() {
  std::vector<formats::ReportTest> tests;
  tests.push_back(formats::MakeReportTest("sled-01", "sled", "a&b", "default", Summary(600.25, true),
                                          Kinematics(400, 80.0, true)));
  tests.push_back(formats::MakeReportTest("sled-02", "sled", "a&b", "default", Summary(700.75, true),
                                          Kinematics(300, 90.0, true), 100));
  tests.push_back(formats::MakeReportTest("sled-03", "sled", "plain", "default", Summary(700.0, false),
                                          Kinematics(200, 85.0, false)));
  return tests;
}

}  // namespace napkin::report_sample

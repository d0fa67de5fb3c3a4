// `napkin demo`: the report's validation scenarios, computed vs known answers.
#include <fmt/core.h>

#include <filesystem>

#include "cli/command.h"
#include "cli/transform.h"
#include "engine/report_known_answers.h"
#include "engine/rotation.h"
#include "engine/synth.h"
#include "engine/units.h"
#include "formats/array_json.h"
#include "formats/csv.h"

namespace napkin::cli {
namespace {

namespace fs = std::filesystem;

// The computed counterparts of the report section 4.5 known answers
// (engine/report_known_answers.h).
struct ScenarioNumbers {
  double rotation_about_y_deg = 0;  // angle of R_end R0^T
  double peak_omega_y_fixed = 0;
  double max_abs_omega_xz_fixed = 0;
  double peak_alpha = 0;
  double peak_acc_g = 0;
  double hic = 0, hic_t1_ms = 0, hic_t2_ms = 0, hic36 = 0, hic15 = 0;
};

ScenarioNumbers Measure(const TransformReport& report) {
  const engine::Kinematics& k = report.kinematics;
  const Eigen::Index last = k.size() - 1;
  auto quat = [&](Eigen::Index i) {
    return Eigen::Quaterniond(k.quat_fixed_from_body(i, 0), k.quat_fixed_from_body(i, 1),
                              k.quat_fixed_from_body(i, 2), k.quat_fixed_from_body(i, 3));
  };
  ScenarioNumbers n;
  n.rotation_about_y_deg = engine::AngleBetween(quat(0), quat(last)) * engine::kDegPerRad;
  n.peak_omega_y_fixed = k.omega_fixed.col(1).maxCoeff();
  n.max_abs_omega_xz_fixed =
      std::max(k.omega_fixed.col(0).cwiseAbs().maxCoeff(), k.omega_fixed.col(2).cwiseAbs().maxCoeff());
  n.peak_alpha = report.summary.peak_alpha_radps2;
  n.peak_acc_g = report.summary.peak_acc_g;
  n.hic = report.summary.hic.value;
  n.hic_t1_ms = report.summary.hic.t1_s * 1e3;
  n.hic_t2_ms = report.summary.hic.t2_s * 1e3;
  n.hic36 = report.summary.hic36.value;
  n.hic15 = report.summary.hic15.value;
  return n;
}

class DemoCommand : public Command {
 public:
  CLI::App* Setup(CLI::App& app, const GlobalOptions&) override {
    CLI::App* sub =
        app.add_subcommand("demo", "run the report's validation scenarios and print known answers");
    sub->add_option("--dir", dir_, "working directory for the demo files")->capture_default_str();
    return sub;
  }

  int Run() override {
    fs::create_directories(dir_);
    const char* geometries[3] = {"ideal-3222", "volpe-table4-2", "denton-3222"};
    ScenarioNumbers numbers[3];
    fmt::print(
        "napkin demo — report section 4.5: rotation about an axis parallel to fixed Y, 10 in from the CG,\n"
        "head initially at phi = theta = psi = 0.5 rad, 100 ms at 10 kHz, processed by `napkin transform`\n"
        "(exact solver) with each 3-2-2-2 geometry. Files in {}/\n\n",
        dir_);
    for (int g = 0; g < 3; ++g) {
      const engine::ArrayGeometry array = formats::LoadArray(geometries[g]);
      const engine::SyntheticTest test = engine::SynthSeedFixedAxis(array, Eigen::Vector3d(0.5, 0.5, 0.5));
      TransformOptions options;
      options.array = geometries[g];
      options.orientation_rad = {0.5, 0.5, 0.5};
      options.input = (fs::path(dir_) / (std::string("seed-fixed-axis_") + geometries[g] + ".csv")).string();
      options.out = (fs::path(dir_) / (std::string("derived_") + geometries[g] + ".csv")).string();
      options.summary = (fs::path(dir_) / (std::string("summary_") + geometries[g] + ".json")).string();
      formats::WriteSignalsCsv(test.signals, options.input);
      numbers[g] = Measure(RunTransform(options));
    }
    fmt::print("{:<40} {:>12} {:>14} {:>14} {:>14}\n", "quantity", "known", geometries[0], geometries[1],
               geometries[2]);
    // The known column is printed as the report states it (`known_format`),
    // the computed columns to the precision that shows the agreement.
    auto row = [&](const char* label, double known, const char* known_format, double ScenarioNumbers::*field,
                   const char* format) {
      fmt::print("{:<40} {:>12}", label, fmt::format(fmt::runtime(known_format), known));
      for (const auto& n : numbers) fmt::print(" {:>14}", fmt::format(fmt::runtime(format), n.*field));
      fmt::print("\n");
    };
    namespace known = engine::report;
    row("total rotation about fixed Y (deg)", known::kTotalRotationDeg, "{:.4f}",
        &ScenarioNumbers::rotation_about_y_deg, "{:.4f}");
    row("peak fixed omega_Y (rad/s)", known::kPeakOmegaFixedYRadps, "{:.0f}",
        &ScenarioNumbers::peak_omega_y_fixed, "{:.4f}");
    row("max |fixed omega_X|, |omega_Z| (rad/s)", known::kOmegaFixedXZRadps, "{:.0f}",
        &ScenarioNumbers::max_abs_omega_xz_fixed, "{:.2e}");
    row("peak angular acceleration (rad/s^2)", known::kPeakAlphaRadps2, "{:.0f}",
        &ScenarioNumbers::peak_alpha, "{:.1f}");
    row("peak resultant CG acceleration (g)", known::kPeakAccG, "{:.2f}", &ScenarioNumbers::peak_acc_g,
        "{:.2f}");
    row("HIC, unlimited window", known::kHic, "{:.2f}", &ScenarioNumbers::hic, "{:.2f}");
    row("  t1 (ms)", known::kHicT1S * 1e3, "{:.1f}", &ScenarioNumbers::hic_t1_ms, "{:.1f}");
    row("  t2 (ms)", known::kHicT2S * 1e3, "{:.1f}", &ScenarioNumbers::hic_t2_ms, "{:.1f}");
    row("HIC36", known::kHic36, "{:.2f}", &ScenarioNumbers::hic36, "{:.2f}");
    row("HIC15", known::kHic15, "{:.2f}", &ScenarioNumbers::hic15, "{:.2f}");

    // The report's point (section 4.5, Table 4-2): the legacy program without
    // compensation for the true geometry is off by percents.
    fmt::print("\nseed solver (LC_COMP, Appendix B) on Table 4-2 data:\n");
    const engine::ArrayGeometry table42 = formats::LoadArray("volpe-table4-2");
    const engine::SyntheticTest test = engine::SynthSeedFixedAxis(table42, Eigen::Vector3d(0.5, 0.5, 0.5));
    const std::string input = (fs::path(dir_) / "seed-fixed-axis_volpe-table4-2.csv").string();
    formats::WriteSignalsCsv(test.signals, input);
    fmt::print("{:<40} {:>16} {:>16} {:>18}\n", "processed as", "peak |omega_X|", "peak |omega_Z|",
               "final orient. err");
    for (const char* as : {"ideal-3222", "volpe-table4-2"}) {
      TransformOptions options;
      options.array = as;
      options.solver = "seed";
      options.orientation_rad = {0.5, 0.5, 0.5};
      options.input = input;
      options.out = (fs::path(dir_) / (std::string("seed_as_") + as + ".csv")).string();
      const TransformReport report = RunTransform(options);
      const engine::Kinematics& k = report.kinematics;
      const Eigen::Index last = k.size() - 1;
      const Eigen::Quaterniond q(k.quat_fixed_from_body(last, 0), k.quat_fixed_from_body(last, 1),
                                 k.quat_fixed_from_body(last, 2), k.quat_fixed_from_body(last, 3));
      const Eigen::Quaterniond q_true(
          test.truth.quat_fixed_from_body(last, 0), test.truth.quat_fixed_from_body(last, 1),
          test.truth.quat_fixed_from_body(last, 2), test.truth.quat_fixed_from_body(last, 3));
      fmt::print("{:<40} {:>11.4f} rad/s {:>11.4f} rad/s {:>14.4f} deg\n", std::string("seed, ") + as,
                 k.omega_fixed.col(0).cwiseAbs().maxCoeff(), k.omega_fixed.col(2).cwiseAbs().maxCoeff(),
                 engine::AngleBetween(q, q_true) * engine::kDegPerRad);
    }
    fmt::print(
        "(report: about {:.0f} % of the {:.0f} rad/s peak in fixed omega_X and omega_Z without "
        "compensation)\n",
        100 * engine::report::kUncompensatedCrossAxisFraction, engine::report::kPeakOmegaFixedYRadps);
    return kExitOk;
  }

 private:
  std::string dir_ = "napkin-demo";
};

}  // namespace

std::unique_ptr<Command> MakeDemoCommand() { return std::make_unique<DemoCommand>(); }

}  // namespace napkin::cli

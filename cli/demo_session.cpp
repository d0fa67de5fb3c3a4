// The work of `napkin demo` (cli/command_demo.cpp).
#include "cli/demo_session.h"

#include <fmt/core.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "app/comparison.h"
#include "app/limits.h"
#include "app/report_builder.h"
#include "app/result_selection.h"
#include "app/table_output.h"
#include "app/transform.h"
#include "app/verdict.h"
#include "cli/catalogue_option.h"
#include "cli/demo_folder.h"
#include "common/error.h"
#include "engine/report_known_answers.h"
#include "engine/rotation.h"
#include "engine/units.h"
#include "formats/array_json.h"
#include "formats/csv.h"
#include "ingest/synthetic_import.h"
#include "jobs/scheduler.h"
#include "records/config_record.h"
#include "synth/synthetic_tests.h"

namespace napkin::cli {
namespace {

namespace fs = std::filesystem;

constexpr const char* kPaddingSeries = "padding-series";
constexpr const char* kValidationSeries = "validation";
constexpr const char* kGeometries[3] = {"ideal-3222", "volpe-table4-2", "denton-3222"};
// The padding series is recorded with the NAP array of the report's tests (Appendix A, Denton 3-2-2-2).
constexpr const char* kPaddingArray = "denton-3222";
// The padding every other is compared with, in the printed table and in the report.
constexpr const char* kPaddingBaseline = "production";

std::string ValidationTestId(const char* geometry) { return std::string("seed-fixed-axis-") + geometry; }

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

ScenarioNumbers Measure(const engine::Kinematics& k, const engine::TestSummary& summary) {
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
  n.peak_alpha = summary.peak_alpha_radps2;
  n.peak_acc_g = summary.peak_acc_g;
  n.hic = summary.hic.value;
  n.hic_t1_ms = summary.hic.t1_s * 1e3;
  n.hic_t2_ms = summary.hic.t2_s * 1e3;
  n.hic36 = summary.hic36.value;
  n.hic15 = summary.hic15.value;
  return n;
}

// The demo's files, in its folder (cli/demo_folder.h).
constexpr const char* kDemoDb = "napkin.db";
constexpr const char* kDemoReport = "report.html";
constexpr const char* kSeedInput = "seed-fixed-axis_volpe-table4-2.csv";
std::string SeedOutput(const char* as) { return std::string("seed_as_") + as + ".csv"; }

// DIR/csv/<variant>/<test>.csv of a padding test (relative to DIR).
fs::path PaddingCsvPath(const synth::ScenarioTest& test) {
  return fs::path("csv") / test.variant.value_or("none") / (test.external_id + ".csv");
}

ingest::SynthPlan PaddingPlan() {
  ingest::SynthRequest padding;
  padding.scenario = synth::SynthScenario::kPaddingSeries;
  padding.array = kPaddingArray;
  return ingest::PlanSynth(padding);
}

// Every file the demo writes, relative to its folder (the stamp aside).
std::vector<fs::path> DemoFiles() {
  std::vector<fs::path> files = {kDemoDb, kDemoReport, kSeedInput};
  for (const char* as : {"ideal-3222", "volpe-table4-2"}) files.emplace_back(SeedOutput(as));
  for (const synth::ScenarioTest& test : PaddingPlan().tests) files.push_back(PaddingCsvPath(test));
  return files;
}

// The padding series and the three validation tests, stored as `napkin
// synth` stores them.
int StoreDemoTests(const std::string& db_path) {
  db::Catalogue catalogue = db::Catalogue::Open(db_path);
  int added = ingest::StoreSynthTests(catalogue, PaddingPlan()).added;
  for (const char* geometry : kGeometries) {
    ingest::SynthRequest validation;
    validation.scenario = synth::SynthScenario::kSeedFixedAxis;
    validation.array = geometry;
    validation.series = kValidationSeries;
    validation.test_id = ValidationTestId(geometry);
    added += ingest::StoreSynthTests(catalogue, ingest::PlanSynth(validation)).added;
  }
  return added;
}

// The padding series' raw channels as a laboratory delivers them, one CSV
// file per test in a folder per padding (DIR/csv/<variant>/<test>.csv), for
// the README's tour of `napkin import`. Returns the folder.
fs::path WritePaddingCsvFiles(const fs::path& dir) {
  const ingest::SynthPlan plan = PaddingPlan();
  for (const synth::ScenarioTest& test : plan.tests) {
    const fs::path path = dir / PaddingCsvPath(test);
    fs::create_directories(path.parent_path());
    formats::WriteSignalsCsv(synth::SynthScenarioTest(plan.array, plan.scenario, test).signals, path);
  }
  return dir / "csv";
}

// The padding series compared by variant against production trim, as
// `napkin compare --series padding-series --baseline production --metrics ...`
// prints it, for the metrics that tell the story: HIC, the CG acceleration, and
// the rotation that the padding barely changes.
void PrintPaddingComparison(db::Catalogue& catalogue, const std::vector<std::string>& limits) {
  app::CompareRequest request;
  request.series = kPaddingSeries;
  request.baseline = kPaddingBaseline;
  request.limits = limits;
  // The verdict first, from compare's default metrics, as the report words it.
  fmt::print("{}\n", app::FormatVerdict(app::BuildVerdict(app::BuildComparison(catalogue, request))));
  request.metrics = {"hic15", "hic_d", "peak_acc_g", "peak_omega_radps", "peak_alpha_radps2", "bric"};
  fmt::print("{}", app::FormatComparison(app::BuildComparison(catalogue, request), app::TableFormat::kTable));
}

// Report section 4.5, from the catalogue's results of the validation tests.
void PrintValidationTable(db::Catalogue& catalogue, db::ConfigId config) {
  ScenarioNumbers numbers[3];
  for (int g = 0; g < 3; ++g) {
    const db::TestId test = catalogue.FindTestByExternalId(ValidationTestId(kGeometries[g])).value();
    numbers[g] = Measure(app::ReadResultKinematics(catalogue, test, config),
                         catalogue.ReadSummary(test, config).value());
  }
  fmt::print(
      "report section 4.5: rotation about an axis parallel to fixed Y, 10 in from the CG, head initially at\n"
      "phi = theta = psi = 0.5 rad, 100 ms at 10 kHz (series '{}'), processed with each 3-2-2-2 geometry\n"
      "(exact solver):\n",
      kValidationSeries);
  fmt::print("{:<40} {:>12} {:>14} {:>14} {:>14}\n", "quantity", "known", kGeometries[0], kGeometries[1],
             kGeometries[2]);
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
  row("peak angular acceleration (rad/s^2)", known::kPeakAlphaRadps2, "{:.0f}", &ScenarioNumbers::peak_alpha,
      "{:.1f}");
  row("peak resultant CG acceleration (g)", known::kPeakAccG, "{:.2f}", &ScenarioNumbers::peak_acc_g,
      "{:.2f}");
  row("HIC, unlimited window", known::kHic, "{:.2f}", &ScenarioNumbers::hic, "{:.2f}");
  row("  t1 (ms)", known::kHicT1S * 1e3, "{:.1f}", &ScenarioNumbers::hic_t1_ms, "{:.1f}");
  row("  t2 (ms)", known::kHicT2S * 1e3, "{:.1f}", &ScenarioNumbers::hic_t2_ms, "{:.1f}");
  row("HIC36", known::kHic36, "{:.2f}", &ScenarioNumbers::hic36, "{:.2f}");
  row("HIC15", known::kHic15, "{:.2f}", &ScenarioNumbers::hic15, "{:.2f}");
}

// The report's point (section 4.5, Table 4-2): the legacy program without
// compensation for the true geometry is off by percents. Computed by `napkin
// transform` (seed solver) on files in `dir`.
void PrintSeedSolverTable(const fs::path& dir) {
  fmt::print("\nseed solver (LC_COMP, Appendix B) on Table 4-2 data:\n");
  const engine::ArrayGeometry table42 = formats::LoadArray("volpe-table4-2");
  const synth::SyntheticTest test = synth::SynthSeedFixedAxis(table42, Eigen::Vector3d(0.5, 0.5, 0.5));
  const std::string input = (dir / kSeedInput).string();
  formats::WriteSignalsCsv(test.signals, input);
  fmt::print("{:<40} {:>16} {:>16} {:>18}\n", "processed as", "peak |omega_X|", "peak |omega_Z|",
             "final orient. err");
  for (const char* as : {"ideal-3222", "volpe-table4-2"}) {
    app::TransformOptions options;
    options.input.array = as;
    options.solver = "seed";
    options.orientation_rad = {0.5, 0.5, 0.5};
    options.input.path = input;
    options.out = (dir / SeedOutput(as)).string();
    const app::TransformReport report = app::RunTransform(options);
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
}

// Processes the demo's tests as `napkin run` does (in parallel, resumably)
// with the default config and prints one line about it. Throws InputError
// when a test failed.
jobs::RunReport ProcessDemoTests(const std::string& db, int threads) {
  const records::ResolvedConfig processing = records::ResolveConfig("");
  jobs::RunOptions options;
  options.threads =
      threads > 0 ? threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const spdlog::level::level_enum log_level = spdlog::get_level();
  spdlog::set_level(spdlog::level::warn);  // the demo prints its own summary line
  jobs::RunReport run = jobs::RunScheduler(db, processing, options);
  spdlog::set_level(log_level);
  fmt::print("  processed {} tests in {:.2f} s on {} threads (config '{}'), {} failed\n\n", run.done,
             run.wall_s, run.threads, processing.record.name, run.failed);
  if (run.failed > 0)
    throw InputError(std::to_string(run.failed) + " demo tests failed; `napkin --db " + db +
                     " status` lists them.");
  return run;
}

// The commands that continue the tour from the demo's folder.
void PrintNextSteps(const std::string& db, const fs::path& csv_dir) {
  const std::string napkin = "napkin --db " + db;
  fmt::print(
      "\nnext, try:\n"
      "  {0} query hic --where \"hic15>700\"\n"
      "  {0} compare --series {1} --by variant --baseline production\n"
      "  {0} report --series {1} --baseline production --align onset --out padding.html\n"
      "  {0} export --test {1}-production-01 --format lsdyna --out head.k\n"
      "  napkin --db lab.db import --array {3} --series sled --variant foam-b {2}/foam-b  "
      "(the raw channels of the padding series are in {2}/)\n",
      napkin, kPaddingSeries, csv_dir.string(), kPaddingArray);
}

}  // namespace

void RunDemo(const DemoRequest& request) {
  const fs::path dir(request.dir);
  // An unknown or malformed --limits stops the demo before it builds anything.
  for (const std::string& limits : request.limits) app::LoadLimits(limits);
  const bool replaced = PrepareDemoFolder(dir, kDemoDb);
  WriteDemoStamp(dir, DemoFiles());
  const fs::path db_path = dir / kDemoDb;
  const fs::path report_path = dir / kDemoReport;
  const std::string db = db_path.string();

  fmt::print("napkin demo: catalogue {}{}\n", db,
             replaced ? " (rebuilt from scratch: the previous demo's catalogue was replaced)" : "");
  const int added = StoreDemoTests(db);
  fmt::print(
      "  {} tests: series '{}' (oblique head impacts modelled on the report's sections 3.3 and 3.10:\n"
      "  production trim, foam-a, foam-b, {} repeats each, {} array) and series '{}' (report 4.5 on {}, "
      "{}, {})\n",
      added, kPaddingSeries, synth::kPaddingRepeats, kPaddingArray, kValidationSeries, kGeometries[0],
      kGeometries[1], kGeometries[2]);

  const jobs::RunReport run = ProcessDemoTests(db, request.threads);

  db::CatalogueOptions read_only;
  read_only.read_only = true;
  db::Catalogue catalogue = db::Catalogue::Open(db, read_only);
  fmt::print("padding series: HIC and rotation of production trim vs foam A and foam B\n");
  PrintPaddingComparison(catalogue, request.limits);
  fmt::print("\n");
  PrintValidationTable(catalogue, run.config);
  PrintSeedSolverTable(dir);
  const fs::path csv_dir = WritePaddingCsvFiles(dir);

  fmt::print("\n");
  app::ReportOptions report_options;
  report_options.baseline = kPaddingBaseline;
  report_options.limits = request.limits;
  fmt::print("{}",
             app::WrittenReportText(app::WriteCatalogueReport(db, {}, report_path.string(), report_options)));
  PrintNextSteps(db, csv_dir);
}

}  // namespace napkin::cli

#include "cli/transform.h"

#include <cmath>
#include <filesystem>
#include <optional>

#include "engine/error.h"
#include "engine/pipeline.h"
#include "engine/processing.h"
#include "formats/array_json.h"
#include "formats/csv.h"
#include "formats/atomic_file.h"
#include "formats/lsdyna.h"
#include "formats/processing_config_json.h"
#include "formats/summary_json.h"
#include "formats/text.h"

namespace napkin::cli {
namespace fs = std::filesystem;

Eigen::Vector3d ParseTriple(const std::string& text, const std::string& flag) {
  if (text.empty()) return Eigen::Vector3d::Zero();
  Eigen::Vector3d values;
  std::size_t start = 0;
  for (int i = 0; i < 3; ++i) {
    const std::size_t end = i < 2 ? text.find(',', start) : text.size();
    const std::optional<double> value =
        end == std::string::npos ? std::nullopt : formats::ParseDouble(std::string_view(text).substr(start, end - start));
    if (!value || !std::isfinite(*value) || (i == 2 && text.find(',', start) != std::string::npos))
      throw InputError(flag + " needs three comma-separated numbers, e.g. 0.5,0.5,0.5 (got '" + text + "').");
    values[i] = *value;
    start = end + 1;
  }
  return values;
}

TransformReport RunTransform(const TransformOptions& options) {
  const engine::ArrayGeometry array = formats::LoadArray(options.array);
  if (!fs::exists(options.input)) throw InputError("input file '" + options.input + "' does not exist.");
  formats::CsvSignals csv = formats::ReadSignalsCsv(options.input, &array);

  engine::ProcessingConfig config;
  if (!options.config.empty())
    config = formats::ReadProcessingConfig(formats::ResolvePreset(options.config, "processing"));
  if (!options.solver.empty())
    config.solver = options.solver == "seed" ? engine::SolverKind::kSeed : engine::SolverKind::kExact;
  engine::InitialState initial;
  initial.orientation_rad = ParseTriple(options.orientation_rad, "--orientation");
  initial.velocity_fixed_mps = ParseTriple(options.initial_velocity_mps, "--initial-velocity");

  TransformReport report;
  report.warnings = std::move(csv.warnings);
  try {
    engine::ProcessedTest processed = engine::ProcessTest(array, csv.signals, initial, config);
    report.kinematics = std::move(processed.kinematics);
    report.summary = std::move(processed.summary);
  } catch (const InputError& error) {
    throw InputError(options.input + ": " + error.what());
  }

  const std::string test_id = fs::path(options.input).stem().string();
  const std::string summary_text =
      formats::SummaryToJson(report.summary, test_id, "", "").dump(2) + "\n";
  // Each writer is atomic; if a later one fails, the earlier outputs of this
  // run are removed too, so a failed transform leaves no output behind.
  std::vector<fs::path> written;
  try {
    formats::WriteDerivedCsv(report.kinematics, options.out);
    written.emplace_back(options.out);
    if (!options.summary.empty()) {
      formats::WriteFileAtomically(options.summary, [&](formats::AtomicFile& file) { file.Write(summary_text); });
      written.emplace_back(options.summary);
    }
    if (!options.lsdyna.empty()) formats::WriteLsDynaKeyword(report.kinematics, options.lsdyna);
  } catch (...) {
    std::error_code ignored;
    for (const auto& path : written) fs::remove(path, ignored);
    throw;
  }
  return report;
}

}  // namespace napkin::cli

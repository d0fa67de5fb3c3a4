#include "app/transform.h"

#include <cmath>
#include <filesystem>
#include <optional>

#include "app/db_protection.h"
#include "app/result_selection.h"
#include "common/error.h"
#include "engine/pipeline.h"
#include "engine/processing.h"
#include "engine/solver.h"
#include "formats/array_json.h"
#include "formats/csv.h"
#include "formats/lsdyna.h"
#include "formats/summary_json.h"
#include "ingest/discovery.h"
#include "ingest/dummy_heads.h"
#include "records/config_record.h"
#include "util/atomic_file.h"
#include "util/output_destination.h"
#include "util/text.h"

namespace napkin::app {
namespace fs = std::filesystem;

namespace {

std::string SolverNames(const std::string& separator) {
  std::string names;
  for (const engine::SolverKind kind : engine::kSolverKinds)
    names += (names.empty() ? "" : separator) + engine::NameOf(kind);
  return names;
}

// t0 and dt from the sampling interval or the sample times.
formats::TimeBase CheckedTimeBase(const SampleTimes& times, Eigen::Index samples, const std::string& source) {
  if (const double* dt = std::get_if<double>(&times)) {
    if (!(std::isfinite(*dt) && *dt > 0.0))
      throw InputError(source + ": dt_s " + util::FormatNumber(*dt) +
                       " s is not a finite positive sampling interval.");
    return {0.0, *dt};
  }
  const std::span<const double> values = std::get<std::span<const double>>(times);
  if (static_cast<Eigen::Index>(values.size()) != samples)
    throw InputError(source + ": time_s has " + std::to_string(values.size()) +
                     " values but the channels have " + std::to_string(samples) + " samples.");
  for (std::size_t k = 0; k < values.size(); ++k)
    if (!std::isfinite(values[k]))
      throw InputError(source + ": time_s[" + std::to_string(k) + "] is " + util::FormatNumber(values[k]) +
                       ", not a finite number.");
  return formats::UniformTimeBase(
      values, source, [](std::size_t k) { return "time_s[" + std::to_string(k) + "]"; }, "sample");
}

Eigen::Vector3d Vector3OrZero(const std::vector<double>& values) {
  return values.size() == 3 ? Eigen::Vector3d(values[0], values[1], values[2]) : Eigen::Vector3d::Zero();
}

}  // namespace

void SetSolver(engine::ProcessingConfig& config, const std::string& name) {
  const std::optional<engine::SolverKind> solver = engine::ParseName<engine::SolverKind>(name);
  if (!solver) throw InputError("unknown solver \"" + name + "\" (use " + SolverNames(" or ") + ").");
  config.solver = *solver;
  config.Check();  // the config's other settings may not suit this solver
}

engine::TestSignals SignalsFromSamples(Eigen::MatrixXd samples, const engine::ArrayGeometry& array,
                                       const SampleTimes& times, const std::string& source) {
  for (Eigen::Index c = 0; c < samples.cols(); ++c)
    for (Eigen::Index k = 0; k < samples.rows(); ++k)
      if (!std::isfinite(samples(k, c)))
        formats::RefuseNonFiniteSample(source + ": sample " + std::to_string(k) + ", channel " +
                                           util::Quoted(array.sensors[static_cast<std::size_t>(c)].slot),
                                       util::FormatNumber(samples(k, c)));
  formats::CheckSampleCount(static_cast<std::size_t>(samples.rows()), source, "sample");
  const formats::TimeBase time_base = CheckedTimeBase(times, samples.rows(), source);
  engine::TestSignals signals;
  signals.t0_s = time_base.t0_s;
  signals.dt_s = time_base.dt_s;
  for (const engine::Sensor& sensor : array.sensors) signals.slots.push_back(sensor.slot);
  signals.samples = std::move(samples);
  return signals;
}

void ProcessSignals(const engine::ArrayGeometry& array, const engine::TestSignals& signals,
                    const engine::InitialState& initial, const engine::ProcessingConfig& config,
                    const std::string& source, engine::Workspace& workspace, engine::ProcessedTest& processed,
                    const std::atomic<bool>* cancel) {
  try {
    engine::ProcessTest(array, signals, initial, config, workspace, processed, cancel);
    // The verdict `napkin run` records: a test that fails there fails here,
    // with the same sentence.
    if (const engine::Finding* failing = engine::FailingFinding(processed))
      throw engine::ScreeningFailure(failing->detail, processed.summary.findings);
  } catch (const engine::ScreeningFailure& failure) {
    throw engine::ScreeningFailure(source + ": " + failure.what(), failure.findings());
  } catch (const InputError& error) {
    throw InputError(source + ": " + error.what());
  }
}

engine::ProcessedTest ProcessSignals(const engine::ArrayGeometry& array, const engine::TestSignals& signals,
                                     const engine::InitialState& initial,
                                     const engine::ProcessingConfig& config, const std::string& source,
                                     const std::atomic<bool>* cancel) {
  engine::Workspace workspace;
  engine::ProcessedTest processed;
  ProcessSignals(array, signals, initial, config, source, workspace, processed, cancel);
  return processed;
}

TestFile ReadTestFile(const TestFileOptions& options) {
  const fs::path presets = options.config_dir.empty() ? formats::DefaultConfigDir() : options.config_dir;
  std::optional<engine::ArrayGeometry> array;
  if (!options.array.empty())
    array =
        formats::ReadArrayJson(formats::ResolvePreset(formats::PresetKind::kArray, options.array, presets));
  std::optional<formats::ChannelMap> channel_map;
  if (!options.channel_map.empty())
    channel_map = formats::ReadChannelMap(
        formats::ResolvePreset(formats::PresetKind::kChannelMap, options.channel_map, presets));
  const formats::ChannelMap default_map =
      formats::ReadChannelMap(formats::ResolvePreset(formats::PresetKind::kChannelMap, "default", presets));
  const ingest::Discovery discovery = ingest::DiscoverInputs({options.path});
  if (!discovery.errors.empty()) throw InputError(discovery.errors.front());
  if (discovery.inputs.size() != 1)
    throw InputError("'" + options.path + "' holds " + std::to_string(discovery.inputs.size()) +
                     " tests; a transform reads one (give one of them).");
  const ingest::ImportInput& input = discovery.inputs.front();

  ingest::HeadReadOptions read;
  read.array = array ? &*array : nullptr;
  read.array_option = options.array_option;
  read.config_dir = presets;
  read.channel_map = channel_map ? &*channel_map : nullptr;
  read.default_map = &default_map;
  read.csv_columns = ingest::CsvColumnsOf(read.channel_map, options.csv_columns);
  read.position = options.position;
  read.one_test_expected = "a transform reads one";
  ingest::InputHeads heads = ingest::ReadInputHeads(input, read, input.name);
  ingest::HeadSignals& head = heads.heads.front();
  TestFile file;
  file.array = std::move(heads.array);
  file.signals = std::move(head.signals);
  file.test_id = heads.test_id.value_or(input.name);
  file.warnings = std::move(heads.warnings);
  file.warnings.insert(file.warnings.end(), head.notes.begin(), head.notes.end());
  return file;
}

TransformReport RunTransform(const TransformOptions& options) {
  // One stream cannot carry two files (docs/formats.md "Output destinations").
  int to_standard_output = 0;
  for (const std::string* output : {&options.out, &options.summary, &options.lsdyna})
    to_standard_output += *output == util::kStandardOutputName;
  if (to_standard_output > 1)
    throw UsageError("only one of --out, --summary and --lsdyna can be standard output (-).");
  // A command's own inputs are never its outputs, nor is one output another
  // (docs/formats.md "Output destinations"): refused before anything is read.
  ProtectInputFromOutput(options.input.path, "the input recording");
  if (!options.input.array.empty())
    ProtectInputFromOutput(formats::ResolvePreset(formats::PresetKind::kArray, options.input.array),
                           "the --array file");
  if (!options.input.channel_map.empty())
    ProtectInputFromOutput(
        formats::ResolvePreset(formats::PresetKind::kChannelMap, options.input.channel_map),
        "the --channel-map file");
  ProtectInputFromOutput(records::ProcessingConfigPath(options.config, formats::DefaultConfigDir()),
                         "the --config file");
  util::CheckDistinctOutputs(
      {{"--out", options.out}, {"--summary", options.summary}, {"--lsdyna", options.lsdyna}});
  for (const std::string* output : {&options.out, &options.summary, &options.lsdyna})
    if (!output->empty()) util::ResolveOutputDestination(*output);  // refused before anything is computed
  TestFile input = ReadTestFile(options.input);
  const engine::ArrayGeometry& array = input.array;

  // The same resolution as `napkin run` (empty: the "default" preset), so a
  // catalogue result equals the transform of the same input.
  engine::ProcessingConfig config = ResolveConfig(options.config).config;
  if (!options.solver.empty()) SetSolver(config, options.solver);
  engine::InitialState initial;
  initial.orientation_rad = Vector3OrZero(options.orientation_rad);
  initial.velocity_fixed_mps = Vector3OrZero(options.initial_velocity_mps);

  TransformReport report;
  report.warnings = std::move(input.warnings);
  // A failing test fails before any output is written.
  engine::ProcessedTest processed = ProcessSignals(array, input.signals, initial, config, options.input.path);
  report.kinematics = std::move(processed.kinematics);
  report.summary = std::move(processed.summary);

  if (!options.lsdyna.empty() && !engine::HasRotation(report.kinematics))
    throw InputError(options.input.path + ": array '" + array.name +
                     "' cannot determine rotation, which --lsdyna needs; --out gives the CG acceleration.");

  const std::string& test_id = input.test_id;
  // The id is the input's file name (or the files' own), of unknown encoding: bytes that are not
  // UTF-8 become U+FFFD.
  const std::string summary_text =
      formats::SummaryToJson(report.summary, test_id, "", "")
          .dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) +
      "\n";
  // Every output is opened (decided on, its temporary file created) before
  // any is written, and all are renamed into place only when all were
  // written: a refused or failed output leaves no other output of this run
  // behind, and nothing napkin did not write is ever removed
  // (docs/formats.md "Output destinations").
  std::optional<util::AtomicFile> out_file, summary_file, lsdyna_file;
  out_file.emplace(options.out);
  if (!options.summary.empty()) summary_file.emplace(options.summary);
  if (!options.lsdyna.empty()) lsdyna_file.emplace(options.lsdyna);
  formats::WriteDerivedCsv(report.kinematics, *out_file);
  if (summary_file) summary_file->Write(summary_text);
  if (lsdyna_file) formats::WriteLsDynaKeyword(report.kinematics, *lsdyna_file);
  out_file->Commit();
  if (summary_file) summary_file->Commit();
  if (lsdyna_file) lsdyna_file->Commit();
  return report;
}

}  // namespace napkin::app

#pragma once
// The transform of one test without a catalogue (docs/architecture.md "A
// test's life"): signals from a file (`napkin transform`, RunTransform) or
// from samples in memory (napkin.transform, SignalsFromSamples), checked as
// the CSV reader checks them, processed as `napkin run` processes a stored
// test (ProcessSignals: engine::ProcessTest, and engine::FailingFinding's
// sentence for a failing test).
#include <Eigen/Core>
#include <atomic>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "engine/kinematics.h"
#include "engine/pipeline.h"
#include "engine/processing.h"
#include "engine/summary.h"

namespace napkin::app {

// Sets the solver named `name` (engine::SolverKind's names); throws
// InputError listing the solvers for an unknown name, and what
// ProcessingConfig::Check finds when the config's other settings do not
// suit that solver.
void SetSolver(engine::ProcessingConfig& config, const std::string& name);

// The sample times of signals in memory: the sampling interval dt in s
// (the first sample at t = 0), or one time per sample in s.
using SampleTimes = std::variant<double, std::span<const double>>;

// The signals of one test from samples in memory: `samples` holds one row per
// sample and one column per sensor of `array`, in its order. Checks every
// value is a finite number and there are at least two samples
// (formats::RefuseNonFiniteSample, CheckSampleCount: the CSV reader's
// sentences, a sample named "sample K, channel \"SLOT\"") and the times:
// dt finite and positive, or one finite time per sample, uniformly spaced
// (formats::UniformTimeBase, a time named "time_s[K]"). Throws InputError
// starting with `source`.
engine::TestSignals SignalsFromSamples(Eigen::MatrixXd samples, const engine::ArrayGeometry& array,
                                       const SampleTimes& times, const std::string& source);

// One test processed as `napkin run` processes a stored one
// (engine::ProcessTest); a test that fails there (engine::FailingFinding)
// fails here with the same sentence, as engine::ScreeningFailure carrying the
// findings. Every InputError starts with `source`.
// `cancel` as engine::ProcessTest's.
engine::ProcessedTest ProcessSignals(const engine::ArrayGeometry& array, const engine::TestSignals& signals,
                                     const engine::InitialState& initial,
                                     const engine::ProcessingConfig& config, const std::string& source,
                                     const std::atomic<bool>* cancel = nullptr);
// The same in the caller's memory (engine::ProcessTest's workspace form): a
// loop over tests of one length maps no new pages (docs/architecture.md
// "Memory").
void ProcessSignals(const engine::ArrayGeometry& array, const engine::TestSignals& signals,
                    const engine::InitialState& initial, const engine::ProcessingConfig& config,
                    const std::string& source, engine::Workspace& workspace, engine::ProcessedTest& processed,
                    const std::atomic<bool>* cancel = nullptr);

// One test file read as `napkin import` reads it (every format of the
// input-format table, ingest/input_formats.h), for a transform without a
// catalogue: `napkin transform` and napkin.read_test.
struct TestFileOptions {
  std::string path;                      // a test file or folder (one test)
  std::string array;                     // preset name or array JSON path; empty: the channel codes define it
  std::string channel_map;               // preset name or path; empty: the "default" map
  std::optional<std::string> position;   // the dummy head to take, of a test that records several
  std::vector<std::string> csv_columns;  // --column SLOT=NAME
  std::string array_option = "--array";  // how the front end names the array in sentences
  std::filesystem::path config_dir;      // the presets (empty: formats::DefaultConfigDir())
};

struct TestFile {
  engine::ArrayGeometry array;        // the one given, or the one the codes define
  engine::TestSignals signals;        // in the array's slot order, each channel's prefiltered class
  std::string test_id;                // the files' id (DTS SLICEWare's Test ID), else the input's name
  std::vector<std::string> warnings;  // the import's warnings and notes (cropped spans)
};

// Throws InputError (one sentence naming the file) when the path holds no
// test or several, for a reader's refusal, and for a test with several dummy
// heads without `position`.
TestFile ReadTestFile(const TestFileOptions& options);

struct TransformOptions {
  TestFileOptions input;                     // the test file, its array, channel map, position, --column
  std::vector<double> orientation_rad;       // phi, theta, psi (empty: 0, 0, 0)
  std::vector<double> initial_velocity_mps;  // vx, vy, vz fixed frame (empty: 0)
  std::string solver;                        // engine::SolverName (empty: the config's solver)
  std::string config;                        // processing config preset/path (empty: default)
  std::string out;                           // derived-channel CSV
  std::string summary;                       // summary JSON (optional)
  std::string lsdyna;                        // LS-DYNA keyword file (optional)
};

struct TransformReport {
  engine::Kinematics kinematics;
  engine::TestSummary summary;
  std::vector<std::string> warnings;
};

// Reads, solves and writes every requested output; nothing is written unless
// everything succeeded (outputs are renamed into place at the end). Throws
// InputError with one sentence naming the file, channel or row at fault.
TransformReport RunTransform(const TransformOptions& options);

}  // namespace napkin::app

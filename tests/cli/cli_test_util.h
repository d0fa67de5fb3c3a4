#pragma once
// Helpers of the CLI end-to-end tests: run the napkin binary in a folder and
// capture its exit status, stdout and stderr (tests/support/run_command.h);
// read a catalogue's state; make synthetic tests in every input format.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <string>
#include <vector>

#include "db/catalogue.h"
#include "engine/pipeline.h"
#include "formats/array_json.h"
#include "records/array_record.h"
#include "records/config_record.h"
#include "synth/synthetic_tests.h"
#include "tests/support/db/catalogue_inspector.h"
#include "tests/support/run_command.h"
#include "util/text.h"

namespace napkin::test_support {

namespace fs = std::filesystem;

using RunResult = napkin::test_support::CommandResult;

inline void WriteText(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// Runs `napkin args...` with `dir` as the working directory (stdin from /dev/null).
inline RunResult RunNapkin(const fs::path& dir, const std::vector<std::string>& args) {
  return napkin::test_support::RunProgram(NAPKIN_BINARY, args, dir);
}

// Starts `napkin args...` (stdout and stderr to the given files); wait with
// napkin::test_support::WaitProgram.
inline pid_t StartNapkin(const std::vector<std::string>& args, const fs::path& out_path,
                         const fs::path& err_path) {
  return napkin::test_support::StartProgram(NAPKIN_BINARY, args, out_path, err_path);
}

inline std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// stderr is exactly one line: "napkin: <one sentence>." holding every fragment.
inline void ExpectOneSentenceError(const RunResult& run, std::initializer_list<std::string> fragments) {
  const std::vector<std::string> lines = Lines(run.err);
  ASSERT_EQ(lines.size(), 1u) << "stderr:\n" << run.err;
  const std::string& line = lines.front();
  EXPECT_EQ(line.rfind("napkin: ", 0), 0u) << line;
  EXPECT_EQ(line.back(), '.') << line;
  for (const std::string& fragment : fragments)
    EXPECT_NE(line.find(fragment), std::string::npos) << "stderr: " << line << "\nmissing: " << fragment;
}

inline db::Catalogue OpenForReading(const fs::path& path) {
  db::CatalogueOptions options;
  options.read_only = true;
  return db::Catalogue::Open(path.string(), options);
}

inline std::string DumpCatalogue(const fs::path& path) {
  db::Catalogue catalogue = OpenForReading(path);
  return db::CatalogueInspector(catalogue).Dump();
}

// A NAP (3-2-2-2) test with a random smooth motion on the Denton geometry.
inline synth::SyntheticTest SynthNapTest(std::uint64_t seed, double duration_s = 0.05) {
  synth::RandomMotionOptions options;
  options.seed = seed;
  options.duration_s = duration_s;
  return synth::SynthRandomMotion(formats::LoadArray("denton-3222"), options);
}

// "--orientation=a,b,c" with numbers in their shortest exact form.
inline std::string TripleFlag(const char* flag, const Eigen::Vector3d& value) {
  return std::string(flag) + "=" + util::FormatNumber(value.x()) + "," + util::FormatNumber(value.y()) + "," +
         util::FormatNumber(value.z());
}

// Computes and stores the result of test `test_id` under the default config
// the way the batch scheduler does (engine::ProcessTest on the catalogue's
// signals, array and initial state; Catalogue::WriteResult with kinematics).
inline engine::ProcessedTest ProcessAndStore(const fs::path& db_path, const std::string& test_id) {
  db::Catalogue catalogue = db::Catalogue::Open(db_path.string());
  const std::optional<db::TestId> key = catalogue.FindTestByExternalId(test_id);
  if (!key) throw std::runtime_error("no test " + test_id);
  const db::TestRow test = catalogue.ReadTest(*key);
  const engine::ArrayGeometry array = records::DecodeArrayRecord(catalogue.ReadArray(test.array_id));
  const records::ResolvedConfig config = records::ResolveConfig("");
  engine::ProcessedTest processed =
      engine::ProcessTest(array, catalogue.ReadTestSignals(*key), test.initial_state, config.config);
  const db::ConfigId config_id = catalogue.WriteConfig(config.record);
  catalogue.WriteResult(*key, config_id, processed.summary, "exact", &processed.kinematics);
  return processed;
}

}  // namespace napkin::test_support

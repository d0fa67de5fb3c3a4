#pragma once
// A test's processing inputs as the catalogue holds them, and the one path
// from them to its result. `napkin run` (jobs/: TestInputReader on its reader
// thread, ComputeResult on a compute thread), the recomputation of a result
// whose config stores no derived channels (export, report: RecomputeResult)
// and `napkin_catalogue_io verify` (bench/) all go through here, so a
// recomputation equals the stored result bit for bit
// (tests/jobs/recomputation_test.cpp; docs/formats.md "Derived-channel
// storage").
#include <map>
#include <memory>
#include <string>

#include "db/catalogue.h"
#include "engine/pipeline.h"

namespace napkin::records {

// What engine::ProcessTest computes a test's result from.
struct TestInputs {
  std::string external_id;
  engine::InitialState initial;
  engine::TestSignals signals;                         // the raw channels
  std::shared_ptr<const engine::ArrayGeometry> array;  // null when its record cannot be decoded:
  std::string array_error;                             // ... then the InputError sentence why
  // The stored array record `array` is decoded from (name, canonical JSON,
  // hash): what every recomputation of the test uses, the Python
  // Catalogue.test_inputs included (issue 29 point 6).
  std::shared_ptr<const db::ArrayRow> array_record;
};

// Reads tests' inputs from one catalogue, decoding each array once (the
// tests of a run share a few arrays).
class TestInputReader {
 public:
  explicit TestInputReader(db::Catalogue& catalogue) : catalogue_(catalogue) {}

  // The stored test record, raw channels and decoded array of `test`. An
  // array that cannot be decoded is no error here (ComputeResult's): the
  // test's other inputs are still read.
  TestInputs Read(db::TestId test);

 private:
  struct DecodedArray {
    std::shared_ptr<const db::ArrayRow> record;
    std::shared_ptr<const engine::ArrayGeometry> geometry;
    std::string error;
  };
  db::Catalogue& catalogue_;
  std::map<db::ArrayId, DecodedArray> arrays_;
};

// The result of `inputs` under `config`: engine::ProcessTest. Throws
// InputError when the array could not be decoded (its sentence), and what
// ProcessTest throws.
engine::ProcessedTest ComputeResult(const TestInputs& inputs, const engine::ProcessingConfig& config);

// ComputeResult in the caller's memory (engine::ProcessTest with a
// workspace and a kept result; engine/pipeline.h Workspace), with the
// derived series `series` (engine::SeriesKept).
void ComputeResult(const TestInputs& inputs, const engine::ProcessingConfig& config,
                   engine::Workspace& workspace, engine::ProcessedTest& out,
                   engine::SeriesKept series = engine::SeriesKept::kAll);

// The result of `test` under the stored config `config` computed again:
// its inputs read (TestInputReader), the config decoded from its record
// (DecodeConfigRecord), ComputeResult. Throws InputError when the test has
// no raw channels (a results file of `run --results` holds none).
engine::ProcessedTest RecomputeResult(db::Catalogue& catalogue, db::TestId test, db::ConfigId config);

}  // namespace napkin::records

#pragma once
// Shared pieces of the scheduler tests: catalogues of synthetic tests and the
// processing setup of a run.
#include <cstdio>
#include <string>

#include "db/catalogue.h"
#include "formats/array_json.h"
#include "ingest/store.h"
#include "jobs/scheduler.h"
#include "records/array_record.h"
#include "records/config_record.h"
#include "synth/synthetic_tests.h"

namespace napkin::test_support {

inline records::ResolvedConfig Processing(const engine::ProcessingConfig& config = {}) {
  return records::ResolvedConfig{config, records::MakeConfigRecord(config, "test-config")};
}

inline std::string TestName(int index) {
  char name[16];
  std::snprintf(name, sizeof name, "r%04d", index);
  return name;
}

// Stores `test` as test `external_id` with the array record `array` (by
// default the record of the test's array; content hash from the id: the
// tests here only need unique hashes).
inline db::TestId StoreTest(db::Catalogue& catalogue, const synth::SyntheticTest& test,
                            const std::string& external_id, const std::string& series = "synthetic",
                            const db::ArrayRow* array = nullptr) {
  db::TestRow record;
  record.external_id = external_id;
  record.series = series;
  record.initial_state = test.initial;
  record.source_path = "synth";
  record.content_hash = "synthetic " + external_id;
  return *ingest::StoreTest(catalogue, test.array, array ? *array : records::MakeArrayRecord(test.array),
                            record, test.signals);
}

// `count` random motions of `samples` samples at 10 kHz on the ideal array,
// ids r0000, r0001, ...
inline void AddRandomTests(const std::string& path, int count, int samples = 1000, int first = 0) {
  db::Catalogue catalogue = db::Catalogue::Open(path);
  const engine::ArrayGeometry array = formats::LoadArray("ideal-3222");
  for (int i = first; i < first + count; ++i) {
    synth::RandomMotionOptions options;
    options.seed = 100 + static_cast<std::uint64_t>(i);
    options.duration_s = (samples - 1) / options.synth.rate_hz;
    StoreTest(catalogue, synth::SynthRandomMotion(array, options), TestName(i));
  }
}

}  // namespace napkin::test_support

#pragma once
// Shared pieces of the scheduler tests: catalogues of synthetic tests and the
// processing setup of a run.
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "db/catalogue.h"
#include "engine/synth.h"
#include "formats/array_json.h"
#include "formats/content_hash.h"
#include "formats/processing_config_json.h"
#include "jobs/scheduler.h"

namespace napkin::jobs::testing {

inline engine::ArrayGeometry DecodeArray(const db::ArrayRecord& record) {
  return formats::ParseArrayJson(nlohmann::json::parse(record.definition_json), record.name);
}

inline RunProcessing Processing(const engine::ProcessingConfig& config = {}) {
  RunProcessing processing;
  processing.config = config;
  processing.record.name = "test-config";
  processing.record.config_json = formats::CanonicalProcessingConfig(config);
  processing.record.config_hash = formats::Sha256Hex(processing.record.config_json);
  processing.decode_array = DecodeArray;
  return processing;
}

inline std::string TestName(int index) {
  char name[16];
  std::snprintf(name, sizeof name, "r%04d", index);
  return name;
}

// Stores `test` as test `external_id` (content hash from the id: the tests
// here only need unique hashes).
inline db::TestId StoreTest(db::Catalogue& catalogue, const engine::SyntheticTest& test,
                            const std::string& external_id, const std::string& series = "synthetic") {
  db::ArrayRecord array;
  array.name = test.array.name;
  array.definition_json = formats::ArrayToJson(test.array).dump();
  array.definition_hash = formats::Sha256Hex(array.definition_json);
  db::Transaction transaction = catalogue.BeginTransaction();
  db::TestRecord record;
  record.external_id = external_id;
  record.series = series;
  record.array_id = catalogue.WriteArray(array);
  record.initial_state = test.initial;
  record.source_path = "synth";
  record.content_hash = "synthetic " + external_id;
  const db::TestId id = catalogue.WriteTest(record);
  std::vector<std::string> units;
  for (const std::string& slot : test.signals.slots) units.push_back(test.array.sensors[*test.array.FindSlot(slot)].unit);
  catalogue.WriteRawChannels(id, test.signals, units);
  transaction.Commit();
  return id;
}

// `count` random motions of `samples` samples at 10 kHz on the ideal array,
// ids r0000, r0001, ...
inline void AddRandomTests(const std::string& path, int count, int samples = 1000, int first = 0) {
  db::Catalogue catalogue = db::Catalogue::Open(path);
  const engine::ArrayGeometry array = formats::LoadArray("ideal-3222");
  for (int i = first; i < first + count; ++i) {
    engine::RandomMotionOptions options;
    options.seed = 100 + static_cast<std::uint64_t>(i);
    options.duration_s = (samples - 1) / options.synth.rate_hz;
    StoreTest(catalogue, engine::SynthRandomMotion(array, options), TestName(i));
  }
}

}  // namespace napkin::jobs::testing
